"""Blocks of the reader (:mod:`workbench.a2l.document`) read into the objects of :mod:`workbench.a2l.objects`.

One function per block keyword. Each reads the block's positional parameters and options
once (``Block.layout``), converts numbers with errors located at the token, and returns a
frozen object. Missing parameters and malformed numbers raise :class:`A2lParseError` at
``file:line:column``; what the grammar check (``a2l check``) reports in detail is only
re-checked as far as reading the value needs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from workbench.a2l.byte_order import BYTE_ORDERS
from workbench.a2l.objects import (
    AXIS_NAMES, Alignments, AxisDescr, AxisPts, Blob, Characteristic, CompuMethod, CompuTab, CompuVtab,
    CompuVtabRange, Function, Group, Instance, LayoutEntry, Location, Measurement, ModCommon, Overwrite, RecordLayout,
    StructureComponent, TypedefStructure, Unit,
)
from workbench.a2l.values import is_int, is_number, parse_int, parse_number

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument, Block

__all__ = ["READERS", "read_mod_common"]

_NONE_WORDS = ("NO_INPUT_QUANTITY", "NO_AXIS_PTS", "NO_COMPU_VTAB")
_NO_TOKEN = -1  # the address a typedef lacks
Members = Callable[[str], tuple[tuple[str, ...], tuple[str, ...]]]  # object name -> (functions, groups)


class _Fields:
    """One block's positional parameters and options, read with errors located at their tokens."""

    def __init__(self, doc: "A2lDocument", block: "Block", needed: int, address_slot: int | None = None):
        """``address_slot``: where the address parameter is; a TYPEDEF_ block (the object without its address)
        lacks it, and reads as the object with a hole there (:meth:`address` None)."""
        self.doc = doc
        self.block = block
        args, options = block.layout()
        self.args = list(args)
        self.options: dict[str, list[int]] = {}
        for keyword, tokens in options:
            self.options.setdefault(keyword, tokens)
        self._children: list[tuple[str, int]] | None = None
        typedef = address_slot is not None and block.keyword.startswith("TYPEDEF_")
        if len(self.args) < needed - typedef:
            raise doc.error(f"{self.label}: {needed - typedef} parameters expected, found {len(self.args)}",
                            block.keyword_token)
        if typedef:
            self.args.insert(address_slot, _NO_TOKEN)

    @property
    def label(self) -> str:
        """``KEYWORD name`` for messages."""
        return self.block.keyword + (f" {self.block.name}" if self.block.name else "")

    @property
    def location(self) -> Location:
        return Location(*self.doc.token_position(self.block.begin_token))

    def where(self, token: int) -> Location:
        return Location(*self.doc.token_position(token))

    def text(self, index: int) -> str:
        return self.doc.text(self.args[index])

    def int(self, index: int) -> int:
        return self._int(self.args[index])

    def float(self, index: int) -> float:
        return self._float(self.args[index])

    def address(self, index: int) -> int | None:
        """The address parameter; None for a typedef (the INSTANCE gives it)."""
        return None if self.args[index] == _NO_TOKEN else self.int(index)

    def ident(self, index: int) -> str | None:
        """A name parameter; None for the ASAP2 words that mean "none" (NO_INPUT_QUANTITY ...)."""
        text = self.text(index)
        return None if text in _NONE_WORDS else text

    def has(self, keyword: str) -> bool:
        return keyword in self.options

    def option(self, keyword: str, count: int = 1) -> list[int] | None:
        """The option's parameter tokens, checked to be ``count`` (None when the option is absent)."""
        tokens = self.options.get(keyword)
        if tokens is None:
            return None
        if len(tokens) < count:
            token = tokens[-1] if tokens else self.block.keyword_token
            raise self.doc.error(f"{self.label}: {keyword} needs {count} parameter(s)", token)
        return tokens

    def option_text(self, keyword: str) -> str | None:
        tokens = self.option(keyword)
        return self.doc.text(tokens[0]) if tokens else None

    def option_int(self, keyword: str) -> int | None:
        tokens = self.option(keyword)
        return self._int(tokens[0]) if tokens else None

    def option_float(self, keyword: str) -> float | None:
        tokens = self.option(keyword)
        return self._float(tokens[0]) if tokens else None

    def option_floats(self, keyword: str, count: int) -> tuple[float, ...] | None:
        tokens = self.option(keyword, count)
        return tuple(self._float(t) for t in tokens[:count]) if tokens else None

    def option_ints(self, keyword: str) -> tuple[int, ...] | None:
        tokens = self.options.get(keyword)
        return tuple(self._int(t) for t in tokens) if tokens is not None else None

    def byte_order(self, default: str | None) -> str | None:
        tokens = self.option("BYTE_ORDER")
        if not tokens:
            return default
        word = self.doc.text(tokens[0])
        if word not in BYTE_ORDERS:
            raise self.doc.error(f"{self.label}: unknown BYTE_ORDER {word!r} (expected one of "
                                 f"{', '.join(BYTE_ORDERS)})", tokens[0])
        return BYTE_ORDERS[word]

    @staticmethod
    def ref_tokens(**tokens: int | None) -> dict[str, int]:
        return {name: token for name, token in tokens.items() if token is not None}

    def arg_token(self, index: int) -> int:
        return self.args[index]

    def option_token(self, keyword: str) -> int | None:
        tokens = self.options.get(keyword)
        return tokens[0] if tokens else None

    def children(self, keyword: str) -> list["Block"]:
        if self._children is None:
            table = self.doc.blocks
            self._children = [(table.keyword[row], row) for row in table.children(self.block.index).tolist()]
        return [self.doc.block(row) for child_keyword, row in self._children if child_keyword == keyword]

    def names_in(self, keyword: str) -> tuple[str, ...]:
        """The names listed in the child blocks ``keyword`` (FUNCTION_LIST, REF_CHARACTERISTIC ...)."""
        names: list[str] = []
        for child in self.children(keyword):
            names.extend(self.doc.text(token) for token in child.args)
        return tuple(names)

    def symbol_link(self) -> tuple[str, int] | None:
        tokens = self.option("SYMBOL_LINK", 2)
        return (self.doc.text(tokens[0]), self._int(tokens[1])) if tokens else None

    def _int(self, token: int) -> int:
        raw = self.doc.raw(token)
        if not is_int(raw):
            raise self.doc.error(f"{self.label}: expected an integer, found '{raw.decode('latin-1')}'", token)
        return parse_int(raw)

    def _float(self, token: int) -> float:
        raw = self.doc.raw(token)
        if not is_number(raw):
            raise self.doc.error(f"{self.label}: expected a number, found '{raw.decode('latin-1')}'", token)
        return float(parse_number(raw))


def read_mod_common(doc: "A2lDocument", block: "Block | None") -> ModCommon:
    """MOD_COMMON (ASAP2's defaults when the module has none)."""
    if block is None:
        return ModCommon()
    fields = _Fields(doc, block, 1)
    own = {slot: fields.option_int(keyword) for keyword, slot in Alignments.KEYWORDS.items()}
    return ModCommon(fields.text(0), fields.byte_order("MSB_FIRST"),
                     Alignments(**{slot: value for slot, value in own.items() if value is not None}),
                     fields.option_text("DEPOSIT"), fields.option_int("DATA_SIZE"), fields.option_text("S_REC_LAYOUT"),
                     location=fields.location)


def _measurement(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Measurement:
    f = _Fields(doc, block, 8)
    name = f.text(0)
    address_tokens = f.option("ECU_ADDRESS")
    functions, groups = members(name)
    bit_operation = None
    for child in f.children("BIT_OPERATION"):
        shifts = {grand.keyword: (doc.int_value(grand.args[0]) if grand.args else 0) for grand in child.children}
        bit_operation = (shifts.get("LEFT_SHIFT", 0), shifts.get("RIGHT_SHIFT", 0), "SIGN_EXTEND" in shifts)
    max_refresh = f.option("MAX_REFRESH", 2)
    return Measurement(
        name, f.text(1), f._int(address_tokens[0]) if address_tokens else None,
        f.option_int("ECU_ADDRESS_EXTENSION") or 0, f.option_text("DISPLAY_IDENTIFIER"), f.symbol_link(),
        tuple(dict.fromkeys(functions + f.names_in("FUNCTION_LIST"))), groups,
        location=f.location,
        ref_tokens=f.ref_tokens(conversion=f.arg_token(3)),
        datatype=f.text(2), conversion=f.text(3), resolution=f.float(4), accuracy=f.float(5),
        lower_limit=f.float(6), upper_limit=f.float(7), byte_order=f.byte_order(common.byte_order),
        bit_mask=f.option_int("BIT_MASK"), bit_operation=bit_operation, matrix_dim=f.option_ints("MATRIX_DIM") or (),
        array_size=f.option_int("ARRAY_SIZE"), layout=f.option_text("LAYOUT"), read_write=f.has("READ_WRITE"),
        discrete=f.has("DISCRETE"), format=f.option_text("FORMAT"), phys_unit=f.option_text("PHYS_UNIT"),
        error_mask=f.option_int("ERROR_MASK"), address_type=f.option_text("ADDRESS_TYPE"),
        ref_memory_segment=f.option_text("REF_MEMORY_SEGMENT"),
        max_refresh=(f._int(max_refresh[0]), f._int(max_refresh[1])) if max_refresh else None,
        virtual=f.names_in("VIRTUAL"),
    )


def _axis_descr(doc: "A2lDocument", block: "Block", axis: str) -> AxisDescr:
    f = _Fields(doc, block, 6)
    par = f.option("FIX_AXIS_PAR", 3)
    dist = f.option("FIX_AXIS_PAR_DIST", 3)
    lists = f.children("FIX_AXIS_PAR_LIST")
    return AxisDescr(
        f.text(0), f.ident(1), f.text(2), f.int(3), f.float(4), f.float(5), axis,
        axis_pts_ref=f.option_text("AXIS_PTS_REF"), curve_axis_ref=f.option_text("CURVE_AXIS_REF"),
        fix_axis_par=(f._float(par[0]), f._int(par[1]), f._int(par[2])) if par else None,
        fix_axis_par_dist=(f._float(dist[0]), f._float(dist[1]), f._int(dist[2])) if dist else None,
        fix_axis_par_list=tuple(f._float(t) for t in lists[0].args) if lists else None,
        deposit=f.option_text("DEPOSIT"), monotony=f.option_text("MONOTONY"),
        extended_limits=f.option_floats("EXTENDED_LIMITS", 2), format=f.option_text("FORMAT"),
        phys_unit=f.option_text("PHYS_UNIT"), read_only=f.has("READ_ONLY"), byte_order=f.byte_order(None),
        max_grad=f.option_float("MAX_GRAD"), step_size=f.option_float("STEP_SIZE"), location=f.location,
        ref_tokens=f.ref_tokens(conversion=f.arg_token(2), input_quantity=f.arg_token(1),
                                      axis_pts_ref=f.option_token("AXIS_PTS_REF"),
                                      curve_axis_ref=f.option_token("CURVE_AXIS_REF")),
    )


def _formula_refs(doc: "A2lDocument", f: _Fields, keyword: str) -> tuple[str, tuple[str, ...]] | None:
    children = f.children(keyword)
    if not children or not children[0].args:
        return None
    args = children[0].args
    return doc.text(args[0]), tuple(doc.text(t) for t in args[1:])


def _characteristic(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Characteristic:
    f = _Fields(doc, block, 9, address_slot=3)
    name = f.text(0)
    functions, groups = members(name)
    axes = tuple(_axis_descr(doc, child, axis) for child, axis in zip(f.children("AXIS_DESCR"), AXIS_NAMES))
    return Characteristic(
        name, f.text(1), f.address(3), f.option_int("ECU_ADDRESS_EXTENSION") or 0, f.option_text("DISPLAY_IDENTIFIER"),
        f.symbol_link(), tuple(dict.fromkeys(functions + f.names_in("FUNCTION_LIST"))), groups,
        location=f.location,
        ref_tokens=f.ref_tokens(record_layout=f.arg_token(4), conversion=f.arg_token(6),
                                      comparison_quantity=f.option_token("COMPARISON_QUANTITY")),
        type=f.text(2), record_layout=f.text(4), max_diff=f.float(5), conversion=f.text(6), lower_limit=f.float(7),
        upper_limit=f.float(8), byte_order=f.byte_order(common.byte_order), bit_mask=f.option_int("BIT_MASK"),
        calibration_access=f.option_text("CALIBRATION_ACCESS"), read_only=f.has("READ_ONLY"),
        extended_limits=f.option_floats("EXTENDED_LIMITS", 2), format=f.option_text("FORMAT"),
        phys_unit=f.option_text("PHYS_UNIT"), matrix_dim=f.option_ints("MATRIX_DIM") or (),
        number=f.option_int("NUMBER"), axes=axes, discrete=f.has("DISCRETE"), step_size=f.option_float("STEP_SIZE"),
        comparison_quantity=f.option_text("COMPARISON_QUANTITY"), encoding=f.option_text("ENCODING"),
        ref_memory_segment=f.option_text("REF_MEMORY_SEGMENT"), model_link=f.option_text("MODEL_LINK"),
        dependent_characteristic=_formula_refs(doc, f, "DEPENDENT_CHARACTERISTIC"),
        virtual_characteristic=_formula_refs(doc, f, "VIRTUAL_CHARACTERISTIC"),
    )


def _axis_pts(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> AxisPts:
    f = _Fields(doc, block, 10, address_slot=2)
    name = f.text(0)
    functions, groups = members(name)
    return AxisPts(
        name, f.text(1), f.address(2), f.option_int("ECU_ADDRESS_EXTENSION") or 0, f.option_text("DISPLAY_IDENTIFIER"),
        f.symbol_link(), tuple(dict.fromkeys(functions + f.names_in("FUNCTION_LIST"))), groups,
        location=f.location,
        ref_tokens=f.ref_tokens(input_quantity=f.arg_token(3), record_layout=f.arg_token(4),
                                      conversion=f.arg_token(6)),
        input_quantity=f.ident(3), record_layout=f.text(4), max_diff=f.float(5), conversion=f.text(6),
        max_axis_points=f.int(7), lower_limit=f.float(8), upper_limit=f.float(9),
        byte_order=f.byte_order(common.byte_order), calibration_access=f.option_text("CALIBRATION_ACCESS"),
        read_only=f.has("READ_ONLY"), deposit=f.option_text("DEPOSIT"),
        extended_limits=f.option_floats("EXTENDED_LIMITS", 2), format=f.option_text("FORMAT"),
        phys_unit=f.option_text("PHYS_UNIT"), monotony=f.option_text("MONOTONY"), step_size=f.option_float("STEP_SIZE"),
        ref_memory_segment=f.option_text("REF_MEMORY_SEGMENT"),
    )


def _blob(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Blob:
    f = _Fields(doc, block, 4, address_slot=2)
    name = f.text(0)
    functions, groups = members(name)
    return Blob(name, f.text(1), f.address(2), f.option_int("ECU_ADDRESS_EXTENSION") or 0,
                f.option_text("DISPLAY_IDENTIFIER"), f.symbol_link(), functions, groups, location=f.location,
                size=f.int(3), calibration_access=f.option_text("CALIBRATION_ACCESS"),
                address_type=f.option_text("ADDRESS_TYPE"))


def _compu_method(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> CompuMethod:
    f = _Fields(doc, block, 5)
    formula = formula_inv = None
    for child in f.children("FORMULA"):
        inner = _Fields(doc, child, 1)
        formula, formula_inv = inner.text(0), inner.option_text("FORMULA_INV")
    coeffs = f.option_floats("COEFFS", 6)
    linear = f.option_floats("COEFFS_LINEAR", 2)
    return CompuMethod(
        f.text(0), f.text(1), f.text(2), f.text(3), f.text(4), coeffs, linear, f.option_text("COMPU_TAB_REF"),
        formula, formula_inv, f.option_text("REF_UNIT"), f.option_text("STATUS_STRING_REF"), location=f.location,
        ref_tokens=f.ref_tokens(compu_tab_ref=f.option_token("COMPU_TAB_REF"),
                                      ref_unit=f.option_token("REF_UNIT")),
    )


def _table_entries(f: _Fields, first: int, width: int) -> list[list[int]]:
    """The (count) groups of ``width`` tokens after the count parameter at ``first``."""
    count = f.int(first)
    tokens = f.args[first + 1:]
    if len(tokens) < count * width:
        raise f.doc.error(f"{f.label}: {count} entries announced, {len(tokens) // width} found", f.arg_token(first))
    return [tokens[i * width:(i + 1) * width] for i in range(count)]


def _compu_tab(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> CompuTab:
    f = _Fields(doc, block, 4)
    pairs = tuple((f._float(raw), f._float(phys)) for raw, phys in _table_entries(f, 3, 2))
    return CompuTab(f.text(0), f.text(1), f.text(2), pairs, f.option_text("DEFAULT_VALUE"),
                    f.option_float("DEFAULT_VALUE_NUMERIC"), location=f.location)


def _compu_vtab(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> CompuVtab:
    f = _Fields(doc, block, 4)
    pairs = tuple((f._float(raw), doc.text(text)) for raw, text in _table_entries(f, 3, 2))
    return CompuVtab(f.text(0), f.text(1), pairs, f.option_text("DEFAULT_VALUE"), location=f.location)


def _compu_vtab_range(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> CompuVtabRange:
    f = _Fields(doc, block, 3)
    triples = tuple((f._float(low), f._float(high), doc.text(text)) for low, high, text in _table_entries(f, 2, 3))
    return CompuVtabRange(f.text(0), f.text(1), triples, f.option_text("DEFAULT_VALUE"), location=f.location)


# RECORD_LAYOUT item keyword (without its axis suffix) -> the meaning of its parameters after the position
_LAYOUT_ITEMS = {
    "FNC_VALUES": ("datatype", "mode", "addressing"), "AXIS_PTS": ("datatype", "mode", "addressing"),
    "AXIS_RESCALE": ("datatype", "count", "mode", "addressing"), "NO_AXIS_PTS": ("datatype",),
    "NO_RESCALE": ("datatype",), "SRC_ADDR": ("datatype",), "RIP_ADDR": ("datatype",), "SHIFT_OP": ("datatype",),
    "OFFSET": ("datatype",), "DIST_OP": ("datatype",), "IDENTIFICATION": ("datatype",), "RESERVED": ("datatype",),
}


def _record_layout(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> RecordLayout:
    f = _Fields(doc, block, 1)
    entries = []
    alignments = []
    for keyword, tokens in block.layout()[1]:
        if keyword in Alignments.KEYWORDS:
            alignments.append((Alignments.KEYWORDS[keyword], f._int(f.option(keyword)[0])))
            continue
        if keyword in ("STATIC_RECORD_LAYOUT", "STATIC_ADDRESS_OFFSETS"):
            continue
        base, axis = keyword, None
        if keyword not in _LAYOUT_ITEMS:
            base, _, axis = keyword.rpartition("_")
        if base == "FIX_NO_AXIS_PTS":
            entries.append(LayoutEntry(base, axis, None, count=_checked_int(f, keyword, tokens, 1)))
            continue
        meaning = _LAYOUT_ITEMS.get(base)
        if meaning is None or (axis is not None and axis not in AXIS_NAMES + ("W",)):
            raise doc.error(f"{f.label}: unknown record layout item {keyword}", tokens[0] - 1 if tokens else
                            block.keyword_token)
        values = dict(zip(meaning, (doc.text(t) for t in tokens[1:])))
        entries.append(LayoutEntry(base, axis, _checked_int(f, keyword, tokens, 1 + len(meaning)),
                                   values.get("datatype"), values.get("mode"), values.get("addressing"),
                                   int(values["count"]) if values.get("count", "").isdigit() else None))
    entries.sort(key=lambda entry: (entry.position is None, entry.position or 0))
    return RecordLayout(f.text(0), tuple(entries), tuple(alignments), f.has("STATIC_RECORD_LAYOUT"),
                        f.has("STATIC_ADDRESS_OFFSETS"), location=f.location)


def _checked_int(f: _Fields, keyword: str, tokens: list[int], count: int) -> int:
    """The first parameter (an int) of a record layout item that must have ``count`` parameters."""
    if len(tokens) < count:
        raise f.doc.error(f"{f.label}: {keyword} needs {count} parameter(s)", tokens[-1] if tokens else
                          f.block.keyword_token)
    return f._int(tokens[0])


def _unit(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Unit:
    f = _Fields(doc, block, 4)
    exponents = f.option_ints("SI_EXPONENTS")
    return Unit(f.text(0), f.text(1), f.text(2), f.text(3), f.option_text("REF_UNIT"), exponents,
                f.option_floats("UNIT_CONVERSION", 2), location=f.location)


def _function(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Function:
    f = _Fields(doc, block, 2)
    return Function(f.text(0), f.text(1), f.option_text("FUNCTION_VERSION"), f.names_in("DEF_CHARACTERISTIC"),
                    f.names_in("REF_CHARACTERISTIC"), f.names_in("IN_MEASUREMENT"), f.names_in("OUT_MEASUREMENT"),
                    f.names_in("LOC_MEASUREMENT"), f.names_in("SUB_FUNCTION"), location=f.location)


def _group(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Group:
    f = _Fields(doc, block, 2)
    return Group(f.text(0), f.text(1), f.has("ROOT"), f.names_in("REF_CHARACTERISTIC"), f.names_in("REF_MEASUREMENT"),
                 f.names_in("SUB_GROUP"), f.names_in("FUNCTION_LIST"), location=f.location)


def _instance(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> Instance:
    f = _Fields(doc, block, 4)
    name = f.text(0)
    functions, groups = members(name)
    max_refresh = f.option("MAX_REFRESH", 2)
    return Instance(
        name, f.text(1), f.int(3), f.option_int("ECU_ADDRESS_EXTENSION") or 0, f.option_text("DISPLAY_IDENTIFIER"),
        f.symbol_link(), functions, groups, location=f.location, ref_tokens=f.ref_tokens(typedef=f.arg_token(2)),
        typedef=f.text(2), matrix_dim=f.option_ints("MATRIX_DIM") or (), address_type=f.option_text("ADDRESS_TYPE"),
        calibration_access=f.option_text("CALIBRATION_ACCESS"), read_write=f.has("READ_WRITE"),
        layout=f.option_text("LAYOUT"), max_refresh=(f._int(max_refresh[0]), f._int(max_refresh[1])) if max_refresh
        else None, model_link=f.option_text("MODEL_LINK"),
        overwrites=tuple(_overwrite(doc, child) for child in f.children("OVERWRITE")),
    )


def _overwrite(doc: "A2lDocument", block: "Block") -> Overwrite:
    f = _Fields(doc, block, 2)
    return Overwrite(f.text(0), f.int(1), f.option_text("CONVERSION"), f.option_floats("EXTENDED_LIMITS", 2),
                     f.option_text("FORMAT"), f.option_text("INPUT_QUANTITY"), f.option_floats("LIMITS", 2),
                     f.option_text("MONOTONY"), f.option_text("PHYS_UNIT"), location=f.location)


def _typedef_structure(doc: "A2lDocument", block: "Block", common: ModCommon, members: Members) -> TypedefStructure:
    f = _Fields(doc, block, 3)
    components = []
    for child in f.children("STRUCTURE_COMPONENT"):
        c = _Fields(doc, child, 3)
        components.append(StructureComponent(
            c.text(0), c.text(1), c.int(2), c.option_ints("MATRIX_DIM") or (), c.option_text("ADDRESS_TYPE"),
            c.option_text("LAYOUT"), c.option_text("SYMBOL_TYPE_LINK"), location=c.location,
            ref_tokens=c.ref_tokens(typedef=c.arg_token(1), offset=c.arg_token(2))))
    return TypedefStructure(f.text(0), f.text(1), f.int(2), tuple(components), f.option_text("ADDRESS_TYPE"),
                            f.option_text("SYMBOL_TYPE_LINK"), location=f.location)


READERS = {
    "MEASUREMENT": _measurement, "CHARACTERISTIC": _characteristic, "AXIS_PTS": _axis_pts, "BLOB": _blob,
    "COMPU_METHOD": _compu_method, "COMPU_TAB": _compu_tab, "COMPU_VTAB": _compu_vtab,
    "COMPU_VTAB_RANGE": _compu_vtab_range, "RECORD_LAYOUT": _record_layout, "UNIT": _unit, "FUNCTION": _function,
    "GROUP": _group, "INSTANCE": _instance, "TYPEDEF_STRUCTURE": _typedef_structure,
    # a typedef reads as the object it makes, without an address (the INSTANCE places it)
    "TYPEDEF_MEASUREMENT": _measurement, "TYPEDEF_CHARACTERISTIC": _characteristic, "TYPEDEF_AXIS": _axis_pts,
    "TYPEDEF_BLOB": _blob,
}
