"""``update``: every address of an A2L (and optionally types, sizes, limits) from an ELF.

The orchestrator takes the addressed objects as columns (:mod:`workbench.a2l.addressed`),
looks their symbols up in one batch, rewrites the address tokens whose value changes,
and adds what ``typecheck`` (``--types``), :func:`workbench.a2l.prune.removal_edits` (missing objects, by
``remove``'s rules) and :mod:`workbench.a2l.epk` (MOD_PAR EPK/ADDR_EPK) change. The result is the input's text
with only those tokens changed; ``/include`` lines stay, and the changes that fall into
included files are returned per file (see :class:`IncludeMode`).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from workbench.a2l.addressed import KEYWORDS, AddressedObjects
from workbench.a2l.byte_order import byte_order_finding
from workbench.a2l.document import A2lDocument, load_a2l
from workbench.a2l.edits import Edit, Edits, indentation_of, newline_bytes, write_source
from workbench.a2l.epk import epk_address_edits, epk_edits, read_elf_epk
from workbench.a2l.grammar import MAX_ADDRESS
from workbench.a2l.includes import edited_texts, includes_not_found_from
from workbench.a2l.reports import IncludeMode, UpdateMode, findings_at
from workbench.a2l.values import format_ints_like, hex_digits_like, int_or_none, int_values
from workbench.elf.debugdata import DebugData, read_beside
from workbench.errors import InputError, WorkbenchError
from workbench.fileio import write_output
from workbench.findings import Finding, Report, Severity, summarize
from workbench.progress import Progress, report as report_progress

__all__ = ["IncludeMode", "UpdateFailed", "UpdateMode", "UpdateReport", "UpdateResult", "update_document",
           "update_file"]

@dataclass
class UpdateReport(Report):
    """Findings of an update, plus per block type tallies (``"MEASUREMENT": {"updated": 3, ...}``)."""

    tally: dict[str, Counter] = field(default_factory=dict)

    def count(self, keyword: str, outcome: str, number: int = 1) -> None:
        self.tally.setdefault(keyword, Counter())[outcome] += number

    def to_dict(self) -> dict:
        return {**super().to_dict(), "tally": {k: dict(v) for k, v in self.tally.items()}}

    def summary(self, output: str | Path) -> str:
        """The one line after ``output`` is written, per block type (``wrote OUT: MEASUREMENT 1 not-found, 6
        updated``), then MOD_PAR's EPK and ADDR_EPKs changed (``; EPK '…' -> '…'``), as the CLI and the GUI say it."""
        parts = [f"{keyword} " + ", ".join(f"{count} {outcome}" for outcome, count in sorted(tally.items()))
                 for keyword, tally in self.tally.items()]
        epk = [f.message for f in self.findings if f.kind in ("epk-updated", "epk-inserted")]  # a new build's, at once
        return f"wrote {output}: " + "; ".join((parts or ["no objects"]) + epk)


@dataclass
class UpdateResult:
    data: bytes  # the updated main file (the input's encoding, without BOM)
    report: UpdateReport
    # included files the update changes: path -> their new bytes as the file stores them (BOM,
    # encoding); empty under IncludeMode.MERGE, where ``data`` holds everything inline
    included: dict[Path, bytes] = field(default_factory=dict)


class UpdateFailed(WorkbenchError):
    """A strict update met objects it cannot update (not in the ELF, address beyond 32 bits), or a
    ``REMOVE_MISSING`` update would remove an object a kept one needs; carries the report."""

    def __init__(self, report: UpdateReport, problem: str = "object(s) cannot be updated (strict)"):
        self.report = report
        errors = report.errors
        super().__init__(f"{len(errors)} {problem}: {summarize(errors)}")


def update_document(doc: A2lDocument, debug: DebugData, *, mode: UpdateMode = UpdateMode.DEFAULT,
                    types: bool = False, epk: bool = True, epk_symbol: str | None = None,
                    includes: IncludeMode = IncludeMode.KEEP, report_addresses: bool = True,
                    drop_optional: bool = False, progress: Progress | None = None) -> UpdateResult:
    """Update ``doc`` from ``debug``; the document itself is not changed.

    ``mode`` decides about objects whose symbol is not in the ELF (see :class:`UpdateMode`);
    ``REMOVE_MISSING`` removes them by :func:`~workbench.a2l.prune.remove_document`'s rules: their entries in
    grouping lists go with them, and a kept object that needs one (an AXIS_PTS_REF, a VIRTUAL's input, a
    MAP_LIST ...) refuses the update (:class:`UpdateFailed`, an error at each reference), as does an optional
    reference (INPUT_QUANTITY, COMPARISON_QUANTITY) unless ``drop_optional`` (then NO_INPUT_QUANTITY, dropped);
    ``types`` also checks data types, array sizes, bit masks and limits; ``epk`` sets
    MOD_PAR EPK/ADDR_EPK from the ELF's EPK; ``includes`` whether the result keeps the
    ``/include`` lines (changes in included files go to :attr:`UpdateResult.included`) or
    writes the included text inline. ``report_addresses=False`` leaves the
    "address-updated" finding of every object out of the report (the tally still counts
    them). Raises :class:`UpdateFailed` in strict mode when an object cannot be updated,
    :class:`A2lParseError` at an address that is not a number, :class:`InputError` for a
    change that would cross an ``/include`` boundary, :class:`Cancelled` when ``progress``
    is cancelled, and :class:`InputError` for an ELF without DWARF and symbol table (stripped: no address
    can be found, and an output with every address as it was must not pass a build).
    """
    if not debug.has_dwarf and not debug.elf.symbols:
        raise InputError(f"{debug.path}: has neither DWARF nor a symbol table (stripped?): no address can be "
                         "found; give the ELF the build linked, before stripping")
    report = UpdateReport("update")
    report_progress(progress, 0, 3, "finding the objects")
    objects = AddressedObjects(doc)
    edits = Edits()
    pending: list[tuple] = []  # findings as (token, kind, name, message, block, severity), located at the end
    report_progress(progress, 1, 3, "looking up symbols")
    if types:
        symbols = debug.symbols(objects.symbols)
        addresses = np.array([-1 if symbol is None else symbol.address if symbol.address < 2**63 else -2
                              for symbol in symbols], dtype=np.int64)
    else:
        addresses = debug.addresses(objects.symbols, progress)
    report_progress(progress, 2, 3, "updating addresses")
    # the new address of every object (-1: the ELF lacks its symbol, -2: its address is beyond 63 bits)
    found = addresses >= 0
    targets = np.where(found, addresses + np.asarray(objects.symbol_offsets, dtype=np.int64), addresses)
    usable = found & (targets >= 0) & (targets <= MAX_ADDRESS)
    has_token = objects.address_token_array >= 0
    removed: dict[int, tuple[int, str]] = {}  # block -> (name token, why): REMOVE_MISSING's objects
    missing = int(np.count_nonzero(addresses == -1))
    if missing > 1 and missing == len(addresses):  # another build's ELF: its EPK and no address would be written
        first = int(np.argmin(objects.name_tokens))
        raise InputError(f"none of the {missing} objects of {doc.name} is in {debug.path.name} (the first: "
                         f"{objects.keyword(first)} {objects.names[first]}): is it the ELF of this A2L's software? "
                         "nothing written")
    for row in np.flatnonzero(~usable | ~has_token).tolist():  # the few objects that need more than a new value
        if addresses[row] == -1:
            _missing(objects, row, debug, mode, report, removed, pending, missing)
        elif not usable[row]:
            target = int(targets[row]) if found[row] else debug.resolve(objects.symbols[row]).address \
                + objects.symbol_offsets[row]
            _unaddressable(objects, row, target, mode, report, pending)
        else:
            _insert_address(objects, row, int(targets[row]), edits, report, pending)
    located = np.flatnonzero(usable & has_token)
    _replace_addresses(objects, located, targets, edits, report, pending if report_addresses else None)
    _update_address_copies(objects, targets, edits, report)
    if types:
        _check_types(objects, symbols, edits, report)
    report_progress(progress, 3, 3, "updating addresses")
    report.findings[:0] = findings_at(doc, pending)
    if mode is UpdateMode.STRICT and report.errors:
        raise UpdateFailed(report)
    if removed:
        _remove(doc, removed, drop_optional, edits, report)
    if epk:
        _epk(doc, debug, epk_symbol, edits, report)
    for module in doc.modules:  # reported, not changed: which one is right is the project's to say
        mismatch = byte_order_finding(doc, module, debug.elf.little_endian, debug.path.name, Severity.WARNING)
        if mismatch is not None:
            report.add(mismatch)
    return _result(doc, edits, report, includes)


def update_file(a2l: str | Path, elf: str | Path, output: str | Path, *, mode: UpdateMode = UpdateMode.DEFAULT,
                types: bool = False, epk: bool = True, epk_symbol: str | None = None,
                includes: IncludeMode = IncludeMode.KEEP, cache_dir: str | Path | None = None,
                use_cache: bool = True, validate: bool = False, report_addresses: bool = True,
                drop_optional: bool = False, progress: Progress | None = None) -> UpdateReport:
    """Read ``a2l`` and ``elf``, update, and write ``output`` atomically (which may be ``a2l``);
    under ``IncludeMode.UPDATE`` also every included file that changes, in place (atomically).

    The file's block structure and every token the update reads or writes are always
    checked; ``validate`` also checks the rest against the ASAP2 grammar (as ``check``
    does), which costs about a third of the time of a large update. The ELF is read while the A2L is
    (:func:`~workbench.elf.debugdata.read_beside`).
    """
    doc, debug_data = read_beside(lambda: load_a2l(a2l, validate=validate), elf, cache_dir=cache_dir,
                                  use_cache=use_cache, progress=progress)
    with debug_data as debug:
        result = update_document(doc, debug, mode=mode, types=types, epk=epk, epk_symbol=epk_symbol, includes=includes,
                                 report_addresses=report_addresses, drop_optional=drop_optional, progress=progress)
    write_source(doc.source, result.data, output)
    if includes is IncludeMode.UPDATE:
        for path, data in result.included.items():
            write_output(path, data)
    if includes is not IncludeMode.MERGE:
        result.report.extend(includes_not_found_from(doc, Path(output)))
    return result.report


def _result(doc: A2lDocument, edits: Edits, report: UpdateReport, includes: IncludeMode) -> UpdateResult:
    """The new text: one self-contained buffer (MERGE), or the main file with its /include lines kept
    plus the changed included files."""
    data, changed = edited_texts(doc, edits, includes, report)
    if includes is IncludeMode.KEEP:
        for change in changed:
            # an error: the output's includes keep stale addresses, which must not pass a build
            name = change.source.name
            report.add(Finding("include-not-updated", name, f"{name}: {change.count} change(s) in this included "
                               "file are not written (the output keeps its /include lines): --update-includes writes "
                               "them into the included files, --merge-includes inline", *change.first, "",
                               Severity.ERROR))
    return UpdateResult(data, report, {change.source.path: change.data for change in changed})


def _insert_address(objects: AddressedObjects, row: int, address: int, edits: Edits, report: UpdateReport,
                    pending: list[tuple]) -> None:
    """A MEASUREMENT without ECU_ADDRESS gets one after its positional parameters."""
    doc = objects.doc
    anchor = doc.tokens.span(objects.anchor_tokens[row])[1]
    indent = indentation_of(doc.data, doc.tokens.span(doc.block_begin[objects.blocks[row]])[0]) + b"  "
    edits.append(Edit(anchor, anchor, newline_bytes(doc) + indent + b"ECU_ADDRESS 0x%X" % address))
    name, keyword = objects.names[row], objects.keyword(row)
    pending.append((int(objects.name_tokens[row]), "address-updated", name, f"{name}: ECU_ADDRESS 0x{address:X} added",
                    keyword, Severity.INFO))
    report.count(keyword, "updated")


def _replace_addresses(objects: AddressedObjects, rows: np.ndarray, targets: np.ndarray, edits: Edits,
                       report: UpdateReport, pending: list[tuple] | None) -> None:
    """Rewrite the address token of ``rows`` where its value is not the target (the hot path of a
    large update: whole columns at a time)."""
    doc = objects.doc
    tokens = objects.address_token_array[rows]
    starts, ends = doc.tokens.starts[tokens], doc.tokens.ends[tokens]
    olds, read = int_values(doc.data, starts, ends)
    new_values = targets[rows]
    news = new_values.tolist()
    differs = read & (olds != new_values)
    old_values = olds.tolist()
    for index in np.flatnonzero(~read).tolist():  # signed, long or malformed: one at a time
        raw = doc.data[int(starts[index]) : int(ends[index])]
        old_values[index] = int_or_none(raw)
        if old_values[index] is None:
            row = int(rows[index])
            raise doc.error(f"{objects.keyword(row)} {objects.names[row]}: the address must be an integer, found "
                            f"'{raw.decode(doc.encoding)}'", int(tokens[index]))
        differs[index] = old_values[index] != news[index]
    changed = np.flatnonzero(differs)
    # hex tokens the new value fits: their digits overwritten as columns; the rest token by token
    done, digit_starts, digits = hex_digits_like(doc.data, starts[changed], ends[changed], new_values[changed])
    edits.overwrite_columns(digit_starts, ends[changed[done]] - digit_starts, digits)
    others = np.delete(changed, done)
    other_starts, other_ends = starts[others].tolist(), ends[others].tolist()
    raws = [doc.data[start:end] for start, end in zip(other_starts, other_ends)]
    edits.extend_columns(other_starts, other_ends, format_ints_like(raws, [news[i] for i in others.tolist()]))
    numbers = objects.keyword_numbers
    totals = np.bincount(numbers[rows], minlength=len(KEYWORDS))
    updated = np.bincount(numbers[rows[changed]], minlength=len(KEYWORDS))
    for keyword, total, count in zip(KEYWORDS, totals.tolist(), updated.tolist()):
        if count:
            report.count(keyword, "updated", count)
        if total > count:
            report.count(keyword, "unchanged", total - count)
    if pending is not None:
        for i in changed.tolist():
            row = int(rows[i])
            name = objects.names[row]
            pending.append((int(tokens[i]), "address-updated", name,
                            "%s: 0x%X -> 0x%X" % (name, old_values[i], news[i]), objects.keyword(row), Severity.INFO))


# IF_DATA that repeat an object's address, read by the tools that wrote them: (IF_DATA name, keyword, the address's
# place after the keyword, what the keyword needs up to it)
_ADDRESS_COPIES = (("CANAPE_EXT", "LINK_MAP", 2, "a symbol name and an address"),  # CANape's own address update
                   ("ASAP1B_CCP", "DP_BLOB", 2, "an address extension and a base address"))  # a CCP master's address


def _update_address_copies(objects: AddressedObjects, targets: np.ndarray, edits: Edits,
                           report: UpdateReport) -> None:
    """CANape's ``IF_DATA CANAPE_EXT ... LINK_MAP "symbol" address ...`` and CCP's ``IF_DATA ASAP1B_CCP DP_BLOB
    extension address size`` repeat an object's address: they follow the new one, as a2ltool keeps them."""
    doc = objects.doc
    row_of_block = None
    for name, keyword, place, needs in _ADDRESS_COPIES:
        if_data, found = doc.option_tokens("IF_DATA", keyword)
        if not len(if_data):
            continue
        row_of_block = row_of_block or {block: row for row, block in enumerate(objects.blocks.tolist())}
        updated = 0
        for block, token in zip(if_data.tolist(), found.tolist()):
            row = row_of_block.get(int(doc.blocks.parent[block]))
            target = int(targets[row]) if row is not None else -1
            if not 0 <= target <= MAX_ADDRESS or doc.raw(doc.block_begin[block] + 2) != name.encode("ascii"):
                continue
            address_token = token + place
            if address_token >= doc.block_end[block]:
                raise doc.error(f"{objects.keyword(row)} {objects.names[row]}: {keyword} needs {needs}", token)
            raw = doc.raw(address_token)
            if int_or_none(raw) is None:
                raise doc.error(f"{objects.keyword(row)} {objects.names[row]}: the {keyword} address must be an "
                                f"integer, found '{raw.decode(doc.encoding)}'", address_token)
            if int_or_none(raw) != target:
                start, end = doc.tokens.span(address_token)
                edits.append(Edit(start, end, format_ints_like([raw], [target])[0]))
                updated += 1
        if updated:
            report.count(f"IF_DATA {name} {keyword}", "updated", updated)


def _check_types(objects: AddressedObjects, symbols: list, edits: Edits, report: UpdateReport) -> None:
    from workbench.a2l.update.typecheck import TypeChecker  # here: an address update needs none of it

    checker = TypeChecker(objects.doc)
    axes_first = np.argsort(objects.keyword_numbers != KEYWORDS.index("AXIS_PTS"), kind="stable")
    for row in axes_first.tolist():  # the point counts of AXIS_PTS, then the COM_AXIS that name them
        symbol = symbols[row]
        if symbol is not None and not objects.symbol_offsets[row]:  # with an offset the link's type is not the object's
            type_edits, type_findings = checker.check(objects.target(row), symbol)
            edits.extend(type_edits)
            report.extend(type_findings)


def _remove(doc: A2lDocument, removed: dict[int, tuple[int, str]], drop_optional: bool, edits: Edits,
            report: UpdateReport) -> None:
    """Take the missing objects out by ``remove``'s rules; a kept object that needs one refuses the update."""
    from workbench.a2l.prune import removal_edits  # here: a plain update needs none

    removal, pending = removal_edits(doc, removed, drop_optional=drop_optional)
    edits.extend(removal)
    report.extend(findings_at(doc, pending))
    if any(item[5] is Severity.ERROR for item in pending):
        raise UpdateFailed(report, "kept reference(s) to objects --remove-missing would remove (without it they "
                           "are kept, each a warning)")


def _missing(objects: AddressedObjects, row: int, debug: DebugData, mode: UpdateMode, report: UpdateReport,
             removed: dict[int, tuple[int, str]], pending: list[tuple], missing: int) -> None:
    from workbench.elf.suggest import MOST_SUGGESTED, missing_symbol_reason  # here: an update finding all needs none

    keyword, name, symbol = objects.keyword(row), objects.names[row], objects.symbols[row]
    # a close name ("not in app.elf; did you mean 'x'?") when a few symbols are missing (renamed variables); more
    # are seldom renames and would cost an index of the ELF's names (20 of 10,000: 17 ms; 100 of 50,000: 60 ms):
    # `a2l check --elf` names them for the first few
    why = missing_symbol_reason(debug, symbol) if missing <= MOST_SUGGESTED else debug.resolve_error(symbol)
    # a name that fits several variables (statics of two functions or units) is never guessed
    kind = "symbol-ambiguous" if debug.is_ambiguous(symbol) else "symbol-not-found"
    link = f" (SYMBOL_LINK {symbol!r})" if symbol != name else ""
    severity = Severity.ERROR if mode is UpdateMode.STRICT else Severity.WARNING
    pending.append((int(objects.name_tokens[row]), kind, name, f"{keyword} {name}{link}: {why}", keyword, severity))
    if mode is UpdateMode.REMOVE_MISSING:  # counted once, as what became of it ("1 removed", not also "1 not-found")
        removed[int(objects.blocks[row])] = (int(objects.name_tokens[row]), f"not in {debug.path.name}")
        report.count(keyword, "removed")
    else:
        report.count(keyword, "not-found")


def _unaddressable(objects: AddressedObjects, row: int, address: int, mode: UpdateMode, report: UpdateReport,
                   pending: list[tuple]) -> None:
    keyword, name = objects.keyword(row), objects.names[row]
    severity = Severity.ERROR if mode is UpdateMode.STRICT else Severity.WARNING
    pending.append((int(objects.name_tokens[row]), "address-out-of-range", name,
                    f"{keyword} {name}: address 0x{address:X} does not fit the 32 bits of an A2L address; "
                    "left unchanged", keyword, severity))
    report.count(keyword, "out-of-range")


def _epk(doc: A2lDocument, debug: DebugData, symbol: str | None, edits: Edits, report: UpdateReport) -> None:
    found = read_elf_epk(debug, symbol)
    if found is None:
        report.add(Finding("epk-not-found", "EPK", f"{debug.path.name} has no EPK variable or .epk section",
                           severity=Severity.INFO))
        return
    for module in doc.modules:
        epk_changes, findings = epk_edits(doc, found, module)
        more_changes, more_findings = epk_address_edits(doc, debug, found, module)
        edits.extend(epk_changes + more_changes)
        report.extend(findings + more_findings)
