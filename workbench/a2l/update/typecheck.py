"""``update --types``: data type, array size, bit mask and limits of an object checked against DWARF.

What the A2L states in the object itself is corrected (MEASUREMENT data type,
MATRIX_DIM/ARRAY_SIZE/NUMBER, BIT_MASK, limits outside the type's range, AXIS_PTS
point count, BLOB size). A CHARACTERISTIC's data type lives in a RECORD_LAYOUT that
other objects share, so a mismatch there is reported, not changed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.a2l.datatypes import array_dims, datatype_for, datatype_range
from workbench.a2l.edits import Edit, indentation_of, newline_bytes, replace_token
from workbench.a2l.reports import finding_at
from workbench.a2l.addressed import Target
from workbench.a2l.values import format_int_like, is_number, parse_number
from workbench.findings import Finding, Severity

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument
    from workbench.elf.debugdata import ResolvedSymbol


class TypeChecker:
    def __init__(self, doc: "A2lDocument"):
        self.doc = doc
        self.record_layouts = _record_layout_datatypes(doc)

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
            findings.append(self._finding(target, target.name_token, "type-not-scalar",
                                          f"{target.name}: {symbol.type.display_name} is a {symbol.type.kind}, "
                                          "not a scalar or array of scalars", Severity.WARNING))
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
        kind = doc.text(target.name_token + 2)
        layout = doc.text(target.name_token + 4)
        stated = self.record_layouts.get(layout)
        needed = datatype_for(symbol.type)
        if kind in ("VALUE", "VAL_BLK") and stated and needed and stated != needed:
            findings.append(self._finding(target, target.name_token + 4, "datatype-mismatch",
                                          f"{target.name}: RECORD_LAYOUT {layout} holds {stated}, "
                                          f"the C type is {needed} ({symbol.type.display_name})", Severity.WARNING))
        if kind == "VAL_BLK":
            self._dims(target, doc.block(target.block), array_dims(symbol.type), edits, findings)
        if stated:
            self._limits(target, target.name_token + 7, target.name_token + 8, stated, edits, findings)
        return edits, findings

    def _axis_pts(self, target: Target, symbol: "ResolvedSymbol"):
        doc, edits, findings = self.doc, [], []
        dims = array_dims(symbol.type)
        count_token = target.name_token + 7
        if len(dims) == 1 and doc.int_value(count_token) != dims[0]:
            edits.append(replace_token(doc, count_token, format_int_like(doc.raw(count_token), dims[0])))
            findings.append(self._finding(target, count_token, "size-updated",
                                          f"{target.name}: MaxAxisPoints {doc.int_value(count_token)} -> {dims[0]}"))
        stated = self.record_layouts.get(doc.text(target.name_token + 4))
        if stated:
            self._limits(target, target.name_token + 8, target.name_token + 9, stated, edits, findings)
        return edits, findings

    def _blob(self, target: Target, symbol: "ResolvedSymbol"):
        size_token = target.name_token + 3
        old = self.doc.int_value(size_token)
        if old == symbol.size:
            return [], []
        return ([replace_token(self.doc, size_token, format_int_like(self.doc.raw(size_token), symbol.size))],
                [self._finding(target, size_token, "size-updated", f"{target.name}: size {old} -> {symbol.size}")])

    # -- shared pieces ----------------------------------------------------------------------
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

    def _limits(self, target: Target, lower_token: int, upper_token: int, datatype: str, edits: list,
                findings: list) -> None:
        limits = datatype_range(datatype)
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


def _record_layout_datatypes(doc: "A2lDocument") -> dict[str, str]:
    """RECORD_LAYOUT name -> the data type of its FNC_VALUES (or AXIS_PTS_X for axis layouts)."""
    found = {}
    for block in doc.blocks_named("RECORD_LAYOUT"):
        for keyword in ("FNC_VALUES", "AXIS_PTS_X"):
            params = block.option(keyword)
            if params and len(params) > 1:
                found[block.name] = doc.text(params[1])
                break
    return found


def _without_ones(dims: tuple[int, ...]) -> tuple[int, ...]:
    return tuple(d for d in dims if d != 1) or (1,)


def _dims_text(dims: tuple[int, ...]) -> str:
    return " ".join(str(d) for d in dims)
