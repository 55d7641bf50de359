"""Apply a dataset to the ECU: every object checked before anything is written, then written and read back.

::

    report = apply_dataset(session, load_dataset("base.dcm"))   # raises when anything is refused
    print(report.to_text())                                     # applied / unchanged, per object

The checks, for every object first: known to the A2L, a calibration object, writable (READ_ONLY,
CALIBRATION_ACCESS), its kind and shape, its limits and monotony
(:func:`~workbench.calib.limits.check_limits`), a value its data type and conversion can take,
inside the A2L's writable memory, and no two objects writing other bytes to the same place (a
MAP's axis and the AXIS_PTS it shares, given twice with other points). One refusal and nothing is
written: :class:`ApplyRefused` carries the report that lists every refusal. Then only the objects
whose bytes change are written, in the dataset's order, each through
:meth:`Session.write <workbench.session.Session.write>` (only the changed bytes, read back): the
session knows what the checks read, so each object is read once. A
failure halfway stops there and raises :class:`ApplyFailed`; its report says which objects reached
the ECU, which one failed (and which of its fields were written), and which were not written.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from contextlib import nullcontext
from dataclasses import dataclass, field

import numpy as np

from workbench.calib.codec import value_edits
from workbench.calib.dataset import DatasetDiff, diff_datasets
from workbench.calib.fixes import ENABLE, fix_pairs_of
from workbench.calib.limits import check_limits
from workbench.calib.memory import ByteEdit, Span
from workbench.calib.values import CalValue
from workbench.calib.writable import check_inside
from workbench.errors import Cancelled, InputError, PartialWriteError, WorkbenchError
from workbench.progress import Progress, report
from workbench.session import Session
from workbench.sync.ecu import EcuReader, on_pages
from workbench.sync.offline import ImageCalibration
from workbench.sync.store import ByteStore
from workbench.sync.values import (as_stored, decode_values, label_differences, object_layouts, resolve_all,
                                   without_name)

__all__ = ["APPLIED", "FAILED", "NOT_WRITTEN", "REFUSED", "SKIPPED", "UNCHANGED", "WOULD_CHANGE", "ApplyFailed", "ApplyRefused",
           "ApplyReport", "ObjectOutcome", "apply_dataset"]

APPLIED, UNCHANGED, WOULD_CHANGE = "applied", "unchanged", "would change"
REFUSED, FAILED, NOT_WRITTEN, SKIPPED = "refused", "failed", "not written", "skipped"
STATUSES = (APPLIED, UNCHANGED, WOULD_CHANGE, SKIPPED, REFUSED, FAILED, NOT_WRITTEN)


@dataclass(frozen=True)
class ObjectOutcome:
    """What became of one object: ``status`` one of the STATUSES, ``reason`` why (refused, failed, not written),
    ``written`` the fields of a failed object that reached the ECU."""

    name: str
    status: str
    reason: str = ""
    written: tuple[str, ...] = ()


@dataclass
class ApplyReport:
    source: str
    dry_run: bool
    outcomes: list[ObjectOutcome] = field(default_factory=list)
    diff: DatasetDiff | None = None  # the objects that change: the ECU before (A), the dataset as stored (B)
    warnings: list[str] = field(default_factory=list)
    extended_limits: list[str] = field(default_factory=list)
    """Objects whose values are beyond their limits and within their EXTENDED_LIMITS: refused unless
    ``allow_extended_limits`` (a choice to offer the user only when this is not empty)."""

    def counts(self) -> dict[str, int]:
        return {status: sum(o.status == status for o in self.outcomes) for status in STATUSES}

    def named(self, status: str) -> list[str]:
        return [o.name for o in self.outcomes if o.status == status]

    @property
    def reached_ecu(self) -> list[str]:
        """Objects whose bytes (some or all) were written."""
        return [o.name for o in self.outcomes if o.status == APPLIED or (o.status == FAILED and o.written)]

    @property
    def ok(self) -> bool:
        return not any(o.status in (REFUSED, FAILED) for o in self.outcomes)

    def summary(self) -> str:
        counts = {status: count for status, count in self.counts().items() if count}
        text = ", ".join(f"{count} {status}" for status, count in counts.items()) or "no objects"
        verb = "dry run" if self.dry_run else "applied" if self.ok else "not applied"
        return f"{self.source}: {verb}: {text}"

    def to_text(self, decimals: Callable[[str, str], int | None] | None = None) -> str:
        """One line per object that is not unchanged, the diff of a dry run (``decimals`` as
        :meth:`~workbench.calib.dataset.DatasetDiff.to_text` takes it), the warnings, a summary."""
        lines = []
        shown = [o for o in self.outcomes if o.status != UNCHANGED]
        width = max((len(o.name) for o in shown), default=0)
        for outcome in shown:
            reason = f"  {outcome.reason}" if outcome.reason else ""
            written = f" (reached the ECU: {', '.join(outcome.written)})" if outcome.written else ""
            lines.append(f"{outcome.name:<{width}}  {outcome.status}{reason}{written}")
        if self.dry_run and self.diff is not None and self.diff.objects:
            lines.append(self.diff.to_text(decimals=decimals))
        lines += [f"warning: {text}" for text in self.warnings]
        lines.append(self.summary())
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"source": self.source, "dry_run": self.dry_run, "ok": self.ok, "counts": self.counts(),
                "reached_ecu": self.reached_ecu,
                "objects": [{"name": o.name, "status": o.status, "reason": o.reason, "written": list(o.written)}
                            for o in self.outcomes],
                "diff": self.diff.to_dict() if self.diff is not None else None, "warnings": self.warnings,
                "extended_limits": self.extended_limits}


class ApplyRefused(InputError):
    """Objects of the dataset failed the checks; nothing was written. ``report`` lists every one."""

    def __init__(self, report: ApplyReport):
        self.report = report
        refused = [o for o in report.outcomes if o.status == REFUSED]
        shown = "; ".join(f"{o.name}: {o.reason}" for o in refused[:3])
        more = f" (and {len(refused) - 3} more)" if len(refused) > 3 else ""
        super().__init__(f"{len(refused)} of {len(report.outcomes)} objects refused, nothing written: {shown}{more}")


class ApplyFailed(WorkbenchError):
    """Writing stopped halfway; ``report`` names what reached the ECU and what did not."""

    def __init__(self, report: ApplyReport, cause: Exception):
        self.report = report
        if isinstance(cause, Cancelled):
            self.exit_code = 130  # as an interrupted command: the user stopped it (Ctrl-C, Cancel)
        reached = report.reached_ecu
        shown = ", ".join(reached[:5]) + (" ..." if len(reached) > 5 else "") if reached else "none"
        super().__init__(f"{cause}; objects that reached the ECU: {shown}; "
                         f"{len(report.named(NOT_WRITTEN))} not written")


@dataclass
class _Planned:
    value: CalValue
    edits: list[ByteEdit]


def apply_dataset(session: Session | ImageCalibration, dataset: Mapping[str, CalValue], *, dry_run: bool = False,
                  allow_extended_limits: bool = False, skip_unknown: bool = False, progress: Progress | None = None,
                  source: str | None = None) -> ApplyReport:
    """Check every object of ``dataset`` against the A2L and the ECU's working page, then write those that change
    into the working page (XCP on it meanwhile, whichever page the ECU runs, as :func:`sync_download` writes).
    ``session`` may be an :class:`~workbench.sync.offline.ImageCalibration` instead: the same checks against an
    s19/hex, where an object whose bytes the file lacks is refused too, and the writes go into the image.

    :param dry_run: check and say what would change; write nothing (also on a read-only session).
    :param allow_extended_limits: values up to the EXTENDED_LIMITS pass (the report's ``extended_limits`` names
        the objects this decides, either way).
    :param skip_unknown: objects the A2L does not know (a dataset of another software version) are left out,
        reported as skipped, instead of refusing the whole dataset; every other refusal still refuses it.
    :returns: the report (every object applied or unchanged; on a dry run, what would change).
    :raises ApplyRefused: an object failed a check; nothing was written (the report lists every one).
    :raises ApplyFailed: a write failed halfway (the report names what reached the ECU).
    :raises EpkMismatchError: the session is read-only (not on a dry run).
    """
    result = ApplyReport(source or getattr(dataset, "source", None) or "dataset", dry_run)
    offline = isinstance(session, ImageCalibration)
    # a dataset is the working page's, as cal save reads it; an image has one page
    with session.lock, nullcontext() if offline else on_pages(session, "working"):
        if not dry_run:
            session.require_writable()
        planned, refused, current = _check(session, dataset, allow_extended_limits, progress, result)
        skipped = {name: refused.pop(name) for name in list(refused) if skip_unknown and name not in session.model}
        changing = _switches_in_order(session, planned, [name for name, plan in planned.items() if plan.edits])
        result.diff = _changes(session, dataset, planned, changing, current, result)
        pending = WOULD_CHANGE if dry_run else NOT_WRITTEN
        why = "other objects were refused" if refused and not dry_run else ""
        result.outcomes = [ObjectOutcome(name, REFUSED, refused[name]) if name in refused
                           else ObjectOutcome(name, SKIPPED, skipped[name]) if name in skipped
                           else ObjectOutcome(name, pending, why) if name in changing
                           else ObjectOutcome(name, UNCHANGED) for name in dataset]
        if refused and not dry_run:
            raise ApplyRefused(result)
        if not dry_run:
            _write(session, planned, changing, allow_extended_limits, progress, result)
        if changing and not offline:
            result.warnings += _not_run(session)
    return result


def _switches_in_order(session: Session | ImageCalibration, planned: dict[str, _Planned], changing: list[str]
                       ) -> list[str]:
    """``changing`` with each fix switch (``_EN``) the dataset turns on after its ``_VALUE`` and one it turns off
    before it, as Session.override and release write them: the ECU never runs the signal on the old override
    between the two writes (in a file's order, _EN first, a rail pressure fixed at 30 bar ran at the old 0 bar
    for a task or two)."""
    explicit = getattr(session, "fix_mapping", None)
    if not explicit and not any(name.upper().endswith(ENABLE) for name in changing):
        return changing  # no switch among them: the A2L's pairs are not looked for (a large A2L's whole list)
    pairs = session.fix_pairs() if isinstance(session, Session) else fix_pairs_of(session.model)
    order = list(changing)
    for pair in pairs:
        if pair.enable in order and pair.value in order:
            obj = session.model.object(pair.enable)
            on = bool(session.model.conversion(obj).to_raw(planned[pair.enable].value.value))
            order.remove(pair.enable)
            order.insert(order.index(pair.value) + (1 if on else 0), pair.enable)
    return order


def _not_run(session: Session) -> list[str]:
    """Segments whose working page the ECU does not run: the values written there take effect on switching."""
    numbers = list(dict.fromkeys(segment.number for segment in session.config.segments))
    return [f"the ECU runs the {state.name(state.ecu_page)} page of segment {state.segment}: the working page's "
            f"values take effect after `workbench cal page working` (Session.set_page('working'))"
            for state in map(session.page, numbers) if state.ecu_page != state.working]


def _check(session: Session | ImageCalibration, dataset: Mapping[str, CalValue], extended: bool,
           progress: Progress | None,
           result: ApplyReport) -> tuple[dict[str, _Planned], dict[str, str], ByteStore]:
    """Every object checked: ``({name: planned edits}, {name: why refused}, the ECU's bytes read)``; the objects
    the EXTENDED_LIMITS decide go to ``result.extended_limits``."""
    model = session.model
    where = getattr(dataset, "where", lambda name, start=False, index=None: "")  # one read from a file: file:line
    layouts, refused = object_layouts(model, dataset)
    # an object the A2L lacks (or has as no calibration) at the line that names it, as a parse error is located
    refused = {name: _located(where(name, start=True), why) for name, why in refused.items()}
    for name in list(layouts):
        violations = check_limits(model, dataset[name], extended=extended)
        if _extended_decides(model, dataset[name], extended, violations):
            result.extended_limits.append(name)
        if violations:
            refused[name] = _located(where(name, index=violations[0].index),
                                     "; ".join(without_name(name, str(v)) for v in violations))
            del layouts[name]
    offline = isinstance(session, ImageCalibration)
    current = ByteStore(fallback=session.fetch if offline else EcuReader(session, progress, "reading the ECU's values"))
    resolved, failed = resolve_all(layouts, current.fetch)
    refused.update(failed)
    current.fetch([span for layout in resolved.values() for span in layout.spans()])
    writable = session.writable_spans()
    planned: dict[str, _Planned] = {}
    for name in resolved:
        value = dataset[name]
        try:
            edits = value_edits(model, value, current.read, check=False)
        except WorkbenchError as exc:
            refused[name] = _located(where(name), without_name(name, str(exc)))
            continue
        try:
            check_inside(name, ((edit.span, edit.field) for edit in edits), writable)
            lacking = session.lacking(name, resolved[name].spans() + [e.span for e in edits]) if offline else None
            if lacking:
                raise InputError(lacking)
        except InputError as exc:
            refused[name] = without_name(name, str(exc))
            continue
        planned[name] = _Planned(value, edits)
    for name, other, where in _conflicts(model, planned, current):
        refused[name] = (f"{other} writes other bytes at {where} (the dataset gives both other values there, as a "
                         "shared axis edited in one place only): make them agree or leave one out")
    for name in refused:
        planned.pop(name, None)
    return planned, refused, current


def _extended_decides(model, value: CalValue, extended: bool, violations: list) -> bool:
    """Whether ``value`` is beyond its object's limits and within its EXTENDED_LIMITS (``violations``: those of
    the check made with ``extended``; the other check is made only for an object that has EXTENDED_LIMITS)."""
    if not getattr(model.object(value.name), "extended_limits", None):
        return False
    if extended:
        normal, wide = check_limits(model, value), violations
    else:
        normal, wide = violations, check_limits(model, value, extended=True)
    return bool(normal) and all(v.rule == "limits" for v in normal) and not wide


def _conflicts(model, planned: dict[str, _Planned], current: ByteStore) -> list[tuple[str, str, str]]:
    """Objects the others' writes undo (e.g. a MAP's shared axis and the AXIS_PTS itself given with other points):
    with every edit made, writing such an object again would still change bytes. ``(name, other, where)``."""
    final = current.copy()
    for plan in planned.values():
        final.apply(plan.edits)
    found = []
    for name, plan in planned.items():
        left = value_edits(model, plan.value, final.read, check=False)
        if not left:
            continue
        others = [other for other, theirs in planned.items() if other != name and any(
            _overlap(edit.span, mine.span) for edit in theirs.edits for mine in left)]
        found.append((name, others[0] if others else "another object", str(left[0].span)))
    return found


def _overlap(a: Span, b: Span) -> bool:
    return a.extension == b.extension and a.address < b.end and b.address < a.end


def _located(where: str, reason: str) -> str:
    return f"{where}: {reason}" if where else reason


def _changes(session: Session | ImageCalibration, dataset: Mapping[str, CalValue], planned: dict[str, _Planned], changing: list[str],
             current: ByteStore, result: ApplyReport) -> DatasetDiff:
    """The ECU's values now against the dataset's as the ECU would hold them, for the objects that change;
    label differences (units, axis names) become warnings."""
    model = session.model
    before, _ = decode_values(object_layouts(model, planned)[0], current.fetch)
    for name, value in before.items():
        result.warnings += [f"{name}: {text}" for text in label_differences(value, dataset[name])]
    after = {name: as_stored(model, planned[name].value, current) for name in changing}
    result.warnings += _shared_axes(model, before, after)
    where = session.label if isinstance(session, ImageCalibration) else "ECU"
    return diff_datasets({name: before[name] for name in changing}, after, a_label=where, b_label=result.source)


_SHARED_AXES = ("COM_AXIS", "RES_AXIS", "CURVE_AXIS")  # points that live in an object of their own


def _shared_axes(model, before: dict[str, CalValue], after: dict[str, CalValue]) -> list[str]:
    """A CURVE's or MAP's new axis points written into the AXIS_PTS (or CURVE) it takes them from, which the dataset
    does not give itself: said, with the other objects on that axis, whose points move too (they were written
    unsaid: a parameter set of one map moved the breakpoints of every map sharing its axis)."""
    found = []
    for name, new in after.items():
        old = before.get(name)
        for letter, was, now in zip("XYZ45", old.axes if old is not None else (), new.axes):
            if (was.kind in _SHARED_AXES and was.name and was.name not in after
                    and not np.array_equal(np.asarray(was.values), np.asarray(now.values))):
                others = [other for other in model.names("CHARACTERISTIC") if other != name and any(
                    was.name in (axis.axis_pts_ref, axis.curve_axis_ref) for axis in model.object(other).axes)]
                holder = "CURVE" if was.kind == "CURVE_AXIS" else "AXIS_PTS"
                also = f"; they move for {', '.join(others)} too" if others else ""
                found.append(f"{name}: its {letter} axis is the {holder} {was.name} ({was.kind}): its points are "
                             f"written too, as the dataset gives them{also}")
    return found


def _write(session: Session | ImageCalibration, planned: dict[str, _Planned], changing: list[str], extended: bool,
           progress: Progress | None, result: ApplyReport) -> None:
    """Write the changing objects in order; on a failure mark what reached the ECU and raise ApplyFailed."""
    index = {o.name: i for i, o in enumerate(result.outcomes)}
    for done, name in enumerate(changing):
        try:
            report(progress, done, len(changing), f"writing {name}")
        except Cancelled as exc:  # between two objects: those before reached the ECU, and the report says so
            for rest in changing[done:]:
                result.outcomes[index[rest]] = ObjectOutcome(rest, NOT_WRITTEN, f"cancelled before {name}")
            raise ApplyFailed(result, exc) from exc
        try:
            session.write(name, planned[name].value, allow_extended_limits=extended)
        except WorkbenchError as exc:
            written = tuple(exc.written) if isinstance(exc, PartialWriteError) else ()
            result.outcomes[index[name]] = ObjectOutcome(name, FAILED, str(exc), written)
            for rest in changing[done + 1:]:
                result.outcomes[index[rest]] = ObjectOutcome(rest, NOT_WRITTEN, f"writing stopped at {name}")
            raise ApplyFailed(result, exc) from exc
        result.outcomes[index[name]] = ObjectOutcome(name, APPLIED)
    report(progress, len(changing), len(changing), "written")
