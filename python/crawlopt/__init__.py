"""crawlopt: simulation and optimal gaits of rate-independent soft crawlers.

A thin Python layer over the Rust library (``crawlopt._crawlopt``): every computation, default
and check is the library's; this package converts arguments, wraps answers in classes with
NumPy arrays, and renders them (text, SVG figures, HTML in Jupyter, a progress bar).

>>> import crawlopt as co
>>> c = co.Crawler(blocks=2, stiffness=1.0, mu_forward=1.0, mu_backward=2.0)
>>> act = co.Actuation.sine(period=1.0, amplitude=[3.0])
>>> round(co.simulate(c, act).displacement_per_period, 9)   # max(0, 2A - 2), theory §10
4.0
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any, Callable, Optional, Union

import numpy as np

from . import _crawlopt as _rs
from ._crawlopt import (
    CrawloptError,
    FileError,
    InadmissibleError,
    InfeasibleError,
    InputError,
    NonUniqueError,
    NumericalError,
    TimeLimitError,
)
from ._progress import progress_callback

__version__ = _rs.__version__

__all__ = [
    "Actuation",
    "Analysis",
    "CrawloptError",
    "Crawler",
    "Figure",
    "FileError",
    "GaitProblem",
    "GaitResult",
    "GeneralProblem",
    "InadmissibleError",
    "InfeasibleError",
    "InputError",
    "Model",
    "NonUniqueError",
    "NumericalError",
    "Quadratic",
    "Simulation",
    "TimeLimitError",
    "load",
    "optimize",
    "simulate",
    "sweep",
]

Numbers = Union[float, Sequence[float]]
Progress = Union[bool, Callable[[dict], Any], None]


def _input_error(field: str, value: Any, reason: str) -> InputError:
    """An InputError raised on the Python side, with ``.field`` and ``.value`` as the library's
    (the value as text)."""
    e = InputError(f"{field}: {reason} (got {value})")
    e.field, e.value = field, str(value)
    return e


def _array(value: Any, name: str, ndim: int, shape: str) -> np.ndarray:
    """``value`` as a float array of exactly ``ndim`` dimensions: an array of another shape is
    refused (InputError, a ValueError, naming ``name`` and the ``shape`` expected), never
    flattened or broadcast (an amplitude of shape (2, 1) is not two links)."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise _input_error(name, repr(value), f"must be {shape} of numbers ({e})") from None
    if a.ndim != ndim:
        raise _input_error(name, f"an array of shape {a.shape}", f"must be {shape}")
    return a


def _vector(value: Any, name: str, what: str = "entries") -> list[float]:
    """A one-dimensional list of numbers (``what`` names its entries in the message)."""
    return [float(v) for v in _array(value, name, 1, f"a list of {what} (shape (n,))")]


def _each(value: Numbers, count: int, name: str) -> list[float]:
    """A number for every entry, or a list of them (as the TOML schema allows)."""
    if np.ndim(value) == 0:
        return [float(_array(value, name, 0, "a number"))] * count
    values = _vector(value, name, "numbers, one per entry, or a single number")
    if len(values) != count:
        raise _input_error(name, len(values), f"must have {count} entries")
    return values


def _instance(value: Any, cls: type, name: str) -> None:
    """TypeError unless ``value`` is a ``cls`` (not an AttributeError from deep inside)."""
    if not isinstance(value, cls):
        raise TypeError(f"{name}: must be a crawlopt.{cls.__name__}, got {type(value).__name__}")


def _table(rows: list[dict]):
    import pandas as pd  # optional dependency

    return pd.DataFrame(rows)


class Figure:
    """A figure: its ``name``, ``caption`` and SVG text; displays itself in Jupyter."""

    def __init__(self, name: str, caption: str, svg: str):
        self.name, self.caption, self.svg = name, caption, svg

    def _repr_svg_(self) -> str:
        return self.svg

    def save(self, path: str) -> None:
        """Writes the SVG to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.svg)

    def __repr__(self) -> str:
        return f"Figure({self.name!r}: {self.caption})"


class Analysis:
    """The analysis of a crawler (``crawlopt analyze``): the polytope C (``faces``,
    ``link_force_ranges``, ``vertices``), the uniqueness condition (paper eq. 3.5), the class of
    v_m and the directions the crawler can move. Every field of the JSON is an attribute."""

    def __init__(self, doc: dict):
        self._doc = doc
        for k, v in doc.items():
            setattr(self, k, v)

    def to_dict(self) -> dict:
        """The fields of the JSON document as a dict (as ``--json`` prints them)."""
        return dict(self._doc)

    def __repr__(self) -> str:
        d = self._doc
        return (
            f"Analysis(N={d['blocks']}, unique={d['uniqueness_ok']}, "
            f"vm_class={d.get('vm_class')}, forward={d.get('moves_forward')})"
        )


class Crawler:
    """A crawler of ``blocks`` blocks: ``stiffness`` per link, ``mu_forward`` and
    ``mu_backward`` (friction thresholds against forward and backward sliding) per block; each a
    number or a list, as in the model file's ``[crawler]`` section."""

    def __init__(
        self,
        blocks: int,
        stiffness: Numbers = 1.0,
        mu_forward: Numbers = 1.0,
        mu_backward: Numbers = 1.0,
        *,
        _inner: Optional[Any] = None,
    ):
        if _inner is None:
            if not isinstance(blocks, (int, np.integer)) or blocks < 2:
                raise _input_error("crawler.blocks", repr(blocks), "must be a whole number >= 2")
            _inner = _rs.Crawler(
                _each(stiffness, blocks - 1, "crawler.stiffness"),
                _each(mu_forward, blocks, "crawler.mu_forward"),
                _each(mu_backward, blocks, "crawler.mu_backward"),
            )
        self._inner = _inner

    blocks = property(lambda self: len(self._inner.mu_forward), doc="N, the number of blocks.")
    links = property(lambda self: len(self._inner.stiffness), doc="n = N - 1, the number of links.")
    stiffness = property(
        lambda self: np.array(self._inner.stiffness), doc="k_l per link (force / length)."
    )
    mu_forward = property(
        lambda self: np.array(self._inner.mu_forward),
        doc="mu_b^+ per block: the friction threshold against forward sliding (force).",
    )
    mu_backward = property(
        lambda self: np.array(self._inner.mu_backward),
        doc="mu_b^- per block: the friction threshold against backward sliding (force).",
    )

    def analyze(self) -> Analysis:
        """The polytope C, the uniqueness condition, v_m's class and directions (exact)."""
        return Analysis(json.loads(self._inner.analyze_json()))

    def vm(self, rates: Sequence[float]) -> float:
        """v_m(z'): the barycentre velocity for the shape rates z' (one per link)."""
        return self._inner.vm(_vector(rates, "rates", "shape rates, one per link"))

    def __repr__(self) -> str:
        def short(v):
            v = list(v)
            return f"{v[0]:g}" if len(set(v)) == 1 else "[" + ", ".join(f"{x:g}" for x in v) + "]"

        return (
            f"Crawler(blocks={self.blocks}, stiffness={short(self.stiffness)}, "
            f"mu_forward={short(self.mu_forward)}, mu_backward={short(self.mu_backward)})"
        )


class Actuation:
    """Prescribed actuator lengths L(t), periodic: ``sine``, ``triangle`` or
    ``piecewise_linear``."""

    def __init__(self, inner):
        self._inner = inner

    @staticmethod
    def _wave(kind, period, amplitude, phase_deg, mean):
        one = np.ndim(amplitude) == 0
        amp = _vector(
            [amplitude] if one else amplitude, "actuation.amplitude", "amplitudes, one per link"
        )
        n = len(amp)
        phase = _each(0.0 if phase_deg is None else phase_deg, n, "actuation.phase_deg")
        inner = _rs.Actuation.wave(
            kind, float(period), _each(mean, n, "actuation.mean"), amp, phase
        )
        return Actuation(inner)

    @staticmethod
    def sine(period: float, amplitude: Numbers, phase_deg: Numbers = None, mean: Numbers = 0.0):
        """``L_l(t) = mean_l + amplitude_l sin(2 pi t / T - phase_l)``, one entry per link."""
        return Actuation._wave("sine", period, amplitude, phase_deg, mean)

    @staticmethod
    def triangle(period: float, amplitude: Numbers, phase_deg: Numbers = None, mean: Numbers = 0.0):
        """A triangle wave with the sine's peaks."""
        return Actuation._wave("triangle", period, amplitude, phase_deg, mean)

    @staticmethod
    def piecewise_linear(period: float, t: Sequence[float], L) -> Actuation:
        """Through the knots (``t`` in [0, period), one row of ``L`` per knot), periodic."""
        times = _vector(t, "actuation.times", "knot times")
        rows = _array(
            L, "actuation.lengths", 2, "one row of lengths per knot (shape (knots, links))"
        )
        inner = _rs.Actuation.piecewise_linear(float(period), times, rows.tolist())
        return Actuation(inner)

    period = property(lambda self: self._inner.period, doc="The period T (time).")

    def __call__(self, t) -> np.ndarray:
        """L at the times ``t``: an array (times x links)."""
        times = [float(t)] if np.ndim(t) == 0 else _vector(t, "t", "times")
        return np.array(self._inner.lengths_at(times))

    def __repr__(self) -> str:
        return f"Actuation(period={self.period:g}, links={self._inner.links})"


class Quadratic:
    """The actuation cost f2(u) = (c/2)|u|^2 with ``weight`` c."""

    def __init__(self, weight: float):
        self.weight = float(weight)

    def __repr__(self) -> str:
        return f"Quadratic({self.weight:g})"


class GaitProblem:
    """The gait problem (P) (theory §5): ``period`` T, ``max_actuator_speed`` (|L'| bound, a number
    or one per link), ``cost`` (None or ``Quadratic(c)``), ``max_total_variation`` (bound on
    TV(u) over a period). Bound to a crawler when optimised (rate bounds a_l = k_l x speed)."""

    def __init__(
        self,
        period: float,
        max_actuator_speed: Numbers = 1.0,
        cost: Optional[Quadratic] = None,
        max_total_variation: Optional[float] = None,
    ):
        self.period = float(period)
        self.max_actuator_speed = max_actuator_speed
        self.cost = cost
        self.max_total_variation = max_total_variation

    def _for(self, crawler: Crawler):
        speed = _each(self.max_actuator_speed, crawler.links, "gait.max_actuator_speed")
        weight = None if self.cost is None else self.cost.weight
        return _rs.GaitProblem(crawler._inner, self.period, speed, weight, self.max_total_variation)

    def __repr__(self) -> str:
        return (
            f"GaitProblem(period={self.period:g}, max_actuator_speed={self.max_actuator_speed}, "
            f"cost={self.cost}, max_total_variation={self.max_total_variation})"
        )


class Model:
    """A model file: ``crawler``, ``gait_problem`` and ``actuation`` (None where absent), and
    ``initial_state`` of ``[simulation]``."""

    def __init__(self, crawler, problem, actuation, initial_state, gait_problem=None):
        self.crawler = crawler
        self._problem = problem
        self.actuation = actuation
        self.initial_state = initial_state
        self.gait_problem = gait_problem

    def __repr__(self) -> str:
        return (
            f"Model({self.crawler!r}, gait_problem={'yes' if self._problem else 'no'}, "
            f"actuation={self.actuation!r})"
        )


class _BoundProblem(GaitProblem):
    """A gait problem as a model file poses it (already bound to its crawler)."""

    def __init__(self, inner):
        doc = json.loads(inner.to_json())
        super().__init__(doc["period"], None, None, doc.get("max_total_variation"))
        self._inner = inner
        self.rate_bound = doc["rate_bound"]
        if isinstance(doc.get("cost"), dict) and doc["cost"].get("kind") == "quadratic":
            self.cost = Quadratic(doc["cost"]["weight"])

    def _for(self, crawler: Crawler):
        return self._inner


def _arrays(d: dict, keys: Sequence[str]) -> dict:
    """The series among ``keys`` of ``d`` as float NumPy arrays (in place)."""
    for k in keys:
        if d.get(k) is not None:
            d[k] = np.asarray(d[k], dtype=float)
    return d


class GeneralProblem:
    """A general problem (P) of the paper's §2 (a ``[sweeping_process]`` file, theory §11): a
    polyhedron C, affine dynamics g = A x + B u + b, a control set U, f1 and f2. Every check and
    default is the library's (``crawlopt analyze``, ``simulate`` and ``optimize`` on the same
    file); answers are dicts with the fields of their ``--json`` documents, series as NumPy
    arrays (states x, controls u, reactions ``lambda`` per face, one row per step)."""

    def __init__(self, inner):
        self._inner = inner

    def analyze(self) -> dict:
        """C's faces, redundant faces, vertices and Chebyshev centre, and the checks;
        ``failure`` is the first failed check's message (None: well posed)."""
        analysis, failure = self._inner.analyze()
        analysis["failure"] = failure
        return analysis

    def simulate(
        self,
        *,
        method: str = "exact",
        steps_per_period: Optional[int] = None,
        max_periods: Optional[int] = None,
        tol: Optional[float] = None,
    ) -> dict:
        """The file's ``[input]`` simulated (exactly where A = 0 and the input is piecewise
        constant, unless ``method="catching_up"``) to its periodic regime: ``simulation`` holds
        ``objective`` (J, None without the regime), ``t``, ``x``, ``u``, ``lambda``."""
        d = self._inner.simulate(method, steps_per_period, max_periods, tol)
        _arrays(d["simulation"], ("t", "x", "u", "lambda", "mean_control"))
        return d

    def optimize(
        self,
        *,
        m: Optional[int] = None,
        method: str = "discrete",
        shifts: Optional[int] = None,
        time_limit: Optional[float] = None,
        certify: bool = False,
        progress: Progress = False,
        max_phases: Optional[int] = None,
        polish: Optional[bool] = None,
    ) -> dict:
        """The paper's P_m on 2^``m`` steps: ``method`` "discrete" (global MILP, with its
        certificate) or "local" (the LPCC active-set method from the file's ``[input]`` or
        square waves, ``shifts`` rotations of each; no global claim). ``solution`` holds
        ``objective`` (J re-verified by simulation), ``x``, ``u``, ``lambda``. ``certify``
        (discrete only) adds ``necessary_conditions``: Theorem 2.2's conditions on the optimum
        with their residuals and ``verdict`` (``crawlopt optimize --certify``). Ctrl-C stops it
        (KeyboardInterrupt); ``progress`` as for ``optimize``. ``method`` "phase" (where A = 0):
        the exact continuous-time gait of at most ``max_phases`` phases (default 4), globally
        (``crawlopt optimize --method phase``); its ``solution`` holds ``objective`` (J
        re-verified by the exact simulation), ``durations``, ``controls``, ``states``,
        ``held`` (faces, 1-based) and ``reactions`` per phase. ``polish`` (discrete only;
        default True): a quadratic cost's answer is polished on its fixed face pattern before it
        is certified (``--no-polish`` is ``polish=False``); ``solution["polish"]`` records it."""
        d = self._inner.optimize(
            method,
            m,
            shifts,
            time_limit,
            certify,
            progress_callback(progress),
            max_phases,
            polish,
        )
        if method == "phase":
            _arrays(d["solution"], ("durations", "controls", "states", "reactions"))
        else:
            _arrays(d["solution"], ("x", "u", "lambda"))
        return d


def load(path: str) -> Union[Model, GeneralProblem]:
    """Reads a model file (the TOML schema of the command line), checked as the CLI checks it:
    a crawler file gives a ``Model``, a general problem file (``[sweeping_process]``) a
    ``GeneralProblem``."""
    general = _rs.load_general(str(path))
    if general is not None:
        return GeneralProblem(general)
    crawler, problem, actuation, x0 = _rs.load(str(path))
    c = Crawler(0, _inner=crawler)
    gp = None if problem is None else _BoundProblem(problem)
    act = None if actuation is None else Actuation(actuation)
    return Model(c, problem, act, x0, gp)


class Simulation:
    """A simulation to the periodic regime: ``displacement_per_period`` (None if the regime was
    not reached), ``converged``, ``periods_to_converge``, ... (every field of ``crawlopt
    simulate --json``), and the recorded periods as NumPy arrays: ``t`` (times), ``x`` (link
    forces, times x links), ``X`` (block positions, times x blocks), ``y`` (barycentre) and
    ``slip`` (int8, times x blocks: -1 backward, 0 stick, 1 forward)."""

    def __init__(self, summary: dict, arrays: dict):
        self._summary = summary
        self.__dict__.update(summary)
        empty = np.zeros((0,))
        self.t = arrays.get("t", empty)
        self.x = arrays.get("x", empty.reshape(0, 0))
        self.X = arrays.get("X", empty.reshape(0, 0))
        self.y = arrays.get("y", empty)
        self.slip = arrays.get("slip", np.zeros((0, 0), dtype=np.int8))

    def to_dict(self) -> dict:
        """The fields of the JSON document as a dict (as ``--json`` prints them)."""
        return dict(self._summary)

    def to_pandas(self):
        """The recorded trajectory as a DataFrame (t, y, x_l, X_b, slip_b)."""
        import pandas as pd

        cols = {"t": self.t, "y": self.y}
        for j in range(self.x.shape[1] if self.x.ndim == 2 else 0):
            cols[f"x_{j + 1}"] = self.x[:, j]
        for b in range(self.X.shape[1] if self.X.ndim == 2 else 0):
            cols[f"X_{b + 1}"] = self.X[:, b]
            cols[f"slip_{b + 1}"] = self.slip[:, b]
        return pd.DataFrame(cols)

    def __repr__(self) -> str:
        d = self.displacement_per_period
        shown = "not reached" if d is None else f"{d:.10g}"
        return f"Simulation(displacement_per_period={shown}, periods={self.periods_simulated})"


def simulate(
    crawler: Crawler,
    actuation: Actuation,
    *,
    method: str = "exact",
    steps_per_period: Optional[int] = None,
    periods: Optional[int] = None,
    max_periods: Optional[int] = None,
    tol: Optional[float] = None,
    accelerate: bool = True,
    accelerate_after: Optional[int] = None,
    initial_state: Optional[Sequence[float]] = None,
    progress: Progress = False,
    newton: bool = True,
    increment_budget: Optional[int] = None,
) -> Simulation:
    """Plays ``actuation`` on ``crawler`` until the periodic regime (the sweeping process of
    theory §3, exact event-driven or catching-up) and records ``periods`` periods of the orbit.
    Arguments as ``crawlopt simulate``'s flags; None takes the library's default (1000 steps or
    knots per period, 1 period recorded, at most 5000 periods, tol 1e-12, acceleration after 50
    plain periods or earlier when plain iteration is predicted too slow: Newton-Krylov steps
    safeguarded by Anderson; ``accelerate=False``: never; ``newton=False``: Anderson alone,
    ``crawlopt simulate --no-newton``). ``search``, ``periods_simulated``, ``newton_steps`` and
    ``tangent_products`` say what the search cost. ``increment_budget``: bytes up to which
    catching-up keeps the period's increments as a table (default 64 MiB); beyond it they are
    formed step by step, memory O(N), the same result. The GIL is released; Ctrl-C stops it
    (KeyboardInterrupt)."""
    _instance(crawler, Crawler, "crawler")
    _instance(actuation, Actuation, "actuation")
    summary, arrays = _rs.simulate(
        crawler._inner,
        actuation._inner,
        method,
        steps_per_period,
        periods,
        max_periods,
        tol,
        accelerate,
        accelerate_after,
        None if initial_state is None else _vector(initial_state, "initial_state", "link forces"),
        progress_callback(progress),
        newton,
        increment_budget,
    )
    return Simulation(summary, arrays)


class GaitResult:
    """An optimal gait with its certificate (what ``crawlopt optimize --json`` writes): every
    field of that document is an attribute (``objective``, ``displacement_per_period``,
    ``status``, ``certificate``, ``phase_growth``, ``convergence``, ...); ``gait`` has the
    arrays ``t`` (knot times), ``L`` (actuator lengths at the knots), ``u`` (controls per piece),
    ``x`` (states), ``slip``."""

    def __init__(self, inner, conditions: Optional[dict] = None, notes=()):
        self._inner = inner
        self._doc = json.loads(inner.to_json())
        for k, v in self._doc.items():
            if k != "gait":
                setattr(self, k, v)
        g = self._doc["gait"]
        self.gait = _Gait(g)
        self.necessary_conditions = conditions
        self.notes = list(notes)

    @staticmethod
    def from_json(text: str, name: str = "result") -> GaitResult:
        """Reads a result document (as ``crawlopt certify`` reads it: checked for
        consistency)."""
        return GaitResult(_rs.GaitResult.from_json(text, name))

    def to_json(self) -> str:
        """The result document (``crawlopt optimize --json``'s form)."""
        return self._inner.to_json()

    def to_dict(self) -> dict:
        """The fields of the JSON document as a dict (as ``--json`` prints them)."""
        return json.loads(self.to_json())

    def certify(self) -> dict:
        """The necessary conditions (Theorem 2.2; discrete form Theorems 6.1–6.2): multipliers,
        every condition with its residual, and a ``verdict``."""
        return json.loads(self._inner.certify_json())

    def figures(self, adjoint: bool = False) -> dict[str, Figure]:
        """The gait's figures by name (``spacetime``, ``actuation``, ...; with ``adjoint``,
        p(t) too)."""
        return {n: Figure(n, c, s) for n, c, s in self._inner.figures(adjoint)}

    def report(self, path: Optional[str] = None, source: str = "crawlopt") -> str:
        """The self-contained HTML report (written to ``path`` when given); returns the HTML."""
        if path is not None:
            self._inner.write_report(str(path), source)
        return self._inner.report_html(source)

    def phase_growth_table(self):
        """The phase growth (one row per K) as a DataFrame (pandas)."""
        return _table((self.phase_growth or {}).get("table", []))

    def convergence_table(self):
        """The J_m table as a DataFrame (pandas)."""
        return _table(self.convergence or [])

    def to_pandas(self):
        """The gait's pieces as a DataFrame: start and end times, controls, slip modes."""
        import pandas as pd

        g = self.gait
        cols = {"t_start": g.t[:-1], "t_end": g.t[1:]}
        for j in range(g.u.shape[1]):
            cols[f"u_{j + 1}"] = g.u[:, j]
        for b in range(g.slip.shape[1]):
            cols[f"slip_{b + 1}"] = g.slip[:, b]
        return pd.DataFrame(cols)

    def __str__(self) -> str:
        return self._inner.text()

    def __repr__(self) -> str:
        c = self.certificate
        gap = c.get("gap")
        gap = "" if gap is None else f", gap={gap:.1e}"
        return (
            f"GaitResult(method={self.method!r}, objective={self.objective:.10g}, "
            f"status={self.status!r}, certificate={c.get('kind')!r}{gap})"
        )

    def _repr_html_(self) -> str:
        import html

        figs = self.figures()
        shown = [figs[n] for n in ("spacetime", "actuation") if n in figs]
        body = "".join(
            f"<figure>{f.svg}<figcaption>{html.escape(f.caption)}</figcaption></figure>"
            for f in shown
        )
        return f"<pre>{html.escape(str(self))}</pre>{body}"


class _Gait:
    """The gait of a result as arrays."""

    def __init__(self, g: dict):
        self.t = np.asarray(g["times"], dtype=float)
        self.durations = np.asarray(g["durations"], dtype=float)
        self.L = np.asarray(g["lengths"], dtype=float)
        self.u = np.asarray(g["controls"], dtype=float)
        self.x = np.asarray(g["states"], dtype=float)
        self.slip = np.asarray(g["slip"], dtype=np.int8)
        self.initial_state = np.asarray(g["initial_state"], dtype=float)

    def __repr__(self) -> str:
        return f"Gait({len(self.u)} pieces, {self.u.shape[1] if self.u.ndim == 2 else 0} links)"


def _bound_settings(bound) -> Optional[tuple]:
    """``optimize``'s ``bound`` as the extension takes it (None: no bound)."""
    if bound is None or bound is False:
        return None
    if bound is True:
        return (None, None, None, None)
    if not isinstance(bound, dict):
        raise _input_error("bound", repr(bound), "must be True, False, None or a dict")
    keys = ("resolution", "box_resolution", "time_limit", "cost_tangents")
    for k in bound:
        if k not in keys:
            raise _input_error(
                f"bound.{k}", repr(bound[k]), f"unknown setting (known: {', '.join(keys)})"
            )
    return tuple(bound.get(k) for k in keys)


def optimize(
    crawler: Crawler,
    problem: GaitProblem,
    *,
    method: str = "auto",
    phases: Optional[int] = None,
    patience: Optional[int] = None,
    max_phases: Optional[int] = None,
    m: Optional[int] = None,
    convergence: bool = False,
    start: Optional[GaitResult] = None,
    shifts: Optional[int] = None,
    time_limit: Optional[float] = None,
    certify: bool = False,
    bound: Union[bool, dict, None] = None,
    progress: Progress = False,
    polish: Optional[bool] = None,
) -> GaitResult:
    """An optimal gait of the problem (P) (paper §§5–7), every method and option of
    ``crawlopt optimize``: ``method`` "auto" (phase gaits with K grown; the discrete P_m when
    TV(u) is bounded), "phase" (global among gaits of at most ``phases`` slip phases), "discrete"
    (the paper's P_m on 2^``m`` steps, §6, global), "local" (P_m by the LPCC active-set method)
    "sequence" (local search over slip sequences) or "chain" (long chains: the best
    structured gait improved by a pattern search over per-link ramp gaits, simulated exactly).
    Every method but "discrete" first evaluates the structured gaits (travelling, alternating and
    grouped waves) and never returns less than the best of them (``result.structured`` then
    says so). Defaults, applicability of each option and
    start gaits are the library's (see the README); a misplaced option raises InputError naming
    it. The answer is verified by simulation; ``certify`` adds the necessary conditions
    (Theorem 2.2) as ``necessary_conditions``. A time limit that ends the search with a gait
    returns it (``status == "time_limit"``, with its gap); TimeLimitError only when there is
    none. ``bound``: True (or a dict with ``resolution``, ``box_resolution``, ``time_limit``,
    ``cost_tangents``; missing keys take the library's defaults 8, 8, 60 s, 4) also proves an
    upper bound on J over all periodic gaits (a piecewise-linear storage function on a grid of
    C x box, theory §12; N <= 4), recorded as ``certificate["upper_bound"]``. The GIL is
    released; Ctrl-C stops the solve within about a second (KeyboardInterrupt).
    ``progress``: True for a progress bar (tqdm if installed, else a text line), a callable to
    receive each event as a dict. ``polish`` (method "discrete" only; the library's default is
    True): P_m's answer of a quadratic cost is polished on its fixed slip pattern before it is
    certified, recorded as ``polish`` (``--no-polish`` is ``polish=False``)."""
    _instance(crawler, Crawler, "crawler")
    _instance(problem, GaitProblem, "problem")
    if start is not None:
        _instance(start, GaitResult, "start")
    inner, conditions, notes = _rs.optimize(
        crawler._inner,
        problem._for(crawler),
        method,
        phases,
        patience,
        max_phases,
        m,
        convergence,
        None if start is None else start._inner,
        shifts,
        time_limit,
        certify,
        _bound_settings(bound),
        progress_callback(progress),
        polish,
    )
    return GaitResult(inner, None if conditions is None else json.loads(conditions), notes)


def _sweep_source(spec) -> tuple[str, bool, str]:
    """A sweep as (source, is_path, base_dir): a file's absolute path, or a dictionary as JSON
    with relative paths (``base``) from the current directory."""
    import os

    if isinstance(spec, dict):
        return json.dumps(spec), False, os.getcwd()
    if isinstance(spec, (str, os.PathLike)):
        return os.path.abspath(os.fspath(spec)), True, ""
    raise _input_error("spec", type(spec).__name__, "must be a sweep file's path or a dict")


def sweep(spec, executor=None, *, threads: int = 0):
    """A parameter study (``crawlopt sweep``): one job over a grid of model parameters, one row
    per point, as a pandas DataFrame sorted by point (columns ``point``, one per axis named by
    its field, ``objective``, ``displacement_per_period``, ``certificate``, ``gap``, ``bound``,
    ``status``, ``seconds``, ``error``; an ill-posed point is a row with its error).

    ``spec`` is a sweep file's path or a dict with the file's keys (``base`` or ``model``,
    ``job``, ``combine``, ``settings``, ``axis``: a list of dicts). Without ``executor`` the
    points run in the library on ``threads`` threads (0: one per core) with the GIL released;
    with any ``concurrent.futures.Executor`` (a process pool, or a Dask cluster's
    ``distributed.Client(...).get_executor()``) each point is one task, run wherever the
    executor runs it (the base model file must be readable there)."""
    source, is_path, base_dir = _sweep_source(spec)
    header, n = _rs.sweep_size(source, is_path, base_dir)
    if executor is None:
        lines = _rs.sweep_run(source, is_path, base_dir, int(threads))
    else:
        futures = [executor.submit(_rs.sweep_point, source, is_path, base_dir, i) for i in range(n)]
        lines = [f.result() for f in futures]
    rows = sorted((json.loads(line) for line in lines), key=lambda r: r["point"])
    import pandas as pd  # optional dependency

    return pd.DataFrame(rows, columns=header)
