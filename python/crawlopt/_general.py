"""The general problem (P) of the paper's §2 as a Python class: read from its file or built
from arrays with the file's fields; answers as typed documents (``GeneralAnalysis``,
``GeneralSimulation``, ``GeneralResult``)."""

from __future__ import annotations

import warnings
from typing import Any, Callable, Optional, Union

import numpy as np

from . import _crawlopt as _rs
from ._convert import (
    NotConvergedWarning,
    _array,
    _count,
    _input_error,
    _settings,
)
from ._documents import GeneralAnalysis, GeneralResult, GeneralSimulation
from ._progress import progress_callback

Progress = Union[bool, Callable[[dict], Any], None]


def _matrix_or_vector(value, name: str, ndim: int) -> list:
    shape = "a matrix (shape (rows, columns))" if ndim == 2 else "a vector (shape (n,))"
    return _array(value, name, ndim, shape).tolist()


def _start_json(start: Optional[GeneralResult]) -> Optional[str]:
    """A start's document for the extension (None stays None): a GeneralResult's JSON; any
    other value is an InputError naming ``start``."""
    if start is None:
        return None
    if not isinstance(start, GeneralResult):
        raise _input_error(
            "start", type(start).__name__, "a general problem starts from a GeneralResult"
        )
    return start.to_json()


class GeneralProblem:
    """A general problem (P) of the paper's §2 (a ``[sweeping_process]`` file, theory §11): a
    polyhedron C = {x : <x*_j, x> <= c_j}, affine dynamics g = A x + B u + b, a control set U,
    f1 and f2. Read from a file (``crawlopt.load``) or built from arrays with the file's fields
    as keywords (NumPy arrays or lists):

    ``normals`` (x*_j, one row per face), ``offsets`` (c_j), ``B``, ``A`` (default 0), ``b``
    (default 0); the control set as a box ``lower``/``upper`` or a polytope ``G`` u <= ``h``,
    ``zero_mean`` (default: the problem is periodic); f1 as ``face_weights`` or
    ``reaction_weights``; ``cost`` None, a number c ((c/2)|u|^2, or ``Quadratic(c)``), a
    matrix R ((1/2) u^T R u) or the file's form (a dict with ``kind``); ``period`` T,
    ``periodic`` (default True) or ``initial_state``;
    ``input`` the control ``simulate`` plays, a dict like the file's ``[input]`` (``kind``
    "piecewise_constant" or "piecewise_linear", ``times``, ``values``).

    Every check and default is the library's (``crawlopt analyze``, ``simulate`` and
    ``optimize`` on the same file); a bad field raises InputError naming it as the file does
    (``dynamics.B``, ``objective.cost.weight``, ...). Answers are ``GeneralSimulation`` and
    ``GeneralResult``. Problems pickle, deep-copy, compare by value and write their file
    (``to_toml``, ``save``)."""

    def __init__(
        self,
        normals=None,
        offsets=None,
        B=None,
        *,
        A=None,
        b=None,
        lower=None,
        upper=None,
        G=None,
        h=None,
        zero_mean: Optional[bool] = None,
        face_weights=None,
        reaction_weights=None,
        cost=None,
        period: Optional[float] = None,
        periodic: Optional[bool] = None,
        initial_state=None,
        input: Optional[dict] = None,
        _inner=None,
    ):
        if _inner is None:
            _inner = _rs.GeneralProblem.from_sections(GeneralProblem._sections(locals()))
        self._inner = _inner

    @staticmethod
    def _sections(a: dict) -> dict:
        """The keyword arguments as the file's sections (arrays as lists; absent keys left
        out, so that the library's defaults apply)."""
        for name in ("normals", "offsets", "B", "period"):
            if a[name] is None:
                raise TypeError(f"GeneralProblem: {name} is required")

        def put(section: dict, key: str, value, field: str, ndim: int):
            if value is not None:
                section[key] = _matrix_or_vector(value, field, ndim)

        sp, dyn, ctl, obj, prob = {}, {}, {}, {}, {}
        put(sp, "normals", a["normals"], "sweeping_process.normals", 2)
        put(sp, "offsets", a["offsets"], "sweeping_process.offsets", 1)
        put(dyn, "A", a["A"], "dynamics.A", 2)
        put(dyn, "B", a["B"], "dynamics.B", 2)
        put(dyn, "b", a["b"], "dynamics.b", 1)
        put(ctl, "lower", a["lower"], "control.lower", 1)
        put(ctl, "upper", a["upper"], "control.upper", 1)
        put(ctl, "G", a["G"], "control.G", 2)
        put(ctl, "h", a["h"], "control.h", 1)
        if a["zero_mean"] is not None:
            ctl["zero_mean"] = bool(a["zero_mean"])
        put(obj, "face_weights", a["face_weights"], "objective.face_weights", 1)
        put(obj, "reaction_weights", a["reaction_weights"], "objective.reaction_weights", 1)
        cost = a["cost"]
        if isinstance(cost, dict):  # the file's form: {"kind": ..., "weight" or "matrix": ...}
            obj["cost"] = dict(cost)
        elif hasattr(cost, "weight"):  # Quadratic(c)
            obj["cost"] = {"kind": "quadratic", "weight": cost.weight}
        elif cost is not None and np.ndim(cost) == 0:
            obj["cost"] = {"kind": "quadratic", "weight": float(cost)}
        elif cost is not None:
            obj["cost"] = {
                "kind": "matrix",
                "matrix": _matrix_or_vector(cost, "objective.cost.matrix", 2),
            }
        prob["period"] = float(_array(a["period"], "problem.period", 0, "a number"))
        if a["periodic"] is not None:
            prob["periodic"] = bool(a["periodic"])
        put(prob, "initial_state", a["initial_state"], "problem.initial_state", 1)
        d = {
            "sweeping_process": sp,
            "dynamics": dyn,
            "control": ctl,
            "objective": obj,
            "problem": prob,
        }
        if a["input"] is not None:
            inp = a["input"]
            if not isinstance(inp, dict):
                raise _input_error("input", type(inp).__name__, "must be a dict like [input]")
            inp = dict(inp)
            if "times" in inp:
                inp["times"] = _matrix_or_vector(inp["times"], "input.times", 1)
            if "values" in inp:
                inp["values"] = _matrix_or_vector(inp["values"], "input.values", 2)
            d["input"] = inp
        return d

    def to_toml(self) -> str:
        """The problem file as TOML text (``crawlopt.load`` and the command line read it
        back)."""
        return self._inner.to_toml()

    def save(self, path) -> None:
        """Writes the problem file (``to_toml``) to ``path``."""
        text = self.to_toml()
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GeneralProblem):
            return NotImplemented
        return self._inner == other._inner

    __hash__ = None  # type: ignore[assignment]

    def to_dict(self) -> dict:
        """The problem's sections as a dict with the file's keys (``sweeping_process``,
        ``dynamics``, ``control``, ``objective``, ``problem``, ``input``)."""
        return self._inner.sections()

    def __repr__(self) -> str:
        d = self._inner.sections()
        normals, B = d["sweeping_process"]["normals"], d["dynamics"]["B"]
        return (
            f"GeneralProblem(faces={len(normals)}, states={len(B)}, "
            f"controls={len(B[0]) if B else 0}, period={d['problem']['period']:g})"
        )

    def analyze(self) -> GeneralAnalysis:
        """C's faces, redundant faces, vertices and Chebyshev centre, and the checks, as a
        ``GeneralAnalysis``; ``failure`` is the first failed check's message (None: well
        posed)."""
        analysis, failure = self._inner.analyze()
        analysis["failure"] = failure
        return GeneralAnalysis(analysis)

    def simulate(
        self,
        *,
        method: str = "exact",
        steps_per_period: Optional[int] = None,
        max_periods: Optional[int] = None,
        tol: Optional[float] = None,
    ) -> GeneralSimulation:
        """The file's ``[input]`` simulated (exactly where A = 0 and the input is piecewise
        constant, unless ``method="catching_up"``) to its periodic regime: a
        ``GeneralSimulation`` (``objective`` J, None without the regime, and ``status``
        "not_converged" then, with a NotConvergedWarning; ``t``, ``x``, ``u``,
        ``reactions``)."""
        doc, record = self._inner.simulate(
            method,
            _count(steps_per_period, "steps_per_period"),
            _count(max_periods, "max_periods"),
            tol,
        )
        r = GeneralSimulation(doc, record)
        if r.status != "converged":
            warnings.warn(
                f"the periodic regime was not reached within {r['simulation'].get('periods')} "
                "periods: objective is None (raise max_periods or tol)",
                NotConvergedWarning,
                stacklevel=2,
            )
        return r

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
        phases: Optional[int] = None,
        patience: Optional[int] = None,
        convergence: bool = False,
        bound: Union[bool, dict, None] = None,
        formulation: Optional[str] = None,
        start: Optional[GeneralResult] = None,
    ) -> GeneralResult:
        """The paper's P_m on 2^``m`` steps: ``method`` "discrete" (global MILP, with its
        certificate) or "local" (the LPCC active-set method from ``start``, a GeneralResult of
        the same numbers of states and controls and the same period, its control averaged on
        the grid (``--start``); else the file's ``[input]``, else where A = 0 the phase optimum,
        else square waves; ``shifts`` rotations of each; no global claim). ``objective`` is J
        re-verified by simulation; ``solution`` holds ``states``, ``controls`` and
        ``reactions`` (rates per step and face). ``certify`` (every method) adds
        ``necessary_conditions``: Theorem 2.2's conditions on the answer with their residuals
        and ``verdict`` (``crawlopt optimize --certify``; a phase gait's on its own phases, the
        durations free); on a Cauchy problem (``periodic = false``) an ``InputError`` naming
        ``certify``, before any work. ``convergence``
        (discrete only) solves P_1..P_``m`` in turn and adds their table ``convergence``
        (``crawlopt optimize --convergence``), the answer being the finest. ``bound`` (as for
        ``optimize``; every method): the crawler's upper bound over all periodic gaits, where
        the problem is a crawler's gait problem of at most four blocks
        (``analyze().check("structure")`` says so), as ``certificate["upper_bound"]``; else an
        ``InputError`` naming ``bound``, before any work. Ctrl-C stops it
        (KeyboardInterrupt); ``progress`` as for ``optimize``. ``method`` "phase" (where A = 0):
        the exact continuous-time gait, globally among those of at most ``phases`` phases, or with K
        grown from 1 to ``max_phases`` (None: the library's default,
        ``api::DEFAULT_GENERAL_PHASES``, or the crawler's ``api::DEFAULT_MAX_PHASES`` slip phases
        where the problem is a crawler's gait problem) until ``patience`` consecutive K bring no
        gain, as for crawlers (``crawlopt optimize --method phase``; ``phase_growth`` holds the
        table of the K solved); ``objective`` is J re-verified by the exact simulation, and
        ``solution`` holds ``durations``, ``controls``, ``states``, ``held`` (faces, 1-based) and
        ``reactions`` per phase. ``method`` "sequence" or "chain" (where the problem is a crawler's
        gait problem, as ``analyze().check("structure")`` says; else an ``InputError`` naming
        ``method``):
        the crawler's local method on that crawler (``time_limit``, ``certify`` and ``bound``,
        and ``phases`` and ``max_phases`` with "sequence", as for ``optimize``), its gait written
        back as a phase gait of the problem and re-verified by the exact simulation; no global
        claim (``status`` "stationary" or "stalled", ``certificate["kind"]`` "local").
        ``polish`` (discrete only;
        default True): a quadratic cost's answer is polished on its fixed face pattern before it
        is certified (``--no-polish`` is ``polish=False``); ``solution["polish"]`` records it.
        ``start`` with "discrete" (not with ``convergence``): the MILP's first incumbent is the
        start's process on the grid, so the answer is never below it (and a time limit returns
        at least it), recorded as ``discrete_start``; without it, under ``time_limit``, the local
        method's answer on the same grid starts it (first half of the limit; ``shifts``
        rotations of its starts, as for "local"; named as a crawler's, e.g. "local on P_3, from
        phase (K = 5)"; with a cost, which the local method takes not, where the first half is
        spent before it runs, or where it fails, its start itself: the file's ``[input]``, else
        where A = 0 the phase gait; a note says why).
        ``max_phases`` with "local" (no ``start``) and with the default start of "discrete"
        bounds the K of the phase gait that starts them, as a crawler's; an ``InputError``
        naming it where no phase gait is grown (the file's ``[input]`` starts, or A != 0).
        ``formulation`` ("phase" only; ``--formulation``): "general" (K phases), "transitions"
        (K slots of a free transition and a phase, as strong as the chain's where measured) or
        "chain" (a crawler's gait problem only); None: the chain's on a crawler's chain, the
        transitions elsewhere."""
        keys = _settings(
            method=method,
            m=m,
            shifts=shifts,
            time_limit=time_limit,
            certify=certify,
            max_phases=max_phases,
            polish=polish,
            phases=phases,
            patience=patience,
            convergence=convergence,
            formulation=formulation,
            bound=bound,
        )
        d, record, notes = self._inner.optimize(
            keys, _start_json(start), progress_callback(progress)
        )
        return GeneralResult(d, record, notes)
