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
import warnings
from collections.abc import Sequence
from typing import Any, Callable, Optional, Union

import numpy as np

from . import _crawlopt as _rs
from ._convert import (
    NotConvergedWarning,
    Numbers,
    _array,
    _count,
    _input_error,
    _instance,
    _numbers,
    _settings,
    _vector,
    require,
)
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
from ._documents import (
    Fields,
    GeneralAnalysis,
    GeneralResult,
    GeneralSimulation,
    NecessaryConditions,
)
from ._fit import FitResult, fit
from ._general import GeneralProblem
from ._progress import progress_callback
from ._simulation import Figure, Simulation
from ._sweep import sweep

__version__ = _rs.__version__

__all__ = [
    "Actuation",
    "Analysis",
    "CrawloptError",
    "Crawler",
    "Figure",
    "FileError",
    "FitResult",
    "GaitProblem",
    "GaitResult",
    "GeneralAnalysis",
    "GeneralProblem",
    "GeneralResult",
    "GeneralSimulation",
    "InadmissibleError",
    "InfeasibleError",
    "InputError",
    "Model",
    "NecessaryConditions",
    "NotConvergedWarning",
    "NonUniqueError",
    "NumericalError",
    "Quadratic",
    "Simulation",
    "TimeLimitError",
    "fit",
    "load",
    "optimize",
    "read_result",
    "simulate",
    "sweep",
]

Progress = Union[bool, Callable[[dict], Any], None]


def _table(rows: list[dict]):
    pd = require("pandas", "the table")

    return pd.DataFrame(rows)


class Analysis:
    """The analysis of a crawler (``crawlopt analyze``): the polytope C (``faces``,
    ``link_force_ranges``, ``vertices``), the uniqueness condition (paper eq. 3.6), the class of
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
            if isinstance(blocks, bool) or not isinstance(blocks, (int, np.integer)):
                raise _input_error("crawler.blocks", repr(blocks), "must be a whole number >= 2")
            if not -(2**62) < int(blocks) < 2**62:
                raise _input_error("crawler.blocks", blocks, "must be a whole number >= 2")
            _inner = _rs.Crawler(
                int(blocks),
                _numbers(stiffness, "crawler.stiffness"),
                _numbers(mu_forward, "crawler.mu_forward"),
                _numbers(mu_backward, "crawler.mu_backward"),
            )
        self._inner = _inner

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Crawler):
            return NotImplemented
        return self._inner == other._inner

    def __hash__(self) -> int:
        return hash(self._inner)

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
    """Prescribed actuator lengths L(t), periodic: ``sine``, ``triangle``,
    ``travelling_wave`` or ``piecewise_linear``, as the model file's ``[actuation]`` section.

    Every value may be a single number, which stands for every link as in the file: an
    actuation whose values are all single numbers fits a crawler of any size (``links`` is
    None until it is simulated on one); one with lists has as many links as they have entries
    (or ``links=``). Actuations pickle, deep-copy, compare by value and write their section
    (``to_toml``)."""

    def __init__(self, inner):
        self._inner = inner

    @staticmethod
    def _section(kind, period, links=None, **fields) -> Actuation:
        given = {k: v for k, v in fields.items() if v is not None}
        for k in ("amplitude", "phase_deg", "mean"):
            if k in given:
                given[k] = _numbers(given[k], f"actuation.{k}")
        if links is not None and (
            isinstance(links, bool) or not isinstance(links, (int, np.integer)) or links < 1
        ):
            raise _input_error("actuation.links", repr(links), "must be a whole number >= 1")
        period = float(_array(period, "actuation.period", 0, "a number"))
        return Actuation(
            _rs.Actuation.section(
                kind, period, links=None if links is None else int(links), **given
            )
        )

    @staticmethod
    def sine(
        period: float,
        amplitude: Numbers,
        phase_deg: Optional[Numbers] = None,
        mean: Optional[Numbers] = None,
        *,
        links: Optional[int] = None,
    ) -> Actuation:
        """``L_l(t) = mean_l + amplitude_l sin(2 pi t / T - phase_l)``: each of ``amplitude``,
        ``phase_deg`` (degrees, default 0) and ``mean`` (default 0) a number for every link or a
        list, one per link (``kind = "sine"`` of the model file)."""
        return Actuation._section(
            "sine", period, links, amplitude=amplitude, phase_deg=phase_deg, mean=mean
        )

    @staticmethod
    def triangle(
        period: float,
        amplitude: Numbers,
        phase_deg: Optional[Numbers] = None,
        mean: Optional[Numbers] = None,
        *,
        links: Optional[int] = None,
    ) -> Actuation:
        """A triangle wave with the sine's peaks (arguments as ``sine``)."""
        return Actuation._section(
            "triangle", period, links, amplitude=amplitude, phase_deg=phase_deg, mean=mean
        )

    @staticmethod
    def travelling_wave(
        links: int,
        period: Optional[float] = None,
        amplitude: Optional[float] = None,
        *,
        lag_deg: Optional[float] = None,
        wavelength: Optional[float] = None,
        direction: Optional[str] = None,
        waveform: Optional[str] = None,
        mean: Optional[float] = None,
    ) -> Actuation:
        """A wave travelling along the body: every link has the same ``waveform`` ("sine",
        the default, or "triangle"), ``period`` (default 1), ``amplitude`` (default 1) and
        ``mean`` (default 0), and each lags its neighbour by the same phase: ``lag_deg``
        degrees, or ``360 / wavelength`` with ``wavelength`` in links (give one of them; with
        neither, one wavelength spans the body: ``wavelength = links``). ``direction``
        "first_to_last" (the default: link l + 1 lags link l, the wave runs from link 1 to link
        n) or "last_to_first". The library's ``TravellingWave``; the result is the sine (or
        triangle) actuation with ``phase_deg = [(l - 1) lag]`` (or ``[(n - l) lag]``)."""
        if isinstance(links, bool) or not isinstance(links, (int, np.integer)) or links < 1:
            raise _input_error("actuation.links", repr(links), "must be a whole number >= 1")

        def num(v, name):
            return None if v is None else float(_array(v, f"actuation.{name}", 0, "a number"))

        return Actuation(
            _rs.Actuation.travelling_wave(
                int(links),
                waveform=waveform,
                period=num(period, "period"),
                amplitude=num(amplitude, "amplitude"),
                mean=num(mean, "mean"),
                lag_deg=num(lag_deg, "lag_deg"),
                wavelength=num(wavelength, "wavelength"),
                direction=direction,
            )
        )

    @staticmethod
    def piecewise_linear(
        period: float, t: Sequence[float], L, *, links: Optional[int] = None
    ) -> Actuation:
        """Through the knots (``t`` in [0, period), one row of ``L`` per knot), periodic; a
        row may be a single number (the same length for every link), as in the file."""
        times = _vector(t, "actuation.times", "knot times")
        if isinstance(L, np.ndarray) and L.ndim not in (1, 2):
            raise _input_error(
                "actuation.lengths", f"an array of shape {L.shape}", "must be one row per knot"
            )
        try:
            rows = list(L)
        except TypeError:
            raise _input_error(
                "actuation.lengths", repr(L), "must be one row of lengths per knot"
            ) from None
        rows = [_numbers(r, f"actuation.lengths[{j + 1}]") for j, r in enumerate(rows)]
        return Actuation._section("piecewise_linear", period, links, times=times, lengths=rows)

    period = property(lambda self: self._inner.period, doc="The period T (time).")
    links = property(
        lambda self: self._inner.links,
        doc="The number of links (None: every value is one number, for a crawler of any size).",
    )
    kind = property(lambda self: self._inner.kind, doc="sine, triangle or piecewise_linear.")

    def for_links(self, links: int) -> Actuation:
        """This actuation for a crawler of ``links`` links (a single number expanded to each)."""
        return Actuation(self._inner.bind(int(links)))

    def to_toml(self) -> str:
        """The ``[actuation]`` section of a model file, as TOML text."""
        return self._inner.to_toml()

    def __call__(self, t) -> np.ndarray:
        """L at the times ``t``: an array (times x links; one column when ``links`` is None)."""
        times = [float(t)] if np.ndim(t) == 0 else _vector(t, "t", "times")
        return np.array(self._inner.lengths_at(times))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Actuation):
            return NotImplemented
        return self._inner == other._inner

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        n = self.links
        return f"Actuation({self.kind}, period={self.period:g}, links={'any' if n is None else n})"


class Quadratic:
    """The actuation cost f2(u) = (c/2)|u|^2 with ``weight`` c."""

    def __init__(self, weight: float):
        self.weight = float(weight)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Quadratic):
            return NotImplemented
        return self.weight == other.weight

    def __hash__(self) -> int:
        return hash(("Quadratic", self.weight))

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
        speed = _numbers(self.max_actuator_speed, "gait.max_actuator_speed")
        weight = None if self.cost is None else self.cost.weight
        return _rs.GaitProblem(crawler._inner, self.period, speed, weight, self.max_total_variation)

    def _fields(self) -> tuple:
        speed = self.max_actuator_speed
        speed = float(speed) if np.ndim(speed) == 0 else [float(v) for v in speed]
        return (self.period, speed, self.cost, self.max_total_variation)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GaitProblem):
            return NotImplemented
        return self._fields() == other._fields()

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"GaitProblem(period={self.period:g}, max_actuator_speed={self.max_actuator_speed}, "
            f"cost={self.cost}, max_total_variation={self.max_total_variation})"
        )


class Model:
    """A model: ``crawler``, ``actuation`` and ``gait_problem`` (None where absent), and
    ``initial_state`` (of ``[simulation]``) — what a model file holds. ``load`` reads one;
    ``to_toml`` and ``save`` write one that ``load`` and the command line read back.
    ``analyze()``, ``simulate()`` and ``optimize()`` run the jobs on it, as on the
    ``GeneralProblem`` that ``load`` returns for a general problem file."""

    def __init__(
        self,
        crawler: Crawler,
        actuation: Optional[Actuation] = None,
        gait_problem: Optional[GaitProblem] = None,
        initial_state: Optional[Sequence[float]] = None,
    ):
        _instance(crawler, Crawler, "crawler")
        if actuation is not None:
            _instance(actuation, Actuation, "actuation")
        if gait_problem is not None:
            _instance(gait_problem, GaitProblem, "gait_problem")
        self.crawler = crawler
        self.actuation = actuation
        self.gait_problem = gait_problem
        self.initial_state = initial_state

    def to_toml(self) -> str:
        """The model file as TOML text, checked first as ``load`` checks a file (each part for
        this crawler): ``crawlopt.load`` and the command line read it back to an equal model."""
        x0 = self.initial_state
        return _rs.model_toml(
            self.crawler._inner,
            None if self.actuation is None else self.actuation._inner,
            None if self.gait_problem is None else self.gait_problem._for(self.crawler),
            None if x0 is None else _vector(x0, "simulation.initial_state", "link forces"),
        )

    def save(self, path) -> None:
        """Writes the model file (``to_toml``) to ``path``."""
        text = self.to_toml()
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)

    def analyze(self) -> Analysis:
        """The crawler's analysis (``crawler.analyze()``; ``crawlopt analyze`` of the file),
        as ``GeneralProblem.analyze()`` is a general problem's: so that code can call one
        method on whatever ``load`` returned."""
        return self.crawler.analyze()

    def simulate(self, **settings) -> Simulation:
        """The model's ``actuation`` played on its ``crawler`` (``simulate``, with every keyword
        of it; ``initial_state`` defaults to the model's own, the file's ``[simulation]``), as
        ``crawlopt simulate FILE`` does and ``GeneralProblem.simulate()`` for a general
        problem. A model without an actuation raises InputError naming ``actuation``."""
        if self.actuation is None:
            raise _input_error(
                "actuation", "nothing", "the model has no actuation ([actuation]) to simulate"
            )
        if self.initial_state is not None:
            settings.setdefault("initial_state", self.initial_state)
        return simulate(self.crawler, self.actuation, **settings)

    def optimize(self, **settings) -> GaitResult:
        """An optimal gait of the model's ``gait_problem`` for its ``crawler`` (``optimize``, with
        every keyword of it and its defaults), as ``crawlopt optimize FILE`` does and
        ``GeneralProblem.optimize()`` for a general problem. A model without a gait problem
        raises InputError naming ``gait_problem``."""
        if self.gait_problem is None:
            raise _input_error(
                "gait_problem", "nothing", "the model poses no gait problem ([gait]) to optimize"
            )
        return optimize(self.crawler, self.gait_problem, **settings)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Model):
            return NotImplemented
        x0, y0 = self.initial_state, other.initial_state
        return (
            self.crawler == other.crawler
            and self.actuation == other.actuation
            and self.gait_problem == other.gait_problem
            and ((x0 is None) == (y0 is None))
            and (x0 is None or list(map(float, x0)) == list(map(float, y0)))
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"Model({self.crawler!r}, gait_problem={self.gait_problem!r}, "
            f"actuation={self.actuation!r})"
        )


class _BoundProblem(GaitProblem):
    """A gait problem as a model file poses it: its ``[gait]`` fields, and the rate bounds
    ``rate_bound`` a_l = k_l x speed for the file's crawler."""

    def __init__(self, inner):
        doc = json.loads(inner.to_json())
        cost = doc.get("cost")
        weight = cost.get("weight") if isinstance(cost, dict) else None
        super().__init__(
            doc["period"],
            inner.max_actuator_speed,
            None if weight is None else Quadratic(weight),
            doc.get("max_total_variation"),
        )
        self.rate_bound = doc["rate_bound"]


def load(path: str) -> Union[Model, GeneralProblem]:
    """Reads a model file (the TOML schema of the command line), checked as the CLI checks it:
    a crawler file gives a ``Model``, a general problem file (``[sweeping_process]``) a
    ``GeneralProblem``."""
    general = _rs.load_general(str(path))
    if general is not None:
        return GeneralProblem(_inner=general)
    crawler, problem, actuation, x0 = _rs.load(str(path))
    c = Crawler(0, _inner=crawler)
    gp = None if problem is None else _BoundProblem(problem)
    act = None if actuation is None else Actuation(actuation)
    return Model(c, act, gp, x0)


def read_result(path: str) -> Union[GaitResult, GeneralResult]:
    """Reads a result file of either kind (what ``crawlopt optimize --json`` writes), checked
    as ``crawlopt certify`` checks it: a ``GaitResult`` for a crawler's gait, a
    ``GeneralResult`` for a general problem's; ``certify()`` on either gives its
    NecessaryConditions."""
    r = _rs.read_result_file(str(path))
    return GeneralResult(*r) if isinstance(r, tuple) else GaitResult(r)


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
        _count(steps_per_period, "steps_per_period"),
        _count(periods, "periods"),
        _count(max_periods, "max_periods"),
        tol,
        accelerate,
        _count(accelerate_after, "accelerate_after"),
        None if initial_state is None else _vector(initial_state, "initial_state", "link forces"),
        progress_callback(progress),
        newton,
        _count(increment_budget, "increment_budget"),
    )
    sim = Simulation(summary, arrays, crawler, actuation)
    if sim.status != "converged":
        warnings.warn(
            f"the periodic regime was not reached within {sim.periods_simulated} periods "
            f"(residual {sim.period_residual:.3e}): displacement_per_period is None "
            "(raise max_periods or tol)",
            NotConvergedWarning,
            stacklevel=2,
        )
    return sim


# The numbers and records a result keeps in its solution beside the gait's arrays (result
# version 4), attributes of a GaitResult as its top-level fields are.
_SOLUTION_NUMBERS = ("displacement_per_period", "actuation_cost", "m", "local", "polish")


class GaitResult(Fields):
    """An optimal gait with its certificate (what ``crawlopt optimize --json`` writes): every
    top-level field of that document is an attribute (``objective``, ``status``,
    ``certificate``, ``problem`` with its ``crawler`` and ``gait``, ``phase_growth``,
    ``convergence``, ...), and so are the solution's own numbers and records
    (``displacement_per_period``, ``actuation_cost``, ``m``, ``local``, ``polish``; None where
    the document has none); ``status`` is what was
    proven: "optimal" (P_m), "optimal_among_k_phases" (K in ``certificate["phases"]``),
    "dominates_k_phases" (a gait of more than K slip phases, e.g. the structured gait named in
    ``structured``, that no gait of at most K slip phases beats), "time_limit",
    "approximation_limit", or a local method's "stationary" / "stalled"; ``d["solution"]``
    and the other fields read as from a dict, as a ``GeneralResult``'s; ``gait`` (also
    ``solution``, the document's name for it) has the arrays ``t`` (knot times), ``L``
    (actuator lengths at the knots), ``u`` (controls per piece), ``x`` (states), ``slip``."""

    def __init__(self, inner, conditions: Optional[dict] = None, notes=()):
        self._inner = inner
        self._doc = json.loads(inner.to_json())
        for k, v in self._doc.items():
            if k != "solution":
                setattr(self, k, v)
        for k in _SOLUTION_NUMBERS:
            setattr(self, k, self._doc["solution"].get(k))
        self.gait = _Gait(self._doc["solution"])
        self.solution = self.gait
        self.necessary_conditions = (
            NecessaryConditions(conditions) if isinstance(conditions, dict) else conditions
        )
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

    def certify(self) -> NecessaryConditions:
        """The necessary conditions (Theorem 2.2; discrete form Theorems 6.1–6.2): multipliers,
        every condition with its residual, and a ``verdict`` (``crawlopt certify``)."""
        return NecessaryConditions(json.loads(self._inner.certify_json()))

    def plot(self):
        """The gait: actuator lengths at the knots and the controls per piece (a matplotlib
        Figure; matplotlib is an optional dependency). ``figures()`` has the library's."""
        from ._plot import gait_plot

        title = f"J = {self.objective:.6g} ({self.status})"
        return gait_plot(self.gait.t, self.gait.L, self.gait.u, title)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GaitResult):
            return NotImplemented
        return (
            self._inner == other._inner
            and self.necessary_conditions == other.necessary_conditions
            and self.notes == other.notes
        )

    __hash__ = None  # type: ignore[assignment]

    def figures(self, adjoint: bool = False) -> dict[str, Figure]:
        """The gait's figures by name (``spacetime``, ``actuation``, ...; with ``adjoint``,
        p(t) too)."""
        return {n: Figure(n, c, s) for n, c, s in self._inner.figures(adjoint)}

    def report(self, path: Optional[str] = None, source: str = "crawlopt") -> str:
        """The self-contained HTML report (written to ``path`` when given); returns the HTML.
        With ``necessary_conditions`` (``optimize(certify=True)``) it has the certificate's
        section: the verdict, every condition's residual, the adjoint figure."""
        nc = self.necessary_conditions
        conditions = None if nc is None else json.dumps(nc.to_dict())
        if path is not None:
            self._inner.write_report(str(path), source, conditions)
        return self._inner.report_html(source, conditions)

    def phase_growth_table(self):
        """The phase growth (one row per K) as a DataFrame (pandas)."""
        return _table((self.phase_growth or {}).get("table", []))

    def convergence_table(self):
        """The J_m table as a DataFrame (pandas)."""
        return _table(self.convergence or [])

    def to_pandas(self):
        """The gait's pieces as a DataFrame: start and end times, controls, slip modes."""
        pd = require("pandas", "to_pandas()")
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

        from ._documents import numbers_table

        c = self.certificate
        rows = [
            ("objective J", self.objective),
            ("displacement per period", self.displacement_per_period),
            ("status", self.status),
            ("certificate", c.get("kind")),
            ("gap", c.get("gap")),
        ]
        if self.necessary_conditions is not None:
            rows.append(("necessary conditions", self.necessary_conditions["verdict"]))
        figs = self.figures()
        shown = [figs[n] for n in ("spacetime", "actuation") if n in figs]
        body = "".join(
            f"<figure>{f.svg}<figcaption>{html.escape(f.caption)}</figcaption></figure>"
            for f in shown
        )
        text = f"<details><summary>text</summary><pre>{html.escape(str(self))}</pre></details>"
        return numbers_table(rows) + body + text


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
    ``cost_tangents``; missing keys take the library's defaults: the grid 8 x 8 up to three
    blocks and 2 x 1 on four, 60 s, 4 tangents (2 on four blocks)) also proves an upper
    bound on J over all periodic gaits (a piecewise-linear storage function on a grid of
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
    keys = _settings(
        method=method,
        phases=phases,
        patience=patience,
        max_phases=max_phases,
        m=m,
        convergence=convergence,
        shifts=shifts,
        time_limit=time_limit,
        certify=certify,
        polish=polish,
        bound=bound,
    )
    inner, conditions, notes = _rs.optimize(
        crawler._inner,
        problem._for(crawler),
        keys,
        None if start is None else start._inner,
        progress_callback(progress),
    )
    return GaitResult(inner, None if conditions is None else json.loads(conditions), notes)
