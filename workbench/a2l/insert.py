"""``insert``: new MEASUREMENTs and CHARACTERISTICs from the ELF's variables (a2ltool's ``--measurement-regex``,
``--characteristic-range``, ``--target-group`` ...).

The DWARF variables at file scope and in namespaces are walked with their members and elements, each
named as a2ltool names it (``outer.arr[2].c``; ``outer.arr._2_.c`` in files older than ASAP2 1.70). What
selects one for a kind of object:

- a regular expression that matches its whole name (as a2ltool: a pattern that starts with ``^`` or ends
  with ``$`` is searched as written); a struct or union it matches brings every member, an array of
  structs every element's members;
- an address range ``[MIN, MAX)`` that holds its first byte (an ELF section: its addresses);
- its symbol path, named alone (a2ltool's ``--measurement``/``--characteristic``; a struct: its members).

A scalar (base type or enum, a bitfield with its BIT_MASK) or an array of scalars becomes one object:
a MEASUREMENT (MATRIX_DIM for an array), or a CHARACTERISTIC VALUE (an array: a VAL_BLK with MATRIX_DIM)
whose RECORD_LAYOUT holds ``FNC_VALUES 1 <type> ROW_DIR DIRECT`` (an equal layout of the MODULE is used,
else one is added, named ``__<type>_Z`` as a2ltool and Vector's tools name it). An array not selected
whole is walked element by element; pointers and functions become nothing. The data type and limits
follow the C type (:mod:`workbench.a2l.datatypes`), an enum gets its COMPU_METHOD TAB_VERB and COMPU_VTAB
(:mod:`workbench.a2l.update.enums`), everything else the identity conversion ``NO_COMPU_METHOD``.

Nothing the file has changes: a name the MODULE has already is reported and left alone (as is a variable
an object of the kind describes under another name, or a member of a variable one describes whole; an
AXIS_PTS describes as a calibration). As a2ltool names them, a variable selected for both
kinds gets the CHARACTERISTIC named ``CHARACTERISTIC.<name>``, and one named as an ASAP2 keyword (``EPK``,
a name A2L readers refuse) ``MEASUREMENT.EPK``. The new blocks go before
``/end MODULE`` in the file's indentation and newline style; the target GROUP is created there, or an
existing one gets the names in its REF_MEASUREMENT/REF_CHARACTERISTIC. With ``structures`` a struct selected whole
is one INSTANCE of a TYPEDEF_STRUCTURE instead (:mod:`workbench.a2l.insert_structures`).
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass, field, replace
from itertools import product
from math import prod
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from workbench.a2l import grammar
from workbench.a2l.addressed import KEYWORDS as ADDRESSED, AddressedObjects
from workbench.a2l.datatypes import array_dims, c_limits, datatype_for, element_type
from workbench.a2l.document import A2lDocument, Block, load_a2l
from workbench.a2l.edits import Edit, Edits, indentation_of, newline_bytes, write_source
from workbench.a2l.patterns import as_typed, literal_prefixes, required_text, selection_pattern, stops_before
from workbench.a2l.reports import finding_at, findings_at, written_line
from workbench.a2l.update.enums import NO_COMPU_METHOD, enum_conversion_blocks, enum_conversion_name, indented
from workbench.a2l.values import is_ident, quote_string
from workbench.elf.debugdata import DebugData, read_beside
from workbench.elf.lookup import Variable
from workbench.errors import InputError, UnknownSymbolError
from workbench.findings import Finding, Report, Severity
from workbench.progress import Progress, report as report_progress

if TYPE_CHECKING:
    from collections.abc import Iterator

    from workbench.elf.ctypes_model import CMember, CType

__all__ = ["InsertReport", "InsertResult", "Selection", "insert_document", "insert_file"]

KINDS = ("MEASUREMENT", "CHARACTERISTIC")
_SCALARS = ("base", "enum")
_GROUPS = ("struct", "union")
_KEYWORDS = frozenset((*grammar.BLOCKS, *grammar.OPTIONS, *grammar.TOP_LEVEL_OPTIONS))
_KIND_OF = {"AXIS_PTS": "CHARACTERISTIC"}  # the kind of object that describes a variable as a calibration too
_NONE: frozenset[str] = frozenset()
_STEP = re.compile(r"\.|\[")  # where a member or element name starts in a path
_LINE = 100  # names of a REF_MEASUREMENT/REF_CHARACTERISTIC are wrapped at about this many columns


@dataclass(frozen=True)
class Selection:
    """The variables to insert as one kind of object: by name pattern, address range ``[low, high)``, ELF section
    (its addresses) or symbol path."""

    regexes: tuple[str, ...] = ()
    ranges: tuple[tuple[int, int], ...] = ()
    paths: tuple[str, ...] = ()
    sections: tuple[str, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.regexes or self.ranges or self.paths or self.sections)


@dataclass
class InsertReport(Report):
    """Findings of an insert, and the names inserted by block (``{"MEASUREMENT": ["outer.a", ...], ...}``; with
    ``--structures`` a struct inserted as one INSTANCE is under ``"INSTANCE"``)."""

    inserted: dict[str, list[str]] = field(default_factory=lambda: {keyword: [] for keyword in (*KINDS, "INSTANCE")})

    def to_dict(self) -> dict:
        return {**super().to_dict(), "inserted": self.inserted}

    def summary(self, output: str | Path | None) -> str:
        """The one line the CLI and the GUI say after ``output`` is written (None: a dry run)."""
        counts = ", ".join(f"{len(names)} {keyword}" for keyword, names in self.inserted.items() if names) or "nothing"
        skipped = len(self.of_kind("exists")) + len(self.of_kind("already-described"))
        tail = f" ({skipped} existed already)" if skipped else ""
        return written_line(output, "insert", "inserted", counts, tail)


@dataclass
class InsertResult:
    data: bytes  # the main file with the new blocks (the input's encoding, without BOM)
    report: InsertReport


class _Leaf(NamedTuple):
    """A variable, member or element that becomes an object."""

    path: str
    address: int
    ctype: "CType"
    bit_size: int | None = None
    bit_position: int | None = None
    spec: str = ""  # Vector's suffix that tells variables of one name apart, for the SYMBOL_LINK

    @property
    def symbol(self) -> str:
        return self.path + self.spec


class _Rules:
    """One kind's selection, compiled, counting what each pattern and range selected."""

    def __init__(self, kind: str, selection: Selection, debug: DebugData):
        self.kind = kind
        self.patterns: list[tuple[str, re.Pattern]] = []
        for text in selection.regexes:
            try:
                self.patterns.append((text, selection_pattern(text)))
            except re.error as exc:
                raise InputError(f"--{kind.lower()}-regex {text!r}: not a regular expression ({exc})") from None
        option = f"--{kind.lower()}"
        self.options: dict[tuple[int, int], str] = {}  # range -> the option that gave it
        for low, high in selection.ranges:
            if low >= high:
                raise InputError(f"{option}-range 0x{low:X} 0x{high:X}: the start must lie below the end")
            self.options[(low, high)] = f"{option}-range 0x{low:X} 0x{high:X}"
        for name in selection.sections:
            section = debug.elf.sections.get(name)
            if section is None or not section.allocated:
                known = ", ".join(n for n, s in debug.elf.sections.items() if s.allocated and s.size)
                raise InputError(f"{option}-section {name}: {debug.path.name} has no such section in memory "
                                 f"(it has {known})")
            self.options.setdefault((section.address, section.address + section.size), f"{option}-section {name}")
        self.ranges = list(self.options)
        self.names = _Names([pattern for _, pattern in self.patterns])
        self.paths = list(selection.paths)
        self.matched: Counter[str] = Counter()
        self.in_range: Counter[tuple[int, int]] = Counter()

    def named(self, path: str) -> bool:
        found = False
        for text, pattern in self.patterns:
            if pattern.search(path):
                self.matched[text] += 1
                found = True
        return found

    def may_hold(self, address: int, size: int) -> bool:
        """Whether a range holds a byte of ``[address, address + size)``."""
        return any(low < address + max(size, 1) and address < high for low, high in self.ranges)

    def holds_whole(self, address: int, size: int) -> bool:
        """Whether a range holds every byte of ``[address, address + size)``."""
        return any(low <= address and address + size <= high for low, high in self.ranges)

    def holds(self, address: int) -> bool:
        found = False
        for low, high in self.ranges:
            if low <= address < high:
                self.in_range[(low, high)] += 1
                found = True
        return found


class _Names:
    """What some patterns may match, from Python's parse of them (the texts their matches start with, a text each
    holds, whether they match past a variable's name): the variables and members none can name are skipped."""

    def __init__(self, patterns: list[re.Pattern]):
        prefixes = [literal_prefixes(pattern) for pattern in patterns]
        self.any = any(found is None or "" in found for found in prefixes)
        self.starts = tuple(prefix for found in prefixes if found is not None for prefix in found)
        self.heads = frozenset(start[:end] for start in self.starts for end in range(len(start)))
        # a pattern that cannot match past a variable's name (into ".member", "[2]") matches the name of every
        # variable it selects: the name alone is matched
        stops = [stops_before(pattern, ".[") for pattern in patterns]
        self.name_searches = [pattern.search for pattern, stop in zip(patterns, stops) if stop]
        # the others, with a text each of their matches holds ("" for none): one a path cannot hold, as its name
        # and suffix hold neither (a text without "." and "[" lies in one of them), needs no search
        held = [required_text(pattern) for pattern in patterns]
        self.path_searches = [(pattern.search, "" if "." in text or "[" in text else text)
                              for pattern, stop, text in zip(patterns, stops, held) if not stop]

    def may_name(self, path: str) -> bool:
        """Whether a pattern may match ``path`` or a name that starts with it (a member, an element)."""
        return self.any or path.startswith(self.starts) or path in self.heads

    def may_name_any(self, variables: list[Variable]) -> list[Variable]:
        """The variables whose names :meth:`may_name` (one pass: a big ELF has 50,000)."""
        if self.any:
            return variables
        starts, heads = self.starts, self.heads
        return [variable for variable in variables if variable.name.startswith(starts) or variable.name in heads]

    def match_one(self, variable: Variable, suffixes: _Suffixes) -> bool:
        """Whether a pattern matches the name of ``variable`` or the path of one of its members and elements."""
        name = variable.name
        for search in self.name_searches:
            if search(name):
                return True
        if self.path_searches:
            paths, text = suffixes.of_variable(variable)
            for search, required in self.path_searches:
                if (required in name or required in text) and any(map(search, map(name.__add__, paths))):
                    return True
        return False


def insert_document(doc: A2lDocument, debug: DebugData, *, measurements: Selection = Selection(),
                    characteristics: Selection = Selection(), target_group: str | None = None,
                    module: str | None = None, structures: bool = False, old_arrays: bool = False,
                    progress: Progress | None = None) -> InsertResult:
    """``doc`` with the objects ``measurements`` and ``characteristics`` select from ``debug``'s variables
    (see the module docstring); the document itself is not changed. ``structures``: a struct selected whole is
    one INSTANCE of a TYPEDEF_STRUCTURE (a2ltool's ``--enable-structures``, :mod:`workbench.a2l.insert_structures`).
    ``old_arrays``: elements named ``a._2_`` and MATRIX_DIM with three numbers in an ASAP2 1.70+ file too, as
    before 1.70 (a2ltool's ``--old-arrays``: for tools that read only those).

    Raises :class:`InputError` for a bad pattern or range, a ``target_group`` that is no A2L name, an ELF
    without DWARF, and new text that would fall into an ``/include``d file; :class:`A2lParseError` for a
    MODULE that is not there (``module``: its name, needed when the file has several).
    """
    rules = {kind: _Rules(kind, selection, debug) for kind, selection in zip(KINDS, (measurements, characteristics))}
    if target_group is not None and not is_ident(target_group.encode("latin-1", "replace")):
        raise InputError(f"--target-group {target_group!r}: not an A2L name")
    if not debug.has_dwarf:
        raise InputError(f"{debug.path}: has no DWARF variables (stripped, or built without -g): insert needs "
                         "their types")
    if module is None and len(doc.modules) > 1:
        raise InputError(f"{doc.name}: {len(doc.modules)} MODULEs ({', '.join(m.name or '?' for m in doc.modules)}): "
                         "name the one to insert into (--module NAME)")
    block = doc.module(module)
    inserter = _Inserter(doc, block, debug, rules)
    version_170 = inserter.new_arrays
    inserter.new_arrays = version_170 and not old_arrays
    if structures:
        from workbench.a2l.insert_structures import StructureTypedefs

        if not version_170:
            raise InputError(f"{doc.name}: --structures writes TYPEDEF_STRUCTUREs and INSTANCEs, which ASAP2 has "
                             "from version 1.70 on; the file's ASAP2_VERSION is older")
        inserter.structures = StructureTypedefs(inserter)
    inserter.walk_variables(progress)
    for rule in rules.values():
        for path in rule.paths:
            inserter.walk_path(rule.kind, path)
    inserter.report_unmatched()
    return inserter.result(target_group)


def insert_file(a2l: str | Path, elf: str | Path, output: str | Path | None, *,
                measurements: Selection = Selection(), characteristics: Selection = Selection(),
                target_group: str | None = None, module: str | None = None, structures: bool = False,
                old_arrays: bool = False, cache_dir: str | Path | None = None, use_cache: bool = True,
                progress: Progress | None = None) -> InsertReport:
    """Read ``a2l`` and ``elf``, insert (see :func:`insert_document`) and write ``output`` atomically (which
    may be ``a2l``); ``output=None`` writes nothing (a dry run)."""
    doc, debug_data = read_beside(lambda: load_a2l(a2l, validate=False), elf, cache_dir=cache_dir,
                                  use_cache=use_cache, progress=progress)
    with debug_data as debug:
        result = insert_document(doc, debug, measurements=measurements, characteristics=characteristics,
                                 target_group=target_group, module=module, structures=structures,
                                 old_arrays=old_arrays, progress=progress)
    if output is not None:
        write_source(doc.source, result.data, output)
    return result.report


class _Inserter:
    """Walks the variables, decides each object, and renders the new blocks."""

    def __init__(self, doc: A2lDocument, module: Block, debug: DebugData, rules: dict[str, _Rules]):
        self.doc, self.module, self.debug, self.rules = doc, module, debug, rules
        self.report = InsertReport("insert")
        self.active = [rule for rule in rules.values() if rule.patterns or rule.ranges]  # what the walk asks
        self.ranged = [rule for rule in self.active if rule.ranges]
        self.new_arrays, self.symbol_links = _version_features(doc)
        self.taken: dict[str, tuple[str, str, int]] = {}  # the file's object names -> (keyword, symbol, name token)
        # (kind, symbol) -> the object that describes the variable as that kind (an AXIS_PTS as a calibration)
        self.described: dict[tuple[str, str], str] = {}
        objects = AddressedObjects(doc)
        numbers, name_tokens = objects.keyword_numbers.tolist(), objects.name_tokens.tolist()
        for row, parent in enumerate(doc.blocks.parent[objects.blocks].tolist()):
            if parent == module.index:
                keyword, name, symbol = ADDRESSED[numbers[row]], objects.names[row], objects.symbols[row]
                self.taken[name] = (keyword, symbol, name_tokens[row])
                self.described.setdefault((_KIND_OF.get(keyword, keyword), symbol), name)
        self.blocks: dict[str, list[bytes]] = {}  # keyword -> the new blocks' text (a blank line first), in order
        children = module.children
        # the MODULE's blocks' indentation: the one most of them have (the first may be an A2ML /include'd at 0)
        indents = Counter(indentation_of(doc.data, child.span[0]) for child in children[::len(children) // 256 + 1])
        self.indent = (indents.most_common(1)[0][0] if indents
                       else indentation_of(doc.data, module.span[0]) + b"  ").decode(doc.encoding)
        self.newline = newline_bytes(doc).decode("ascii")
        self.encoding = doc.encoding
        self.types: dict[tuple, tuple[str, str, int | None] | str] = {}  # see _typed
        self.planned: dict[str, tuple[str, str]] = {}  # new object name -> (its keyword, its symbol)
        self.layouts: dict[str, str] = {}  # data type -> the RECORD_LAYOUT its CHARACTERISTICs use
        self.conversions: set[str] = {block.name for block in module.children_named("COMPU_METHOD")}
        self.structures = None  # StructureTypedefs with --structures
        self.referenced: dict[str, list[str]] = {kind: [] for kind in KINDS}  # what a GROUP refers to, INSTANCEs too
        self.at_tokens: list[tuple[int, int]] = []  # (a finding's index in the report, the token it is at)
        self.bounds: dict[int, list[tuple[int, int]]] = {}  # DWARF type offset -> see _may_hold

    # -- what to insert ---------------------------------------------------------------------------
    def walk_variables(self, progress: Progress | None) -> None:
        """Every variable with its members and elements. A name several variables have (file statics of several
        units, statics of several functions) is the first one's, with a SYMBOL_LINK that says which (Vector's
        ``name{Function:f}{CompileUnit:unit_c}{Namespace:Global}``, as a2ltool writes it)."""
        variables = self.debug.variables()
        names = _Names([pattern for rule in self.active for _, pattern in rule.patterns])
        if not self.ranged:  # what no pattern can name is known without its type (a range may hold anything)
            variables = names.may_name_any(variables)
        by_name: dict[str, list] = {}
        for variable in variables:
            if variable.address is not None and variable.type_offset is not None:
                by_name.setdefault(variable.name, []).append(variable)  # a2ltool's names: without their scopes
        # ... and with it, before the walk: a variable none of whose paths a pattern matches, and of which no range
        # holds a byte, yields nothing (the walk costs ~6 us a member or element, a match of its path ~0.5: 1,000
        # of 50,000 variables whose names start alike, 0.40 -> 0.05 s)
        suffixes = _Suffixes(self.debug, self.new_arrays)
        by_name = {name: found for name, found in by_name.items()
                   if names.match_one(found[0], suffixes) or self.ranged and any(map(self._may_hold, found))}
        for number, (name, found) in enumerate(by_name.items()):
            if number % 256 == 0:
                report_progress(progress, number, len(by_name), "walking the ELF's variables")
            first, *others = found
            self._walk(_Leaf(name, first.address, self.debug.type_of(first), spec=_vector_spec(first) if others
                             else ""), frozenset())
            for other in others:
                if any(rule.named(name) or rule.holds(other.address) for rule in self.rules.values()):
                    self._skip("ambiguous", name, f"{name}{_vector_spec(other)}: {len(found)} variables have this "
                               f"name; the objects are {name}{_vector_spec(first)}'s: not inserted",
                               Severity.WARNING)

    def walk_path(self, kind: str, path: str) -> None:
        """``path`` named alone for ``kind`` (a2ltool's -M/-C)."""
        try:
            symbol = self.debug.resolve(path)
        except UnknownSymbolError:
            from workbench.elf.suggest import missing_symbol_reason  # with the closest name: a typo in -M/-C

            self._skip("symbol-not-found", path, f"{kind} {path}: {missing_symbol_reason(self.debug, path)}",
                       Severity.WARNING)
            return
        if symbol.type is None:
            self._skip("type-unknown", path, f"{kind} {path}: no DWARF type", Severity.WARNING)
            return
        self._walk(_Leaf(path, symbol.address, symbol.type, symbol.bit_size, symbol.bit_position),
                   frozenset((kind,)), named=True)

    def _walk(self, leaf: _Leaf, inherited: frozenset[str], named: bool = False) -> None:
        """Insert ``leaf`` (or its members and elements) for the kinds that select it. ``inherited``: the kinds
        an enclosing struct's name selected."""
        by_name = frozenset([rule.kind for rule in self.active if rule.named(leaf.path)])
        by_range = frozenset([rule.kind for rule in self.ranged if rule.holds(leaf.address)]) if self.ranged else \
            _NONE
        selected = inherited | by_name | by_range
        ctype = leaf.ctype
        element = element_type(ctype)
        if ctype.kind in _SCALARS or leaf.bit_size or (ctype.kind == "array" and element.kind in _SCALARS):
            for kind in KINDS:
                if kind in selected:
                    self._object(kind, leaf)
            if not selected and ctype.kind == "array" and self._may_select(leaf):  # perhaps some of its elements
                self._elements(leaf, element, inherited)
            return
        passed = inherited | by_name
        if not (passed or named or self._may_select(leaf)):
            return  # nothing in it can be selected
        whole = passed | frozenset(kind for kind in by_range if self.rules[kind].holds_whole(leaf.address, ctype.size))
        if self.structures is not None and whole and element.kind in _GROUPS and self.structures.takes(leaf):
            for kind in KINDS:
                if kind in whole:
                    self._object(kind, leaf, "INSTANCE")
            return
        if ctype.kind in _GROUPS:
            for member in _members(ctype):
                if member.offset is not None:
                    self._walk(_Leaf(leaf.path + _member_step(member), leaf.address + member.offset, member.type,
                                     member.bit_size, member.bit_position, leaf.spec), passed)
        elif ctype.kind == "array" and element.kind in _GROUPS:
            self._elements(leaf, element, passed)
        elif by_name or named:
            self._skip("not-insertable", leaf.path, f"{leaf.path}: a {ctype.kind} ({ctype.display_name}) is no "
                       "value to measure or calibrate: not inserted", Severity.INFO)

    def _may_hold(self, variable: Variable) -> bool:
        """Whether a range holds a byte of ``variable`` (:meth:`_Rules.may_hold` as bounds of its address)."""
        bounds = self.bounds.get(variable.type_offset)
        if bounds is None:
            size = max(self.debug.type_of(variable).size, 1)
            bounds = self.bounds[variable.type_offset] = [(low - size, high) for rule in self.ranged
                                                          for low, high in rule.ranges]
        address = variable.address
        for low, high in bounds:
            if low < address < high:
                return True
        return False

    def _may_select(self, leaf: _Leaf) -> bool:
        """Whether a pattern may name ``leaf`` or a member or element of it, or a range hold a byte of it."""
        return any(rule.names.may_name(leaf.path) or rule.may_hold(leaf.address, leaf.ctype.size)
                   for rule in self.active)

    def _elements(self, leaf: _Leaf, element: "CType", inherited: frozenset[str]) -> None:
        for number, step in enumerate(_element_steps(array_dims(leaf.ctype), self.new_arrays)):
            self._walk(_Leaf(leaf.path + step, leaf.address + number * element.size, element, spec=leaf.spec),
                       inherited)

    def _object(self, kind: str, leaf: _Leaf, keyword: str | None = None) -> None:
        """``leaf`` inserted as an object of ``kind`` (``keyword`` INSTANCE: a struct as one INSTANCE of its
        TYPEDEF_STRUCTURE, made by :mod:`workbench.a2l.insert_structures`), unless the file describes it."""
        name, symbol = leaf.path.replace("::", "__"), leaf.symbol  # a C++ name's "::" as a2ltool writes it
        for whole in (*_enclosing(leaf.path, leaf.spec), symbol):
            found = self.described.get((kind, whole))
            if found is not None:
                keyword = self.taken[found][0] if found in self.taken else kind
                what = f"{keyword} {found} describes {symbol} already" if whole == symbol else \
                    f"it lies in {whole}, which {keyword} {found} describes"
                self._skip("already-described", name, f"{kind} {name}: {what}: not inserted", Severity.INFO,
                           self.taken[found][2] if found in self.taken else None)
                return
        owner = self.taken.get(name)
        if owner is not None:  # the file's: left alone
            if owner[1] == symbol:
                self._skip("exists", name, f"{kind} {name}: {owner[0]} {name} describes {symbol} already: not "
                           "inserted", Severity.INFO, owner[2])
            else:
                self._skip("exists", name, f"{kind} {name} for {symbol}: the name is taken by {owner[0]} {name} "
                           f"(SYMBOL_LINK {owner[1]}): not inserted", Severity.WARNING, owner[2])
            return
        planned = self.planned.get(name)
        if name in _KEYWORDS or planned is not None:
            # an ASAP2 keyword (a variable called EPK) is no name A2L readers take; a variable selected for both kinds
            # has the other kind's object by its name: KIND.name, as a2ltool names the second object of a variable
            name = f"{kind}.{name}"
            if name in self.taken or name in self.planned:
                self._skip("exists", name, f"{kind} {name} for {symbol}: the name is taken: not inserted",
                           Severity.WARNING, self.taken[name][2] if name in self.taken else None)
                return
        if not is_ident(name.encode("latin-1", "replace")):
            self._skip("bad-name", name, f"{kind} {name}: not an A2L name: not inserted", Severity.WARNING)
            return
        keyword = keyword or kind
        rendered = self.structures.instance(kind, name, leaf) if keyword == "INSTANCE" else \
            self._render(kind, name, leaf)
        if rendered is None:
            return
        text, what = rendered
        self.blocks.setdefault(keyword, []).append(text)
        self.planned[name] = (kind, symbol)
        self.described[(kind, symbol)] = name
        self.report.inserted[keyword].append(name)
        self.referenced[kind].append(name)
        self.report.add(Finding("inserted", name, f"{keyword} {name} inserted (0x{leaf.address:X}, {what})",
                                block=keyword))

    # -- the blocks ------------------------------------------------------------------------------
    def _render(self, kind: str, name: str, leaf: _Leaf) -> tuple[bytes, str] | None:
        """The object's block (a blank line first, indented) and its data type, or None when the C type has no A2L
        form (reported)."""
        element = element_type(leaf.ctype)
        typed = self._typed(element, leaf.bit_size, leaf.bit_position)
        if typed.__class__ is str:
            self._skip("no-datatype" if leaf.bit_size is None else "bit-mask-unrepresentable", name,
                       f"{kind} {name}: {typed}: not inserted", Severity.WARNING)
            return None
        datatype, limits, mask = typed
        conversion = self._conversion(element, name)
        dims = () if leaf.bit_size else array_dims(leaf.ctype)
        n, i = self.newline, self.indent
        items = f"{n}{i}  BIT_MASK 0x{mask:X}" if mask is not None else ""
        if kind == "MEASUREMENT":
            head = f"measurement for symbol {leaf.path}"
            first = f"{datatype} {conversion} 0 0 {limits}"
            items += f"{n}{i}  ECU_ADDRESS 0x{leaf.address:X}"
        else:
            head = f"characteristic for {leaf.path}"
            first = (f"{'VAL_BLK' if dims else 'VALUE'} 0x{leaf.address:X} {self._layout(datatype)} 0 {conversion} "
                     f"{limits}")
        if dims:
            items += f"{n}{i}  MATRIX_DIM " + " ".join(map(str, dims if self.new_arrays else _three(dims)))
        if self.symbol_links:
            items += f"{n}{i}  SYMBOL_LINK {_quoted(leaf.symbol)} 0"
        text = f"{n}{i}/begin {kind} {name} {_quoted(head)}{n}{i}  {first}{items}{n}{i}/end {kind}{n}"
        return text.encode(self.encoding), f"{datatype} [{']['.join(map(str, dims))}]" if dims else datatype

    def _typed(self, element: "CType", bit_size: int | None, bit_position: int | None):
        """(data type, limits as text, BIT_MASK or None) of an element type (and bitfield), or why there is none;
        worked out once per type (a big ELF has few of them)."""
        key = (id(element), bit_size, bit_position)
        found = self.types.get(key)
        if found is not None:
            return found
        datatype, limits, mask = datatype_for(element), c_limits(element, bit_size), None
        if datatype is None or limits is None:
            found = f"{element.display_name} ({element.size} bytes) has no ASAP2 data type"
        elif bit_size and not 0 <= (bit_position or 0) <= 8 * element.size - bit_size:
            found = (f"the bitfield of {bit_size} bits lies across more than the {8 * element.size} bits of its type "
                     "(a packed struct): no BIT_MASK describes it")
        else:
            mask = ((1 << bit_size) - 1) << (bit_position or 0) if bit_size else None
            found = (datatype, " ".join(map(_number, limits)), mask)
        self.types[key] = found
        return found

    def _chunk(self, lines: list[bytes]) -> bytes:
        """A block's lines (/begin, items, /end) as the MODULE's blocks are written, a blank line first."""
        newline, indent = self.newline.encode("ascii"), self.indent.encode(self.doc.encoding)
        return newline + b"".join(line + newline for line in indented(lines, indent))

    def _conversion(self, element: "CType", name: str) -> str:
        if element.kind != "enum" or not element.enumerators:
            return NO_COMPU_METHOD
        conversion = enum_conversion_name(element, name)
        if conversion not in self.conversions:
            self.conversions.add(conversion)
            for keyword, lines in enum_conversion_blocks(self.module, conversion, element):
                self.blocks.setdefault(keyword, []).append(self._chunk(lines))
            self.report.add(Finding("conversion-added", conversion, f"COMPU_METHOD {conversion} added (TAB_VERB: "
                                    f"{len(element.enumerators)} values of enum {element.display_name})",
                                    block="COMPU_METHOD"))
        return conversion

    def _layout(self, datatype: str) -> str:
        """The RECORD_LAYOUT of a CHARACTERISTIC of ``datatype``: an equal one of the MODULE, else a new one."""
        found = self.layouts.get(datatype)
        if found is not None:
            return found
        wanted = ("FNC_VALUES", "1", datatype, "ROW_DIR", "DIRECT")
        existing = self.module.children_named("RECORD_LAYOUT")
        found = next((block.name for block in existing if _layout_items(block) == [wanted]), None)
        if found is None:
            names = {block.name for block in existing}
            found = base = f"__{datatype}_Z"
            number = 1
            while found in names:
                number += 1
                found = f"{base}_{number}"
            self.blocks.setdefault("RECORD_LAYOUT", []).append(self._chunk(
                [f"/begin RECORD_LAYOUT {found}".encode("ascii"), " ".join(wanted).encode("ascii"),
                 b"/end RECORD_LAYOUT"]))
            self.report.add(Finding("record-layout-added", found, f"RECORD_LAYOUT {found} added "
                                    f"(FNC_VALUES of {datatype})", block="RECORD_LAYOUT"))
        self.layouts[datatype] = found
        return found

    # -- reports and the result ------------------------------------------------------------------
    def _skip(self, kind: str, name: str, message: str, severity: Severity, token: int | None = None) -> None:
        if token is not None:  # located in one pass by result(): one by one, 7,000 cost 0.2 s in a big file
            self.at_tokens.append((len(self.report.findings), token))
        self.report.add(Finding(kind, name, message, severity=severity))

    def report_unmatched(self) -> None:
        for rule in self.rules.values():
            option = rule.kind.lower()
            for text, _ in rule.patterns:
                if not rule.matched[text]:
                    self._skip("regex-matched-nothing", text, f"--{option}-regex {as_typed(text)} matches no "
                               f"variable of {self.debug.path.name}", Severity.WARNING)
            for extent, given in rule.options.items():
                if not rule.in_range[extent]:
                    self._skip("range-matched-nothing", given.split(" ", 1)[1], f"{given} holds no variable of "
                               f"{self.debug.path.name}", Severity.WARNING)

    def result(self, target_group: str | None) -> InsertResult:
        doc, module, names = self.doc, self.module, self.referenced
        findings = self.report.findings  # those _skip left at a token get their places
        located = findings_at(doc, [(token, *findings[index][:3], "", findings[index].severity)
                                    for index, token in self.at_tokens])
        for (index, _), finding in zip(self.at_tokens, located):
            findings[index] = finding
        edits = Edits()
        group = _find(module, "GROUP", target_group) if target_group else None
        if target_group and any(names.values()):
            if group is None:
                self.blocks["GROUP"] = [self._chunk(_group_lines(target_group, names))]
                self.report.add(Finding("group-created", target_group, f"GROUP {target_group} created (ROOT)",
                                        block="GROUP"))
            else:
                edits.extend(_group_edits(doc, group, names))
                self.report.add(finding_at(doc, group.name_token, "group-updated", target_group,
                                           f"GROUP {target_group}: {sum(map(len, names.values()))} reference(s) "
                                           "added", "GROUP"))
        order = ("MEASUREMENT", "CHARACTERISTIC", "INSTANCE", "TYPEDEF_MEASUREMENT", "TYPEDEF_CHARACTERISTIC",
                 "TYPEDEF_STRUCTURE", "RECORD_LAYOUT", "COMPU_METHOD", "COMPU_VTAB", "GROUP")
        body = b"".join(text for keyword in order for text in self.blocks.get(keyword, []))
        if body:
            edits.append(_before_end(doc, module, body))
        data = doc.source.data
        for source, file_edits in edits.by_file(doc.source_map):
            if source is not doc.source:
                raise InputError(f"{source.name}: the GROUP {target_group} is in this included file, which insert "
                                 "does not write: merge the includes first (workbench a2l update --merge-includes)")
            data = file_edits.apply(source.data)
        return InsertResult(data, self.report)


def _version_features(doc: A2lDocument) -> tuple[bool, bool]:
    """(array elements as ``[2]``, SYMBOL_LINK allowed) by the file's ASAP2_VERSION (1.70+, 1.60+); a file
    without one is taken as the current version."""
    own = doc.own_tokens(-1)
    for number, token in enumerate(own[:-2]):
        if doc.raw(token) == b"ASAP2_VERSION":
            try:
                version = (int(doc.raw(own[number + 1])), int(doc.raw(own[number + 2])))
            except ValueError:
                break
            return version >= (1, 70), version >= (1, 60)
    return True, True


class _Suffixes:
    """What the walk appends to a variable's name to name its members and elements (``""``, ``.a``, ``.a.b[2]``
    ...), every one, per C type: a variable none of whose paths a pattern matches needs no walk."""

    def __init__(self, debug: DebugData, new_arrays: bool):
        self.debug, self.new_arrays = debug, new_arrays
        # id(type) -> (the type, kept alive; its suffixes; they as one text, a line each)
        self._known: dict[int, tuple["CType", list[str], str]] = {}
        self._of_variables: dict[int, tuple[list[str], str]] = {}  # by the variables' DWARF type offset

    def of_variable(self, variable: Variable) -> tuple[list[str], str]:
        """The suffixes of a variable's type, and they as one text."""
        found = self._of_variables.get(variable.type_offset)
        if found is None:
            found = self._of_variables[variable.type_offset] = self.of(self.debug.type_of(variable))
        return found

    def of(self, ctype: "CType") -> tuple[list[str], str]:
        """The suffixes of a type, and they as one text (a line each)."""
        known = self._known.get(id(ctype))
        if known is None:
            found = self._make(ctype)
            known = self._known[id(ctype)] = (ctype, found, "\n".join(found))
        return known[1:]

    def _make(self, ctype: "CType") -> list[str]:
        found = [""]
        element = element_type(ctype)
        if ctype.kind == "array":
            inner = self.of(element)[0] if element.kind in _GROUPS else [""]
            for step in _element_steps(array_dims(ctype), self.new_arrays):
                found += [step + rest for rest in inner]
        elif ctype.kind in _GROUPS:
            for member in _members(ctype):
                found += [_member_step(member) + rest for rest in self.of(member.type)[0]]
        return found


def _element_steps(dims: tuple[int, ...], new_arrays: bool) -> Iterator[str]:
    """What names each element of an array of ``dims`` after the array's name, in memory order (the last index
    fastest): ``[1][2]``, or ``._1_._2_`` before ASAP2 1.70."""
    for indices in product(*map(range, dims)):
        yield "".join(f"[{i}]" if new_arrays else f"._{i}_" for i in indices)


def _member_step(member: "CMember") -> str:
    """What names ``member`` after its struct's name (nothing for an anonymous struct or union: its members are
    the struct's own)."""
    return f".{member.name}" if member.name else ""


def _members(ctype: "CType") -> list["CMember"]:
    """A struct's members, those of its base classes first (named as its own: ``derived.baseMember``)."""
    inherited = [replace(member, offset=None if base.offset is None or member.offset is None
                         else base.offset + member.offset)
                 for base in ctype.bases for member in _members(base.type)]
    return [*inherited, *ctype.members]


def _enclosing(path: str, spec: str) -> list[str]:
    """The symbols of the variable, members and elements that hold ``path`` (``a.b[2].c``: ``a``, ``a.b``,
    ``a.b[2]``), outermost first, with ``spec`` (Vector's suffix) each."""
    if "." not in path and "[" not in path:  # most: a variable's own name
        return []
    return [path[:match.start()] + spec for match in _STEP.finditer(path) if match.start()]


def _vector_spec(variable: Variable) -> str:
    """Vector's suffix that names one of several variables of a name: ``{Function:f}{Namespace:inner}...
    {CompileUnit:unit_c}{Namespace:Global}`` (innermost namespace first, as a2ltool writes it)."""
    scope = variable.scope[:-1] if variable.function else variable.scope
    function = f"{{Function:{variable.scope[-1]}}}" if variable.function else ""
    namespaces = "".join(f"{{Namespace:{name}}}" for name in reversed(scope))
    unit = f"{{CompileUnit:{variable.unit}}}" if variable.unit else ""
    return f"{function}{namespaces}{unit}{{Namespace:Global}}"


def _three(dims: tuple[int, ...]) -> tuple[int, ...]:
    """MATRIX_DIM before ASAP2 1.70 has exactly three dimensions (x y z): padded with 1, or the innermost
    ones folded into the third."""
    return (*dims, 1, 1)[:3] if len(dims) <= 3 else (*dims[:2], prod(dims[2:]))


def _number(value: int | float) -> str:
    """A limit as a2ltool writes it: integers exactly, floats shortest (``3.4028234663852886e38``)."""
    return str(value) if isinstance(value, int) else repr(value).replace("e+", "e")


def _layout_items(block: Block) -> list[tuple[str, ...]]:
    doc = block.doc
    return [(keyword, *(doc.text(token) for token in params)) for keyword, params in block.layout()[1]]


def _find(module: Block, keyword: str, name: str) -> Block | None:
    return next((block for block in module.children_named(keyword) if block.name == name), None)


def _wrapped(names: list[str]) -> list[str]:
    """Names as lines of about :data:`_LINE` columns."""
    lines, line = [], ""
    for name in names:
        if line and len(line) + 1 + len(name) > _LINE:
            lines.append(line)
            line = name
        else:
            line = f"{line} {name}" if line else name
    return [*lines, line] if line else lines


def _group_lines(name: str, names: dict[str, list[str]]) -> list[bytes]:
    lines = [f'/begin GROUP {name} ""', "ROOT"]
    for kind, listed in names.items():
        if listed:
            lines += [f"/begin REF_{kind}", *("  " + line for line in _wrapped(listed)), f"/end REF_{kind}"]
    return [line.encode("latin-1") for line in lines] + [b"/end GROUP"]


def _group_edits(doc: A2lDocument, group: Block, names: dict[str, list[str]]) -> list[Edit]:
    """The names added to an existing GROUP: into its REF_MEASUREMENT/REF_CHARACTERISTIC, or in a new one."""
    edits, newline = [], newline_bytes(doc)
    indent = indentation_of(doc.data, group.span[0]) + b"  "
    for kind, listed in names.items():
        if not listed:
            continue
        references = group.first(f"REF_{kind}")
        if references is not None:
            inner = indentation_of(doc.data, references.span[0]) + b"  "
            lines = [inner + line.encode(doc.encoding) for line in _wrapped(listed)]
            edits.append(_at_end_line(doc, references.end_token, lines, newline))
        else:
            lines = indented([f"/begin REF_{kind}".encode("ascii"),
                              *(line.encode(doc.encoding) for line in _wrapped(listed)),
                              f"/end REF_{kind}".encode("ascii")], indent)
            edits.append(_at_end_line(doc, group.end_token, lines, newline))
    return edits


def _at_end_line(doc: A2lDocument, end_token: int, lines: list[bytes], newline: bytes) -> Edit:
    """``lines`` inserted before a block's ``/end``: whole lines before its line when it stands alone there, else
    on the line (the names after the block's last token)."""
    start = doc.tokens.starts_list[end_token]
    line_start = doc.data.rfind(b"\n", 0, start) + 1
    if doc.data[line_start:start].strip():
        return Edit(start, start, b" ".join(line.strip() for line in lines) + b" ")
    return Edit(line_start, line_start, b"".join(line + newline for line in lines))


def _before_end(doc: A2lDocument, module: Block, body: bytes) -> Edit:
    """The new blocks' text before ``/end MODULE`` (on a line of its own)."""
    start = doc.tokens.starts_list[module.end_token]
    line_start = doc.data.rfind(b"\n", 0, start) + 1
    if doc.data[line_start:start].strip():  # /end MODULE shares its line with other text
        return Edit(start, start, newline_bytes(doc) + body + indentation_of(doc.data, module.span[0]))
    return Edit(line_start, line_start, body)


def _quoted(text: str) -> str:
    """An A2L string of ``text`` (C names need no escapes; others get them)."""
    return f'"{text}"' if '"' not in text and "\\" not in text else quote_string(text, "utf-8").decode("utf-8")
