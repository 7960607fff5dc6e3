"""Rendering a job's progress events: a tqdm bar where tqdm is installed, a text line
otherwise, or the caller's own function."""

from __future__ import annotations

import json
import sys
from typing import Any, Callable, Optional


def _line(event: dict) -> str:
    kind = event["kind"]
    if kind in ("stage", "note"):
        return ("note: " if kind == "note" else "") + event["text"]
    if kind == "phase":
        head = "start: " if event["start"] else ""
        return f"{head}K = {event['K']}: J = {event['objective']:.6g} (bound {event['bound']:.6g})"
    if kind == "discrete":
        return f"m = {event['m']}: J = {event['objective']:.6g} (gap {event['gap']:.1e})"
    inc, bound = event.get("incumbent"), event.get("bound")
    shown = "none" if inc is None else f"{inc:.6g}"
    return f"MILP: incumbent J = {shown}, bound {'none' if bound is None else f'{bound:.6g}'}"


class _Bar:
    """A status line updated in place: tqdm when importable (notebook-aware), else stderr."""

    def __init__(self):
        try:
            from tqdm.auto import tqdm

            self._bar = tqdm(total=None, bar_format="{elapsed} {desc}", leave=False)
        except ImportError:
            self._bar = None

    def __call__(self, text: str) -> None:
        event = json.loads(text)
        line = f"[{event['seconds']:.1f} s] {_line(event)}"
        if self._bar is not None:
            self._bar.set_description_str(line)
        else:
            sys.stderr.write("\r" + line[:100].ljust(100))
            sys.stderr.flush()


def progress_callback(progress: Any) -> Optional[Callable[[str], None]]:
    """What the extension calls with each event's JSON text."""
    if progress is None or progress is False:
        return None
    if progress is True:
        return _Bar()
    if callable(progress):
        return lambda text: progress(json.loads(text))
    raise TypeError("progress must be True, False, None or a callable")
