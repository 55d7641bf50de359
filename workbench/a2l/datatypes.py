"""ASAP2 data types: their sizes and ranges, and which one a C type needs."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from workbench.elf.ctypes_model import CMember, CType

__all__ = ["DATATYPES", "array_dims", "c_limits", "datatype_for", "datatype_range", "element_type", "member_at"]

# data type -> (size in bytes, encoding)
DATATYPES: dict[str, tuple[int, str]] = {
    "UBYTE": (1, "unsigned"), "SBYTE": (1, "signed"), "UWORD": (2, "unsigned"), "SWORD": (2, "signed"),
    "ULONG": (4, "unsigned"), "SLONG": (4, "signed"), "A_UINT64": (8, "unsigned"), "A_INT64": (8, "signed"),
    "FLOAT16_IEEE": (2, "float"), "FLOAT32_IEEE": (4, "float"), "FLOAT64_IEEE": (8, "float"),
}
_BY_SIZE_AND_ENCODING = {value: key for key, value in DATATYPES.items()}


def datatype_for(ctype: "CType") -> str | None:
    """The ASAP2 data type of a scalar C type (arrays: of their element), None for structs and the like."""
    ctype = element_type(ctype)
    if ctype.kind not in ("base", "enum", "pointer"):
        return None
    encoding = {"bool": "unsigned", "address": "unsigned"}.get(ctype.encoding or "unsigned", ctype.encoding)
    return _BY_SIZE_AND_ENCODING.get((ctype.size, encoding))


def datatype_range(datatype: str) -> tuple[float, float] | None:
    """The values an integer data type can hold (None for floats and unknown names)."""
    found = DATATYPES.get(datatype)
    if found is None or found[1] == "float":
        return None
    size, encoding = found
    bits = 8 * size
    return (0, 2**bits - 1) if encoding == "unsigned" else (-(2 ** (bits - 1)), 2 ** (bits - 1) - 1)


# the largest finite value of each float data type
_FLOAT_MAX = {"FLOAT16_IEEE": 65504.0, "FLOAT32_IEEE": 3.4028234663852886e38, "FLOAT64_IEEE": 1.7976931348623157e308}


def c_limits(ctype: "CType", bit_size: int | None = None) -> tuple[int | float, int | float] | None:
    """The values a C scalar (arrays: their element) can hold, as a2ltool gives them an object it inserts:
    an enum's lowest and highest enumerator, a bitfield's range by its width, else its data type's range
    (a float's largest finite values); None for a type without data type."""
    element = element_type(ctype)
    datatype = datatype_for(element)
    if datatype is None:
        return None
    if element.kind == "enum" and element.enumerators:
        values = [value for _, value in element.enumerators]
        return min(values), max(values)
    if bit_size:
        signed = DATATYPES[datatype][1] == "signed"
        return (-(1 << (bit_size - 1)), (1 << (bit_size - 1)) - 1) if signed else (0, (1 << bit_size) - 1)
    if datatype in _FLOAT_MAX:
        return -_FLOAT_MAX[datatype], _FLOAT_MAX[datatype]
    return datatype_range(datatype)


def array_dims(ctype: "CType") -> tuple[int, ...]:
    """All dimensions of a (possibly nested) C array, outermost first; () for a scalar."""
    dims: tuple[int, ...] = ()
    while ctype.kind == "array" and ctype.element is not None:
        dims += ctype.dims
        ctype = ctype.element
    return dims


def element_type(ctype: "CType") -> "CType":
    """The element of a (possibly nested) C array; the type itself for a scalar."""
    while ctype.kind == "array" and ctype.element is not None:
        ctype = ctype.element
    return ctype


def member_at(ctype: "CType", position: int) -> "CMember | None":
    """What a RECORD_LAYOUT item at ``position`` holds of a variable of this C type, as a2ltool reads it:
    a struct's member number ``position`` (counted from 1), else the variable itself at position 1 (or 0)."""
    from workbench.elf.ctypes_model import CMember  # here: this module is read without the ELF reader

    if ctype.kind == "struct":
        return ctype.members[position - 1] if 1 <= position <= len(ctype.members) else None
    return CMember("", 0, ctype) if position in (0, 1) else None
