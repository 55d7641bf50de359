"""``check``: syntax, references, names and memory placement of an A2L, each finding located.

Checks: every block against the keyword table (parameters, the words allowed in
enumerated ones, an option given twice where ASAP2 allows it once); references (:mod:`workbench.a2l.references`: COMPU_METHOD,
RECORD_LAYOUT, typedefs, INSTANCE components, FUNCTION, conversion tables, units,
measurements, axes, groups, memory segments); names defined twice; typedef structures
(:mod:`workbench.a2l.structures`: components beyond their structure, a structure that contains
itself, a component twice; what the workbench does not support, a pointer, as info); and
(:mod:`workbench.a2l.placement`) objects that overlap, objects outside every MEMORY_SEGMENT,
calibrations outside a RAM data segment (CAL RAM); ADDR_EPKs outside a MEMORY_SEGMENT, without room for the EPK or
two in one segment (:mod:`workbench.a2l.epk_check`); display formats that are not ASAP2's ``"%Length.Layout"``
(:mod:`workbench.a2l.display_format`). With an ELF, every object's symbol must
exist and its address must match, MOD_COMMON's BYTE_ORDER must be the ELF's, and the ELF must hold MOD_PAR's EPK at
every ADDR_EPK (so must a flash file given, where it has bytes; and the file's every byte must lie in a
MEMORY_SEGMENT: :mod:`workbench.a2l.image_check`). An ``/include``
whose file cannot be read is one finding; the rest is checked without it.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from workbench.a2l.addressed import AddressedObjects
from workbench.a2l.byte_order import byte_order_finding
from workbench.a2l.display_format import check_formats
from workbench.a2l.document import A2lDocument, Block
from workbench.a2l.epk_check import check_epk_addresses
from workbench.a2l.grammar import NAMESPACES
from workbench.a2l.image_check import check_image_memory
from workbench.a2l.includes import cannot_include
from workbench.a2l.placement import check_placement
from workbench.a2l.references import check_references
from workbench.a2l.reports import finding_at
from workbench.a2l.source import read_source, source_from_text
from workbench.a2l.structures import check_structures
from workbench.a2l.values import quote_string
from workbench.a2l.validate import validate_document
from workbench.elf.debugdata import DebugData, read_beside
from workbench.errors import A2lParseError
from workbench.findings import Finding, Report, Severity
from workbench.progress import Progress, report as report_progress

if TYPE_CHECKING:
    from workbench.image import MemoryImage

__all__ = ["check_document", "check_file"]

_WRAPPER = "INCLUDED"  # the PROJECT (and MODULE) around a file written for /include

def check_file(a2l: str | Path, elf: str | Path | None = None, *, image: str | Path | None = None,
               cache_dir: str | Path | None = None, use_cache: bool = True, progress: Progress | None = None) -> Report:
    """Load ``a2l`` (syntax errors become findings where the file can still be read) and check it; ``image``: a
    flash file (s19/hex) of the build, which must hold MOD_PAR's EPK at the ADDR_EPKs it has bytes at.

    A file without PROJECT, written for ``/include`` (a MODULE, or module-level blocks), is
    checked as if included where it belongs: in a PROJECT (and MODULE) around it.

    :raises InputError: ``image`` cannot be read (or is an ELF).
    """
    flash = None
    if image is not None:
        from workbench.image import load_image

        flash = (Path(image).name, load_image(image))
    if elf is None:
        return check_document(_load_for_check(Path(a2l)), progress=progress, image=flash)
    doc, debug_data = read_beside(lambda: _load_for_check(Path(a2l)), elf, cache_dir=cache_dir, use_cache=use_cache)
    with debug_data as debug:
        return check_document(doc, debug, progress=progress, image=flash)


def check_document(doc: A2lDocument, debug: DebugData | None = None, *, progress: Progress | None = None,
                   image: tuple[str, MemoryImage] | None = None) -> Report:
    """Every problem of ``doc`` as a finding; the report is ``ok`` (clean) only when there is none. ``image``: (its
    name, its bytes) of a flash file of the build, compared at every ADDR_EPK."""
    report = Report("check", fails_on=Severity.WARNING)
    for include, holder, why in doc.missing_includes:  # left out: the rest is checked without it
        line, column = holder.position(include.offset)
        report.add(Finding("include-not-found", include.name, f"{cannot_include(include.path, why)} (the rest is "
                           "checked without it)", holder.name, line, column, "", Severity.ERROR))
    syntax: list[A2lParseError] = []
    validate_document(doc, syntax, options_once=True)
    for error in syntax:
        name, keyword = _concerned(doc, getattr(error, "block", None))
        report.add(Finding(getattr(error, "kind", "syntax"), name, error.reason, error.path, error.line, error.column,
                           keyword, Severity.ERROR))
    report_progress(progress, 1, 4, "checking references")
    try:
        objects = AddressedObjects(doc)
    except A2lParseError as error:  # an object without its parameters: nothing can be placed
        objects = None
        _add_syntax(report, error)
    for module in doc.modules:
        names = _namespaces(doc, module, report)
        check_references(doc, module, names, report)
        try:
            check_structures(doc, module, report)
        except A2lParseError as error:  # a typedef without its parameters
            _add_syntax(report, error)
        report_progress(progress, 2, 4, "checking memory")
        placed = []
        if objects is not None:
            try:
                placed = check_placement(doc, module, objects, debug, report)
            except A2lParseError as error:  # a MEMORY_SEGMENT without its parameters: the memory is not known
                _add_syntax(report, error)
        try:
            check_epk_addresses(doc, module, debug, report, image, placed)
            if image is not None:
                check_image_memory(doc, module, *image, report)
        except A2lParseError as error:  # a MEMORY_SEGMENT (or ADDR_EPK) without its parameters
            _add_syntax(report, error)
        if debug is not None:
            mismatch = byte_order_finding(doc, module, debug.elf.little_endian, debug.path.name)
            if mismatch is not None:
                report.add(mismatch)
    check_formats(doc, report)
    report_progress(progress, 4, 4, "checked")
    report.findings.sort(key=lambda f: (f.file, f.line, f.column))
    return report


def _add_syntax(report: Report, error: A2lParseError) -> None:
    """``error`` as a finding, unless the grammar check has one at its place already."""
    if not any((f.file, f.line, f.column) == (error.path, error.line, error.column) for f in report.findings):
        report.add(Finding("syntax", "", error.reason, error.path, error.line, error.column, "", Severity.ERROR))


def _load_for_check(path: Path) -> A2lDocument:
    doc = A2lDocument.from_source(read_source(path), validate=False, missing_ok=True)
    within = doc.included_in()
    if within is None:
        return doc
    include = f"/include {quote_string(path.name, 'utf-8').decode('utf-8')}"
    body = include if within == "PROJECT" else f'/begin MODULE {_WRAPPER} "" {include} /end MODULE'
    wrapper = source_from_text(f'/begin PROJECT {_WRAPPER} "" {body} /end PROJECT\n', path.with_name(f"{path.name} "
                               "(included in a PROJECT)"))
    return A2lDocument.from_source(wrapper, validate=False, missing_ok=True)


def _concerned(doc: A2lDocument, block: int | None) -> tuple[str, str]:
    """(name, keyword) of the object a finding inside ``block`` concerns: the nearest named block
    (an AXIS_DESCR's CHARACTERISTIC), and the block's own keyword."""
    if block is None:
        return "", ""
    found: Block | None = doc.block(block)
    while found is not None and not found.name:
        found = found.parent
    return (found.name if found is not None else ""), doc.blocks.keyword[block]


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


