"""Numbers as an engineer reads and types them: the A2L's decimals, verbal names, units."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["format_value", "parse_typed", "range_decimals", "with_unit"]

MAX_DECIMALS = 6  # beyond these a fixed number of decimals says less than significant digits do


def format_value(value, decimals: int | None = None, states=()) -> str:
    """``value`` for display: a verbal state's name when it has one (``TANK1_ON``), else the number
    with ``decimals`` (the A2L's FORMAT), else up to 6 significant digits; "—" for no value."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    for number, text in states:
        if value == number:
            return text
    value = float(value)
    if math.isnan(value):
        return "NaN"
    if decimals is not None:
        return f"{value:.{decimals}f}"
    if value == int(value) and abs(value) < 1e9:
        return str(int(value))
    return f"{value:.6g}"


def range_decimals(values: np.ndarray, digits: int = 4) -> int | None:
    """Decimals for a signal that comes without a display format (another tool's measurement file): its
    largest magnitude with ``digits`` significant digits, and at least three of its span (a small swing
    about a large value shows); 0 for whole numbers; None (significant digits) for tiny values."""
    finite = np.asarray(values, dtype=np.float64)
    finite = finite[np.isfinite(finite)]
    if not finite.size or np.array_equal(finite, np.round(finite)):
        return 0
    magnitude, span = float(np.max(np.abs(finite))), float(np.ptp(finite))
    decimals = digits - 1 - math.floor(math.log10(magnitude))
    if span > 0:
        decimals = max(decimals, 2 - math.floor(math.log10(span)))
    return max(decimals, 0) if decimals <= MAX_DECIMALS else None


def with_unit(text: str, unit: str) -> str:
    return f"{text} {unit}" if unit else text


def parse_typed(text: str, states: Sequence[str] = ()) -> float | str:
    """The value ``text`` means: one of ``states`` (any case) as its text, else a number (``,`` or ``.``
    as the decimal point), else :class:`ValueError` saying what is expected."""
    typed = text.strip()
    for state in states:
        if typed.casefold() == state.casefold():
            return state
    try:
        return float(typed.replace(",", "."))
    except ValueError:
        pass
    if states:
        raise ValueError(f"{typed!r} is not one of {', '.join(states)} (nor a number)")
    raise ValueError(f"{typed!r} is not a number" if typed else "type a value")
