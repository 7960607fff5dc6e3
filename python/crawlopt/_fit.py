"""Identification of a crawler from a measured trajectory (``crawlopt fit``): :func:`fit` and
its :class:`FitResult`. The method is in docs/guide/fit.md."""

from __future__ import annotations

from typing import Any, Callable, Optional, Union

import numpy as np

from . import _crawlopt as _rs
from ._convert import _array, _input_error, _vector
from ._progress import progress_callback

Progress = Union[bool, Callable[[dict], Any], None]


class FitResult:
    """A crawler fitted to a measured trajectory (what ``crawlopt fit --json`` prints): every
    field of that document is an attribute: ``crawler`` (the estimates, None where the data
    bound a parameter only from below), ``intervals`` (per parameter ``[lo, hi]``, ``hi`` None
    where unbounded; None when the data contradict the model), ``model`` (the values of the
    fitted model), ``scale``, ``noise``, ``slip_episodes``, ``outlier_rows``, ``residuals``,
    ``prediction``, ``warnings``. ``fitted`` is the fitted model as a :class:`Crawler` (None if
    none could be built) and ``predicted`` its re-simulated positions (samples x blocks)."""

    def __init__(self, doc: dict, predicted):
        self._doc = doc
        self.__dict__.update(doc)
        from . import Crawler  # the package's class (this module is imported by the package)

        m = doc.get("model")
        self.fitted = (
            None
            if m is None
            else Crawler(len(m["mu_forward"]), m["stiffness"], m["mu_forward"], m["mu_backward"])
        )
        self.predicted = predicted

    def to_dict(self) -> dict:
        """The fields of the JSON document as a dict (as ``--json`` prints them)."""
        return dict(self._doc)

    def __repr__(self) -> str:
        return (
            f"FitResult(blocks={self.blocks}, samples={self.samples}, "
            f"intervals={'none' if self.intervals is None else 'yes'}, "
            f"warnings={len(self.warnings)})"
        )


def fit(
    t,
    L,
    X,
    *,
    blocks: int,
    fix: Optional[dict] = None,
    noise: Optional[float] = None,
    noise_bound: Optional[float] = None,
    progress: Progress = False,
) -> FitResult:
    """Identifies a crawler of ``blocks`` blocks from a measured trajectory (``crawlopt fit``):
    ``t`` the sample times (increasing), ``L`` the actuator lengths (samples x links; a 1-D
    array for one link), ``X`` the block positions (samples x blocks). ``fix`` maps known
    parameters to their values (``{"stiffness[1]": 1.0}``): one sets the force scale; without
    it every force parameter is a ratio to ``stiffness[1]``. ``noise`` is the standard
    deviation of the position noise (default: estimated); the intervals assume every position
    error is at most ``noise_bound`` (default 5) times it. See docs/guide/fit.md."""
    if not isinstance(blocks, (int, np.integer)) or blocks < 2:
        raise _input_error("blocks", repr(blocks), "must be a whole number >= 2")
    times = _vector(t, "t", "times")
    lengths = _array(L, "L", np.ndim(L) if np.ndim(L) in (1, 2) else 2, "samples x links")
    if lengths.ndim == 1:
        lengths = lengths.reshape(-1, 1)
    positions = _array(X, "X", 2, "samples x blocks (shape (samples, blocks))")
    fixes = []
    for name, value in (fix or {}).items():
        if not isinstance(name, str):
            raise TypeError(f"fix: keys must be names such as 'stiffness[1]', got {name!r}")
        fixes.append((name, float(value)))
    doc, predicted = _rs.fit(
        times,
        lengths.tolist(),
        positions.tolist(),
        int(blocks),
        fixes,
        None if noise is None else float(noise),
        None if noise_bound is None else float(noise_bound),
        progress_callback(progress),
    )
    return FitResult(doc, predicted)
