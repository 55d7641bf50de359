"""C objects of an ELF by name, from its symbol table and DWARF, with pyelftools only.

The asset tests use this instead of ``workbench.elf`` on purpose: they check the demo
ECU's files against an independent reading of the ELF, so a bug in the workbench's own
ELF code cannot make both sides agree.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from math import prod
from pathlib import Path

from elftools.elf.elffile import ELFFile
from elftools.elf.sections import SymbolTableSection

_STRIPPED_TAGS = {"DW_TAG_typedef", "DW_TAG_const_type", "DW_TAG_volatile_type"}
# DW_AT_encoding of a base type -> our encoding class
_ENCODINGS = {
    0x02: "unsigned",  # DW_ATE_boolean
    0x04: "float",  # DW_ATE_float
    0x05: "signed",  # DW_ATE_signed
    0x06: "signed",  # DW_ATE_signed_char
    0x07: "unsigned",  # DW_ATE_unsigned
    0x08: "unsigned",  # DW_ATE_unsigned_char
}


@dataclass(frozen=True)
class CType:
    """A C type with typedefs and qualifiers removed.

    ``kind`` is "scalar" (``encoding`` "unsigned", "signed" or "float"), "array"
    (``element`` and ``dims``, outermost first), "struct" (``members``) or "other".
    ``size`` is in bytes.
    """

    kind: str
    name: str
    size: int
    encoding: str = ""
    element: CType | None = None
    dims: tuple[int, ...] = ()
    members: tuple[Member, ...] = ()

    def member(self, name: str) -> Member:
        for member in self.members:
            if member.name == name:
                return member
        raise KeyError(f"{self.name or 'the struct'} has no member {name!r}")

    def element_count(self) -> int:
        return prod(self.dims)

    def scalar_element(self) -> CType:
        """The innermost element type of an array (the type itself for a scalar)."""
        return self.element.scalar_element() if self.kind == "array" else self


@dataclass(frozen=True)
class Member:
    name: str
    offset: int
    type: CType


@dataclass(frozen=True)
class CObject:
    """A variable or a part of one: absolute address (bytes) and C type."""

    address: int
    type: CType


@dataclass(frozen=True)
class Section:
    name: str
    address: int
    size: int
    load_address: int
    writable: bool

    def contains(self, address: int, size: int) -> bool:
        return self.address <= address and address + size <= self.address + self.size


class DwarfLookup:
    """Global variables of one ELF: their addresses, types, sections and bytes."""

    def __init__(self, path: Path):
        self._file = open(path, "rb")  # noqa: SIM115 - pyelftools reads lazily from the open file
        self._elf = ELFFile(self._file)
        self.little_endian: bool = self._elf.little_endian
        self.symbols = self._read_symbols()
        self.sections = self._read_sections()
        self._variable_types = self._read_variable_types()

    def close(self) -> None:
        self._file.close()

    def resolve(self, path: str) -> CObject:
        """The object a C access path names, e.g. ``Pdu.Data[3]`` or ``zvRailPConv``.

        :raises KeyError: the variable, a member or an index does not exist.
        """
        tokens = re.findall(r"\[\d+\]|[A-Za-z_]\w*", path)
        if "".join(f".{t}" if not t.startswith("[") else t for t in tokens).lstrip(".") != path:
            raise KeyError(f"cannot parse the access path {path!r}")
        variable = tokens[0]
        if variable not in self.symbols or variable not in self._variable_types:
            raise KeyError(f"no global variable {variable!r} in the ELF")
        address, ctype = self.symbols[variable][0], self._variable_types[variable]
        for token in tokens[1:]:
            if token.startswith("["):
                index = int(token[1:-1])
                if ctype.kind != "array" or index >= ctype.dims[0]:
                    raise KeyError(f"{path}: index {index} outside {ctype.name}")
                inner = _array_tail(ctype)
                address, ctype = address + index * inner.size, inner
            else:
                if ctype.kind != "struct":
                    raise KeyError(f"{path}: {ctype.name} is not a struct")
                member = ctype.member(token)
                address, ctype = address + member.offset, member.type
        return CObject(address, ctype)

    def section_of(self, address: int, size: int) -> Section | None:
        for section in self.sections:
            if section.size and section.contains(address, size):
                return section
        return None

    def read(self, address: int, size: int) -> bytes:
        """Bytes of the file image at a (virtual) address, as the linker placed them."""
        for section in self._elf.iter_sections():
            start, length = section["sh_addr"], section["sh_size"]
            if section["sh_type"] != "SHT_NOBITS" and start <= address and address + size <= start + length:
                return section.data()[address - start : address - start + size]
        raise KeyError(f"no section holds 0x{address:X}+{size} in the file")

    def _read_symbols(self) -> dict[str, tuple[int, int]]:
        table = self._elf.get_section_by_name(".symtab")
        assert isinstance(table, SymbolTableSection), "the ELF has no .symtab"
        return {
            symbol.name: (symbol["st_value"], symbol["st_size"])
            for symbol in table.iter_symbols()
            if symbol["st_info"]["type"] == "STT_OBJECT"
        }

    def _read_sections(self) -> list[Section]:
        load_address = {}
        for segment in self._elf.iter_segments():
            if segment["p_type"] == "PT_LOAD":
                for section in self._elf.iter_sections():
                    if segment.section_in_segment(section):
                        offset = section["sh_addr"] - segment["p_vaddr"]
                        load_address[section.name] = segment["p_paddr"] + offset
        return [
            Section(
                name=section.name,
                address=section["sh_addr"],
                size=section["sh_size"],
                load_address=load_address.get(section.name, section["sh_addr"]),
                writable=bool(section["sh_flags"] & 0x1),  # SHF_WRITE
            )
            for section in self._elf.iter_sections()
            if section["sh_flags"] & 0x2  # SHF_ALLOC
        ]

    def _read_variable_types(self) -> dict[str, CType]:
        assert self._elf.has_dwarf_info(), "the ELF has no DWARF (built without -g?)"
        types: dict[str, CType] = {}
        cache: dict[int, CType] = {}
        for unit in self._elf.get_dwarf_info().iter_CUs():
            for die in unit.get_top_DIE().iter_children():
                if die.tag != "DW_TAG_variable" or "DW_AT_declaration" in die.attributes:
                    continue
                declaration = die.get_DIE_from_attribute("DW_AT_specification") if "DW_AT_specification" in die.attributes else die
                if "DW_AT_name" not in declaration.attributes or "DW_AT_type" not in declaration.attributes:
                    continue
                name = declaration.attributes["DW_AT_name"].value.decode()
                types[name] = _ctype(declaration.get_DIE_from_attribute("DW_AT_type"), cache)
        return types


def _array_tail(array: CType) -> CType:
    """The type of ``array[i]``: the element, or a sub-array for a multi-dimensional array."""
    if len(array.dims) == 1:
        return array.element
    inner_dims = array.dims[1:]
    return CType("array", f"{array.element.name}{''.join(f'[{d}]' for d in inner_dims)}",
                 array.element.size * prod(inner_dims), element=array.element, dims=inner_dims)


def _ctype(die, cache: dict[int, CType]) -> CType:
    while die.tag in _STRIPPED_TAGS:
        die = die.get_DIE_from_attribute("DW_AT_type")
    if die.offset in cache:
        return cache[die.offset]
    name = die.attributes["DW_AT_name"].value.decode() if "DW_AT_name" in die.attributes else ""
    if die.tag == "DW_TAG_base_type":
        encoding = _ENCODINGS.get(die.attributes["DW_AT_encoding"].value, "other")
        result = CType("scalar", name, die.attributes["DW_AT_byte_size"].value, encoding=encoding)
    elif die.tag == "DW_TAG_enumeration_type":
        values = [child.attributes["DW_AT_const_value"].value for child in die.iter_children()]
        result = CType("scalar", name, die.attributes["DW_AT_byte_size"].value,
                       encoding="signed" if any(v < 0 for v in values) else "unsigned")
    elif die.tag == "DW_TAG_array_type":
        element = _ctype(die.get_DIE_from_attribute("DW_AT_type"), cache)
        dims = tuple(_subrange_length(child) for child in die.iter_children() if child.tag == "DW_TAG_subrange_type")
        result = CType("array", f"{element.name}{''.join(f'[{d}]' for d in dims)}", element.size * prod(dims),
                       element=element, dims=dims)
    elif die.tag == "DW_TAG_structure_type":
        members = tuple(
            Member(child.attributes["DW_AT_name"].value.decode(), _member_offset(child),
                   _ctype(child.get_DIE_from_attribute("DW_AT_type"), cache))
            for child in die.iter_children()
            if child.tag == "DW_TAG_member"
        )
        result = CType("struct", name, die.attributes["DW_AT_byte_size"].value, members=members)
    else:
        size = die.attributes["DW_AT_byte_size"].value if "DW_AT_byte_size" in die.attributes else 0
        result = CType("other", name or die.tag, size)
    cache[die.offset] = result
    return result


def _subrange_length(subrange) -> int:
    if "DW_AT_count" in subrange.attributes:
        return subrange.attributes["DW_AT_count"].value
    return subrange.attributes["DW_AT_upper_bound"].value + 1


def _member_offset(member) -> int:
    location = member.attributes["DW_AT_data_member_location"].value
    if isinstance(location, int):
        return location
    # DWARF 2 style: an expression DW_OP_plus_uconst <ULEB128 offset>
    offset, shift = 0, 0
    for byte in location[1:]:
        offset |= (byte & 0x7F) << shift
        shift += 7
        if not byte & 0x80:
            break
    return offset
