"""A small, fast reader of DWARF 2-5 ``.debug_info``: global variables and the DIEs of their types.

pyelftools builds an object per DIE and attribute (about 15 us a DIE), too slow for
an ELF with 50,000 variables. This reader decodes only what the A2L tool chain
needs: one pass over the top-level DIEs of every unit (children are skipped through
DW_AT_sibling, or walked when a DIE lacks it) to list the global variables with their
address and type reference, and single DIEs on demand for types.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import NamedTuple
from workbench.progress import Progress, report

# tags
TAG_ARRAY, TAG_CLASS, TAG_ENUM, TAG_MEMBER, TAG_POINTER = 0x01, 0x02, 0x04, 0x0D, 0x0F
TAG_REFERENCE, TAG_STRUCT, TAG_SUBROUTINE_TYPE, TAG_TYPEDEF, TAG_UNION = 0x10, 0x13, 0x15, 0x16, 0x17
TAG_SUBRANGE, TAG_BASE, TAG_CONST, TAG_VARIABLE, TAG_VOLATILE = 0x21, 0x24, 0x26, 0x34, 0x35
TAG_RESTRICT, TAG_NAMESPACE, TAG_ATOMIC = 0x37, 0x39, 0x47

# attributes
AT_SIBLING, AT_LOCATION, AT_NAME, AT_BYTE_SIZE, AT_BIT_OFFSET, AT_BIT_SIZE = 0x01, 0x02, 0x03, 0x0B, 0x0C, 0x0D
AT_UPPER_BOUND, AT_ABSTRACT_ORIGIN, AT_COUNT, AT_MEMBER_LOCATION = 0x2F, 0x31, 0x37, 0x38
AT_DECLARATION, AT_ENCODING, AT_SPECIFICATION, AT_TYPE, AT_DATA_BIT_OFFSET = 0x3C, 0x3E, 0x47, 0x49, 0x6B

_VARIABLE_ATTRS = frozenset({AT_SIBLING, AT_NAME, AT_TYPE, AT_LOCATION, AT_SPECIFICATION, AT_ABSTRACT_ORIGIN,
                             AT_DECLARATION})
_SIBLING = frozenset({AT_SIBLING})

_OP_ADDR, _OP_PLUS_UCONST = 0x03, 0x23  # DW_OP_addrx is not read: see global_variables

_FIXED_SIZE = {0x0B: 1, 0x05: 2, 0x06: 4, 0x07: 8, 0x0C: 1, 0x11: 1, 0x12: 2, 0x13: 4, 0x14: 8, 0x1E: 16,
               0x20: 8, 0x25: 1, 0x26: 2, 0x27: 3, 0x28: 4, 0x29: 1, 0x2A: 2, 0x2B: 3, 0x2C: 4, 0x1C: 4, 0x24: 8}


class DwarfError(Exception):
    """The DWARF data is malformed or uses a form this reader does not know."""


@dataclass(frozen=True)
class Unit:
    offset: int  # of the unit header in .debug_info
    first_die: int
    end: int
    version: int
    address_size: int
    offset_size: int  # 4 (32-bit DWARF) or 8
    abbrev_offset: int


@dataclass(frozen=True)
class Die:
    offset: int
    tag: int
    attrs: dict[int, object]
    has_children: bool
    next_offset: int  # the first child when has_children, else the next sibling
    unit: Unit


class GlobalVariable(NamedTuple):
    name: str
    address: int | None  # None: no static location (optimised out, extern declaration only)
    type_offset: int | None  # DIE offset of its type in .debug_info


class DwarfReader:
    """Decodes DIEs from the raw DWARF sections of one ELF."""

    def __init__(self, sections: dict[str, bytes], little_endian: bool):
        self.info = sections.get(".debug_info", b"")
        self.abbrev = sections.get(".debug_abbrev", b"")
        self.strings = sections.get(".debug_str", b"")
        self.line_strings = sections.get(".debug_line_str", b"")
        self.str_offsets = sections.get(".debug_str_offsets", b"")
        self.addresses = sections.get(".debug_addr", b"")
        self.order = "<" if little_endian else ">"
        self._abbrev_tables: dict[int, dict[int, tuple[int, bool, tuple]]] = {}
        self._plan_cache: dict[tuple, dict[int, tuple[int, bool, tuple]]] = {}
        self.units = self._read_units()
        self._unit_starts = [unit.offset for unit in self.units]

    # -- units and abbreviations ---------------------------------------------------------
    def _read_units(self) -> list[Unit]:
        units = []
        data, order, offset = self.info, self.order, 0
        while offset + 11 <= len(data):
            (length,) = struct.unpack_from(order + "I", data, offset)
            offset_size, header = 4, offset + 4
            if length == 0xFFFFFFFF:
                (length,) = struct.unpack_from(order + "Q", data, header)
                offset_size, header = 8, header + 8
            end = header + length
            (version,) = struct.unpack_from(order + "H", data, header)
            position = header + 2
            if version >= 5:
                unit_type, address_size = data[position], data[position + 1]
                abbrev_offset = self._offset(data, position + 2, offset_size)
                position += 2 + offset_size
                if unit_type in (2, 6):  # type unit, split type unit: signature + type offset
                    position += 8 + offset_size
                elif unit_type in (4, 5):  # skeleton, split compile: dwo id
                    position += 8
            elif 2 <= version <= 4:
                abbrev_offset = self._offset(data, position, offset_size)
                address_size = data[position + offset_size]
                position += offset_size + 1
            else:
                raise DwarfError(f"unsupported DWARF version {version} in the unit at 0x{offset:x}")
            units.append(Unit(offset, position, end, version, address_size, offset_size, abbrev_offset))
            offset = end
        return units

    def _offset(self, data: bytes, position: int, size: int) -> int:
        return struct.unpack_from(self.order + ("I" if size == 4 else "Q"), data, position)[0]

    def _abbrevs(self, offset: int) -> dict[int, tuple[int, bool, tuple]]:
        table = self._abbrev_tables.get(offset)
        if table is not None:
            return table
        table = {}
        data, position = self.abbrev, offset
        while True:
            code, position = _uleb(data, position)
            if code == 0:
                break
            tag, position = _uleb(data, position)
            has_children = data[position] == 1
            position += 1
            specs = []
            while True:
                attr, position = _uleb(data, position)
                form, position = _uleb(data, position)
                implicit = None
                if form == 0x21:  # implicit_const: the value lives in the abbreviation
                    implicit, position = _sleb(data, position)
                if attr == 0 and form == 0:
                    break
                specs.append((attr, form, implicit))
            table[code] = (tag, has_children, tuple(specs))
        self._abbrev_tables[offset] = table
        return table

    def unit_of(self, die_offset: int) -> Unit:
        low, high = 0, len(self._unit_starts) - 1
        while low < high:  # the last unit starting at or before the offset
            middle = (low + high + 1) // 2
            if self._unit_starts[middle] <= die_offset:
                low = middle
            else:
                high = middle - 1
        return self.units[low]

    # -- DIEs -----------------------------------------------------------------------------
    def die(self, offset: int, unit: Unit | None = None) -> Die | None:
        """The DIE at ``offset`` (None for a null entry, which ends a list of children)."""
        unit = unit or self.unit_of(offset)
        code, position = _uleb(self.info, offset)
        if code == 0:
            return None
        try:
            tag, has_children, specs = self._abbrevs(unit.abbrev_offset)[code]
        except KeyError:
            raise DwarfError(f"unknown abbreviation {code} at .debug_info+0x{offset:x}") from None
        attrs: dict[int, object] = {}
        for attr, form, implicit in specs:
            value, position = self._read_form(form, position, unit, implicit)
            attrs[attr] = value
        return Die(offset, tag, attrs, has_children, position, unit)

    def children(self, die: Die) -> list[Die]:
        """The direct children of ``die``, in order."""
        if not die.has_children:
            return []
        found, offset = [], die.next_offset
        while offset < die.unit.end:
            child = self.die(offset, die.unit)
            if child is None:
                break
            found.append(child)
            offset = self._after(child)
        return found

    def _after(self, die: Die) -> int:
        """The offset of the DIE that follows ``die`` and all its descendants."""
        if not die.has_children:
            return die.next_offset
        sibling = die.attrs.get(AT_SIBLING)
        if isinstance(sibling, int) and sibling > die.offset:
            return sibling
        offset, depth = die.next_offset, 1
        while depth and offset < die.unit.end:
            child = self.die(offset, die.unit)
            if child is None:
                depth -= 1
                offset += 1
            elif child.has_children and isinstance(child.attrs.get(AT_SIBLING), int):
                offset = child.attrs[AT_SIBLING]
            else:
                depth += child.has_children
                offset = child.next_offset
        return offset

    def global_variables(self, progress: Progress | None = None) -> list[GlobalVariable]:
        """Every variable DIE at the top level of a unit (or namespace) that has a name.

        Definitions that only point at a declaration (DW_AT_specification) take the
        declaration's name and type. Reports progress in bytes of .debug_info. A location
        given as DW_OP_addrx (clang's DWARF 5, split DWARF) is not read: such a variable
        has no address here, and :class:`DebugData` takes it from ``.symtab`` (its type
        still comes from DWARF).
        """
        variables: list[GlobalVariable] = []
        total = len(self.info)
        for unit in self.units:
            report(progress, unit.offset, total, "reading DWARF")
            root = self.die(unit.first_die, unit)
            if root is None or not root.has_children:
                continue
            self._collect(root, variables)
        report(progress, total, total, "reading DWARF")
        return variables

    def _collect(self, parent: Die, variables: list[GlobalVariable]) -> None:
        """The variables among ``parent``'s children; other DIEs are skipped without decoding them."""
        unit = parent.unit
        plans = self._plans(unit)
        data, end, offset = self.info, unit.end, parent.next_offset
        while offset < end:
            code = data[offset]
            position = offset + 1
            if code >= 0x80:
                code, position = _uleb(data, offset)
            if code == 0:
                break
            try:
                tag, has_children, plan, prefix = plans[code]
            except KeyError:
                raise DwarfError(f"unknown abbreviation {code} at .debug_info+0x{offset:x}") from None
            if tag == TAG_NAMESPACE:
                die = self.die(offset, unit)
                if die.has_children:
                    self._collect(die, variables)
                offset = self._after(die)
                continue
            if tag == TAG_VARIABLE:
                attrs, position = self._decode(plan, position, unit, _VARIABLE_ATTRS, prefix)
            else:
                attrs, position = self._decode(plan, position, unit, _SIBLING)
            if tag == TAG_VARIABLE:
                variable = self._variable(attrs, unit, offset)
                if variable is not None:
                    variables.append(variable)
            sibling = attrs.get(AT_SIBLING)
            if not has_children:
                offset = position
            elif sibling is not None and sibling > offset:
                offset = sibling
            else:
                offset = self._after(self.die(offset, unit))

    def _plans(self, unit: Unit) -> dict[int, tuple[int, bool, tuple]]:
        """Per abbreviation: (tag, has children, ((attribute, form, bytes or -1 when variable), ...))."""
        key = (unit.abbrev_offset, unit.offset_size, unit.address_size, unit.version)
        plans = self._plan_cache.get(key)
        if plans is None:
            sizes = {0x0E: unit.offset_size, 0x1F: unit.offset_size, 0x17: unit.offset_size,
                     0x10: unit.address_size if unit.version == 2 else unit.offset_size,
                     0x01: unit.address_size, 0x19: 0, 0x21: 0, 0x1D: unit.offset_size}
            plans = {}
            for code, (tag, has_children, specs) in self._abbrevs(unit.abbrev_offset).items():
                steps = tuple((attr, form, _FIXED_SIZE.get(form, sizes.get(form, -1))) for attr, form, _ in specs)
                prefix = _fixed_prefix(specs, steps, _VARIABLE_ATTRS, self.order) if tag == TAG_VARIABLE else None
                plans[code] = (tag, has_children, steps, prefix)
            self._plan_cache[key] = plans
        return plans

    def _decode(self, plan: tuple, position: int, unit: Unit, wanted: frozenset, prefix=None) -> tuple[dict, int]:
        """Decode the ``wanted`` attributes of one DIE and step over the others; returns them and the
        offset after the attributes. ``prefix`` (see :func:`_fixed_prefix`) reads the leading
        fixed-size attributes with one ``struct`` call."""
        data = self.info
        attrs = {}
        if prefix is not None:
            layout, fields, count = prefix
            for (attr, kind, constant), value in zip(fields, layout.unpack_from(data, position)
                                                     if layout.size else ()):
                attrs[attr] = value
            for attr, kind, constant in fields:
                if kind == "strp":
                    attrs[attr] = _cstring(self.strings, attrs[attr])
                elif kind == "line_strp":
                    attrs[attr] = _cstring(self.line_strings, attrs[attr])
                elif kind == "ref":
                    attrs[attr] += unit.offset
                elif kind == "constant":
                    attrs[attr] = constant
            position += layout.size
            plan = plan[count:]
        for attr, form, size in plan:
            if attr in wanted:
                attrs[attr], position = self._read_form(form, position, unit, None)
            elif size >= 0:
                position += size
            elif form in (0x18, 0x09):  # exprloc, block: uleb length
                length, position = _uleb(data, position)
                position += length
            elif form == 0x0A:
                position += 1 + data[position]
            elif form == 0x08:
                position = data.index(b"\0", position) + 1
            else:
                _, position = self._read_form(form, position, unit, None)
        return attrs, position

    def _variable(self, attrs: dict, unit: Unit, offset: int) -> GlobalVariable | None:
        name, type_offset = attrs.get(AT_NAME), attrs.get(AT_TYPE)
        spec = attrs.get(AT_SPECIFICATION) or attrs.get(AT_ABSTRACT_ORIGIN)
        if isinstance(spec, int) and (name is None or type_offset is None):
            declaration = self.die(spec)
            if declaration is not None:
                name = name or declaration.attrs.get(AT_NAME)
                type_offset = type_offset or declaration.attrs.get(AT_TYPE)
        if not isinstance(name, str):
            return None
        address = static_address(attrs.get(AT_LOCATION), unit.address_size, self.order)
        if address is None and attrs.get(AT_DECLARATION):
            return None
        return GlobalVariable(name, address, type_offset if isinstance(type_offset, int) else None)

    # -- forms ----------------------------------------------------------------------------
    def _read_form(self, form: int, position: int, unit: Unit, implicit) -> tuple[object, int]:
        data = self.info
        size = _FIXED_SIZE.get(form)
        if size is not None:
            if form in (0x11, 0x12, 0x13, 0x14):  # ref1/2/4/8: unit relative
                return unit.offset + int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
            if form in (0x25, 0x26, 0x27, 0x28):  # strx1-4
                index = int.from_bytes(data[position : position + size], _BYTEORDER[self.order])
                return self._indexed_string(index, unit), position + size
            if form in (0x1E, 0x20):  # data16, ref_sig8: opaque
                return data[position : position + size], position + size
            return int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
        if form == 0x0E:  # strp
            offset = self._offset(data, position, unit.offset_size)
            return _cstring(self.strings, offset), position + unit.offset_size
        if form == 0x1F:  # line_strp
            offset = self._offset(data, position, unit.offset_size)
            return _cstring(self.line_strings, offset), position + unit.offset_size
        if form == 0x08:  # string
            end = data.index(b"\0", position)
            return data[position:end].decode("utf-8", "replace"), end + 1
        if form == 0x0F:  # udata
            return _uleb(data, position)
        if form == 0x0D:  # sdata
            return _sleb(data, position)
        if form == 0x15:  # ref_udata
            value, position = _uleb(data, position)
            return unit.offset + value, position
        if form in (0x10, 0x17):  # ref_addr, sec_offset
            size = unit.address_size if form == 0x10 and unit.version == 2 else unit.offset_size
            return self._offset(data, position, size) if size in (4, 8) else \
                int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
        if form == 0x01:  # addr
            size = unit.address_size
            return int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
        if form in (0x18, 0x09):  # exprloc, block
            length, position = _uleb(data, position)
            return data[position : position + length], position + length
        if form == 0x0A:  # block1
            length = data[position]
            return data[position + 1 : position + 1 + length], position + 1 + length
        if form in (0x03, 0x04):  # block2, block4
            width = 2 if form == 0x03 else 4
            length = int.from_bytes(data[position : position + width], _BYTEORDER[self.order])
            start = position + width
            return data[start : start + length], start + length
        if form == 0x19:  # flag_present
            return True, position
        if form == 0x21:  # implicit_const
            return implicit, position
        if form in (0x1A, 0x1B, 0x22, 0x23, 0x1F02, 0x1F01):  # strx, addrx, loclistx, rnglistx (uleb index)
            index, position = _uleb(data, position)
            return (self._indexed_string(index, unit) if form in (0x1A, 0x1F02) else index), position
        if form in (0x1D, 0x1F20, 0x1F21):  # strp_sup, GNU_ref_alt, GNU_strp_alt: another file
            return None, position + unit.offset_size
        if form == 0x16:  # indirect
            actual, position = _uleb(data, position)
            return self._read_form(actual, position, unit, implicit)
        raise DwarfError(f"unknown DWARF form 0x{form:x} at .debug_info+0x{position:x}")

    def _indexed_string(self, index: int, unit: Unit) -> str | None:
        # DW_AT_str_offsets_base defaults to just after the first .debug_str_offsets header
        base = 8 if unit.offset_size == 4 else 16
        position = base + index * unit.offset_size
        if position + unit.offset_size > len(self.str_offsets):
            return None
        return _cstring(self.strings, self._offset(self.str_offsets, position, unit.offset_size))


_BYTEORDER = {"<": "little", ">": "big"}
_STRUCT_CODES = {1: "B", 2: "H", 4: "I", 8: "Q"}


def _fixed_prefix(specs: tuple, steps: tuple, wanted: frozenset, order: str):
    """How to read the leading fixed-size attributes of an abbreviation with one ``struct`` call:
    (Struct, [(attribute, kind, constant)] of the wanted ones in order, steps covered); None when
    the first attribute already has a variable size."""
    codes, fields, count = [], [], 0
    for (attr, form, implicit), (_, _, size) in zip(specs, steps):
        if size < 0 or form in (0x1E, 0x20, 0x25, 0x26, 0x27, 0x28):  # data16, ref_sig8, strx1-4: leave
            break
        count += 1
        if attr not in wanted:
            codes.append(f"{size}x" if size else "")
            continue
        if size == 0:  # flag_present, implicit_const: the value is in the abbreviation
            fields.append((attr, "constant", True if form == 0x19 else implicit))
            continue
        if size not in _STRUCT_CODES:
            return None if not count - 1 else _finish(codes, fields, count - 1, order)
        kind = {0x0E: "strp", 0x1F: "line_strp", 0x11: "ref", 0x12: "ref", 0x13: "ref", 0x14: "ref"}.get(form, "int")
        codes.append(_STRUCT_CODES[size])
        fields.append((attr, kind, None))
    return _finish(codes, fields, count, order) if count else None


def _finish(codes: list[str], fields: list, count: int, order: str):
    # struct-decoded fields first (in order), then the constants, matching the unpack order
    decoded = [f for f in fields if f[1] != "constant"]
    constants = [f for f in fields if f[1] == "constant"]
    return struct.Struct(order + "".join(codes)), decoded + constants, count


def static_address(location: object, address_size: int, order: str) -> int | None:
    """The address of a DW_AT_location that is a single DW_OP_addr, else None."""
    if isinstance(location, (bytes, bytearray)) and len(location) == 1 + address_size and location[0] == _OP_ADDR:
        return int.from_bytes(location[1:], _BYTEORDER[order])
    return None


def member_offset(value: object) -> int | None:
    """DW_AT_data_member_location: a constant, or DW_OP_plus_uconst n."""
    if isinstance(value, int):
        return value
    if isinstance(value, (bytes, bytearray)) and value[:1] == bytes([_OP_PLUS_UCONST]):
        return _uleb(value, 1)[0]
    return None


def _uleb(data: bytes, position: int) -> tuple[int, int]:
    byte = data[position]
    if byte < 0x80:
        return byte, position + 1
    result, shift = 0, 0
    while True:
        byte = data[position]
        position += 1
        result |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return result, position


def _sleb(data: bytes, position: int) -> tuple[int, int]:
    value, end = _uleb(data, position)
    if data[end - 1] & 0x40:  # the sign bit of the last byte
        value -= 1 << (7 * (end - position))
    return value, end


def _cstring(section: bytes, offset: int) -> str:
    end = section.find(b"\0", offset)
    return section[offset : end if end >= 0 else len(section)].decode("utf-8", "replace")

