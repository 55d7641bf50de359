"""ASAP2 data types as numpy sees them: bytes <-> raw numbers, rounding and range checks.

Raw integers come out as int64 (uint64 for A_UINT64), floats as float64, so every value of
every type is held exactly. Writing rounds half away from zero for the integer types (ASAM
MCD-2 MC) and refuses a value the type cannot hold. Byte orders: ``MSB_FIRST`` (big-endian),
``MSB_LAST`` (little-endian) and the word-swapped ``MSB_FIRST_MSW_LAST`` / ``MSB_LAST_MSW_FIRST``
of ASAP2 1.7 (bytes in each 16-bit word in the named order, the words the other way round).
"""

from __future__ import annotations

import numpy as np

from workbench.a2l.datatypes import DATATYPES, datatype_range
from workbench.errors import ConversionError

__all__ = ["decode", "element_size", "encode", "extract_bits", "insert_bits", "mask_shift", "numpy_dtype",
           "round_half_away", "signed", "struct_format", "to_datatype"]

_CODES = {"UBYTE": "u1", "SBYTE": "i1", "UWORD": "u2", "SWORD": "i2", "ULONG": "u4", "SLONG": "i4",
          "A_UINT64": "u8", "A_INT64": "i8", "FLOAT16_IEEE": "f2", "FLOAT32_IEEE": "f4", "FLOAT64_IEEE": "f8"}
_ORDERS = {"MSB_FIRST": ">", "MSB_LAST": "<", "MSB_FIRST_MSW_LAST": ">", "MSB_LAST_MSW_FIRST": "<"}
_WORD_SWAPPED = ("MSB_FIRST_MSW_LAST", "MSB_LAST_MSW_FIRST")
_WIDE = {"u": np.uint64, "i": np.int64, "f": np.float64}


def _known(datatype: str) -> str:
    code = _CODES.get(datatype)
    if code is None:
        raise ConversionError(f"unknown data type {datatype!r} (expected one of {', '.join(_CODES)})")
    return code


def element_size(datatype: str) -> int:
    """Bytes per element; :raises ConversionError: unknown data type."""
    return int(_known(datatype)[1])


def numpy_dtype(datatype: str, byte_order: str) -> np.dtype | None:
    """The numpy dtype of one element as stored (None for the word-swapped orders, which numpy has not)."""
    code = _known(datatype)
    if byte_order in _WORD_SWAPPED and int(code[1]) > 2:
        return None
    return np.dtype(_ORDERS[_order(byte_order)] + code)


def struct_format(datatype: str, byte_order: str) -> str | None:
    """The :mod:`struct` format of one element as stored (None for the word-swapped orders)."""
    code = _known(datatype)
    if byte_order in _WORD_SWAPPED and int(code[1]) > 2:
        return None
    return _ORDERS[_order(byte_order)] + _STRUCT_CODES[code]


_STRUCT_CODES = {"u1": "B", "i1": "b", "u2": "H", "i2": "h", "u4": "I", "i4": "i", "u8": "Q", "i8": "q", "f2": "e",
                 "f4": "f", "f8": "d"}


def _order(byte_order: str) -> str:
    if byte_order not in _ORDERS:
        raise ConversionError(f"unknown byte order {byte_order!r}")
    return byte_order


def _swap_words(data: bytes | np.ndarray, size: int) -> np.ndarray:
    """Reverse the order of the 16-bit words inside every ``size``-byte element."""
    raw = np.frombuffer(bytes(data), np.uint8) if not isinstance(data, np.ndarray) else data.astype(np.uint8)
    return np.ascontiguousarray(raw.reshape(-1, size // 2, 2)[:, ::-1, :]).reshape(-1)


def decode(data: bytes, datatype: str, byte_order: str, count: int | None = None) -> np.ndarray:
    """``count`` elements (default: as many as ``data`` holds) as int64 / uint64 / float64.

    :raises ConversionError: unknown type or order, or fewer bytes than ``count`` elements need.
    """
    code = _known(datatype)
    size = int(code[1])
    count = len(data) // size if count is None else count
    if len(data) < count * size:
        raise ConversionError(f"{count} {datatype} need {count * size} bytes, {len(data)} given")
    stored = np.dtype(_ORDERS[_order(byte_order)] + code)
    raw = bytes(data[:count * size])
    if byte_order in _WORD_SWAPPED and size > 2:
        raw = _swap_words(raw, size).tobytes()
    return np.frombuffer(raw, stored, count).astype(_WIDE[code[0]])


def encode(values: np.ndarray, datatype: str, byte_order: str) -> bytes:
    """The bytes of ``values`` (already of the type's range, see :func:`to_datatype`), in memory order."""
    code = _known(datatype)
    size = int(code[1])
    stored = np.dtype(_ORDERS[_order(byte_order)] + code)
    data = np.asarray(values).astype(stored).tobytes()
    if byte_order in _WORD_SWAPPED and size > 2:
        data = _swap_words(data, size).tobytes()
    return data


def round_half_away(values: np.ndarray) -> np.ndarray:
    """Round to integers, halves away from zero (2.5 -> 3, -2.5 -> -3), exactly for every float64."""
    values = np.asarray(values, dtype=np.float64)
    magnitude = np.abs(values)
    whole = np.floor(magnitude)
    return np.copysign(whole + (magnitude - whole >= 0.5), values)


def to_datatype(raw, datatype: str, what: str = "") -> np.ndarray:
    """Raw values (unrounded numbers) made into the exact values ``datatype`` stores: integers
    rounded half away from zero and range-checked, floats checked not to overflow the type.

    :param what: names the object in errors (``"xsTHR"``).
    :raises ConversionError: a value (NaN, infinite, too large) the type cannot hold, named with the
        type's range.
    """
    code = _known(datatype)
    array = np.asarray(raw)
    prefix = f"{what}: " if what else ""
    if code[0] == "f":
        floats = array.astype(np.float64)
        with np.errstate(over="ignore"):
            stored = floats.astype(np.dtype(code))
        overflow = np.isinf(stored) & np.isfinite(floats)
        if overflow.any():
            bad = floats[overflow].ravel()[0]
            limit = float(np.finfo(np.dtype(code)).max)
            raise ConversionError(f"{prefix}{bad:g} does not fit {datatype} (largest {limit:g})")
        return stored.astype(np.float64)
    low, high = datatype_range(datatype)
    if array.dtype.kind in "iu":
        exact = array
        outside = (exact < low) | (exact > high)
    else:
        floats = array.astype(np.float64)
        if not np.isfinite(floats).all():
            bad = floats[~np.isfinite(floats)].ravel()[0]
            raise ConversionError(f"{prefix}{bad} cannot be stored as {datatype}")
        exact = round_half_away(floats)
        outside = (exact < float(low)) | (exact >= float(high + 1))  # both bounds are exact in float64
    if np.any(outside):
        bad = np.asarray(array)[outside].ravel()[0]
        raise ConversionError(f"{prefix}{_shown(bad)} does not fit {datatype} [{low}, {high}]")
    return exact.astype(_WIDE[code[0]])


def _shown(value) -> str:
    return f"{value:g}" if isinstance(value, (float, np.floating)) else str(value)


def mask_shift(mask: int) -> tuple[int, int]:
    """(shift, width): the BIT_MASK's lowest set bit and the number of bits from there to its highest."""
    if mask <= 0:
        raise ConversionError(f"BIT_MASK 0x{mask:X} selects no bit")
    shift = (mask & -mask).bit_length() - 1
    return shift, (mask >> shift).bit_length()


def signed(datatype: str) -> bool:
    return DATATYPES.get(datatype, (0, ""))[1] == "signed"


def extract_bits(raw: np.ndarray, mask: int, datatype: str,
                 bit_operation: tuple[int, int, bool] | None = None) -> np.ndarray:
    """The value of a bit field: ``raw & mask`` moved down to bit 0 (or, with a BIT_OPERATION
    ``(left_shift, right_shift, sign_extend)``, shifted as it says), sign-extended over the field's
    width for a signed data type (or SIGN_EXTEND). Works on 64-bit masks; returns int64 (uint64
    for a 64-bit unsigned field)."""
    bits = np.asarray(raw).astype(np.int64).view(np.uint64) if np.asarray(raw).dtype.kind == "i" else \
        np.asarray(raw).astype(np.uint64)
    field = bits & np.uint64(mask)
    if bit_operation is None:
        shift, width = mask_shift(mask)
        field = field >> np.uint64(shift)
        extend = signed(datatype)
    else:
        left, right, extend = bit_operation
        field = (field >> np.uint64(right)) << np.uint64(left)
        width = ((mask >> right) << left).bit_length()
    if extend and 0 < width < 64:
        sign_bit = np.uint64(1 << (width - 1))
        value = field.astype(np.int64)
        return np.where(field & sign_bit, value - np.int64(1 << (width - 1)) * 2, value)
    if width >= 64 and not signed(datatype):
        return field
    return field.astype(np.uint64).view(np.int64) if extend else field.astype(np.int64)


def insert_bits(old: np.ndarray, value: np.ndarray, mask: int, datatype: str, what: str = "") -> np.ndarray:
    """``old`` with the bits of ``mask`` replaced by ``value`` (the field's value, shifted up to the
    mask's lowest bit); the other bits stay. :raises ConversionError: ``value`` needs more bits
    than the mask has."""
    shift, width = mask_shift(mask)
    value = np.asarray(value).astype(np.int64)
    low, high = (-(1 << (width - 1)), (1 << (width - 1)) - 1) if signed(datatype) else (0, (1 << width) - 1)
    outside = (value < low) | (value > high)
    if outside.any():
        prefix = f"{what}: " if what else ""
        raise ConversionError(f"{prefix}{int(value[outside].ravel()[0])} does not fit its BIT_MASK 0x{mask:X} "
                              f"({width} bits: [{low}, {high}])")
    field = (value.view(np.uint64) << np.uint64(shift)) & np.uint64(mask)
    bits = np.asarray(old).astype(np.int64).view(np.uint64) if np.asarray(old).dtype.kind == "i" else \
        np.asarray(old).astype(np.uint64)
    merged = (bits & ~np.uint64(mask)) | field
    return merged.view(np.int64) if signed(datatype) or np.asarray(old).dtype.kind == "i" else merged
