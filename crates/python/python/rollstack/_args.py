"""The conversion of the arguments of the newer functions: a value of the wrong type or
sign raises ``ValueError`` naming the parameter, as the command line names its flag."""

from __future__ import annotations

import math
import numbers
from typing import Any, Iterable, List, Optional, Union

_USIZE_MAX = 2**64 - 1


def number(name: str, value: Any) -> float:
    """``value`` as a float (NaN and infinities are left to the library to refuse)."""
    if isinstance(value, (bool, str, bytes)) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a number, got {value!r}")
    return float(value)


def positive(name: str, value: Any) -> float:
    """``value`` as a finite float > 0 (:func:`number`), else ``ValueError`` naming it."""
    v = number(name, value)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a positive finite number, got {v!r}")
    return v


def in_range(name: str, value: Any, low: float, high: float) -> float:
    """``value`` as a float in [``low``, ``high``] (:func:`number`), else ``ValueError``
    naming it."""
    v = number(name, value)
    if not low <= v <= high:
        raise ValueError(f"{name} must lie in [{low!r}, {high!r}], got {v!r}")
    return v


def optional_number(name: str, value: Any) -> Optional[float]:
    """``None``, or ``value`` as a float (:func:`number`)."""
    return None if value is None else number(name, value)


def count(name: str, value: Any) -> int:
    """``value`` as a non-negative integer that fits the library's counts."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    if value < 0:
        raise ValueError(f"{name} must not be negative, got {value}")
    if value > _USIZE_MAX:
        raise ValueError(f"{name} is too large, got {value}")
    return int(value)


def number_list(name: str, value: Any) -> List[float]:
    """``value``, a sequence of numbers, as floats; each wrong one named ``name[i]``."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise ValueError(f"{name} must be a sequence of numbers, got {value!r}")
    return [number(f"{name}[{i}]", v) for i, v in enumerate(value)]


def values(name: str, value: Any) -> Union[str, List[float]]:
    """The values of a swept parameter: the command line's text (``"10deg:40deg:10deg"``,
    ``"0.1,0.2"``, passed on as it is), one number, or a sequence of numbers."""
    if isinstance(value, str):
        return value
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return [float(value)]
    try:
        items = list(value)
    except TypeError:
        raise ValueError(
            f"{name} must be a number, a sequence of numbers or a text like '0.1:0.5:0.1', got {value!r}"
        ) from None
    return [number(f"{name}[{i}]", v) for i, v in enumerate(items)]
