"""A small, fast reader of DWARF 2-5 ``.debug_info``: DIEs, attribute forms and static locations.

pyelftools builds an object per DIE and attribute (about 15 us a DIE), too slow for
an ELF with 50,000 variables. This reader decodes single DIEs on demand and gives
:mod:`workbench.elf.dwarf_index` what it needs for its fast pass over the units.

DWARF 5 as clang and newer gcc write it is read here: strings through
``.debug_str_offsets`` (DW_FORM_strx*, from each unit's DW_AT_str_offsets_base),
addresses through ``.debug_addr`` (DW_FORM_addrx*, DW_OP_addrx, from DW_AT_addr_base),
``.debug_line_str``, DW_FORM_implicit_const, and type units, both DWARF 5's (in
``.debug_info``) and DWARF 4's ``.debug_types`` (appended behind ``.debug_info`` here,
so every DIE keeps one integer offset); DW_FORM_ref_sig8 reads as the offset of the
signed type's DIE. (pyelftools 0.33 resolves strx/addrx forms too, but neither
DW_OP_addrx in a location nor DWARF 5 type units.)
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Iterator
from typing import NamedTuple

__all__ = ["AT_ABSTRACT_ORIGIN", "AT_BIT_OFFSET", "AT_BIT_SIZE", "AT_BYTE_SIZE", "AT_CONST_VALUE", "AT_COUNT",
           "AT_DATA_BIT_OFFSET", "AT_DECLARATION", "AT_ENCODING", "AT_EXTERNAL", "AT_LOCATION", "AT_MEMBER_LOCATION",
           "AT_NAME", "AT_SIBLING", "AT_SIGNATURE", "AT_SPECIFICATION", "AT_TYPE", "AT_UPPER_BOUND", "AT_VIRTUALITY",
           "DECODED_FORMS", "OP_ADDR", "TAG_ARRAY", "TAG_ATOMIC", "TAG_BASE", "TAG_CLASS", "TAG_CONST", "TAG_ENUM",
           "TAG_ENUMERATOR", "TAG_INHERITANCE", "TAG_INLINED_SUBROUTINE", "TAG_LEXICAL_BLOCK", "TAG_MEMBER",
           "TAG_NAMESPACE", "TAG_POINTER", "TAG_REFERENCE", "TAG_RESTRICT", "TAG_STRUCT", "TAG_SUBPROGRAM",
           "TAG_SUBRANGE", "TAG_SUBROUTINE_TYPE", "TAG_TYPEDEF", "TAG_UNION", "TAG_VARIABLE", "TAG_VOLATILE",
           "VARIABLE_ATTRS", "Die", "DwarfError", "DwarfReader", "Unit", "cstring", "member_offset", "uleb"]

# tags
TAG_ARRAY, TAG_CLASS, TAG_ENUM, TAG_LEXICAL_BLOCK, TAG_MEMBER, TAG_POINTER = 0x01, 0x02, 0x04, 0x0B, 0x0D, 0x0F
TAG_REFERENCE, TAG_COMPILE_UNIT, TAG_STRUCT, TAG_SUBROUTINE_TYPE, TAG_TYPEDEF = 0x10, 0x11, 0x13, 0x15, 0x16
TAG_UNION, TAG_INHERITANCE, TAG_INLINED_SUBROUTINE, TAG_ENUMERATOR = 0x17, 0x1C, 0x1D, 0x28
TAG_SUBRANGE, TAG_BASE, TAG_CONST, TAG_SUBPROGRAM, TAG_VARIABLE, TAG_VOLATILE = 0x21, 0x24, 0x26, 0x2E, 0x34, 0x35
TAG_RESTRICT, TAG_NAMESPACE, TAG_PARTIAL_UNIT, TAG_TYPE_UNIT, TAG_ATOMIC = 0x37, 0x39, 0x3C, 0x41, 0x47

# attributes
AT_SIBLING, AT_LOCATION, AT_NAME, AT_BYTE_SIZE, AT_BIT_OFFSET, AT_BIT_SIZE = 0x01, 0x02, 0x03, 0x0B, 0x0C, 0x0D
AT_LANGUAGE, AT_CONST_VALUE, AT_UPPER_BOUND, AT_ABSTRACT_ORIGIN, AT_COUNT = 0x13, 0x1C, 0x2F, 0x31, 0x37
AT_MEMBER_LOCATION = 0x38
AT_DECLARATION, AT_ENCODING, AT_EXTERNAL, AT_SPECIFICATION, AT_TYPE = 0x3C, 0x3E, 0x3F, 0x47, 0x49
AT_VIRTUALITY, AT_SIGNATURE, AT_DATA_BIT_OFFSET, AT_STR_OFFSETS_BASE, AT_ADDR_BASE = 0x4C, 0x69, 0x6B, 0x72, 0x73
AT_GNU_ADDR_BASE = 0x2133

# what a variable's DIE is decoded for (see DwarfReader.scan)
VARIABLE_ATTRS = frozenset({AT_SIBLING, AT_NAME, AT_TYPE, AT_LOCATION, AT_SPECIFICATION, AT_ABSTRACT_ORIGIN,
                            AT_DECLARATION, AT_EXTERNAL})
_SIBLING = frozenset({AT_SIBLING})

# DW_OP codes of the static locations read here
OP_ADDR, _OP_CONSTU, _OP_PLUS, _OP_PLUS_UCONST, _OP_ADDRX, _OP_GNU_ADDR_INDEX = 0x03, 0x10, 0x22, 0x23, 0xA1, 0xFB

_FIXED_SIZE = {0x0B: 1, 0x05: 2, 0x06: 4, 0x07: 8, 0x0C: 1, 0x11: 1, 0x12: 2, 0x13: 4, 0x14: 8, 0x1E: 16,
               0x20: 8, 0x25: 1, 0x26: 2, 0x27: 3, 0x28: 4, 0x29: 1, 0x2A: 2, 0x2B: 3, 0x2C: 4, 0x1C: 4, 0x24: 8}


class DwarfError(Exception):
    """The DWARF data is malformed or uses a form this reader does not know."""


class Unit(NamedTuple):
    offset: int  # of the unit header in .debug_info
    first_die: int
    end: int
    version: int
    address_size: int
    offset_size: int  # 4 (32-bit DWARF) or 8
    abbrev_offset: int
    type_signature: int | None = None  # type units: the signature DW_FORM_ref_sig8 refers to


class Die(NamedTuple):
    offset: int
    tag: int
    attrs: dict[int, object]
    has_children: bool
    next_offset: int  # the first child when has_children, else the next sibling
    unit: Unit


class DwarfReader:
    """Decodes DIEs from the raw DWARF sections of one ELF."""

    def __init__(self, sections: dict[str, bytes], little_endian: bool):
        info, types = sections.get(".debug_info", b""), sections.get(".debug_types", b"")
        self.info = info + types  # one offset space: .debug_types units start at len(.debug_info)
        self.abbrev = sections.get(".debug_abbrev", b"")
        self.strings = sections.get(".debug_str", b"")
        self.line_strings = sections.get(".debug_line_str", b"")
        self.str_offsets = sections.get(".debug_str_offsets", b"")
        self.addresses = sections.get(".debug_addr", b"")
        self.order = "<" if little_endian else ">"
        self._abbrev_tables: dict[int, dict[int, tuple[int, bool, tuple]]] = {}
        self._plan_cache: dict[tuple, dict[int, tuple[int, bool, tuple]]] = {}
        self._bases: dict[int, tuple[int, int]] = {}  # unit offset -> (str_offsets_base, addr_base)
        self._type_dies: dict[int, int] = {}  # type unit offset -> offset of its type's DIE
        self.units = self._read_units(0, len(info), False) + self._read_units(len(info), len(self.info), True)
        self._unit_starts = [unit.offset for unit in self.units]
        # type signature -> offset of the type's DIE (DW_FORM_ref_sig8)
        self.signatures: dict[int, int] = {}
        for unit in self.units:
            if unit.type_signature is not None:
                self.signatures.setdefault(unit.type_signature, self._type_dies[unit.offset])

    # -- units and abbreviations ---------------------------------------------------------
    def _read_units(self, offset: int, stop: int, debug_types: bool) -> list[Unit]:
        """The unit headers between ``offset`` and ``stop``; ``debug_types``: DWARF 4 type units."""
        units = []
        data, order = self.info, self.order
        while offset + 11 <= stop:
            (length,) = struct.unpack_from(order + "I", data, offset)
            offset_size, header = 4, offset + 4
            if length == 0xFFFFFFFF:
                (length,) = struct.unpack_from(order + "Q", data, header)
                offset_size, header = 8, header + 8
            end = header + length
            (version,) = struct.unpack_from(order + "H", data, header)
            position = header + 2
            signature = type_die = None
            if version >= 5:
                unit_type, address_size = data[position], data[position + 1]
                abbrev_offset = self._offset(data, position + 2, offset_size)
                position += 2 + offset_size
                if unit_type in (2, 6):  # type unit, split type unit: signature + type offset
                    (signature,) = struct.unpack_from(order + "Q", data, position)
                    type_die = offset + self._offset(data, position + 8, offset_size)
                    position += 8 + offset_size
                elif unit_type in (4, 5):  # skeleton, split compile: dwo id
                    position += 8
            elif 2 <= version <= 4:
                abbrev_offset = self._offset(data, position, offset_size)
                address_size = data[position + offset_size]
                position += offset_size + 1
                if debug_types:
                    (signature,) = struct.unpack_from(order + "Q", data, position)
                    type_die = offset + self._offset(data, position + 8, offset_size)
                    position += 8 + offset_size
            else:
                raise DwarfError(f"unsupported DWARF version {version} in the unit at 0x{offset:x}")
            units.append(Unit(offset, position, end, version, address_size, offset_size, abbrev_offset, signature))
            if type_die is not None:
                self._type_dies[offset] = type_die
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
            code, position = uleb(data, position)
            if code == 0:
                break
            tag, position = uleb(data, position)
            has_children = data[position] == 1
            position += 1
            specs = []
            while True:
                attr, position = uleb(data, position)
                form, position = uleb(data, position)
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
        code, position = uleb(self.info, offset)
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
            offset = self.after(child)
        return found

    def after(self, die: Die) -> int:
        """The offset of the DIE that follows ``die`` and all its descendants."""
        if not die.has_children:
            return die.next_offset
        sibling = die.attrs.get(AT_SIBLING)
        if isinstance(sibling, int) and sibling > die.offset:
            return sibling
        return self._skip_subtree(die.next_offset, die.unit)

    def scan(self, unit: Unit, descend: frozenset[int], collect: frozenset[int], wanted: frozenset[int],
             within: frozenset[int] | None = None, note: frozenset[int] = frozenset(), start: int | None = None
             ) -> Iterator[tuple[str, int, int, dict]]:
        """Walk the DIE tree of ``unit`` in order, fast: yields ("enter", offset, tag, attrs) for a DIE of
        a tag in ``descend`` that has children (then its children, then ("leave", offset, tag, {})), and
        ("item", offset, tag, attrs) for a DIE of a tag in ``collect`` (with ``within``: only inside a DIE
        of one of those tags); a variable DIE collected for :data:`VARIABLE_ATTRS` comes as a tuple in
        :data:`~workbench.elf.die_readers.VARIABLE_FIELDS` order instead of a dict. Only the
        ``wanted`` attributes are decoded; every other DIE is stepped over with its subtree, through
        DW_AT_sibling or, where the producer left it out (clang), by stepping over each descendant's
        attributes; before stepping over a DIE with children of a tag in ``note``, ("note", offset, tag,
        None) is yielded. ``start``: walk only the DIE at that offset (and its subtree)."""
        root = self.die(unit.first_die, unit)
        if root is None or not root.has_children:
            return
        plans = self._plans(unit)
        data, end, offset = self.info, unit.end, root.next_offset if start is None else start
        open_scopes: list[tuple[int, int]] = []
        inside = 0 if within is not None else 1  # open DIEs of a ``within`` tag
        while offset < end:
            if start is not None and offset != start and not open_scopes:
                return  # the DIE at ``start`` is done
            code = data[offset]
            position = offset + 1
            if code >= 0x80:
                code, position = uleb(data, offset)
            if code == 0:
                if not open_scopes:
                    return
                scope_offset, scope_tag = open_scopes.pop()
                if within is not None and scope_tag in within:
                    inside -= 1
                yield "leave", scope_offset, scope_tag, {}
                offset = position
                continue
            try:
                tag, has_children, plan, variable_reader, skip = plans[code]
            except KeyError:
                raise DwarfError(f"unknown abbreviation {code} at .debug_info+0x{offset:x}") from None
            if tag in descend and has_children:
                attrs, position = self._decode(plan, position, unit, wanted)
                yield "enter", offset, tag, attrs
                open_scopes.append((offset, tag))
                if within is not None and tag in within:
                    inside += 1
                offset = position
                continue
            if inside and tag in collect:
                if variable_reader is not None and wanted is VARIABLE_ATTRS:
                    fields, position = variable_reader(data, position, unit)
                    sibling = fields[-1]
                    yield "item", offset, tag, fields
                else:
                    attrs, position = self._decode(plan, position, unit, wanted)
                    sibling = attrs.get(AT_SIBLING)
                    yield "item", offset, tag, attrs
            elif skip is not None and not has_children:
                offset = position + skip if skip.__class__ is int else skip(data, position)
                continue
            else:
                if has_children and tag in note:
                    yield "note", offset, tag, None
                attrs, position = self._decode(plan, position, unit, _SIBLING)
                sibling = attrs.get(AT_SIBLING)
            if not has_children:
                offset = position
            elif isinstance(sibling, int) and sibling > offset:
                offset = sibling
            else:
                offset = self._skip_subtree(position, unit)

    def _skip_subtree(self, position: int, unit: Unit) -> int:
        """The offset after the children that start at ``position`` (and their null terminator)."""
        plans = self._plans(unit)
        data, end, depth = self.info, unit.end, 1
        while depth and position < end:
            code, position = uleb(data, position)
            if code == 0:
                depth -= 1
                continue
            tag, has_children, plan, _, skip = plans[code]
            if skip is not None and not has_children:
                position = position + skip if skip.__class__ is int else skip(data, position)
                continue
            attrs, position = self._decode(plan, position, unit, _SIBLING)
            if has_children:
                sibling = attrs.get(AT_SIBLING)
                if isinstance(sibling, int) and sibling > position:
                    position = sibling
                else:
                    depth += 1
        return position

    def _plans(self, unit: Unit) -> dict[int, tuple[int, bool, tuple, Callable | None, int | tuple | None]]:
        """Per abbreviation: (tag, has children, ((attribute, form, bytes or -1 when variable), ...), the
        reader of a variable DIE (see :mod:`workbench.elf.die_readers`), how to step over its
        attributes (see :func:`~workbench.elf.die_readers.skipper`))."""
        key = (unit.abbrev_offset, unit.offset_size, unit.address_size, unit.version)
        plans = self._plan_cache.get(key)
        if plans is None:
            from workbench.elf.die_readers import skipper, variable_reader  # made from this module's forms
            sizes = {0x0E: unit.offset_size, 0x1F: unit.offset_size, 0x17: unit.offset_size,
                     0x10: unit.address_size if unit.version == 2 else unit.offset_size,
                     0x01: unit.address_size, 0x19: 0, 0x21: 0, 0x1D: unit.offset_size}
            plans = {}
            for code, (tag, has_children, specs) in self._abbrevs(unit.abbrev_offset).items():
                steps = tuple((attr, form, _FIXED_SIZE.get(form, sizes.get(form, -1))) for attr, form, _ in specs)
                reader = variable_reader(self, specs, steps) if tag == TAG_VARIABLE else None
                plans[code] = (tag, has_children, steps, reader, skipper(steps))
            self._plan_cache[key] = plans
        return plans

    def _decode(self, plan: tuple, position: int, unit: Unit, wanted: frozenset) -> tuple[dict, int]:
        """Decode the ``wanted`` attributes of one DIE and step over the others; returns them and the
        offset after the attributes."""
        data = self.info
        attrs = {}
        for attr, form, size in plan:
            if attr in wanted:
                attrs[attr], position = self._read_form(form, position, unit, None)
            elif size >= 0:
                position += size
            elif form in (0x18, 0x09):  # exprloc, block: uleb length
                length, position = uleb(data, position)
                position += length
            elif form == 0x0A:
                position += 1 + data[position]
            elif form == 0x08:
                position = data.index(b"\0", position) + 1
            else:
                _, position = self._read_form(form, position, unit, None)
        return attrs, position

    # -- unit bases and locations ----------------------------------------------------------
    def _unit_bases(self, unit: Unit) -> tuple[int, int]:
        """(DW_AT_str_offsets_base, DW_AT_addr_base) of a unit, read from its root DIE; without them,
        just after the header of the sections' first contribution (what a single-unit file has)."""
        bases = self._bases.get(unit.offset)
        if bases is None:
            header = 8 if unit.offset_size == 4 else 16
            self._bases[unit.offset] = (header, header)  # the root's own strx forms are read against this
            root = self.die(unit.first_die, unit)
            attrs = root.attrs if root is not None else {}
            str_base = attrs.get(AT_STR_OFFSETS_BASE)
            addr_base = attrs.get(AT_ADDR_BASE, attrs.get(AT_GNU_ADDR_BASE))
            bases = (str_base if isinstance(str_base, int) else header,
                     addr_base if isinstance(addr_base, int) else header)
            self._bases[unit.offset] = bases
        return bases

    def indexed_address(self, index: int, unit: Unit) -> int | None:
        """Entry ``index`` of the unit's ``.debug_addr`` table (DW_FORM_addrx, DW_OP_addrx)."""
        position = self._unit_bases(unit)[1] + index * unit.address_size
        if position + unit.address_size > len(self.addresses):
            return None
        return int.from_bytes(self.addresses[position : position + unit.address_size], _BYTEORDER[self.order])

    def static_address(self, location: object, unit: Unit) -> int | None:
        """The address a DW_AT_location names when it is a static one, else None.

        Read: DW_OP_addr a, DW_OP_addrx i (DWARF 5) or DW_OP_GNU_addr_index i (split DWARF 4),
        optionally followed by an offset (DW_OP_plus_uconst n, or DW_OP_constu n DW_OP_plus:
        clang's merged globals). Anything else (a register, the frame, a computed value, a
        location list) has no static address.
        """
        if not isinstance(location, (bytes, bytearray)) or not location:
            return None
        op = location[0]
        if op == OP_ADDR:
            end = 1 + unit.address_size
            address = int.from_bytes(location[1:end], _BYTEORDER[self.order])
        elif op in (_OP_ADDRX, _OP_GNU_ADDR_INDEX):
            index, end = uleb(location, 1)
            address = self.indexed_address(index, unit)
            if address is None:
                return None
        else:
            return None
        rest = location[end:]
        if not rest:
            return address
        if rest[0] == _OP_PLUS_UCONST:
            offset, after = uleb(rest, 1)
            return address + offset if after == len(rest) else None
        if rest[0] == _OP_CONSTU:
            offset, after = uleb(rest, 1)
            return address + offset if rest[after:] == bytes([_OP_PLUS]) else None
        return None

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
            if form == 0x20:  # ref_sig8: the type unit's DIE (None for a type this file lacks)
                signature = int.from_bytes(data[position : position + size], _BYTEORDER[self.order])
                return self.signatures.get(signature), position + size
            if form in (0x29, 0x2A, 0x2B, 0x2C):  # addrx1-4
                index = int.from_bytes(data[position : position + size], _BYTEORDER[self.order])
                return self.indexed_address(index, unit), position + size
            if form == 0x1E:  # data16: opaque
                return data[position : position + size], position + size
            return int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
        if form == 0x0E:  # strp
            offset = self._offset(data, position, unit.offset_size)
            return cstring(self.strings, offset), position + unit.offset_size
        if form == 0x1F:  # line_strp
            offset = self._offset(data, position, unit.offset_size)
            return cstring(self.line_strings, offset), position + unit.offset_size
        if form == 0x08:  # string
            end = data.index(b"\0", position)
            return data[position:end].decode("utf-8", "replace"), end + 1
        if form == 0x0F:  # udata
            return uleb(data, position)
        if form == 0x0D:  # sdata
            return _sleb(data, position)
        if form == 0x15:  # ref_udata
            value, position = uleb(data, position)
            return unit.offset + value, position
        if form in (0x10, 0x17):  # ref_addr, sec_offset
            size = unit.address_size if form == 0x10 and unit.version == 2 else unit.offset_size
            return self._offset(data, position, size) if size in (4, 8) else \
                int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
        if form == 0x01:  # addr
            size = unit.address_size
            return int.from_bytes(data[position : position + size], _BYTEORDER[self.order]), position + size
        if form in (0x18, 0x09):  # exprloc, block
            length, position = uleb(data, position)
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
        if form in (0x1A, 0x1F02):  # strx, GNU_str_index
            index, position = uleb(data, position)
            return self._indexed_string(index, unit), position
        if form in (0x1B, 0x1F01):  # addrx, GNU_addr_index
            index, position = uleb(data, position)
            return self.indexed_address(index, unit), position
        if form in (0x22, 0x23):  # loclistx, rnglistx: an index, not followed here
            return uleb(data, position)
        if form in (0x1D, 0x1F20, 0x1F21):  # strp_sup, GNU_ref_alt, GNU_strp_alt: another file
            return None, position + unit.offset_size
        if form == 0x16:  # indirect
            actual, position = uleb(data, position)
            return self._read_form(actual, position, unit, implicit)
        raise DwarfError(f"unknown DWARF form 0x{form:x} at .debug_info+0x{position:x}")

    def _indexed_string(self, index: int, unit: Unit) -> str | None:
        position = self._unit_bases(unit)[0] + index * unit.offset_size
        if position + unit.offset_size > len(self.str_offsets):
            return None
        return cstring(self.strings, self._offset(self.str_offsets, position, unit.offset_size))


_BYTEORDER = {"<": "little", ">": "big"}
# fixed-size forms whose value needs more than a struct read: data16, ref_sig8, strx1-4, addrx1-4
DECODED_FORMS = frozenset({0x1E, 0x20, 0x25, 0x26, 0x27, 0x28, 0x29, 0x2A, 0x2B, 0x2C})


def member_offset(value: object) -> int | None:
    """DW_AT_data_member_location: a constant, or DW_OP_plus_uconst n."""
    if isinstance(value, int):
        return value
    if isinstance(value, (bytes, bytearray)) and value[:1] == bytes([_OP_PLUS_UCONST]):
        return uleb(value, 1)[0]
    return None


def uleb(data: bytes, position: int) -> tuple[int, int]:
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
    value, end = uleb(data, position)
    if data[end - 1] & 0x40:  # the sign bit of the last byte
        value -= 1 << (7 * (end - position))
    return value, end


def cstring(section: bytes, offset: int) -> str:
    """The NUL-terminated UTF-8 string at ``offset`` of a string section."""
    end = section.find(b"\0", offset)
    return section[offset : end if end >= 0 else len(section)].decode("utf-8", "replace")

