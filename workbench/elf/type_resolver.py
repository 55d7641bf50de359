"""C and C++ types read from DWARF: :class:`TypeResolver` turns a type DIE into a
:class:`~workbench.elf.ctypes_model.CType`, looking through typedefs and const/volatile qualifiers
(remembering the outermost typedef name), type units (DW_AT_signature) and declarations (to the
definition another unit holds). Pointers are not followed, so self-referencing structs are finite.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from workbench.elf import dwarf
from workbench.elf.ctypes_model import VOID, CMember, CType

__all__ = ["TypeResolver"]

_ENCODINGS = {0x01: "address", 0x02: "bool", 0x04: "float", 0x05: "signed", 0x06: "signed",
              0x07: "unsigned", 0x08: "unsigned", 0x10: "unsigned"}  # 0x06/0x08: (un)signed char, 0x10: UTF


class TypeResolver:
    """Builds :class:`CType` objects from DWARF, memoised by DIE offset."""

    def __init__(self, reader: dwarf.DwarfReader, cache: dict[int, CType] | None = None,
                 definitions: Callable[[dwarf.Die], int | None] | None = None):
        self.reader = reader
        self.definitions = definitions  # declaration DIE -> offset of its definition (see DwarfIndex.definition_of)
        self.cache: dict[int, CType] = cache if cache is not None else {}
        self._building: set[int] = set()

    def resolve(self, offset: int | None) -> CType:
        """The type whose DIE is at ``offset``; raises :class:`dwarf.DwarfError` for a type that contains
        itself (only damaged DWARF does: pointers, the one legal way back, are not followed)."""
        if offset is None:
            return VOID
        found = self.cache.get(offset)
        if found is None:
            if offset in self._building:
                raise dwarf.DwarfError(f"the type at .debug_info+0x{offset:x} contains itself")
            self._building.add(offset)
            try:
                found = self._build(offset)
            finally:
                self._building.discard(offset)
            self.cache[offset] = found
        return found

    def _build(self, offset: int) -> CType:
        die = self.reader.die(offset)
        if die is None:
            return VOID
        attrs, tag = die.attrs, die.tag
        name = attrs.get(dwarf.AT_NAME)
        name = name if isinstance(name, str) else None
        if tag == dwarf.TAG_TYPEDEF:
            target = self.resolve(attrs.get(dwarf.AT_TYPE))
            return replace(target, typedef=name)
        if tag in (dwarf.TAG_CONST, dwarf.TAG_VOLATILE, dwarf.TAG_RESTRICT, dwarf.TAG_ATOMIC):
            return self.resolve(attrs.get(dwarf.AT_TYPE))
        size = attrs.get(dwarf.AT_BYTE_SIZE)
        size = size if isinstance(size, int) else 0
        if tag == dwarf.TAG_BASE:
            return CType("base", size, name, _ENCODINGS.get(attrs.get(dwarf.AT_ENCODING), "unsigned"))
        if tag == dwarf.TAG_ENUM:
            underlying = attrs.get(dwarf.AT_TYPE)
            encoding = self.resolve(underlying).encoding if underlying is not None else "unsigned"
            encoding = encoding or "unsigned"
            return CType("enum", size, name, encoding, enumerators=self._enumerators(die, size, encoding == "signed"))
        if tag in (dwarf.TAG_POINTER, dwarf.TAG_REFERENCE):
            return CType("pointer", size or die.unit.address_size, name, "address")
        if tag == dwarf.TAG_SUBROUTINE_TYPE:
            return CType("function", 0, name)
        if tag in (dwarf.TAG_STRUCT, dwarf.TAG_UNION, dwarf.TAG_CLASS):
            return self._record(die, name, size)
        if tag == dwarf.TAG_ARRAY:
            return self._array(die)
        return CType("void", size, name)

    def _record(self, die: dwarf.Die, name: str | None, size: int) -> CType:
        """A struct, class or union; a declaration is followed to its type unit or its definition."""
        attrs = die.attrs
        if attrs.get(dwarf.AT_DECLARATION):
            signed = attrs.get(dwarf.AT_SIGNATURE)
            definition = signed if isinstance(signed, int) else (
                self.definitions(die) if self.definitions is not None else None)
            if definition is not None and definition != die.offset:
                return self.resolve(definition)
            return CType("union" if die.tag == dwarf.TAG_UNION else "struct", size, name, declared_only=True)
        members, bases = [], []
        for child in self.reader.children(die):
            if child.tag == dwarf.TAG_MEMBER and not child.attrs.get(dwarf.AT_DECLARATION):  # not a static member
                members.append(self._member(child, size))
            elif child.tag == dwarf.TAG_INHERITANCE:
                bases.append(self._base(child))
        kind = "union" if die.tag == dwarf.TAG_UNION else "struct"
        return CType(kind, size, name, members=tuple(members), bases=tuple(bases))

    def _enumerators(self, die: dwarf.Die, size: int, signed: bool) -> tuple[tuple[str, int], ...]:
        """(name, value) of an enum's enumerators; of a signed enum, a value stored as unsigned data of
        the enum's size with its high bit set is the negative one."""
        found = []
        for child in self.reader.children(die):
            name, value = child.attrs.get(dwarf.AT_NAME), child.attrs.get(dwarf.AT_CONST_VALUE)
            if child.tag == dwarf.TAG_ENUMERATOR and isinstance(name, str) and isinstance(value, int):
                if signed and size and 1 << (8 * size - 1) <= value < 1 << (8 * size):
                    value -= 1 << (8 * size)
                found.append((name, value))
        return tuple(found)

    def _base(self, die: dwarf.Die) -> CMember:
        base = self.resolve(die.attrs.get(dwarf.AT_TYPE))
        location = die.attrs.get(dwarf.AT_MEMBER_LOCATION)
        virtual = die.attrs.get(dwarf.AT_VIRTUALITY)
        offset = None if virtual else (dwarf.member_offset(location) if location is not None else 0)
        return CMember(base.display_name, offset, base)

    def _array(self, die: dwarf.Die) -> CType:
        element = self.resolve(die.attrs.get(dwarf.AT_TYPE))
        dims = []
        for child in self.reader.children(die):
            if child.tag != dwarf.TAG_SUBRANGE:
                continue
            count = child.attrs.get(dwarf.AT_COUNT)
            upper = child.attrs.get(dwarf.AT_UPPER_BOUND)
            if isinstance(count, int):
                dims.append(count)
            elif isinstance(upper, int):
                dims.append(upper + 1)
            else:
                dims.append(0)  # flexible array member
        dims = dims or [0]
        total = element.size
        for dim in dims:
            total *= dim
        return CType("array", total, element=element, dims=tuple(dims))

    def _member(self, die: dwarf.Die, record_size: int) -> CMember:
        attrs = die.attrs
        name = attrs.get(dwarf.AT_NAME)
        member_type = self.resolve(attrs.get(dwarf.AT_TYPE))
        offset = dwarf.member_offset(attrs.get(dwarf.AT_MEMBER_LOCATION))
        bit_size = attrs.get(dwarf.AT_BIT_SIZE)
        if not isinstance(bit_size, int):
            return CMember(name if isinstance(name, str) else "", offset or 0, member_type)
        declared = attrs.get(dwarf.AT_BYTE_SIZE)
        storage = member_type.size or declared or 1  # the unit read is of the member's type (the A2L's data type)
        big_endian = self.reader.order == ">"
        data_bit_offset = attrs.get(dwarf.AT_DATA_BIT_OFFSET)
        if isinstance(data_bit_offset, int):  # DWARF 4+: bits from the start of the struct, in memory order
            first, unit = data_bit_offset, None
        else:  # DWARF 2/3: DW_AT_bit_offset counts from the MSB of the DW_AT_byte_size unit at the member offset
            unit, counted_in = offset or 0, declared or storage
            bit_offset = attrs.get(dwarf.AT_BIT_OFFSET) or 0
            first = 8 * unit + (bit_offset if big_endian else 8 * counted_in - bit_offset - bit_size)
            unit = unit if counted_in == storage else None
        start, position = _storage_unit(first, bit_size, storage, unit, record_size, big_endian)
        return CMember(name if isinstance(name, str) else "", start, member_type, bit_size, position)


def _storage_unit(first: int, bit_size: int, storage: int, unit: int | None, record_size: int,
                  big_endian: bool) -> tuple[int, int]:
    """(byte offset, lowest bit in the value) of the ``storage``-byte unit a bitfield is read through, whose
    first bit in memory order (from the LSB of byte 0 on little-endian targets, from the MSB on big-endian
    ones) is ``first``: the aligned unit when the field lies inside it, else the producer's (``unit``, DWARF
    2/3; m68k's gcc aligns 32-bit units to 2 bytes), else the one starting at the field's first byte or
    ending at its last (a packed struct's field across an aligned boundary), preferring one inside the
    struct of ``record_size`` bytes. A field that no unit of ``storage`` bytes holds gets a position
    outside the unit (``update --types`` reports it)."""
    candidates = [first // (8 * storage) * storage, unit, first // 8, (first + bit_size - 1) // 8 + 1 - storage]
    holding = [start for start in candidates
               if start is not None and 0 <= first - 8 * start <= 8 * storage - bit_size] or [first // 8]
    inside = [start for start in holding if 0 <= start and start + storage <= record_size]
    start = (inside or holding)[0]
    within = first - 8 * start
    return start, 8 * storage - within - bit_size if big_endian else within
