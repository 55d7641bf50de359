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
  reported when the C array is flat and only the total can be compared. An object whose
  C variable is a struct with axes and values in one record is not compared item by item.
- BLOB: its size.
- Limits outside the range of the C type's element are narrowed to it; never to the
  range of a data type the A2L states wrongly (a uint16 calibration whose layout says
  UBYTE keeps its limit of 1000).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from math import prod

from workbench.a2l.addressed import Target
from workbench.a2l.datatypes import array_dims, datatype_for, datatype_range
from workbench.a2l.edits import Edit, indentation_of, newline_bytes, replace_token
from workbench.a2l.reports import finding_at
from workbench.a2l.update.layouts import RecordLayouts
from workbench.a2l.values import format_int_like, is_number, parse_number
from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument
    from workbench.elf.debugdata import ResolvedSymbol


_AXES = {"CURVE": 1, "MAP": 2, "CUBOID": 3, "CUBE_4": 4, "CUBE_5": 5}


class TypeChecker:
    def __init__(self, doc: "A2lDocument"):
        self.doc = doc
        self.layouts = RecordLayouts(doc)

    def check(self, target: Target, symbol: "ResolvedSymbol") -> tuple[list[Edit], list[Finding]]:
        if symbol.type is None:
            return [], [self._finding(target, target.name_token, "type-unknown",
                                      f"{target.name}: {symbol.path} has no DWARF type to check", Severity.WARNING)]
        handler = getattr(self, "_" + target.keyword.lower(), None)
        return handler(target, symbol) if handler else ([], [])

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
        self._dims(target, block, array_dims(symbol.type), edits, findings)
        if symbol.bit_size is not None:
            self._bit_mask(target, block, ((1 << symbol.bit_size) - 1) << (symbol.bit_position or 0), edits, findings)
        self._limits(target, target.name_token + 6, target.name_token + 7, datatype, edits, findings)
        return edits, findings

    def _characteristic(self, target: Target, symbol: "ResolvedSymbol"):
        doc, edits, findings = self.doc, [], []
        block = doc.block(target.block)
        kind = doc.text(target.name_token + 2)
        needed = datatype_for(symbol.type)
        if not self._element_type(target, target.name_token + 4, "FNC_VALUES", symbol, needed, edits, findings):
            return edits, findings
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
            self._bit_mask(target, block, ((1 << symbol.bit_size) - 1) << (symbol.bit_position or 0), edits, findings)
        self._limits(target, target.name_token + 7, target.name_token + 8, needed, edits, findings)
        return edits, findings

    def _axis_pts(self, target: Target, symbol: "ResolvedSymbol"):
        doc, edits, findings = self.doc, [], []
        needed = datatype_for(symbol.type)
        if not self._element_type(target, target.name_token + 4, "AXIS_PTS_X", symbol, needed, edits, findings):
            return edits, findings
        dims = array_dims(symbol.type)
        count_token = target.name_token + 7
        points = prod(dims)
        if len(dims) > 1:
            findings.append(self._finding(target, count_token, "shape-mismatch", f"{target.name}: an axis is one "
                                          f"row of points, the C object is [{']['.join(map(str, dims))}]",
                                          Severity.WARNING))
        elif doc.int_value(count_token) != points:
            edits.append(replace_token(doc, count_token, format_int_like(doc.raw(count_token), points)))
            findings.append(self._finding(target, count_token, "size-updated",
                                          f"{target.name}: MaxAxisPoints {doc.int_value(count_token)} -> {points}"))
        self._limits(target, target.name_token + 8, target.name_token + 9, needed, edits, findings)
        return edits, findings

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
        stated = self.layouts.datatype(name, item)
        if stated == needed:
            return True
        users = self.layouts.users[name]
        alternative = self.layouts.alternative(name, item, needed)
        if alternative is not None:
            edits.append(replace_token(doc, deposit_token, alternative.encode("ascii")))
            findings.append(self._finding(target, deposit_token, "record-layout-updated",
                                          f"{target.name}: RECORD_LAYOUT {name} -> {alternative} ({item} {stated} -> "
                                          f"{needed}, the C type is {symbol.type.display_name})"))
        elif users <= 1:
            token = layout.datatypes[item]
            edits.append(replace_token(doc, token, needed.encode("ascii")))
            findings.append(self._finding(target, token, "datatype-updated",
                                          f"{target.name}: RECORD_LAYOUT {name} {item} {stated} -> {needed} "
                                          "(no other object uses the layout)"))
        else:
            findings.append(self._finding(target, deposit_token, "datatype-mismatch",
                                          f"{target.name}: RECORD_LAYOUT {name} holds {item} {stated}, the C type "
                                          f"is {needed} ({symbol.type.display_name}); {users} objects share the "
                                          f"layout, so it is not changed: give {target.name} a layout of {needed}",
                                          Severity.WARNING))
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
            tokens = block.option(keyword)
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

    def _bit_mask(self, target: Target, block, mask: int, edits: list, findings: list) -> None:
        doc = self.doc
        tokens = block.option("BIT_MASK")
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


def _without_ones(dims: tuple[int, ...]) -> tuple[int, ...]:
    return tuple(d for d in dims if d != 1) or (1,)


def _dims_text(dims: tuple[int, ...]) -> str:
    return " ".join(str(d) for d in dims)
