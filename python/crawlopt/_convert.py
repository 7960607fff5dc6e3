"""Conversion of Python arguments into what the extension takes: arrays checked for shape
(never flattened or broadcast: the library broadcasts a single number as the file does), and
the InputError raised on the Python side."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Union

import numpy as np

from ._crawlopt import InputError

Numbers = Union[float, Sequence[float]]


def _input_error(field: str, value: Any, reason: str) -> InputError:
    """An InputError raised on the Python side, with ``.field`` and ``.value`` as the library's
    (the value as text)."""
    e = InputError(f"{field}: {reason} (got {value})")
    e.field, e.value = field, str(value)
    return e


def _count(value: Any, name: str, bits: int = 64) -> Any:
    """A whole-number setting as the extension holds it (unsigned, ``bits`` wide; None stays
    None): an integer out of that range is an InputError naming the setting, where the
    extension's conversion raises a bare OverflowError. Its range within that (``phases >= 1``)
    is the library's to check; other types are left to the extension's TypeError."""
    if isinstance(value, int) and not isinstance(value, bool) and not 0 <= value < 2**bits:
        raise _input_error(name, value, f"must be a whole number in [0, 2^{bits})")
    return value


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


def _numbers(value: Numbers, name: str) -> Union[float, list[float]]:
    """A number (for every entry) or a list of them, as the model file takes it: the library
    expands a number to every link or block and checks a list's length."""
    if np.ndim(value) == 0:
        return float(_array(value, name, 0, "a number"))
    return _vector(value, name, "numbers, one per entry, or a single number")


class NotConvergedWarning(UserWarning):
    """A simulation that did not reach its periodic regime (its ``status`` is
    ``"not_converged"`` and ``displacement_per_period`` is None)."""


def _instance(value: Any, cls: type, name: str) -> None:
    """TypeError unless ``value`` is a ``cls`` (not an AttributeError from deep inside)."""
    if not isinstance(value, cls):
        raise TypeError(f"{name}: must be a crawlopt.{cls.__name__}, got {type(value).__name__}")


def require(module: str, purpose: str):
    """Imports an optional dependency, or raises ImportError saying what needs it and how to
    install it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as e:
        top = module.split(".")[0]
        raise ImportError(
            f"{purpose} needs {top}, an optional dependency of crawlopt: pip install {top}"
        ) from e


def _settings(**keys: Any) -> dict:
    """An optimisation's settings as the extension takes them: the keywords given, by the
    library's own names (``max_phases``), those at None (the library's default) left out. The
    library reads them and names the key of a value it refuses."""
    return {k: v for k, v in keys.items() if v is not None}
