"""``update --types``: element type, shape, bit mask and limits of every object checked against DWARF.

- MEASUREMENT: data type, MATRIX_DIM/ARRAY_SIZE of an array (added when missing),
  BIT_MASK of a bitfield: corrected in the object.
- CHARACTERISTIC and AXIS_PTS: the element type is the data type of FNC_VALUES
  (AXIS_PTS_X) in the RECORD_LAYOUT; corrected as :mod:`.layouts` says (switch to an
  equal layout of the right type, or fix a layout no other object uses, else report).
  The shape: a VALUE holds one element; a VAL_BLK's MATRIX_DIM/NUMBER and an AXIS_PTS's
  MaxAxisPoints are the C array's; a CURVE's, MAP's (CUBOID's ...) axes' MaxAxisPoints
  are the C array's dimensions, outermost first for ROW_DIR values (``map[x][y]``: Y runs
  fastest), innermost first for COLUMN_DIR (``map[y][x]``: X runs fastest, as Simulink's
  column-major tables; :mod:`workbench.calib.layout` reads the values by the same rule) -
  corrected in the object's own AXIS_DESCRs, or
  reported when the C array is flat and only the total can be compared.
- A CHARACTERISTIC or AXIS_PTS whose C variable is a struct (axes, counts and values in one
  record) is read as a2ltool reads it: the RECORD_LAYOUT item at position N is the struct's
  N-th member. FNC_VALUES' member gives the element type, limits, enum and bit mask, an
  AXIS_PTS_<axis> member an internal axis' point count (an AXIS_PTS named by a COM_AXIS gives
  that axis' count), and the layout's typed items and FIX_NO_AXIS_PTS counts follow the
  members (switched, corrected or reported as above).
- BLOB: its size. INSTANCE: ADDRESS_TYPE by the size of the pointer it is reached through.
- An enum element type gives an object without conversion a COMPU_METHOD TAB_VERB and its
  COMPU_VTAB (:mod:`.enums`); CANape's LINK_MAP beside an object states the element type.
- Limits outside the range of the C type's element are narrowed to it; never to the
  range of a data type the A2L states wrongly (a uint16 calibration whose layout says
  UBYTE keeps its limit of 1000).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from math import prod

from workbench.a2l.addressed import Target
from workbench.a2l.datatypes import array_dims, datatype_for, datatype_range, element_type, member_at
from workbench.a2l.edits import Edit, indentation_of, newline_bytes, remove_span, replace_token
from workbench.a2l.reports import finding_at
from workbench.a2l.update.enums import EnumConversions
from workbench.a2l.update.layouts import AXES, Correction, Layout, RecordLayouts
from workbench.a2l.values import format_int_like, int_or_none, is_number, parse_number
from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block
    from workbench.elf.ctypes_model import CMember, CType
    from workbench.elf.debugdata import ResolvedSymbol

__all__ = ["TypeChecker"]


_AXES = {"CURVE": 1, "MAP": 2, "CUBOID": 3, "CUBE_4": 4, "CUBE_5": 5}
_ADDRESS_TYPES = {1: "PBYTE", 2: "PWORD", 4: "PLONG", 8: "PLONGLONG"}  # by the size of a pointer


class TypeChecker:
    """Checks objects one by one; AXIS_PTS before the CHARACTERISTICs whose COM_AXIS names them."""

    def __init__(self, doc: "A2lDocument"):
        self.doc = doc
        self.layouts = RecordLayouts(doc)
        self.enums = EnumConversions(doc)
        self.axis_points: dict[str, int] = {}  # AXIS_PTS -> its MaxAxisPoints, as checked

    def check(self, target: Target, symbol: "ResolvedSymbol") -> tuple[list[Edit], list[Finding]]:
        if symbol.type is None:
            return [], [self._finding(target, target.name_token, "type-unknown",
                                      f"{target.name}: {symbol.path} has no DWARF type to check", Severity.WARNING)]
        handler = getattr(self, "_" + target.keyword.lower(), None)
        edits, findings = handler(target, symbol) if handler else ([], [])
        return edits + self._link_map_type(target, symbol), findings

    # -- per block type --------------------------------------------------------------------
    def _measurement(self, target: Target, symbol: "ResolvedSymbol"):
        doc, edits, findings = self.doc, [], []
        block = doc.block(target.block)
        datatype = datatype_for(symbol.type)
        if datatype is None:
            findings.append(self._not_scalar(target, symbol))
            return edits, findings
        datatype_token = target.name_token + 2
        old = doc.text(datatype_token)
        if old != datatype:
            edits.append(replace_token(doc, datatype_token, datatype.encode("ascii")))
            findings.append(self._finding(target, datatype_token, "datatype-updated",
                                          f"{target.name}: data type {old} -> {datatype}"))
        self._enum(target, target.name_token + 3, symbol.type, edits, findings)
        self._dims(target, block, array_dims(symbol.type), edits, findings)
        if symbol.bit_size is not None:
            self._bit_mask(target, block, symbol, edits, findings)
        self._limits(target, target.name_token + 6, target.name_token + 7, datatype, edits, findings)
        return edits, findings

    def _characteristic(self, target: Target, symbol: "ResolvedSymbol"):
        doc, edits, findings = self.doc, [], []
        if symbol.type.kind == "struct":
            return self._struct_characteristic(target, symbol)
        block = doc.block(target.block)
        kind = doc.text(target.name_token + 2)
        needed = datatype_for(symbol.type)
        if not self._element_type(target, target.name_token + 4, "FNC_VALUES", symbol, needed, edits, findings):
            return edits, findings
        self._enum(target, target.name_token + 6, symbol.type, edits, findings)
        dims = array_dims(symbol.type)
        if kind == "VALUE" and prod(dims) != 1:
            findings.append(self._finding(target, target.name_token + 2, "shape-mismatch",
                                          f"{target.name}: a VALUE holds one element, the C object is an array "
                                          f"[{']['.join(map(str, dims))}] of {needed}", Severity.WARNING))
        elif kind in ("VAL_BLK", "ASCII"):
            self._dims(target, block, dims, edits, findings)
        elif kind in _AXES:
            mode = self.layouts.layouts[doc.text(target.name_token + 4)].index_modes.get("FNC_VALUES", "")
            self._axes(target, block, kind, dims, mode, edits, findings)
        if symbol.bit_size is not None:
            self._bit_mask(target, block, symbol, edits, findings)
        self._limits(target, target.name_token + 7, target.name_token + 8, needed, edits, findings)
        return edits, findings

    def _axis_pts(self, target: Target, symbol: "ResolvedSymbol"):
        edits, findings = [], []
        if symbol.type.kind == "struct":
            return self._struct_axis_pts(target, symbol)
        needed = datatype_for(symbol.type)
        if not self._element_type(target, target.name_token + 4, "AXIS_PTS_X", symbol, needed, edits, findings):
            return edits, findings
        self._enum(target, target.name_token + 6, symbol.type, edits, findings)
        dims = array_dims(symbol.type)
        count_token = target.name_token + 7
        if len(dims) > 1:
            findings.append(self._finding(target, count_token, "shape-mismatch", f"{target.name}: an axis is one "
                                          f"row of points, the C object is [{']['.join(map(str, dims))}]",
                                          Severity.WARNING))
        else:
            self._points(target, count_token, prod(dims), edits, findings)
        self._limits(target, target.name_token + 8, target.name_token + 9, needed, edits, findings)
        return edits, findings

    def _points(self, target: Target, count_token: int, points: int, edits: list, findings: list) -> None:
        """An AXIS_PTS's MaxAxisPoints, remembered for the COM_AXIS of CHARACTERISTICs (see _struct_characteristic)."""
        doc = self.doc
        self.axis_points[target.name] = points
        if doc.int_value(count_token) != points:
            edits.append(replace_token(doc, count_token, format_int_like(doc.raw(count_token), points)))
            findings.append(self._finding(target, count_token, "size-updated",
                                          f"{target.name}: MaxAxisPoints {doc.int_value(count_token)} -> {points}"))

    # -- a struct whose members are the object's axes, counts and values (a2ltool's reading) -----------
    def _struct_characteristic(self, target: Target, symbol: "ResolvedSymbol"):
        """A CHARACTERISTIC whose C variable is a struct: the member at the RECORD_LAYOUT's FNC_VALUES
        position is its values (data type, limits, enum, bit mask), the member at an AXIS_PTS_<axis>
        position an internal axis (its point count), an AXIS_PTS a COM_AXIS names gives that axis' count;
        the layout is corrected to the members' data types and FIX_NO_AXIS_PTS counts."""
        doc, edits, findings = self.doc, [], []
        layout = self.layouts.layouts.get(doc.text(target.name_token + 4))
        if layout is None:
            return edits, findings  # an undefined RECORD_LAYOUT is the reference check's finding
        values = self._member(target, symbol, layout, "FNC_VALUES", findings)
        if values is None:
            return edits, findings
        self._enum(target, target.name_token + 6, values.type, edits, findings)
        self._limits(target, target.name_token + 7, target.name_token + 8, datatype_for(values.type), edits, findings)
        if values.bit_size is not None:
            self._bit_mask(target, doc.block(target.block), values, edits, findings)
        for axis, descr in zip(AXES, doc.block(target.block).children_named("AXIS_DESCR")):
            if len(descr.args) < 4:
                continue
            reference = _option(doc, descr, "AXIS_PTS_REF")
            if reference:
                points = self.axis_points.get(doc.text(reference[0]))
            else:
                member = self._member(target, symbol, layout, f"AXIS_PTS_{axis}", None)
                points = member.type.dims[0] if member is not None and member.type.kind == "array" else None
            count_token = descr.args[3]
            if points is not None and doc.int_value(count_token) != points:
                edits.append(replace_token(doc, count_token, format_int_like(doc.raw(count_token), points)))
                findings.append(self._finding(target, count_token, "size-updated", f"{target.name}: MaxAxisPoints "
                                              f"of axis {axis} {doc.int_value(count_token)} -> {points}"))
        self._struct_layout(target, target.name_token + 4, layout, symbol.type, edits, findings)
        return edits, findings

    def _struct_axis_pts(self, target: Target, symbol: "ResolvedSymbol"):
        """An AXIS_PTS whose C variable is a struct: the member at AXIS_PTS_X's position is the axis."""
        doc, edits, findings = self.doc, [], []
        layout = self.layouts.layouts.get(doc.text(target.name_token + 4))
        if layout is None:
            return edits, findings
        points = self._member(target, symbol, layout, "AXIS_PTS_X", findings)
        if points is None:
            return edits, findings
        self._enum(target, target.name_token + 6, points.type, edits, findings)
        if points.type.kind in ("array", "enum"):
            self._points(target, target.name_token + 7, points.type.dims[0] if points.type.dims else 1, edits,
                         findings)
        self._limits(target, target.name_token + 8, target.name_token + 9, datatype_for(points.type), edits, findings)
        self._struct_layout(target, target.name_token + 4, layout, symbol.type, edits, findings)
        return edits, findings

    def _member(self, target: Target, symbol: "ResolvedSymbol", layout: Layout, item: str, findings: list | None):
        """The struct member at ``item``'s position in the layout (position 1 when the layout lacks the item);
        None, with a finding when ``findings`` is given, when the struct has no member there."""
        position = layout.typed[item][0] if item in layout.typed else 1
        member = member_at(symbol.type, position)
        if member is None and findings is not None:
            findings.append(self._finding(target, target.name_token + 4, "type-not-checked",
                                          f"{target.name}: {item} of RECORD_LAYOUT {layout.name} is at position "
                                          f"{position}, {symbol.type.display_name} has {len(symbol.type.members)} "
                                          "members", Severity.WARNING))
        return member

    def _struct_layout(self, target: Target, deposit_token: int, layout: Layout, ctype: "CType", edits: list,
                       findings: list) -> None:
        """The layout's typed items and FIX_NO_AXIS_PTS counts as the struct's members say (see :mod:`.layouts`)."""
        datatypes, counts = {}, {}
        for item, (position, _) in layout.typed.items():
            member = member_at(ctype, position)
            datatype = datatype_for(member.type) if member is not None else None
            if datatype is not None:
                datatypes[item] = datatype
            if member is not None and item.startswith("AXIS_PTS_") and member.type.kind == "array":
                counts[item[len("AXIS_PTS_"):]] = member.type.dims[0]
        correction = self.layouts.correction(layout.name, datatypes, counts)
        if correction is not None:
            self._correct_layout(target, deposit_token, layout, correction, f"the members of {ctype.display_name}",
                                 edits, findings)

    def _correct_layout(self, target: Target, deposit_token: int, layout: Layout, correction: Correction, why: str,
                        edits: list, findings: list) -> None:
        """Switch to the equal layout, edit one only this object uses, or report a shared one (see :mod:`.layouts`)."""
        doc = self.doc
        what = ", ".join(correction.described)
        if correction.alternative is not None:
            edits.append(replace_token(doc, deposit_token, correction.alternative.encode("ascii")))
            findings.append(self._finding(target, deposit_token, "record-layout-updated", f"{target.name}: "
                                          f"RECORD_LAYOUT {layout.name} -> {correction.alternative} ({what}: {why})"))
        elif correction.users <= 1:
            edits.extend(replace_token(doc, token, text.encode("ascii")) for token, text in correction.changes.items())
            findings.append(self._finding(target, next(iter(correction.changes)), "datatype-updated",
                                          f"{target.name}: RECORD_LAYOUT {layout.name} {what} ({why}; no other "
                                          "object uses the layout)"))
        else:
            findings.append(self._finding(target, deposit_token, "datatype-mismatch",
                                          f"{target.name}: RECORD_LAYOUT {layout.name} states {what.replace(' -> ', ', needs ')} "
                                          f"({why}); {correction.users} objects share the layout, so it is not "
                                          f"changed: give {target.name} a layout of its own", Severity.WARNING))

    def _instance(self, target: Target, symbol: "ResolvedSymbol"):
        """An INSTANCE reached through a pointer says so, with the pointer's size (ADDRESS_TYPE); one that
        is not, does not."""
        doc, ctype = self.doc, symbol.type
        tokens = _option(doc, doc.block(target.block), "ADDRESS_TYPE")
        if ctype.kind == "pointer":
            wanted = _ADDRESS_TYPES.get(ctype.size, "DIRECT")
            if not tokens:
                edits: list[Edit] = []
                self._insert(target, f"ADDRESS_TYPE {wanted}", edits)
                return edits, [self._finding(target, target.name_token, "address-type-updated",
                                             f"{target.name}: ADDRESS_TYPE {wanted} added")]
            if doc.text(tokens[0]) != wanted:
                return ([replace_token(doc, tokens[0], wanted.encode("ascii"))],
                        [self._finding(target, tokens[0], "address-type-updated",
                                       f"{target.name}: ADDRESS_TYPE {doc.text(tokens[0])} -> {wanted}")])
        elif tokens:
            start, end = doc.tokens.span(tokens[0] - 1)[0], doc.tokens.span(tokens[-1])[1]
            return ([remove_span(doc, start, end)], [self._finding(target, tokens[0], "address-type-updated",
                                                                   f"{target.name}: ADDRESS_TYPE removed "
                                                                   f"({ctype.display_name} is no pointer)")])
        return [], []

    def _link_map_type(self, target: Target, symbol: "ResolvedSymbol") -> list[Edit]:
        """CANape's ``IF_DATA CANAPE_EXT ... LINK_MAP "symbol" address ... valid datatype bit_offset`` states
        the element type as CANape codes it (as a2ltool writes it): set when the type is a scalar's."""
        doc, edits = self.doc, []
        code, bit_offset = _canape_type(symbol)
        for if_data in doc.block(target.block).children_named("IF_DATA"):
            own = if_data.own_tokens
            if len(own) < 10 or doc.raw(own[0]) != b"CANAPE_EXT":
                continue
            link = next((i for i, token in enumerate(own) if doc.raw(token) == b"LINK_MAP"), None)
            if link is None or link + 8 >= len(own):
                continue
            for token, value in zip(own[link + 6 : link + 9], (1 if code else 0, code, bit_offset)):
                raw = doc.raw(token)
                if int_or_none(raw) is not None and int_or_none(raw) != value:
                    edits.append(replace_token(doc, token, format_int_like(raw, value)))
        return edits

    def _enum(self, target: Target, conversion_token: int, ctype: "CType", edits: list, findings: list) -> None:
        element = element_type(ctype)
        if element.kind == "enum" and element.enumerators:
            enum_edits, enum_findings = self.enums.convert(target, conversion_token, element)
            edits.extend(enum_edits)
            findings.extend(enum_findings)

    def _blob(self, target: Target, symbol: "ResolvedSymbol"):
        size_token = target.name_token + 3
        old = self.doc.int_value(size_token)
        if old == symbol.size:
            return [], []
        return ([replace_token(self.doc, size_token, format_int_like(self.doc.raw(size_token), symbol.size))],
                [self._finding(target, size_token, "size-updated", f"{target.name}: size {old} -> {symbol.size}")])

    # -- shared pieces ----------------------------------------------------------------------
    def _element_type(self, target: Target, deposit_token: int, item: str, symbol: "ResolvedSymbol",
                      needed: str | None, edits: list, findings: list) -> bool:
        """Check the layout's element type against the C type (see :mod:`.layouts`); False when the
        object is not one whose C variable is its values (a struct of axes and values, an unknown layout)."""
        doc = self.doc
        name = doc.text(deposit_token)
        layout = self.layouts.layouts.get(name)
        if layout is None or item not in layout.datatypes:
            return False
        if not layout.values_only:
            findings.append(self._finding(target, deposit_token, "type-not-checked",
                                          f"{target.name}: RECORD_LAYOUT {name} holds more than {item} (axes, "
                                          f"counts): {symbol.type.display_name} is not compared item by item"))
            return False
        if needed is None:
            findings.append(self._not_scalar(target, symbol))
            return False
        correction = self.layouts.correction(name, {item: needed}, {})
        if correction is not None:
            self._correct_layout(target, deposit_token, layout, correction, f"the C type is "
                                 f"{symbol.type.display_name}", edits, findings)
        return True

    def _axes(self, target: Target, block, kind: str, dims: tuple[int, ...], mode: str, edits: list,
              findings: list) -> None:
        """The MaxAxisPoints of each AXIS_DESCR against the C array's dimensions."""
        doc = self.doc
        axes = [axis for axis in block.children_named("AXIS_DESCR") if len(axis.args) > 3]
        counts = [axis.args[3] for axis in axes]
        if len(axes) != _AXES[kind]:
            return  # the grammar check reports a missing AXIS_DESCR
        stated = [doc.int_value(token) for token in counts]
        wanted = list(reversed(dims)) if mode == "COLUMN_DIR" else list(dims)  # COLUMN_DIR: x runs fastest
        if len(wanted) != len(axes):
            if prod(stated) != prod(dims):
                findings.append(self._finding(target, counts[0], "shape-mismatch",
                                              f"{target.name}: the axes hold {' x '.join(map(str, stated))} = "
                                              f"{prod(stated)} values, the C object {prod(dims)}", Severity.WARNING))
            return
        for axis_name, token, old, new in zip("XYZ45", counts, stated, wanted):
            if old != new:
                edits.append(replace_token(doc, token, format_int_like(doc.raw(token), new)))
                findings.append(self._finding(target, token, "size-updated",
                                              f"{target.name}: MaxAxisPoints of axis {axis_name} {old} -> {new}"))

    def _not_scalar(self, target: Target, symbol: "ResolvedSymbol") -> Finding:
        return self._finding(target, target.name_token, "type-not-scalar",
                             f"{target.name}: {symbol.type.display_name} is a {symbol.type.kind}, "
                             "not a scalar or array of scalars", Severity.WARNING)

    def _dims(self, target: Target, block, dims: tuple[int, ...], edits: list, findings: list) -> None:
        doc = self.doc
        for keyword in ("MATRIX_DIM", "ARRAY_SIZE", "NUMBER"):
            tokens = _option(doc, block, keyword)
            if tokens is None:
                continue
            stated = tuple(doc.int_value(t) for t in tokens)
            wanted = dims or (1,)
            if keyword != "MATRIX_DIM":
                total = 1
                for dim in wanted:
                    total *= dim
                wanted = (total,)
            if _without_ones(stated) != _without_ones(wanted):
                start = doc.tokens.starts_list[tokens[0]]
                end = doc.tokens.ends_list[tokens[-1]]
                edits.append(Edit(start, end, " ".join(str(d) for d in wanted).encode("ascii")))
                findings.append(self._finding(target, tokens[0], "size-updated",
                                              f"{target.name}: {keyword} {_dims_text(stated)} -> {_dims_text(wanted)}"))
            return
        if dims and dims != (1,):
            self._insert(target, f"MATRIX_DIM {' '.join(str(d) for d in dims)}", edits)
            findings.append(self._finding(target, target.name_token, "size-updated",
                                          f"{target.name}: MATRIX_DIM {_dims_text(dims)} added"))

    def _bit_mask(self, target: Target, block, field: "ResolvedSymbol | CMember", edits: list, findings: list) -> None:
        """BIT_MASK of a bitfield in the value of its storage unit (the element type) as the ECU reads it."""
        doc = self.doc
        position, bits = field.bit_position or 0, 8 * element_type(field.type).size
        if not 0 <= position <= bits - field.bit_size:
            findings.append(self._finding(target, target.name_token, "bit-mask-unrepresentable",
                                          f"{target.name}: the bitfield of {field.bit_size} bits lies across more "
                                          f"than the {bits} bits of its type (a packed struct): no BIT_MASK "
                                          "describes it", Severity.WARNING))
            return
        mask = ((1 << field.bit_size) - 1) << position
        tokens = _option(doc, block, "BIT_MASK")
        if tokens:
            old = doc.int_value(tokens[0])
            if old != mask:
                edits.append(replace_token(doc, tokens[0], format_int_like(doc.raw(tokens[0]), mask)))
                findings.append(self._finding(target, tokens[0], "bit-mask-updated",
                                              f"{target.name}: BIT_MASK 0x{old:X} -> 0x{mask:X}"))
            return
        self._insert(target, f"BIT_MASK 0x{mask:X}", edits)
        findings.append(self._finding(target, target.name_token, "bit-mask-updated",
                                      f"{target.name}: BIT_MASK 0x{mask:X} added"))

    def _limits(self, target: Target, lower_token: int, upper_token: int, datatype: str | None, edits: list,
                findings: list) -> None:
        """Narrow limits outside the range of ``datatype``, the C type's element (never a stated one)."""
        limits = datatype_range(datatype) if datatype else None
        if limits is None:
            return
        for token, bound, outside in ((lower_token, limits[0], lambda v: v < limits[0]),
                                      (upper_token, limits[1], lambda v: v > limits[1])):
            raw = self.doc.raw(token)
            if is_number(raw) and outside(parse_number(raw)):
                edits.append(replace_token(self.doc, token, str(bound).encode("ascii")))
                findings.append(self._finding(target, token, "limits-updated",
                                              f"{target.name}: limit {raw.decode('ascii')} -> {bound} "
                                              f"(the range of {datatype})"))

    def _insert(self, target: Target, text: str, edits: list) -> None:
        doc = self.doc
        anchor = doc.tokens.ends_list[target.anchor_token]
        indent = indentation_of(doc.data, doc.tokens.starts_list[doc.block_begin[target.block]]) + b"  "
        edits.append(Edit(anchor, anchor, newline_bytes(doc) + indent + text.encode("ascii")))

    def _finding(self, target: Target, token: int, kind: str, message: str,
                 severity: Severity = Severity.INFO) -> Finding:
        return finding_at(self.doc, token, kind, target.name, message, target.keyword, severity)


def _canape_type(symbol: "ResolvedSymbol") -> tuple[int, int]:
    """CANape's code of a symbol's element type (0: none it has a code for) and the bit offset of a bitfield:
    0x80 | 0x40 for signed | the bits - 1, 0x01 float, 0x02 double."""
    element = element_type(symbol.type)
    if symbol.bit_size is not None:
        return 0x80 | (0x40 if element.encoding == "signed" else 0) | (symbol.bit_size - 1), symbol.bit_position or 0
    if element.kind not in ("base", "enum") or element.size not in (1, 2, 4, 8):
        return 0, 0
    if element.encoding == "float":
        return {4: 0x01, 8: 0x02}.get(element.size, 0), 0
    return 0x80 | (0x40 if element.encoding == "signed" else 0) | (8 * element.size - 1), 0


def _without_ones(dims: tuple[int, ...]) -> tuple[int, ...]:
    return tuple(d for d in dims if d != 1) or (1,)


def _dims_text(dims: tuple[int, ...]) -> str:
    return " ".join(str(d) for d in dims)


def _option(doc: "A2lDocument", block: "Block", keyword: str) -> list[int] | None:
    """:meth:`Block.option`; raises :class:`A2lParseError` at an option written without its value (at the end of
    its block), which the update would otherwise take as missing and insert again."""
    tokens = block.option(keyword)
    if tokens == []:
        own = block.own_tokens
        at = next(token for token in reversed(own) if doc.raw(token) == keyword.encode("ascii"))
        what = f"{block.keyword} {block.name}" if block.name else block.keyword
        raise doc.error(f"{what}: {keyword} without its value", at)
    return tokens

