"""A crawler's simulation (``crawlopt simulate``) as a Python class."""

from __future__ import annotations

import numpy as np

from . import _crawlopt as _rs
from ._convert import require
from ._crawlopt import CrawloptError
from ._documents import same
from ._figure import Figure


class Simulation:
    """A simulation to the periodic regime: ``status`` ("converged", or "not_converged" when
    the regime was not reached: then ``displacement_per_period`` is None, ``repr`` says so
    and ``simulate`` warned with NotConvergedWarning), the envelope of every simulation
    (``format``, ``version``, ``kind`` "crawler", ``objective``: J with no actuation cost, the
    displacement per period), ``converged``, ``periods_to_converge``, ... (every field of
    ``crawlopt simulate --json``), and the
    recorded periods as NumPy arrays: ``t`` (times), ``x`` (link forces, times x links), ``X``
    (block positions, times x blocks), ``y`` (barycentre) and ``slip`` (int8, times x blocks:
    -1 backward, 0 stick, 1 forward). ``plot()`` draws them (matplotlib); in Jupyter it shows
    the library's figures and key numbers."""

    def __init__(self, summary: dict, arrays: dict, crawler=None, actuation=None):
        self._summary = summary
        self.__dict__.update(summary)
        empty = np.zeros((0,))
        self.t = arrays.get("t", empty)
        self.x = arrays.get("x", empty.reshape(0, 0))
        self.X = arrays.get("X", empty.reshape(0, 0))
        self.y = arrays.get("y", empty)
        self.slip = arrays.get("slip", np.zeros((0, 0), dtype=np.int8))
        self._crawler, self._actuation = crawler, actuation

    @property
    def status(self) -> str:
        """ "converged" when the periodic regime was reached, else "not_converged"."""
        return "converged" if self._summary.get("converged") else "not_converged"

    def to_dict(self) -> dict:
        """The fields of the JSON document as a dict (as ``--json`` prints them)."""
        return dict(self._summary)

    def to_pandas(self):
        """The recorded trajectory as a DataFrame (t, y, x_l, X_b, slip_b)."""
        pd = require("pandas", "to_pandas()")
        cols = {"t": self.t, "y": self.y}
        for j in range(self.x.shape[1] if self.x.ndim == 2 else 0):
            cols[f"x_{j + 1}"] = self.x[:, j]
        for b in range(self.X.shape[1] if self.X.ndim == 2 else 0):
            cols[f"X_{b + 1}"] = self.X[:, b]
            cols[f"slip_{b + 1}"] = self.slip[:, b]
        return pd.DataFrame(cols)

    def figures(self, periods: int = 3) -> dict[str, Figure]:
        """The library's figures of the periodic regime by name (``actuation``, ``spacetime``
        over ``periods`` periods, ``polytope``: the orbit in C), as ``crawlopt simulate
        --plot`` draws them; CrawloptError without the regime."""
        if self.status != "converged":
            raise CrawloptError("no figures: the periodic regime was not reached")
        if self._crawler is None:
            raise CrawloptError("no figures: the simulation does not know its crawler")
        figs = _rs.simulation_figures(
            self._crawler._inner,
            self._actuation._inner,
            self._summary["method"],
            int(self._summary["steps_per_period"]),
            [float(v) for v in self._summary["orbit_state"]],
            int(periods),
        )
        return {n: Figure(n, c, svg) for n, c, svg in figs}

    def plot(self):
        """The recorded periods: block positions and barycentre, link forces (a matplotlib
        Figure; matplotlib is an optional dependency)."""
        from ._plot import simulation_plot

        d = self.displacement_per_period
        title = "periodic regime NOT reached" if d is None else f"displacement per period {d:.6g}"
        return simulation_plot(self.t, self.x, self.X, self.y, title)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Simulation):
            return NotImplemented
        return same(self._summary, other._summary) and all(
            same(getattr(self, k), getattr(other, k)) for k in ("t", "x", "X", "y", "slip")
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        d = self.displacement_per_period
        if d is None:
            return (
                f"Simulation(status='not_converged': the periodic regime was NOT reached in "
                f"{self.periods_simulated} periods (residual {self.period_residual:.3e}), "
                f"displacement_per_period=None)"
            )
        return (
            f"Simulation(status='converged', displacement_per_period={d:.10g}, "
            f"periods={self.periods_simulated})"
        )

    def _repr_html_(self) -> str:
        import html

        from ._documents import numbers_table

        rows = [
            ("status", self.status),
            ("displacement per period", self.displacement_per_period),
            ("periods to converge", self.periods_to_converge),
            ("period residual", self.period_residual),
            ("method", self.method),
        ]
        body = ""
        if self.status == "converged" and self._crawler is not None:
            figs = self.figures()
            body = "".join(
                f"<figure>{figs[n].svg}<figcaption>{html.escape(figs[n].caption)}"
                "</figcaption></figure>"
                for n in ("spacetime", "actuation")
                if n in figs
            )
        return numbers_table(rows) + body
