"""``insert --structures`` (a2ltool's ``-t``/``--enable-structures``): a struct variable selected whole becomes one
INSTANCE of a TYPEDEF_STRUCTURE instead of one object per member.

The structure has one STRUCTURE_COMPONENT per member at its offset: a scalar, enum or bitfield (and an array of
them, with MATRIX_DIM) is a TYPEDEF_MEASUREMENT (for a measurement) or a TYPEDEF_CHARACTERISTIC VALUE (for a
calibration, whose RECORD_LAYOUT is the plain insert's ``__<TYPE>_Z``) shared by every member of its data type,
conversion and BIT_MASK, named as a2ltool names them (``Measurement_UByte``, ``Parameter_ULong``,
``Measurement_ULong_0xFFF`` for a bitfield); a nested struct is a nested TYPEDEF_STRUCTURE (an array of them with
MATRIX_DIM); base classes' members and those of an anonymous struct or union are the structure's own, as
a2ltool writes them. An array of structs is an INSTANCE with MATRIX_DIM. A structure is named by its C tag or
typedef and written once for every variable of that C type. Pointers and functions are left out, as the plain
insert leaves them. So the objects the INSTANCE stands for (:mod:`workbench.a2l.instances`) have the names,
addresses and types the plain insert gives the members.

A struct some of whose members the file describes already is inserted member by member, as without
``--structures`` (an INSTANCE would describe those members a second time).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from workbench.a2l.datatypes import array_dims, element_type
from workbench.a2l.insert import _members, _quoted
from workbench.a2l.instances import TYPEDEF_KINDS
from workbench.findings import Severity

if TYPE_CHECKING:
    from workbench.a2l.insert import _Inserter, _Leaf
    from workbench.elf.ctypes_model import CType

__all__ = ["StructureTypedefs"]

_WORDS = {"UBYTE": "UByte", "SBYTE": "SByte", "UWORD": "UWord", "SWORD": "SWord", "ULONG": "ULong", "SLONG": "SLong",
          "A_UINT64": "UInt64", "A_INT64": "Int64", "FLOAT16_IEEE": "Float16", "FLOAT32_IEEE": "Float32",
          "FLOAT64_IEEE": "Float64"}
_PREFIXES = {"MEASUREMENT": "Measurement", "CHARACTERISTIC": "Parameter"}
_GROUPS = ("struct", "union")
_SCALARS = ("base", "enum")
_NOT_A_NAME = re.compile(r"[^A-Za-z0-9_]+")


class StructureTypedefs:
    """The typedefs and INSTANCEs an insert with ``--structures`` adds (into the inserter's new blocks)."""

    def __init__(self, inserter: _Inserter):
        self.inserter = inserter
        module = inserter.module
        self.names: set[str] = {block.name for keyword in TYPEDEF_KINDS for block in module.children_named(keyword)}
        self.by_content: dict[tuple, str] = {}  # (keyword, the block's lines without its name) -> the typedef
        self.structures: dict[tuple[int, str], str | None] = {}  # (id of the C type, kind) -> its TYPEDEF_STRUCTURE
        # the file's object names and the symbols it describes with every symbol that holds them (a.b[2].c: a, a.b ...)
        self.inside = {symbol[:match.start()] for _, symbol in inserter.described
                       for match in re.finditer(r"[.\[]", symbol.partition("{")[0])}
        self.inside |= {name[:match.start()] for name in inserter.taken for match in re.finditer(r"[.\[]", name)}

    def takes(self, leaf: _Leaf) -> bool:
        """Whether ``leaf`` (a struct or an array of them) becomes one INSTANCE: not when the file describes some of
        its members already, or has an object of its name (its members are inserted one by one then)."""
        name = leaf.path.replace("::", "__")
        return leaf.path not in self.inside and name not in self.inside and name not in self.inserter.taken

    def instance(self, kind: str, name: str, leaf: _Leaf) -> tuple[bytes, str] | None:
        """The INSTANCE block of ``leaf`` named ``name`` for ``kind`` and what it is (``tRxPduInfo [2]``), its
        typedefs added on the way; None when the struct has no member to describe (reported)."""
        inserter = self.inserter
        typedef = self._structure(kind, element_type(leaf.ctype), leaf.path, leaf.path)
        if typedef is None:
            inserter._skip("not-insertable", name, f"INSTANCE {name}: {leaf.ctype.display_name} has no member to "
                           f"{'measure' if kind == 'MEASUREMENT' else 'calibrate'}: not inserted", Severity.INFO)
            return None
        dims = array_dims(leaf.ctype)
        head = f"instance for symbol {leaf.path}"  # as a2ltool writes it (its typedefs say measure or calibrate)
        lines = [f"/begin INSTANCE {name} {_quoted(head)}", f"{typedef} 0x{leaf.address:X}"]
        if dims:
            lines.append("MATRIX_DIM " + " ".join(map(str, dims)))
        if inserter.symbol_links:
            lines.append(f"SYMBOL_LINK {_quoted(leaf.symbol)} 0")
        lines.append("/end INSTANCE")
        what = f"{typedef} [{']['.join(map(str, dims))}]" if dims else typedef
        return self._chunk(lines), what

    # -- the typedefs ------------------------------------------------------------------------------
    def _structure(self, kind: str, ctype: CType, path: str, label: str) -> str | None:
        """The TYPEDEF_STRUCTURE of a struct or union for ``kind`` (one per C type), None without components.
        ``path``: where it was met first (for reports); ``label``: its name when the C type has none (the enclosing
        type's name and the member's: ``tOuter.inner``), also what an anonymous enum's COMPU_METHOD is named by."""
        key = (id(ctype), kind)
        if key in self.structures:
            return self.structures[key]
        self.structures[key] = None  # a struct holds itself only through a pointer: never reached again here
        lines = []
        c_name = ctype.name or ctype.typedef
        for member_name, member, offset in _flat_members(ctype):
            typedef, dims = self._component(kind, member, f"{path}.{member_name}", f"{c_name or label}.{member_name}")
            if typedef is None:
                continue
            lines += ["/begin STRUCTURE_COMPONENT", f"  {member_name} {typedef}", f"  {offset}",
                      *([f"  MATRIX_DIM {' '.join(map(str, dims))}"] if dims else []),
                      f"  SYMBOL_TYPE_LINK {_quoted(member_name)}", "/end STRUCTURE_COMPONENT"]
        if not lines:
            return None
        body = [f"0x{ctype.size:X}", *lines, *([f"SYMBOL_TYPE_LINK {_quoted(c_name)}"] if c_name else [])]
        name = self._typedef("TYPEDEF_STRUCTURE", c_name or f"{label}_type", body)
        self.structures[key] = name
        return name

    def _component(self, kind: str, member, path: str, label: str) -> tuple[str | None, tuple[int, ...]]:
        """(typedef, MATRIX_DIM) of one member; (None, ()) for what has no A2L form (a pointer, a function)."""
        ctype = member.type
        element = element_type(ctype)
        if member.bit_size or element.kind in _SCALARS:
            return self._leaf(kind, element, member.bit_size, member.bit_position, path, label), \
                () if member.bit_size else array_dims(ctype)
        if element.kind in _GROUPS:
            return self._structure(kind, element, path, label), array_dims(ctype)
        return None, ()

    def _leaf(self, kind: str, element: CType, bit_size: int | None, bit_position: int | None, path: str,
              label: str) -> str | None:
        """The TYPEDEF_MEASUREMENT or TYPEDEF_CHARACTERISTIC of one scalar type (and bitfield)."""
        inserter = self.inserter
        typed = inserter._typed(element, bit_size, bit_position)
        if typed.__class__ is str:
            inserter._skip("no-datatype" if bit_size is None else "bit-mask-unrepresentable", path,
                           f"{kind} {path}: {typed}: left out of its TYPEDEF_STRUCTURE", Severity.WARNING)
            return None
        datatype, limits, mask = typed
        conversion = inserter._conversion(element, label.replace("::", "__"))
        if kind == "MEASUREMENT":
            first = f"{datatype} {conversion} 0 0 {limits}"
        else:
            first = f"VALUE {inserter._layout(datatype)} 0 {conversion} {limits}"
        base = f"{_PREFIXES[kind]}_{_WORDS.get(datatype, datatype)}"
        if mask is not None:
            base += f"_0x{mask:X}"
        if conversion != "NO_COMPU_METHOD":
            base += f"_{conversion}"
        return self._typedef(f"TYPEDEF_{kind}", base, [first, *([f"BIT_MASK 0x{mask:X}"] if mask is not None else [])])

    def _typedef(self, keyword: str, base: str, body: list[str]) -> str:
        """The name of a typedef block with ``body`` (its lines after the /begin line): an equal one added before,
        else a new one, named ``base`` (``base_2`` ... where the name is taken)."""
        content = (keyword, tuple(body))
        found = self.by_content.get(content)
        if found is not None:
            return found
        base = _NOT_A_NAME.sub("_", base.replace("::", "__")).strip("_") or keyword
        name, number = base, 1
        while name in self.names:
            number += 1
            name = f"{base}_{number}"
        self.names.add(name)
        self.by_content[content] = name
        self.inserter.blocks.setdefault(keyword, []).append(self._chunk([f'/begin {keyword} {name} ""', *body,
                                                                         f"/end {keyword}"]))
        return name

    def _chunk(self, lines: list[str]) -> bytes:
        encoding = self.inserter.doc.encoding
        return self.inserter._chunk([line.encode(encoding, "replace") for line in lines])


def _flat_members(ctype: CType, offset: int = 0) -> list[tuple[str, object, int]]:
    """(name, member, offset) of every member of a struct or union, those of its base classes and of an anonymous
    struct or union in it as its own (a2ltool's reading)."""
    found = []
    for member in _members(ctype):
        if member.offset is None:
            continue
        if not member.name:
            if member.type.kind in _GROUPS:
                found += _flat_members(member.type, offset + member.offset)
            continue
        found.append((member.name, member, offset + member.offset))
    return found

