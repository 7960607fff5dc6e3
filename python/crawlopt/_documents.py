"""Typed views of the library's JSON documents: results and certificates as classes whose
attributes are the document's fields, with ``to_dict()``, ``to_pandas()``, ``plot()`` and an
HTML form for Jupyter. Nothing is computed here: every number is the library's."""

from __future__ import annotations

import html
import math
from typing import Any, Optional

import numpy as np

from ._convert import require
from ._figure import Figure


def same(a: Any, b: Any) -> bool:
    """Equality by value of documents holding NumPy arrays, dicts and lists."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        try:
            return np.array_equal(np.asarray(a), np.asarray(b))
        except (TypeError, ValueError):
            return False
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return bool(a == b)


def plain(value: Any) -> Any:
    """``value`` with NumPy arrays as lists (what ``json.dumps`` takes), and a number that is
    not finite as None: JSON has no NaN, and the library writes a missing bound as null."""
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [plain(v) for v in value]
    return value


def numbers_table(rows: list[tuple[str, Any]]) -> str:
    """Key numbers as an HTML table (None shown as 'not reached')."""

    def cell(v):
        if v is None:
            return "<b>not reached</b>"
        if isinstance(v, float):
            return f"{v:.10g}"
        return html.escape(str(v))

    body = "".join(f"<tr><th>{html.escape(k)}</th><td>{cell(v)}</td></tr>" for k, v in rows)
    return f"<table>{body}</table>"


def figure_svg(fig) -> str:
    """A matplotlib figure as SVG text (then closed, so that Jupyter does not draw it twice)."""
    import io

    plt = require("matplotlib.pyplot", "the figure")
    buf = io.StringIO()
    fig.savefig(buf, format="svg", bbox_inches="tight")
    plt.close(fig)
    return buf.getvalue()


class Fields:
    """A document's fields read by name, as from a dict: ``d["field"]``, ``"field" in d``,
    ``d.get("field")``, ``d.keys()``. Every document of the library has them, a crawler's
    ``GaitResult`` as a ``GeneralResult`` (the one envelope of every result: ``d["problem"]``,
    ``d["solution"]``, ...)."""

    _doc: dict

    def __getitem__(self, key: str) -> Any:
        return self._doc[key]

    def __contains__(self, key: str) -> bool:
        return key in self._doc

    def get(self, key: str, default: Any = None) -> Any:
        """The field ``key``, or ``default``."""
        return self._doc.get(key, default)

    def keys(self):
        """The document's fields."""
        return self._doc.keys()


class Document(Fields):
    """A JSON document of the library: each field an attribute; ``d["field"]`` reads it too
    (as the dict it used to be)."""

    def __init__(self, doc: dict):
        self._doc = doc
        for k, v in doc.items():
            if k.isidentifier() and not hasattr(type(self), k):
                setattr(self, k, v)

    def to_dict(self) -> dict:
        """The fields of the document as a dict (series as NumPy arrays)."""
        return dict(self._doc)

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return same(self._doc, other._doc)

    __hash__ = None  # type: ignore[assignment]

    def __getstate__(self) -> dict:
        return {"_doc": self._doc}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["_doc"])


class GeneralAnalysis(Document):
    """The analysis of a general problem (P) (``crawlopt analyze --json`` on a general file):
    ``problem`` (its data as the library reads it), ``geometry`` (C's faces, redundant faces,
    vertices, Chebyshev centre and radius, boundedness), ``checks`` (each a dict of ``name``,
    ``status`` "pass", "fail" or "info", and ``detail``: the conditions (P) asks of C, U and the
    face weights, the dynamics, and the structure recognised, such as a crawler's chain) and
    ``failure``, the first failed check's message (None: well posed). Every field of the JSON
    is an attribute; ``a["field"]`` reads it too."""

    @property
    def well_posed(self) -> bool:
        """Whether every check passed (``failure`` is None)."""
        return self._doc.get("failure") is None

    def check(self, name: str) -> dict:
        """The check named ``name`` (such as "structure"); a KeyError names the ones there
        are."""
        for c in self._doc.get("checks", []):
            if c.get("name") == name:
                return c
        names = [c.get("name") for c in self._doc.get("checks", [])]
        raise KeyError(f"no check {name!r}; the checks are {names}")

    def __repr__(self) -> str:
        g = self._doc.get("geometry", {})
        return (
            f"GeneralAnalysis(well_posed={self.well_posed}, faces={g.get('faces')}, "
            f"bounded={g.get('bounded')})"
        )

    def _repr_html_(self) -> str:
        checks = self._doc.get("checks", [])
        rows = [(c.get("name"), f"{c.get('status')}: {c.get('detail')}") for c in checks]
        return numbers_table(rows)


class NecessaryConditions(Document):
    """A certificate of the necessary conditions (Theorem 2.2; discrete form Theorems
    6.1–6.2), for a crawler's gait or a general problem's optimum: ``verdict`` ("holds",
    "degenerate", "fails", ...), ``reason``, ``conditions`` (each with its name, theorem,
    statement and residual) and ``multipliers`` (the adjoint p, ...)."""

    verdict: str

    def to_pandas(self):
        """The conditions as a DataFrame, one row per condition (its residual among the
        columns)."""
        pd = require("pandas", "to_pandas()")
        return pd.DataFrame(self._doc.get("conditions", []))

    def __repr__(self) -> str:
        n = len(self._doc.get("conditions", []))
        return f"NecessaryConditions(verdict={self._doc.get('verdict')!r}, {n} conditions)"

    def _repr_html_(self) -> str:
        rows = [("verdict", self._doc.get("verdict")), ("reason", self._doc.get("reason"))]
        conds = "".join(
            "<tr><td>{}</td><td>{}</td><td>{}</td></tr>".format(
                html.escape(str(c.get("name"))),
                html.escape(str(c.get("theorem", ""))),
                html.escape(str(c.get("residual", ""))),
            )
            for c in self._doc.get("conditions", [])
        )
        return (
            numbers_table(rows)
            + "<table><tr><th>condition</th><th>theorem</th><th>residual</th></tr>"
            + conds
            + "</table>"
        )


def _series(d: dict, keys) -> dict:
    for k in keys:
        if d.get(k) is not None:
            d[k] = np.asarray(d[k], dtype=float)
    return d


class _LibraryFigures:
    """The library's figures and report of a general problem's record (``figures()``,
    ``report()``), kept by the object ``simulate`` or ``optimize`` returned and by a result
    read back with ``read_result`` or ``GeneralResult.from_json`` (an unpickled copy has
    none)."""

    _record: Any = None

    def figures(self) -> dict:
        """The library's figures by name, as ``--plot`` writes them: ``polytope`` (C with the
        path of the state: the interval and x(t) in 1-D, the polygon in 2-D, projections
        beyond), ``states`` (n >= 2), ``controls``, ``reactions``, ``integrand`` (f1 - f2,
        whose integral is J), and ``adjoint`` with the necessary conditions. CrawloptError
        without the periodic regime."""
        return {n: Figure(n, c, svg) for n, c, svg in self._library().figures()}

    def report(self, path: Optional[str] = None, source: str = "crawlopt") -> str:
        """The self-contained HTML report (written to ``path`` when given, as ``crawlopt
        optimize --report``); returns the HTML."""
        if path is not None:
            self._library().write_report(str(path), source)
        return self._library().report_html(source)

    def _library(self):
        if self._record is None:
            from ._crawlopt import CrawloptError

            raise CrawloptError(
                "no figures: this document was read back without the library's record "
                "(figures and reports are made from the object simulate or optimize returned, "
                "or from a result file read with crawlopt.read_result)"
            )
        return self._record


class GeneralSimulation(_LibraryFigures, Document):
    """A general problem's ``[input]`` played to its periodic regime (``crawlopt simulate
    --json``): ``converged``, ``status`` ("converged" or "not_converged"), ``objective`` (J;
    None without the regime), ``reward``, ``cost``, and the period as arrays ``t``, ``x``
    (states, one row per time), ``u`` and ``reactions`` (lambda per face, one row per step).
    ``d["simulation"]`` is the document's section as before. ``figures()`` and ``report()``
    are the library's (``crawlopt simulate --plot``)."""

    def __init__(self, doc: dict, record: Any = None):
        self._record = record
        super().__init__(doc)
        sim = _series(doc["simulation"], ("t", "x", "u", "lambda", "mean_control"))
        for k, v in sim.items():
            if k != "lambda":
                setattr(self, k, v)
        self.reactions = sim.get("lambda")

    @property
    def status(self) -> str:
        """ "converged" when the periodic regime was reached, else "not_converged"."""
        return "converged" if self._doc["simulation"].get("converged") else "not_converged"

    def to_pandas(self):
        """The period as a DataFrame: t, x_k, and u_k and lambda_j of the step ending at t."""
        pd = require("pandas", "to_pandas()")
        s = self._doc["simulation"]
        t = np.asarray(s.get("t", []), dtype=float)
        cols: dict = {"t": t}
        x = np.asarray(s.get("x", np.zeros((0, 0))), dtype=float).reshape(len(t), -1)
        for k in range(x.shape[1]):
            cols[f"x_{k + 1}"] = x[:, k]
        for name, key in (("u", "u"), ("lambda", "lambda")):
            a = np.asarray(s.get(key, np.zeros((0, 0))), dtype=float)
            if a.size:
                a = a.reshape(len(a), -1)
                for j in range(a.shape[1]):
                    cols[f"{name}_{j + 1}"] = np.concatenate([[np.nan], a[:, j]])[: len(t)]
        return pd.DataFrame(cols)

    def plot(self):
        """The states x(t) and controls u(t) over the period: a matplotlib Figure."""
        from ._plot import general_plot

        s = self._doc["simulation"]
        return general_plot(s.get("t"), s.get("x"), s.get("u"), self._title())

    def _title(self) -> str:
        j = self._doc["simulation"].get("objective")
        return "periodic regime NOT reached" if j is None else f"J = {j:.6g}"

    def __repr__(self) -> str:
        s = self._doc["simulation"]
        j = s.get("objective")
        return (
            f"GeneralSimulation(status={self.status!r}, "
            f"objective={'not reached' if j is None else f'{j:.10g}'}, periods={s.get('periods')})"
        )

    def _repr_html_(self) -> str:
        s = self._doc["simulation"]
        rows = [
            ("status", self.status),
            ("objective J", s.get("objective")),
            ("reward", s.get("reward")),
            ("cost", s.get("cost")),
            ("periods", s.get("periods")),
        ]
        return numbers_table(rows) + _optional_svg(self)


# The methods whose answer is an exact gait of phases (durations, controls, states): the phase
# MILPs, and the crawler's local methods on a problem that is a chain.
_EXACT_GAITS = ("phase", "sequence", "chain")


class GeneralResult(_LibraryFigures, Document):
    """An optimum of a general problem (``crawlopt optimize --json``), in the envelope of every
    result: ``format``, ``version``, ``kind`` ("general"), ``method``, ``problem`` (the
    problem's sections, as the file has them), ``objective`` (J re-verified by simulation),
    ``status`` (what was proven), ``certificate`` (``kind`` global, global_k_phases or local,
    ``bound``, ``gap``, as a crawler's), ``necessary_conditions`` (a NecessaryConditions, with
    ``certify=True``), ``solver_objective`` (the MILP methods'), and the gait as arrays named
    alike for every method (since result version 3): ``states`` (one row per knot), ``controls`` and
    ``reactions`` (one row per step of P_m or per phase), with ``durations`` and ``held`` per
    phase for methods "phase", "sequence" and "chain"; ``x`` and ``u`` are the same arrays as
    ``states`` and ``controls`` (a crawler's gait names them so). ``d["solution"]`` is the
    document's section. ``from_json``/``to_json`` read and write the
    document (read back checked as ``crawlopt certify`` checks it); ``certify()`` gives its
    NecessaryConditions; ``figures()`` and ``report()`` are the library's (``crawlopt optimize
    --plot --report``). ``notes``: how the job went (a start refused and the one tried
    instead, ...), as a crawler's ``GaitResult.notes``; empty for a result read back."""

    def __init__(self, doc: dict, record: Any = None, notes=()):
        self._record = record
        self.notes = list(notes)
        sol = doc["solution"]
        _series(sol, ("durations", "controls", "states", "reactions"))
        if isinstance(doc.get("necessary_conditions"), dict):
            doc["necessary_conditions"] = NecessaryConditions(doc["necessary_conditions"])
        super().__init__(doc)
        for k, v in sol.items():
            if k not in doc and not hasattr(type(self), k):
                setattr(self, k, v)
        self.necessary_conditions = doc.get("necessary_conditions")

    @property
    def x(self):
        """``states``, under the name a crawler's gait gives them."""
        return self.states

    @property
    def u(self):
        """``controls``, under the name a crawler's gait gives them."""
        return self.controls

    def _knots(self) -> np.ndarray:
        """The knot times: the phases' durations summed, or P_m's equal steps."""
        s = self._doc["solution"]
        if "durations" in s:
            d = np.asarray(s["durations"], dtype=float)
        else:
            n = len(s["controls"])
            d = np.full(n, float(self._doc["problem"]["problem"]["period"]) / max(n, 1))
        return np.concatenate([[0.0], np.cumsum(d)])

    def to_dict(self) -> dict:
        d = dict(self._doc)
        if isinstance(d.get("necessary_conditions"), NecessaryConditions):
            d["necessary_conditions"] = d["necessary_conditions"].to_dict()
        return d

    @property
    def status(self) -> Optional[str]:
        """What was proven: "optimal", "optimal_among_k_phases", "time_limit", ... or a local
        method's "stationary" / "stalled"."""
        return self._doc.get("status")

    @staticmethod
    def from_json(text: str, name: str = "result") -> GeneralResult:
        """Reads a general problem's result document, checked as ``crawlopt certify`` checks
        it (the problem rebuilt from the document, the solution replayed by simulation; a
        number that disagrees raises InputError naming its field)."""
        from . import _crawlopt as _rs

        return GeneralResult(*_rs.read_general_result(text, name))

    def to_json(self) -> str:
        """The result document (``crawlopt optimize --json``'s form)."""
        import json

        return json.dumps(plain(self.to_dict()))

    def certify(self) -> NecessaryConditions:
        """The necessary conditions (Theorem 2.2; discrete form Theorems 6.1–6.2) on the
        stored P_m process (methods "discrete" and "local") or phase gait (methods "phase",
        "sequence" and "chain", on its own phases with the durations free): ``crawlopt
        certify RESULT.json``."""
        import json

        from . import _crawlopt as _rs

        return NecessaryConditions(json.loads(_rs.certify_json(self.to_json())))

    def to_pandas(self):
        """The gait as a DataFrame: one row per step (P_m: t_start, t_end) or per phase (methods
        "phase", "sequence", "chain": t_start, duration), then u_k, x_k at its end and the
        reaction rates lambda_j."""
        pd = require("pandas", "to_pandas()")
        s = self._doc["solution"]
        cols: dict = {}
        t = self._knots()
        n = len(t) - 1
        cols["t_start"] = t[:-1]
        if self._doc.get("method") in _EXACT_GAITS:
            cols["duration"] = np.diff(t)
        else:
            cols["t_end"] = t[1:]
        u = np.asarray(s["controls"], dtype=float).reshape(n, -1)
        x = np.asarray(s["states"], dtype=float).reshape(n + 1, -1)[1:]
        for k in range(u.shape[1]):
            cols[f"u_{k + 1}"] = u[:, k]
        for k in range(x.shape[1]):
            cols[f"x_{k + 1}"] = x[:, k]
        lam = s.get("reactions")
        if lam is not None and np.size(lam):
            lam = np.asarray(lam, dtype=float).reshape(n, -1)
            for j in range(lam.shape[1]):
                cols[f"lambda_{j + 1}"] = lam[:, j]
        return pd.DataFrame(cols)

    def plot(self):
        """The optimal states x(t) and controls u(t) over a period: a matplotlib Figure."""
        from ._plot import general_plot

        s = self._doc["solution"]
        title = f"J = {self._doc.get('objective', float('nan')):.6g} ({self.status})"
        return general_plot(self._knots(), s["states"], s["controls"], title)

    def __repr__(self) -> str:
        c = self._doc.get("certificate") or {}
        gap = c.get("gap")
        gap = "" if gap is None else f", gap={gap:.1e}"
        nc = self._doc.get("necessary_conditions")
        verdict = "" if nc is None else f", necessary_conditions={nc['verdict']!r}"
        return (
            f"GeneralResult(method={self._doc.get('method')!r}, "
            f"objective={self._doc.get('objective'):.10g}, status={self.status!r}{gap}{verdict})"
        )

    def _repr_html_(self) -> str:
        c = self._doc.get("certificate") or {}
        nc = self._doc.get("necessary_conditions")
        rows = [
            ("method", self._doc.get("method")),
            ("objective J", self._doc.get("objective")),
            ("status", self.status),
            ("bound", c.get("bound")),
            ("gap", c.get("gap")),
        ]
        if nc is not None:
            rows.append(("necessary conditions", nc["verdict"]))
        return numbers_table(rows) + _optional_svg(self)


def _optional_svg(result) -> str:
    """The library's figures of C and of the integrand when the result has its record, else
    its ``plot()`` as inline SVG when matplotlib is installed, else nothing."""
    if result._record is not None and result.status != "not_converged":
        figs = result.figures()
        return "".join(
            f"<figure>{figs[n].svg}<figcaption>{html.escape(figs[n].caption)}</figcaption></figure>"
            for n in ("polytope", "integrand")
            if n in figs
        )
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return ""
    return figure_svg(result.plot())
