"""Numbers in dataset files: read exactly, written so that they read back to the same value.

A token with a decimal point, an exponent, ``NaN`` or ``Inf`` is a float (float64); any other
number is an integer (Python ``int``, in arrays int64, or uint64 for A_UINT64 values above
2**63 - 1). Floats are written with :func:`repr`, the shortest text that reads back to the same
float64, so a value survives any number of trips through a file; integers stay integers.

NaN and infinities: erased flash read through a float record layout is NaN, so a dataset can
hold them. Both formats write them (``NaN``, ``Inf``, ``-Inf`` in DCM; ``NaN``, ``INF``, ``-INF``,
the XML Schema spelling, in CDFX) and both readers accept any of these spellings, case-insensitive.
A NaN keeps its sign (``-NaN``: erased flash, 0xFFFFFFFF, is a negative NaN), not its payload.
Other tools may refuse such a file; the A2L check reports them as outside the limits.

A decimal comma (``1,5``) is refused rather than guessed: DCM and CDF both use a decimal point.
"""

from __future__ import annotations

import math
import re

import numpy as np

__all__ = ["NumberError", "as_typed", "format_number", "parse_number", "shown_difference", "shown_number",
           "shown_value", "to_array"]

_INT = re.compile(r"[+-]?\d+\Z")
_HEX = re.compile(r"[+-]?0[xX][0-9a-fA-F]+\Z")
_BIN = re.compile(r"[+-]?0[bB][01]+\Z")
_FLOAT = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\Z")
_SPECIAL = {"nan": math.nan, "+nan": math.nan, "-nan": -math.nan, "inf": math.inf, "+inf": math.inf,
            "-inf": -math.inf, "infinity": math.inf, "+infinity": math.inf, "-infinity": -math.inf}
_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+([eE][+-]?\d+)?\Z")

_INT64 = (-(2**63), 2**63 - 1)
_UINT64_MAX = 2**64 - 1


class NumberError(ValueError):
    """A token that is not a number of a dataset file; the message says what was found."""


def parse_number(token: str) -> int | float:
    """The number ``token`` spells: ``int`` for integers (decimal, ``0x`` hex, ``0b`` binary), else float.

    :raises NumberError: not a number (the message names the token; a decimal comma is named as such).
    """
    if _INT.match(token):
        return int(token)
    if _FLOAT.match(token):
        return float(token)
    special = _SPECIAL.get(token.lower())
    if special is not None:
        return special
    if _HEX.match(token):
        return int(token, 16)
    if _BIN.match(token):
        return int(token, 2)
    if _DECIMAL_COMMA.match(token):
        raise NumberError(f"{token!r} is not a number (a decimal comma? the format uses a decimal point)")
    raise NumberError(f"{token!r} is not a number")


def format_number(value, *, nan: str = "NaN", inf: str = "Inf") -> str:
    """The text of ``value`` that :func:`parse_number` reads back as the same value and type.

    ``nan``/``inf`` spell the special floats (``-`` is put before ``inf`` for minus infinity).
    """
    if isinstance(value, (bool, np.bool_)):
        return str(int(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    value = float(value)
    if math.isnan(value):
        return f"-{nan}" if math.copysign(1, value) < 0 else nan
    if math.isinf(value):
        return inf if value > 0 else f"-{inf}"
    return repr(value)


def shown_number(value) -> str:
    """``value`` as a person reads it (a table, a message; files use :func:`format_number`): a float that
    is exactly a float32 in the float32's shortest text (25.123, not the 25.12299919128418 it holds:
    typed as 25.123, it is what a FLOAT32 calibration stores), any other float in the shortest text
    that reads back to it, integers as integers."""
    return format_number(as_typed(value))


def shown_value(value, places: int | None = None) -> str:
    """A value as ``cal get`` and ``cal diff`` show it: a number with ``places`` decimals (the A2L's FORMAT) when
    known, else a whole float as an integer and any other number as :func:`shown_number`; a text as it is."""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_, int, np.integer)):
        return str(int(value))
    value = float(value)
    if math.isnan(value) or math.isinf(value):
        return str(value)
    if places is not None:
        return f"{value:.{places}f}"
    if value == int(value) and abs(value) < 1e16:
        return str(int(value))
    return shown_number(value)  # a float32 ECU value as float32 prints it (0.02); JSON keeps it exact


def as_typed(value):
    """``value`` (a number or an array) with every float that is exactly a float32 replaced by the float64
    nearest that float32's shortest text: a FLOAT32 calibration typed as 0.3 holds 0.30000001192092896,
    and becomes 0.3 again. Written to a file it reads 0.3, as CANape writes it, and written to the ECU it is
    the same float32. Integers and the other floats stay as they are."""
    if isinstance(value, np.ndarray):
        if value.dtype.kind != "f" or not value.size:
            return value
        single = value.astype(np.float32)
        exact = (single.astype(np.float64) == value) & np.isfinite(value)
        if not exact.any():
            return value
        typed = value.copy()
        typed[exact] = single[exact].astype(str).astype(np.float64)
        return typed
    if isinstance(value, (float, np.floating)) and math.isfinite(value) and float(np.float32(value)) == value:
        return float(str(np.float32(value)))
    return value


def shown_difference(a, b) -> str:
    """``b - a`` as the difference of the numbers :func:`shown_number` shows for them (25.123 - 5.0 shows
    20.123, and 12.5 - 25.12 shows -12.62, not -12.620000000000001)."""
    from decimal import Decimal, InvalidOperation  # here: reading and writing files need none of it

    if isinstance(a, (int, np.integer)) and isinstance(b, (int, np.integer)):
        return str(int(b) - int(a))
    try:
        delta = Decimal(shown_number(b)) - Decimal(shown_number(a))
    except InvalidOperation:  # NaN or an infinity on either side
        delta = None
    if delta is not None and delta.is_finite() and -7 < delta.adjusted() < 16:
        return f"{delta:f}"
    return format_number(float(b) - float(a))


def to_array(items: list, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """The values of a file as the array :class:`~workbench.calib.values.CalValue` holds.

    Texts only: an ``object`` array of ``str``; integers only: int64 (uint64 when a value needs
    it); numbers with at least one float: float64; texts and numbers mixed: an ``object`` array
    of both. ``shape`` reshapes the flat list (C order).

    :raises NumberError: an integer that no 64-bit type holds, or one that float64 cannot hold
        exactly next to floats.
    """
    texts = sum(isinstance(v, str) for v in items)
    if texts:
        array = np.empty(len(items), dtype=object)
        array[:] = items
    elif all(isinstance(v, int) for v in items):
        array = np.array(items, dtype=_int_dtype(items))
    else:
        for v in items:
            if isinstance(v, int) and float(v) != v:
                raise NumberError(f"{v} cannot be held exactly next to the fractional values of the same object")
        array = np.array(items, dtype=np.float64)
    return array.reshape(shape) if shape is not None else array


def _int_dtype(items: list[int]) -> type:
    low, high = (min(items), max(items)) if items else (0, 0)
    if _INT64[0] <= low and high <= _INT64[1]:
        return np.int64
    if low >= 0 and high <= _UINT64_MAX:
        return np.uint64
    bad = low if low < _INT64[0] else high
    raise NumberError(f"{bad} does not fit a 64-bit integer")


def scalar(value: int | float) -> int | float:
    """A scalar as a Python number (the VALUE form of :class:`~workbench.calib.values.CalValue`).

    :raises NumberError: an integer beyond 64 bits.
    """
    if isinstance(value, int) and not _INT64[0] <= value <= _UINT64_MAX:
        raise NumberError(f"{value} does not fit a 64-bit integer")
    return value
