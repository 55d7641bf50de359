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
from workbench.a2l.edits import Edit, apply_edits, indentation_of, newline_bytes, replace_token, write_output
from workbench.a2l.epk import epk_edits, read_elf_epk
from workbench.a2l.reports import Finding, Report, Severity, UpdateMode, finding_at
from workbench.a2l.update.removal import removal_edits
from workbench.a2l.update.targets import Target, collect_targets
from workbench.a2l.update.typecheck import TypeChecker
from workbench.a2l.values import format_int_like, is_int, parse_int
from workbench.elf.debugdata import DebugData
from workbench.errors import WorkbenchError
from workbench.progress import Progress, report as report_progress

__all__ = ["UpdateMode", "UpdateReport", "UpdateResult", "update", "update_file"]

_PROGRESS_STEP = 2000  # objects between progress reports


@dataclass
class UpdateReport(Report):
    """Findings of an update, plus per block type tallies (``"MEASUREMENT": {"updated": 3, ...}``)."""

    tally: dict[str, Counter] = field(default_factory=dict)

    def count(self, keyword: str, outcome: str) -> None:
        self.tally.setdefault(keyword, Counter())[outcome] += 1

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
           epk: bool = True, epk_symbol: str | None = None, progress: Progress | None = None) -> UpdateResult:
    """Update ``doc`` from ``debug``; the document itself is not changed.

    ``mode`` decides about objects whose symbol is not in the ELF (see :class:`UpdateMode`);
    ``types`` also checks data types, array sizes, bit masks and limits; ``epk`` sets
    MOD_PAR EPK/ADDR_EPK from the ELF's EPK. Raises :class:`UpdateFailed` in strict mode
    when a symbol is missing, :class:`Cancelled` when ``progress`` is cancelled.
    """
    report = UpdateReport("update")
    edits: list[Edit] = []
    removed: dict[str, int] = {}
    checker = TypeChecker(doc) if types else None
    all_targets = [t for keyword in grammar.ADDRESSED_OBJECTS for t in collect_targets(doc, keyword)]
    total = len(all_targets)
    for done, target in enumerate(all_targets):
        if done % _PROGRESS_STEP == 0:
            report_progress(progress, done, total, "updating addresses")
        symbol = debug.find(target.symbol)
        if symbol is None:
            _missing(doc, target, debug, mode, report, removed)
            continue
        _address(doc, target, symbol.address + target.symbol_offset, edits, report)
        if checker is not None:
            type_edits, type_findings = checker.check(target, symbol)
            edits.extend(type_edits)
            report.extend(type_findings)
    report_progress(progress, total, total, "updating addresses")
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
                cache_dir: str | Path | None = None, use_cache: bool = True,
                progress: Progress | None = None) -> UpdateReport:
    """Read ``a2l`` and ``elf``, update, and write ``output`` atomically (which may be ``a2l``)."""
    doc = load(a2l)
    with DebugData(elf, cache_dir=cache_dir, use_cache=use_cache, progress=progress) as debug:
        result = update(doc, debug, mode=mode, types=types, epk=epk, epk_symbol=epk_symbol, progress=progress)
    write_output(doc, result.data, output)
    return result.report


def _address(doc: A2lDocument, target: Target, address: int, edits: list[Edit], report: UpdateReport) -> None:
    token = target.address_token
    if token is None:  # a MEASUREMENT without ECU_ADDRESS: add one after the positional parameters
        anchor = doc.tokens.ends_list[target.anchor_token]
        indent = indentation_of(doc.data, doc.tokens.starts_list[doc.block_begin[target.block]]) + b"  "
        edits.append(Edit(anchor, anchor, newline_bytes(doc) + indent + f"ECU_ADDRESS 0x{address:X}".encode("ascii")))
        report.add(finding_at(doc, target.name_token, "address-updated", target.name,
                              f"{target.name}: ECU_ADDRESS 0x{address:X} added", target.keyword))
        report.count(target.keyword, "updated")
        return
    raw = doc.raw(token)
    if not is_int(raw):
        raise doc.error(f"{target.keyword} {target.name}: the address must be an integer, found "
                        f"'{raw.decode(doc.encoding)}'", token)
    old = parse_int(raw)
    if old == address:
        report.count(target.keyword, "unchanged")
        return
    edits.append(replace_token(doc, token, format_int_like(raw, address)))
    report.add(finding_at(doc, token, "address-updated", target.name,
                          f"{target.name}: 0x{old:X} -> 0x{address:X}", target.keyword))
    report.count(target.keyword, "updated")


def _missing(doc: A2lDocument, target: Target, debug: DebugData, mode: UpdateMode, report: UpdateReport,
             removed: dict[str, int]) -> None:
    why = debug.resolve_error(target.symbol)
    link = f" (SYMBOL_LINK {target.symbol!r})" if target.symbol != target.name else ""
    severity = Severity.ERROR if mode is UpdateMode.STRICT else Severity.WARNING
    report.add(finding_at(doc, target.name_token, "symbol-not-found", target.name,
                          f"{target.keyword} {target.name}{link}: {why}", target.keyword, severity))
    report.count(target.keyword, "not-found")
    if mode is UpdateMode.REMOVE_MISSING:
        removed[target.name] = target.block
        report.add(finding_at(doc, target.name_token, "removed", target.name,
                              f"{target.keyword} {target.name} removed", target.keyword, Severity.WARNING))
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
