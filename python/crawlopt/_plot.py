"""``plot()`` of results: matplotlib figures (an optional dependency) of the series the library
computed. The library's own SVG figures (``figures()``) are what ``_repr_html_`` shows."""

from __future__ import annotations

import numpy as np

from ._convert import require


def _pyplot():
    return require("matplotlib.pyplot", "plot()")


def _columns(a, rows: int) -> np.ndarray:
    a = np.asarray(a if a is not None else np.zeros((0, 0)), dtype=float)
    return a.reshape(rows, -1) if a.size else np.zeros((rows, 0))


def simulation_plot(t, x, X, y, title: str):
    """Block positions X_b(t) with the barycentre y(t) above, link forces x_l(t) below."""
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    t = np.asarray(t, dtype=float)
    X = _columns(X, len(t))
    for b in range(X.shape[1]):
        top.plot(t, X[:, b], lw=1, label=f"X_{b + 1}")
    if len(t):
        top.plot(t, np.asarray(y, dtype=float), "k--", lw=1.5, label="y (barycentre)")
    top.set_ylabel("position")
    top.legend(loc="best", fontsize="small")
    x = _columns(x, len(t))
    for k in range(x.shape[1]):
        bottom.plot(t, x[:, k], lw=1, label=f"x_{k + 1}")
    bottom.set_xlabel("t")
    bottom.set_ylabel("link force")
    if x.shape[1]:
        bottom.legend(loc="best", fontsize="small")
    fig.suptitle(title)
    return fig


def _above_controls(t, top_values, name: str, ylabel: str, u, title: str):
    """Two panels over one period: the series ``name_k`` at the times ``t`` above (piecewise
    linear), the controls ``u_k`` per piece (piecewise constant) below."""
    plt = _pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    t = np.asarray(t, dtype=float)
    values = _columns(top_values, len(t))
    for k in range(values.shape[1]):
        top.plot(t, values[:, k], lw=1.5, label=f"{name}_{k + 1}")
    top.set_ylabel(ylabel)
    top.legend(loc="best", fontsize="small")
    u = _columns(u, max(len(t) - 1, 0))
    for k in range(u.shape[1]):
        bottom.stairs(u[:, k], t, lw=1.5, label=f"u_{k + 1}")
    bottom.set_xlabel("t")
    bottom.set_ylabel("control u")
    if u.shape[1]:
        bottom.legend(loc="best", fontsize="small")
    fig.suptitle(title)
    return fig


def gait_plot(t, L, u, title: str):
    """The gait: actuator lengths L_l at the knots (piecewise linear) above, the controls u_l
    per piece (piecewise constant) below."""
    return _above_controls(t, L, "L", "actuator length", u, title)


def general_plot(t, x, u, title: str):
    """A general problem's period: states x_k(t) above, controls u_k per step below."""
    return _above_controls(t, x, "x", "state x", u, title)
