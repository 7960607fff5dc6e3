"""Parameter studies (``crawlopt sweep``): :func:`sweep`, one job over a grid of the numbers of a
problem file, on threads in the library or as tasks of any ``concurrent.futures`` executor."""

from __future__ import annotations

import json

from . import _crawlopt as _rs
from ._convert import _input_error, require


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
    """A parameter study (``crawlopt sweep``): one job over a grid of the numbers of a problem
    file, one row per point, as a pandas DataFrame sorted by point (columns ``point``, one per
    axis named by its field, ``objective``, ``displacement_per_period``, ``method``,
    ``certificate``, ``gap``, ``bound``, ``status``, ``verdict``, ``seconds``, ``error``; an
    ill-posed point is a row with its error).

    ``spec`` is a sweep file's path or a dict with the file's keys (``base`` or ``model``,
    ``job``, ``combine``, ``settings``, ``axis``: a list of dicts). The base is a crawler's
    model or a general problem (``[sweeping_process]``), whose axes are over its own fields
    (``problem.period``, ``sweeping_process.offsets[2]``, ``dynamics.A[1][2]``, ...). Without
    ``executor`` the points run in the library on ``threads`` threads (0: one per core) with
    the GIL released; with any ``concurrent.futures.Executor`` (a process pool, or a Dask
    cluster's ``distributed.Client(...).get_executor()``) each point is one task, run wherever
    the executor runs it (the base file must be readable there)."""
    source, is_path, base_dir = _sweep_source(spec)
    header, n = _rs.sweep_size(source, is_path, base_dir)
    if executor is None:
        lines = _rs.sweep_run(source, is_path, base_dir, int(threads))
    else:
        futures = [executor.submit(_rs.sweep_point, source, is_path, base_dir, i) for i in range(n)]
        lines = [f.result() for f in futures]
    rows = sorted((json.loads(line) for line in lines), key=lambda r: r["point"])
    pd = require("pandas", "sweep()")
    return pd.DataFrame(rows, columns=header)
