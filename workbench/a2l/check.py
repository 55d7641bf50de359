"""``check``: syntax, references, names and memory placement of an A2L, each finding located.

Checks: every block against the keyword table (parameters, the words allowed in
enumerated ones); references (:mod:`workbench.a2l.references`: COMPU_METHOD,
RECORD_LAYOUT, typedefs, INSTANCE components, FUNCTION, conversion tables, units,
measurements, axes, groups, memory segments); names defined twice; objects that overlap; objects outside every
MEMORY_SEGMENT; calibrations outside a RAM data segment (CAL RAM). With an ELF, every
object's symbol must exist and its address must match.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from workbench.a2l.addressed import AddressedObjects
from workbench.a2l.datatypes import DATATYPES
from workbench.a2l.document import A2lDocument, Block, load_a2l
from workbench.a2l.grammar import MAX_ADDRESS, NAMESPACES
from workbench.a2l.references import check_references
from workbench.a2l.reports import finding_at
from workbench.a2l.validate import validate_document
from workbench.elf.debugdata import DebugData
from workbench.errors import A2lParseError
from workbench.findings import Finding, Report, Severity
from workbench.progress import Progress, report as report_progress

__all__ = ["check_document", "check_file"]

_CALIBRATIONS = ("CHARACTERISTIC", "AXIS_PTS")


@dataclass(frozen=True)
class _Placed:
    name: str
    keyword: str
    address: int
    size: int
    token: int


def check_file(a2l: str | Path, elf: str | Path | None = None, *, cache_dir: str | Path | None = None,
               use_cache: bool = True, progress: Progress | None = None) -> Report:
    """Load ``a2l`` (syntax errors become findings where the file can still be read) and check it."""
    doc = load_a2l(a2l, validate=False)
    if elf is None:
        return check_document(doc, progress=progress)
    with DebugData(elf, cache_dir=cache_dir, use_cache=use_cache) as debug:
        return check_document(doc, debug, progress=progress)


def check_document(doc: A2lDocument, debug: DebugData | None = None, *, progress: Progress | None = None) -> Report:
    """Every problem of ``doc`` as a finding; the report is clean (``not findings``) only when none."""
    report = Report("check")
    syntax: list[A2lParseError] = []
    validate_document(doc, syntax)
    for error in syntax:
        report.add(Finding("syntax", "", error.reason, error.path, error.line, error.column, "",
                           Severity.ERROR))
    report_progress(progress, 1, 4, "checking references")
    try:
        objects = AddressedObjects(doc)
    except A2lParseError as error:  # an object without its parameters: nothing can be placed
        objects = None
        if not any((f.file, f.line, f.column) == (error.path, error.line, error.column) for f in report.findings):
            report.add(Finding("syntax", "", error.reason, error.path, error.line, error.column, "", Severity.ERROR))
    for module in doc.modules:
        names = _namespaces(doc, module, report)
        check_references(doc, module, names, report)
        report_progress(progress, 2, 4, "checking memory")
        if objects is not None:
            placed = _placements(doc, module, objects, debug, report)
            _overlaps(doc, placed, report)
            _segments(doc, module, placed, report)
    report_progress(progress, 4, 4, "checked")
    report.findings.sort(key=lambda f: (f.file, f.line, f.column))
    return report


def _namespaces(doc: A2lDocument, module: Block, report: Report) -> dict[str, dict[str, Block]]:
    names: dict[str, dict[str, Block]] = {}
    for block in module.children:
        namespace = NAMESPACES.get(block.keyword)
        if namespace is None or not block.name:
            continue
        known = names.setdefault(namespace, {})
        if block.name in known:
            first = known[block.name].position
            report.add(finding_at(doc, block.name_token, "duplicate-name", block.name,
                                  f"{block.keyword} {block.name} is defined twice (first at line {first[1]})",
                                  block.keyword, Severity.ERROR))
            continue
        known[block.name] = block
    mod_par = module.first("MOD_PAR")
    if mod_par is not None:
        names["memory segment"] = {b.name: b for b in mod_par.children_named("MEMORY_SEGMENT") if b.name}
    return names


def _placements(doc: A2lDocument, module: Block, objects: AddressedObjects, debug: DebugData | None,
                report: Report) -> list[_Placed]:
    """Address and size of every object that has both (sizes from the ELF when given, else the A2L)."""
    layouts = _record_layout_sizes(doc)
    placed = []
    parents = doc.blocks.parent
    for row in range(len(objects)):
        target = objects.target(row)
        keyword = target.keyword
        if keyword == "INSTANCE" or target.address_token is None or parents[target.block] != module.index:
            continue
        try:
            address = doc.int_value(target.address_token)
        except A2lParseError:
            continue  # already a syntax finding
        if address > MAX_ADDRESS:
            report.add(finding_at(doc, target.address_token, "address-out-of-range", target.name,
                                  f"{keyword} {target.name}: address 0x{address:X} does not fit the 32 bits of an "
                                  "A2L address", keyword, Severity.ERROR))
            continue
        size = None
        if debug is not None:
            symbol = debug.find(target.symbol)
            if symbol is None:
                report.add(finding_at(doc, target.name_token, "symbol-not-found", target.name,
                                      f"{keyword} {target.name}: {debug.resolve_error(target.symbol)}",
                                      keyword, Severity.ERROR))
            else:
                size = symbol.size
                expected = symbol.address + target.symbol_offset
                if expected != address:
                    report.add(finding_at(doc, target.address_token, "address-mismatch", target.name,
                                          f"{keyword} {target.name}: the A2L says 0x{address:X}, "
                                          f"{debug.path.name} says 0x{expected:X}", keyword, Severity.ERROR))
        if size is None:
            size = _a2l_size(doc, doc.block(target.block), layouts)
        if size:
            placed.append(_Placed(target.name, keyword, address, size, target.address_token))
    return placed


def _a2l_size(doc: A2lDocument, block: Block, layouts: dict[str, int]) -> int | None:
    args = block.args
    keyword = block.keyword
    if keyword == "BLOB":
        return doc.int_value(args[3]) if len(args) > 3 else None
    if keyword == "MEASUREMENT":
        element = DATATYPES.get(doc.text(args[2]), (None,))[0] if len(args) > 2 else None
    elif keyword == "CHARACTERISTIC" and len(args) > 4 and doc.text(args[2]) in ("VALUE", "VAL_BLK"):
        element = layouts.get(doc.text(args[4]))
    else:
        return None  # curves, maps and axes: only the ELF knows their size
    if element is None:
        return None
    count = 1
    for option in ("MATRIX_DIM", "ARRAY_SIZE", "NUMBER"):
        params = block.option(option)
        if params:
            for token in params:
                count *= max(doc.int_value(token), 1)
            break
    return element * count


def _record_layout_sizes(doc: A2lDocument) -> dict[str, int]:
    sizes = {}
    for block in doc.blocks_named("RECORD_LAYOUT"):
        params = block.option("FNC_VALUES")
        if params and len(params) > 1 and doc.text(params[1]) in DATATYPES:
            sizes[block.name] = DATATYPES[doc.text(params[1])][0]
    return sizes


def _overlaps(doc: A2lDocument, placed: list[_Placed], report: Report) -> None:
    """Partial overlaps are errors; an object that only repeats another's bytes is a warning.
    An object inside a larger one (a struct member, an array element) is a deliberate view."""
    ordered = sorted(placed, key=lambda p: (p.address, -p.size))
    reach: _Placed | None = None  # the object reaching furthest so far
    for item in ordered:
        if reach is not None and item.address < reach.address + reach.size:
            end, reach_end = item.address + item.size, reach.address + reach.size
            if item.address == reach.address and item.size == reach.size:
                report.add(finding_at(doc, item.token, "same-address", item.name,
                                      f"{item.keyword} {item.name} occupies the same {item.size} byte(s) at "
                                      f"0x{item.address:X} as {reach.keyword} {reach.name}", item.keyword,
                                      Severity.WARNING))
            elif end > reach_end:
                report.add(finding_at(doc, item.token, "overlap", item.name,
                                      f"{item.keyword} {item.name} (0x{item.address:X}, {item.size} bytes) overlaps "
                                      f"{reach.keyword} {reach.name} (0x{reach.address:X}, {reach.size} bytes)",
                                      item.keyword, Severity.ERROR))
            if end <= reach_end:
                continue
        reach = item


def _segments(doc: A2lDocument, module: Block, placed: list[_Placed], report: Report) -> None:
    segments = doc.memory_segments(module.name)
    if not segments:
        return
    cal_ram = [s for s in segments if s.memory_type == "RAM" and s.prg_type in ("DATA", "CALIBRATION_VARIABLES")]
    for item in placed:
        inside = [s for s in segments if s.contains(item.address, item.size)]
        if not inside:
            report.add(finding_at(doc, item.token, "outside-memory", item.name,
                                  f"{item.keyword} {item.name} (0x{item.address:X}, {item.size} bytes) lies outside "
                                  "every MEMORY_SEGMENT", item.keyword, Severity.ERROR))
        elif item.keyword in _CALIBRATIONS and cal_ram and not any(s in cal_ram for s in inside):
            report.add(finding_at(doc, item.token, "calibration-outside-cal-ram", item.name,
                                  f"{item.keyword} {item.name} at 0x{item.address:X} is in {inside[0].name} "
                                  f"({inside[0].prg_type} {inside[0].memory_type}), not in a DATA RAM segment "
                                  f"({', '.join(s.name for s in cal_ram)})", item.keyword, Severity.ERROR))
