"""``update``: every address of an A2L (and optionally types, sizes, limits) from an ELF.

The orchestrator walks MEASUREMENT, CHARACTERISTIC, AXIS_PTS, BLOB and INSTANCE in
turn (``targets`` finds them, ``typecheck`` checks types, ``removal`` drops missing
ones), sets MOD_PAR's EPK/ADDR_EPK (``workbench.a2l.epk``), and returns the new text
as edits of the original: only the changed tokens differ.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from workbench.a2l import grammar
from workbench.a2l.document import A2lDocument, load
from workbench.a2l.edits import Edit, apply_edits, indentation_of, newline_bytes, write_output
from workbench.a2l.epk import epk_edits, read_elf_epk
from workbench.a2l.reports import Finding, Report, Severity, UpdateMode, findings_at
from workbench.a2l.update.removal import removal_edits
from workbench.a2l.update.targets import Target, collect_targets
from workbench.a2l.update.typecheck import TypeChecker
from workbench.a2l.values import INT_RE, format_int_like
from workbench.elf.debugdata import DebugData
from workbench.errors import WorkbenchError
from workbench.progress import Progress, report as report_progress

__all__ = ["UpdateFailed", "UpdateMode", "UpdateReport", "UpdateResult", "update", "update_file"]

_PROGRESS_STEP = 2000  # objects between progress reports


@dataclass
class UpdateReport(Report):
    """Findings of an update, plus per block type tallies (``"MEASUREMENT": {"updated": 3, ...}``)."""

    tally: dict[str, Counter] = field(default_factory=dict)

    def count(self, keyword: str, outcome: str) -> None:
        tally = self.tally.get(keyword)
        if tally is None:
            tally = self.tally[keyword] = Counter()
        tally[outcome] += 1

    def to_dict(self) -> dict:
        return {**super().to_dict(), "tally": {k: dict(v) for k, v in self.tally.items()}}


@dataclass
class UpdateResult:
    data: bytes  # the updated document buffer (the input's encoding, without BOM)
    report: UpdateReport


class UpdateFailed(WorkbenchError):
    """A strict update met objects the ELF does not have; carries the report."""

    def __init__(self, report: UpdateReport):
        self.report = report
        missing = report.of_kind("symbol-not-found")
        shown = ", ".join(f"{f.name} ({f.location})" for f in missing[:3])
        more = f" and {len(missing) - 3} more" if len(missing) > 3 else ""
        super().__init__(f"{len(missing)} object(s) not found in the ELF (strict): {shown}{more}")


def update(doc: A2lDocument, debug: DebugData, *, mode: UpdateMode = UpdateMode.DEFAULT, types: bool = False,
           epk: bool = True, epk_symbol: str | None = None, report_addresses: bool = True,
           progress: Progress | None = None) -> UpdateResult:
    """Update ``doc`` from ``debug``; the document itself is not changed.

    ``mode`` decides about objects whose symbol is not in the ELF (see :class:`UpdateMode`);
    ``types`` also checks data types, array sizes, bit masks and limits; ``epk`` sets
    MOD_PAR EPK/ADDR_EPK from the ELF's EPK. ``report_addresses=False`` leaves the
    "address-updated" finding of every object out of the report (the tally still counts
    them), which saves a fifth of the time of a large update. Raises :class:`UpdateFailed` in strict mode
    when a symbol is missing, :class:`A2lParseError` at an address that is not a number,
    :class:`Cancelled` when ``progress`` is cancelled.
    """
    report = UpdateReport("update")
    edits: list[Edit] = []
    pending: list[tuple] = []  # findings as (token, kind, name, message, block, severity), located at the end
    removed: dict[str, int] = {}
    checker = TypeChecker(doc) if types else None
    all_targets = [t for keyword in grammar.ADDRESSED_OBJECTS for t in collect_targets(doc, keyword)]
    total = len(all_targets)
    address_of = debug.address_of
    located: list[tuple[Target, int]] = []  # objects with an address token, and their new address
    for done, target in enumerate(all_targets):
        if done % _PROGRESS_STEP == 0:
            report_progress(progress, done, total, "updating addresses")
        symbol = debug.find(target.symbol) if checker is not None else None
        address = symbol.address if symbol is not None else address_of(target.symbol)
        if address is None:
            _missing(target, debug, mode, report, removed, pending)
            continue
        address += target.symbol_offset
        if target.address_token is None:
            _insert_address(doc, target, address, edits, report, pending)
        else:
            located.append((target, address))
        if symbol is not None and not target.symbol_offset:  # with an offset the link's type is not the object's
            type_edits, type_findings = checker.check(target, symbol)
            edits.extend(type_edits)
            report.extend(type_findings)
    _replace_addresses(doc, located, edits, report, pending if report_addresses else None)
    report_progress(progress, total, total, "updating addresses")
    report.findings[:0] = findings_at(doc, pending)
    if mode is UpdateMode.STRICT and report.errors:
        raise UpdateFailed(report)
    if removed:
        removal, findings = removal_edits(doc, removed)
        edits.extend(removal)
        report.extend(findings)
    if epk:
        _epk(doc, debug, epk_symbol, edits, report)
    return UpdateResult(apply_edits(doc.data, edits), report)


def update_file(a2l: str | Path, elf: str | Path, output: str | Path, *, mode: UpdateMode = UpdateMode.DEFAULT,
                types: bool = False, epk: bool = True, epk_symbol: str | None = None,
                cache_dir: str | Path | None = None, use_cache: bool = True, validate: bool = False,
                report_addresses: bool = True, progress: Progress | None = None) -> UpdateReport:
    """Read ``a2l`` and ``elf``, update, and write ``output`` atomically (which may be ``a2l``).

    The file's block structure and every token the update reads or writes are always
    checked; ``validate`` also checks the rest against the ASAP2 grammar (as ``check``
    does), which costs about a third of the time of a large update.
    """
    doc = load(a2l, validate=validate)
    with DebugData(elf, cache_dir=cache_dir, use_cache=use_cache, progress=progress) as debug:
        result = update(doc, debug, mode=mode, types=types, epk=epk, epk_symbol=epk_symbol,
                        report_addresses=report_addresses, progress=progress)
    write_output(doc, result.data, output)
    return result.report


def _insert_address(doc: A2lDocument, target: Target, address: int, edits: list[Edit], report: UpdateReport,
                    pending: list[tuple]) -> None:
    """A MEASUREMENT without ECU_ADDRESS gets one after its positional parameters."""
    anchor = doc.tokens.ends_list[target.anchor_token]
    indent = indentation_of(doc.data, doc.tokens.starts_list[doc.block_begin[target.block]]) + b"  "
    edits.append(Edit(anchor, anchor, newline_bytes(doc) + indent + b"ECU_ADDRESS 0x%X" % address))
    pending.append((target.name_token, "address-updated", target.name,
                    f"{target.name}: ECU_ADDRESS 0x{address:X} added", target.keyword, Severity.INFO))
    report.count(target.keyword, "updated")


def _replace_addresses(doc: A2lDocument, located: list[tuple[Target, int]], edits: list[Edit], report: UpdateReport,
                       pending: list[tuple] | None) -> None:
    """Rewrite every address token whose value changes (the hot loop of a large update)."""
    data, starts, ends = doc.data, doc.tokens.starts_list, doc.tokens.ends_list
    fullmatch = INT_RE.fullmatch
    tally: dict[str, Counter] = {}
    for target, address in located:
        token = target.address_token
        start, end = starts[token], ends[token]
        raw = data[start:end]
        if fullmatch(raw) is None:
            raise doc.error(f"{target.keyword} {target.name}: the address must be an integer, found "
                            f"'{raw.decode(doc.encoding)}'", token)
        old = int(raw, 16) if b"x" in raw or b"X" in raw else int(raw)
        counter = tally.get(target.keyword)
        if counter is None:
            counter = tally[target.keyword] = Counter()
        if old == address:
            counter["unchanged"] += 1
            continue
        counter["updated"] += 1
        edits.append(Edit(start, end, format_int_like(raw, address)))
        if pending is not None:
            pending.append((token, "address-updated", target.name, "%s: 0x%X -> 0x%X" % (target.name, old, address),
                            target.keyword, Severity.INFO))
    for keyword, counter in tally.items():
        report.tally.setdefault(keyword, Counter()).update(counter)


def _missing(target: Target, debug: DebugData, mode: UpdateMode, report: UpdateReport, removed: dict[str, int],
             pending: list[tuple]) -> None:
    why = debug.resolve_error(target.symbol)
    link = f" (SYMBOL_LINK {target.symbol!r})" if target.symbol != target.name else ""
    severity = Severity.ERROR if mode is UpdateMode.STRICT else Severity.WARNING
    pending.append((target.name_token, "symbol-not-found", target.name, f"{target.keyword} {target.name}{link}: {why}",
                    target.keyword, severity))
    report.count(target.keyword, "not-found")
    if mode is UpdateMode.REMOVE_MISSING:
        removed[target.name] = target.block
        pending.append((target.name_token, "removed", target.name, f"{target.keyword} {target.name} removed",
                        target.keyword, Severity.WARNING))
        report.count(target.keyword, "removed")


def _epk(doc: A2lDocument, debug: DebugData, symbol: str | None, edits: list[Edit], report: UpdateReport) -> None:
    found = read_elf_epk(debug, symbol)
    if found is None:
        report.add(Finding("epk-not-found", "EPK", f"{debug.path.name} has no EPK variable or .epk section",
                           severity=Severity.INFO))
        return
    for module in doc.modules:
        epk_changes, findings = epk_edits(doc, found, module)
        edits.extend(epk_changes)
        report.extend(findings)
