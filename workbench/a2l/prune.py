"""``remove`` and ``cleanup``: objects taken out of an A2L with what refers to them (a2ltool's ``--remove``,
``--remove-range`` and ``--cleanup``).

``remove`` takes out the MEASUREMENTs, CHARACTERISTICs, AXIS_PTS, BLOBs and INSTANCEs (a2ltool's five)
whose whole name a pattern matches (a2ltool's rule: one that starts with ``^`` or ends with ``$`` is
searched as written) or whose address lies in a range ``[MIN, MAX)``, as a2ltool 3.4 takes them. What
refers to a removed object is settled so that the file stays consistent:

- an entry of a list that only groups objects (GROUP REF_MEASUREMENT/REF_CHARACTERISTIC, FUNCTION
  DEF_/REF_CHARACTERISTIC and IN_/OUT_/LOC_MEASUREMENT, FRAME_MEASUREMENT, TRANSFORMER_IN/OUT_OBJECTS)
  is removed with it, and a list left empty goes too (a2ltool cleans GROUPs only);
- a reference a kept object cannot do without (an AXIS_DESCR's AXIS_PTS_REF or CURVE_AXIS_REF, a VIRTUAL
  measurement's or a DEPENDENT_/VIRTUAL_CHARACTERISTIC's inputs, a MAP_LIST, VAR_MEASUREMENT,
  VAR_SELECTION_CHARACTERISTIC) refuses the removal: nothing is written, and each is an error naming both
  objects at the reference's file:line:column (a2ltool leaves them dangling);
- an optional reference (an INPUT_QUANTITY, a COMPARISON_QUANTITY) refuses it likewise, unless
  ``drop_optional``: then the INPUT_QUANTITY becomes ``NO_INPUT_QUANTITY`` and the COMPARISON_QUANTITY is
  removed, each a warning;
- a VAR_CHARACTERISTIC of a removed CHARACTERISTIC goes with it.

``cleanup`` takes out what nothing uses, as a2ltool's ``--cleanup`` does, until nothing more goes (a2ltool
makes one pass: a UNIT only a removed UNIT referred to stays until its next run): COMPU_METHODs,
COMPU_TABs, COMPU_VTABs, COMPU_VTAB_RANGEs, RECORD_LAYOUTs and UNITs no kept block refers to; GROUPs with
no REF_CHARACTERISTIC, REF_MEASUREMENT or SUB_GROUP entry left that no USER_RIGHTS names; FUNCTIONs with no
DEF_/REF_CHARACTERISTIC, IN_/OUT_/LOC_MEASUREMENT or SUB_FUNCTION entry left that no FUNCTION_LIST names;
and the list entries that name nothing (SUB_GROUP and SUB_FUNCTION entries of removed GROUPs and FUNCTIONs
too). Unlike a2ltool, every reference the checker knows counts (a COMPU_METHOD used only by an INSTANCE's
OVERWRITE stays; an AXIS_PTS or an INSTANCE component in a GROUP is no dangling entry), and a CONVERSION
that names no COMPU_METHOD is left for ``check`` to report (a2ltool makes it NO_COMPU_METHOD).

Only the removed text differs from the input (:func:`~workbench.a2l.edits.cut_spans`). Changes that fall
into ``/include``\\ d files are written there (:attr:`IncludeMode.UPDATE`), inline (``MERGE``), or refused
(``KEEP``, the default: nothing written).

Both report to a ``progress`` (:mod:`workbench.progress`) between their steps (reading, selecting, settling the
references, writing); a cancelled one raises :class:`~workbench.errors.Cancelled` there, before anything is written.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from workbench.a2l.addressed import AddressedObjects
from workbench.a2l.document import A2lDocument, Block, load_a2l
from workbench.a2l.edits import Edit, Edits, cut_spans, replace_token, write_source
from workbench.a2l.includes import edited_texts, includes_not_found_from
from workbench.a2l.patterns import as_typed, selection_pattern
from workbench.a2l.reports import IncludeMode, findings_at, written_line
from workbench.a2l.usage import ENTRY, Usage
from workbench.a2l.values import int_or_none, int_values
from workbench.errors import InputError, WorkbenchError
from workbench.fileio import write_output
from workbench.findings import Finding, Report, Severity, summarize
from workbench.progress import Progress, report as report_progress

__all__ = ["PruneFailed", "PruneReport", "PruneResult", "cleanup_document", "cleanup_file", "removal_edits",
           "remove_document", "remove_file"]

# lists that only group objects: an entry goes with what it names
_GROUPING = frozenset({"REF_MEASUREMENT", "REF_CHARACTERISTIC", "DEF_CHARACTERISTIC", "IN_MEASUREMENT",
                       "OUT_MEASUREMENT", "LOC_MEASUREMENT", "SUB_GROUP", "SUB_FUNCTION", "FUNCTION_LIST",
                       "TRANSFORMER_IN_OBJECTS", "TRANSFORMER_OUT_OBJECTS", "FRAME_MEASUREMENT"})
# references a kept object can do without: dropped with drop_optional (a positional one becomes the "none" word)
_OPTIONAL = {"AXIS_PTS#3": "NO_INPUT_QUANTITY", "AXIS_DESCR#1": "NO_INPUT_QUANTITY",
             "TYPEDEF_AXIS#2": "NO_INPUT_QUANTITY", "INPUT_QUANTITY": None, "COMPARISON_QUANTITY": None}
_SUPPORT = frozenset({"COMPU_METHOD", "COMPU_TAB", "COMPU_VTAB", "COMPU_VTAB_RANGE", "RECORD_LAYOUT", "UNIT"})
# GROUP and FUNCTION: the lists that make one not empty, and the list whose entry keeps one though empty
_CONTENT = {"GROUP": frozenset({"REF_CHARACTERISTIC", "REF_MEASUREMENT", "SUB_GROUP"}),
            "FUNCTION": frozenset({"DEF_CHARACTERISTIC", "REF_CHARACTERISTIC", "IN_MEASUREMENT", "OUT_MEASUREMENT",
                                   "LOC_MEASUREMENT", "SUB_FUNCTION"})}
_KEEPS = {"GROUP": "REF_GROUP", "FUNCTION": "FUNCTION_LIST"}
_STEPS = 4  # the check points: reading, selecting, settling the references, writing


@dataclass
class PruneReport(Report):
    """Findings of a remove or cleanup, and the names removed by keyword (``{"MEASUREMENT": ["a", ...]}``)."""

    removed: dict[str, list[str]] = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {**super().to_dict(), "removed": self.removed}

    def summary(self, output: str | Path | None) -> str:
        """The one line after ``output`` is written (None: a dry run)."""
        counts = ", ".join(f"{len(names)} {keyword}" for keyword, names in self.removed.items()) or "nothing"
        dropped = len(self.of_kind("reference-removed"))
        tail = f" ({dropped} reference(s) with them)" if dropped else ""
        return written_line(output, "remove", "removed", counts, tail)


@dataclass
class PruneResult:
    data: bytes  # the main file without what was removed (the input's encoding, without BOM)
    report: PruneReport
    included: dict[Path, bytes] = field(default_factory=dict)  # IncludeMode.UPDATE: included files that change


class PruneFailed(WorkbenchError):
    """A removal that would break a kept object, or a change in an included file not allowed; carries the report."""

    def __init__(self, report: PruneReport):
        self.report = report
        errors = report.errors
        super().__init__(f"{report.operation}: {len(errors)} problem(s), nothing written: {summarize(errors)}")


def remove_document(doc: A2lDocument, *, regexes: tuple[str, ...] = (), ranges: tuple[tuple[int, int], ...] = (),
                    cleanup: bool = False, drop_optional: bool = False,
                    includes: IncludeMode = IncludeMode.KEEP, progress: Progress | None = None) -> PruneResult:
    """``doc`` without the objects ``regexes`` (whole names) and ``ranges`` (``[low, high)`` holding the address)
    select, and with what referred to them settled (see the module docstring); ``cleanup`` then also removes what
    nothing uses. The document itself is not changed.

    :raises InputError: a pattern that is no regular expression, a range whose start is not below its end.
    :raises PruneFailed: a kept object would lose a reference it needs (or an optional one, without
        ``drop_optional``), or a change falls into an included file under ``IncludeMode.KEEP``.
    :raises Cancelled: ``progress`` was cancelled.
    """
    patterns = []
    for text in regexes:
        try:
            patterns.append((text, selection_pattern(text)))
        except Exception as exc:  # re.error
            raise InputError(f"--regex {text!r}: not a regular expression ({exc})") from None
    for low, high in ranges:
        if low >= high:
            raise InputError(f"--range 0x{low:X} 0x{high:X}: the start must lie below the end")
    report = PruneReport("remove")
    report_progress(progress, 1, _STEPS, "selecting the objects")
    selected = _select(doc, patterns, ranges, report)
    return _prune(doc, report, selected, cleanup, drop_optional, includes, progress)


def cleanup_document(doc: A2lDocument, *, includes: IncludeMode = IncludeMode.KEEP,
                     progress: Progress | None = None) -> PruneResult:
    """``doc`` without what nothing uses (see the module docstring); the document itself is not changed.

    :raises PruneFailed: a change falls into an included file under ``IncludeMode.KEEP``.
    :raises Cancelled: ``progress`` was cancelled.
    """
    return _prune(doc, PruneReport("cleanup"), {}, True, False, includes, progress)


def remove_file(a2l: str | Path, output: str | Path | None, *, regexes: tuple[str, ...] = (),
                ranges: tuple[tuple[int, int], ...] = (), cleanup: bool = False, drop_optional: bool = False,
                includes: IncludeMode = IncludeMode.KEEP, progress: Progress | None = None) -> PruneReport:
    """Read ``a2l``, remove (see :func:`remove_document`) and write ``output`` atomically (which may be ``a2l``;
    None: a dry run, nothing written); under ``IncludeMode.UPDATE`` also the included files that change. A
    cancelled ``progress`` stops it at its next step, nothing written (:class:`~workbench.errors.Cancelled`)."""
    doc = _read(a2l, progress)
    result = remove_document(doc, regexes=regexes, ranges=ranges, cleanup=cleanup, drop_optional=drop_optional,
                             includes=includes, progress=progress)
    return _write(doc, result, output, includes)


def cleanup_file(a2l: str | Path, output: str | Path | None, *, includes: IncludeMode = IncludeMode.KEEP,
                 progress: Progress | None = None) -> PruneReport:
    """Read ``a2l``, clean it up (see :func:`cleanup_document`) and write ``output`` as :func:`remove_file` does."""
    doc = _read(a2l, progress)
    return _write(doc, cleanup_document(doc, includes=includes, progress=progress), output, includes)


def _read(a2l: str | Path, progress: Progress | None) -> A2lDocument:
    report_progress(progress, 0, _STEPS, f"reading {Path(a2l).name}")
    return load_a2l(a2l, validate=False)


def _write(doc: A2lDocument, result: PruneResult, output: str | Path | None, includes: IncludeMode) -> PruneReport:
    """``result`` written to ``output`` (None: a dry run); no check point from here on: written is written."""
    if output is None:
        return result.report
    write_source(doc.source, result.data, output)
    for path, data in result.included.items():
        write_output(path, data)
    if includes is not IncludeMode.MERGE:
        result.report.extend(includes_not_found_from(doc, Path(output)))
    return result.report


def _member_hint(doc: A2lDocument, pattern) -> str:
    """When ``pattern`` names objects an INSTANCE stands for: that only whole INSTANCEs go (a2ltool's rule too)."""
    if not doc.block_indices("INSTANCE"):
        return ""
    model = doc.model()
    for kind in ("CHARACTERISTIC", "MEASUREMENT", "AXIS_PTS", "BLOB"):
        for name in model.names(kind):
            placed = model.placed(name) if pattern.search(name) else None
            if placed is not None:
                return (f"; it matches {name} of INSTANCE {placed.instance}: remove takes whole INSTANCEs "
                        f"(-R {placed.instance})")
    return ""


def _select(doc: A2lDocument, patterns: list, ranges: tuple[tuple[int, int], ...],
            report: PruneReport) -> dict[int, tuple[int, str]]:
    """The objects to remove: block -> (name token, why), in document order; a pattern or range that selects
    nothing is a warning."""
    objects = AddressedObjects(doc)
    selected: dict[int, tuple[int, str]] = {}
    matched: Counter[str] = Counter()
    for text, pattern in patterns:
        search = pattern.search
        for row, name in enumerate(objects.names):
            if search(name):
                matched[text] += 1
                selected.setdefault(int(objects.blocks[row]), (int(objects.name_tokens[row]), f"matches {text!r}"))
    held: Counter[tuple[int, int]] = Counter()
    if ranges:
        rows = np.flatnonzero(objects.address_token_array >= 0)
        tokens = objects.address_token_array[rows]
        values, read = int_values(doc.data, doc.tokens.starts[tokens], doc.tokens.ends[tokens])
        addresses = values.tolist()
        for index in np.flatnonzero(~read).tolist():
            value = int_or_none(doc.raw(int(tokens[index])))
            addresses[index] = -1 if value is None else value
        for (low, high) in ranges:
            for index in np.flatnonzero((values >= low) & (values < high) & read).tolist() + \
                    [i for i in np.flatnonzero(~read).tolist() if low <= addresses[i] < high]:
                row = int(rows[index])
                held[(low, high)] += 1
                selected.setdefault(int(objects.blocks[row]), (int(objects.name_tokens[row]),
                                                               f"at 0x{addresses[index]:X}"))
    for text, pattern in patterns:
        if not matched[text]:
            report.add(Finding("regex-matched-nothing", text, f"--regex {as_typed(text)} matches no MEASUREMENT, "
                               "CHARACTERISTIC, AXIS_PTS, BLOB or INSTANCE" + _member_hint(doc, pattern),
                               severity=Severity.WARNING))
    for low, high in ranges:
        if not held[(low, high)]:
            report.add(Finding("range-matched-nothing", f"0x{low:X} 0x{high:X}", f"--range 0x{low:X} 0x{high:X} "
                               "holds no object's address", severity=Severity.WARNING))
    return dict(sorted(selected.items()))


def removal_edits(doc: A2lDocument, selected: dict[int, tuple[int, str]], *, drop_optional: bool = False,
                  cleanup: bool = False) -> tuple[list[Edit], list[tuple]]:
    """The one removal engine (``remove``, ``cleanup``, ``update --remove-missing``): the edits that take the
    blocks of ``selected`` (block -> (its name token, why it goes)) out of ``doc`` with what refers to them
    settled as the module docstring says, and the findings as (token, kind, name, message, keyword, severity)
    tuples in document order. Errors among them (``still-referenced``: a kept object needs a removed one)
    mean the edits must not be written."""
    edits: list[Edit] = []
    pending: list[tuple] = []
    for module in doc.modules:
        gone = {block: why for block, why in selected.items() if int(doc.blocks.parent[block]) == module.index}
        if not gone and not cleanup:
            continue
        plan = _ModulePlan(doc, module, None if cleanup else frozenset({"object"}), pending)
        for block, (token, why) in gone.items():
            plan.remove(block, token, why)
        if cleanup:
            plan.clean_up()
        edits.extend(plan.settle(cleanup, drop_optional))
    pending.sort(key=lambda item: item[0])
    return edits, pending


def _prune(doc: A2lDocument, report: PruneReport, selected: dict[int, tuple[int, str]], cleanup: bool,
           drop_optional: bool, includes: IncludeMode, progress: Progress | None) -> PruneResult:
    report_progress(progress, 2, _STEPS, "finding what nothing uses" if report.operation == "cleanup"
                    else "settling the references to them")
    removal, pending = removal_edits(doc, selected, drop_optional=drop_optional, cleanup=cleanup)
    edits = Edits(removal)
    report.findings[:0] = findings_at(doc, pending)
    for _, kind, name, _, keyword, _ in pending:
        if kind == "removed":
            report.removed.setdefault(keyword, []).append(name)
    if report.errors:
        raise PruneFailed(report)
    report_progress(progress, 3, _STEPS, "writing")  # the last check point: nothing is written before it
    return _result(doc, edits, report, includes)


class _ModulePlan:
    """What goes from one MODULE: whole blocks, list entries, optional references."""

    def __init__(self, doc: A2lDocument, module: Block, namespaces: frozenset[str] | None, pending: list[tuple]):
        self.doc = doc
        self.usage = Usage(doc, module, namespaces)
        self.gone: set[int] = set()
        self.pending = pending

    def remove(self, block: int, name_token: int, why: str) -> None:
        keyword = self.doc.blocks.keyword_of(block)
        name = self.doc.text(name_token)
        self.gone.add(block)
        self.pending.append((name_token, "removed", name, f"{keyword} {name} removed ({why})", keyword, Severity.INFO))

    def clean_up(self) -> None:
        """Remove what nothing kept uses, until nothing more goes."""
        usage, doc, gone = self.usage, self.doc, self.gone
        keywords = {block: doc.blocks.keyword_of(block) for block in usage.children.tolist()}
        # a name defined twice (check's error) is left alone: which definition the references mean is not known
        candidates = {block for block, keyword in keywords.items()
                      if (keyword in _SUPPORT or keyword in _CONTENT) and block in usage.defined_once}
        keeps: Counter[int] = Counter()  # candidate -> references that keep it
        content: Counter[int] = Counter()  # GROUP/FUNCTION -> entries that name something kept
        by_owner: dict[int, list[int]] = {}
        by_target: dict[int, list[int]] = {}
        targets, owners = usage.targets.tolist(), usage.owners.tolist()
        for row, (target, owner, where) in enumerate(zip(targets, owners, usage.wheres)):
            if owner in candidates:
                by_owner.setdefault(owner, []).append(row)
            if target in candidates:
                by_target.setdefault(target, []).append(row)
            if owner in gone:
                continue
            if target in candidates and target != owner and self._keeps(keywords[target], where):
                keeps[target] += 1
            if (target >= 0 and target not in gone and owner in candidates
                    and where in _CONTENT.get(keywords[owner], ())):
                content[owner] += 1
        queue = [block for block in candidates if self._unused(block, keywords[block], keeps, content)]
        while queue:
            block = queue.pop()
            if block in gone:
                continue
            keyword = keywords[block]
            what = "nothing refers to it" if keyword in _SUPPORT else "empty"
            self.remove(block, doc.block_begin[block] + 2, what)
            for row in by_owner.get(block, ()):
                target = targets[row]
                if target in candidates and target != block and self._keeps(keywords[target], usage.wheres[row]):
                    keeps[target] -= 1
                    if target not in gone and self._unused(target, keywords[target], keeps, content):
                        queue.append(target)
            for row in by_target.get(block, ()):
                owner = owners[row]
                if owner in candidates and owner not in gone and usage.wheres[row] in _CONTENT.get(keywords[owner], ()):
                    content[owner] -= 1
                    if self._unused(owner, keywords[owner], keeps, content):
                        queue.append(owner)

    @staticmethod
    def _keeps(target_keyword: str, where: str) -> bool:
        """Whether a reference of ``where`` keeps a block of ``target_keyword`` (a GROUP: only a REF_GROUP)."""
        keeper = _KEEPS.get(target_keyword)
        return keeper is None or where == keeper

    @staticmethod
    def _unused(block: int, keyword: str, keeps: Counter, content: Counter) -> bool:
        return keeps[block] == 0 and (keyword not in _CONTENT or content[block] == 0)

    def settle(self, cleanup: bool, drop_optional: bool) -> list[Edit]:
        """The edits: removed blocks, the entries and references that named them (and, in a cleanup, the
        entries that name nothing); errors for references a kept object needs."""
        usage, doc, gone = self.usage, self.doc, self.gone
        spans = [(doc.tokens.span(doc.block_begin[block])[0], doc.tokens.span(doc.block_end[block] + 1)[1])
                 for block in gone]
        edits: list[Edit] = []
        gone_array = np.fromiter(gone, np.int64, len(gone))
        named = np.isin(usage.targets, gone_array)
        grouping = np.fromiter((where in _GROUPING for where in usage.wheres), bool, len(usage))
        concerned = (named | (cleanup & (usage.targets == -1) & (usage.kinds == ENTRY) & grouping)) \
            & ~np.isin(usage.owners, gone_array)
        dropped: dict[int, list[int]] = {}  # list holder -> its entries to remove
        for row in np.flatnonzero(concerned).tolist():
            where, token, holder = usage.wheres[row], int(usage.tokens[row]), int(usage.holders[row])
            target = int(usage.targets[row])
            name = usage.names[row]
            if where in _GROUPING:
                dropped.setdefault(holder, []).append(token)
                what = "removed" if target >= 0 else "names nothing"
                place = self._label(holder) + ("" if doc.blocks.keyword_of(holder) == where else f" {where}")
                self._note(token, "reference-removed", name, f"{name} ({what}) taken out of {place}", holder,
                           Severity.INFO)
            elif where == "VAR_CHARACTERISTIC#0":
                spans.append(self._block_span(holder))
                self._note(token, "reference-removed", name, f"VAR_CHARACTERISTIC {name} removed with it", holder,
                           Severity.INFO)
            elif where in _OPTIONAL and drop_optional:
                none = _OPTIONAL[where]
                if none is not None:
                    edits.append(replace_token(doc, token, none.encode("ascii")))
                else:
                    spans.append((doc.tokens.span(token - 1)[0], doc.tokens.span(token)[1]))
                option = where.split("#")[0] if none is None else "INPUT_QUANTITY"
                self._note(token, "reference-dropped", name, f"{self._label(holder)}: {option} {name} is removed: "
                           + (f"now {none}" if none else f"{where} dropped"), holder, Severity.WARNING)
            else:
                hint = ("; --drop-optional-references drops it" if where in _OPTIONAL else
                        f"; remove {self._label(usage.owners[row])} too, or keep {name}")
                self._note(token, "still-referenced", name, f"{self._label(holder)}: {self._what(where)} {name} "
                           f"would name a removed object{hint}", holder, Severity.ERROR)
        listed = Counter(usage.holders[np.isin(usage.holders, list(dropped))].tolist()) if dropped else Counter()
        for holder, tokens in dropped.items():
            if len(tokens) < listed[holder]:
                spans.extend(doc.tokens.span(token) for token in tokens)
            elif doc.blocks.keyword_of(holder) == "FRAME":  # FRAME_MEASUREMENT emptied: the option goes
                spans.append((doc.tokens.span(min(tokens) - 1)[0], doc.tokens.span(max(tokens))[1]))
            else:
                spans.append(self._block_span(holder))
        return [*cut_spans(doc, spans), *edits]

    def _block_span(self, block: int) -> tuple[int, int]:
        tokens = self.doc.tokens
        return tokens.span(self.doc.block_begin[block])[0], tokens.span(self.doc.block_end[block] + 1)[1]

    def _note(self, token: int, kind: str, name: str, message: str, holder: int, severity: Severity) -> None:
        self.pending.append((token, kind, name, message, self.doc.blocks.keyword_of(holder), severity))

    @staticmethod
    def _what(where: str) -> str:
        keyword, _, index = where.partition("#")
        return "its input quantity" if index else keyword

    def _label(self, block: int) -> str:
        """``KEYWORD name`` of a block; an unnamed one (AXIS_DESCR, a list) after the named one it is in."""
        doc, parts, found = self.doc, [], int(block)
        while found >= 0:
            keyword = doc.blocks.keyword_of(found)
            name = doc.block(found).name
            parts.append(f"{keyword} {name}" if name else keyword)
            if name:
                break
            found = int(doc.blocks.parent[found])
        return " ".join(reversed(parts))


def _result(doc: A2lDocument, edits: Edits, report: PruneReport, includes: IncludeMode) -> PruneResult:
    """The main file's new text (all text inline under MERGE), and the included files that change (UPDATE)."""
    data, changed = edited_texts(doc, edits, includes, report)
    if includes is IncludeMode.KEEP:
        for change in changed:
            report.add(Finding("include-not-updated", change.source.name, f"{change.source.name}: {change.count} "
                               "removal(s) fall into this included file: --update-includes writes them there, "
                               "--merge-includes inline", *change.first, "", Severity.ERROR))
        if changed:
            raise PruneFailed(report)
    return PruneResult(data, report, {change.source.path: change.data for change in changed})
