"""The jobs of the window's A2L tools dialog: what ``workbench a2l update|check|merge|insert|remove|cleanup|flatten``
do, as plain functions a worker runs (no Qt here). Each returns an :class:`A2lOutcome`: the report, the summary line
the CLI prints, whether the CLI would exit 0, and the files written; a refusal the CLI reports as a failed
operation (exit 1: a strict update, merge conflicts, a removal that would break a kept object) is an outcome too,
while bad input (exit 2) raises as in the library."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from workbench.findings import Report

__all__ = ["A2lOutcome", "check_a2l", "cleanup_a2l", "flatten_a2l", "insert_a2l", "merge_a2l", "remove_a2l",
           "update_a2l"]


@dataclass(frozen=True)
class A2lOutcome:
    """One run: its report, the summary line the CLI prints, whether it succeeded (the CLI's exit code 0), the
    file it wrote (None: nothing written, a dry run or a refusal) and the included files it rewrote
    (--update-includes)."""

    report: Report
    summary: str
    ok: bool
    written: Path | None = None
    includes_written: tuple[Path, ...] = ()

    def files_written(self) -> list[Path]:
        return ([self.written] if self.written is not None else []) + list(self.includes_written)


def _written(report: Report, output: str | None, ok: bool) -> A2lOutcome:
    """The outcome of a job that wrote ``output`` (None: a dry run) and the included files its report names."""
    if output is None:
        return A2lOutcome(report, report.summary(None), ok)
    includes = tuple(Path(f.file) for f in report.of_kind("include-updated"))
    return A2lOutcome(report, report.summary(output), ok, Path(output), includes)


def update_a2l(a2l: str, elf: str, output: str, *, mode, types: bool, epk: bool, includes, drop_optional: bool = False,
               progress=None) -> A2lOutcome:
    """``workbench a2l update`` (every address listed: the dialog's "show all"; ``drop_optional``:
    ``--drop-optional-references``, with ``UpdateMode.REMOVE_MISSING``); strict refusals are outcomes."""
    from workbench.a2l.update import UpdateFailed, update_file

    try:
        report = update_file(a2l, elf, output, mode=mode, types=types, epk=epk, includes=includes,
                             drop_optional=drop_optional, progress=progress)
    except UpdateFailed as exc:
        return A2lOutcome(exc.report, f"{exc}; nothing written", False)
    return _written(report, output, report.ok)  # written, errors or not


def check_a2l(a2l: str, elf: str | None, progress=None) -> A2lOutcome:
    """``workbench a2l check [--elf]``: fails on any problem, a warning included."""
    from workbench.a2l.check import check_file

    report = check_file(a2l, elf or None, progress=progress)
    return A2lOutcome(report, f"{a2l}: " + ("clean" if report.ok else f"{len(report.problems)} problem(s)"), report.ok)


def merge_a2l(master: str, fragments: list[str], output: str, *, policy, progress=None) -> A2lOutcome:
    """``workbench a2l merge``; conflicts under the policy "error" are an outcome (nothing written)."""
    from workbench.a2l.merge import MergeFailed, merge_files

    try:
        report = merge_files(master, fragments, output, policy=policy, progress=progress)
    except MergeFailed as exc:
        return A2lOutcome(exc.report, str(exc), False)
    merged = len(report.of_kind("merged"))
    return A2lOutcome(report, f"merged {merged} fragment(s) into {output}", report.ok, Path(output))


def insert_a2l(a2l: str | None, elf: str, output: str | None, *, measurements: str, characteristics: str,
               group: str, structures: bool = False, progress=None) -> A2lOutcome:
    """``workbench a2l insert`` with one pattern per kind (``|`` between names), ``--target-group`` and
    ``--structures``; ``a2l`` None: ``--create`` (a new A2L from the ELF alone); ``output`` None: ``--dry-run``."""
    from workbench.a2l.insert import Selection, insert_file

    options = dict(measurements=Selection((measurements,) if measurements else ()),
                   characteristics=Selection((characteristics,) if characteristics else ()),
                   target_group=group or None, structures=structures, progress=progress)
    if a2l is None:
        from workbench.a2l.create import create_file

        report = create_file(elf, output, **options)
    else:
        report = insert_file(a2l, elf, output, **options)
    return _written(report, output, report.ok)


def remove_a2l(a2l: str, output: str | None, *, regexes: tuple[str, ...], ranges: tuple[tuple[int, int], ...],
               cleanup: bool, drop_optional: bool, includes, progress=None) -> A2lOutcome:
    """``workbench a2l remove`` (``output`` None: ``--dry-run``); a removal that would break a kept object is a
    failed outcome listing each reference at its file:line:column (nothing written)."""
    from workbench.a2l.prune import remove_file

    return _pruned(lambda: remove_file(a2l, output, regexes=regexes, ranges=ranges, cleanup=cleanup,
                                       drop_optional=drop_optional, includes=includes, progress=progress), output)


def cleanup_a2l(a2l: str, output: str | None, *, includes, progress=None) -> A2lOutcome:
    """``workbench a2l cleanup`` (``output`` None: ``--dry-run``)."""
    from workbench.a2l.prune import cleanup_file

    return _pruned(lambda: cleanup_file(a2l, output, includes=includes, progress=progress), output)


def _pruned(run, output: str | None) -> A2lOutcome:
    from workbench.a2l.prune import PruneFailed

    try:
        report = run()
    except PruneFailed as exc:
        return A2lOutcome(exc.report, str(exc), False)
    return _written(report, output, True)  # the CLI's exit 0: warnings allowed


def flatten_a2l(a2l: str, output: str, progress=None) -> A2lOutcome:
    """``workbench a2l flatten``: the text of every /include written inline."""
    from workbench.a2l.includes import flatten_file, flatten_summary

    report = flatten_file(a2l, output, progress=progress)
    return A2lOutcome(report, flatten_summary(report, output), True, Path(output))
