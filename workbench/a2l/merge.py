"""``merge``: module fragments into a master A2L (the thesis's ASAP2 Merger step).

The master supplies PROJECT, MODULE, MOD_PAR, MOD_COMMON, IF_DATA and A2ML (a master
with several MODULEs names the one to merge into); each fragment's MODULE content is
inserted verbatim (comments and layout kept) before the master's ``/end MODULE``, minus
what the master already has. A fragment is a whole A2L file or a bare one: module-level
blocks only, as written for ``/include`` (:func:`load_fragment`). A name defined
twice is compared token by token: identical definitions merge silently (reported
as info), different ones follow the :class:`ConflictPolicy`. Every decision is a
finding in the returned report.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

from workbench.a2l import grammar
from workbench.a2l.grammar import NAMESPACES
from workbench.a2l.document import A2lDocument, Block, load_a2l
from workbench.a2l.edits import Edit, Edits, apply_edits, newline_bytes, remove_block, replace_token, write_source
from workbench.a2l.includes import includes_not_found_from
from workbench.a2l.reports import ConflictPolicy, finding_at
from workbench.a2l.source import SourceFile, transcoded
from workbench.a2l.tokens import shown
from workbench.a2l.validate import validate_document
from workbench.errors import InputError, WorkbenchError
from workbench.findings import Finding, Report, Severity, summarize
from workbench.progress import Progress, report as report_progress

__all__ = ["ConflictPolicy", "MergeFailed", "MergeResult", "load_fragment", "merge_documents", "merge_files"]

MASTER_ONLY = frozenset({"MOD_PAR", "MOD_COMMON", "IF_DATA", "A2ML"})


@dataclass
class MergeResult:
    data: bytes  # the merged buffer, in the master's encoding (without BOM)
    report: Report


class MergeFailed(WorkbenchError):
    """Conflicting definitions the policy does not resolve (``ConflictPolicy.ERROR``; a name one fragment defines twice
    under ``RENAME``); carries the report."""

    def __init__(self, report: Report, policy: ConflictPolicy = ConflictPolicy.ERROR):
        self.report = report
        conflicts = report.of_kind("conflict")
        choices = "keep-first or keep-last" if policy is ConflictPolicy.RENAME else "keep-first, keep-last or rename"
        super().__init__(f"{len(conflicts)} conflicting definition(s): {summarize(conflicts)} "
                         f"(choose --on-conflict {choices})")
        self.exit_code = 1


class _Definition(NamedTuple):
    """Where a name is defined (a row per name of the merged module: a named tuple, not a Block)."""

    doc: A2lDocument
    index: int  # block index in ``doc``
    origin: int  # 0: master, n: fragment n

    @property
    def block(self) -> Block:
        return Block(self.doc, self.index)


@dataclass
class _Plan:
    """What happens to one fragment's MODULE content."""

    doc: A2lDocument
    module: Block | None  # None: a bare fragment, whose top level is the MODULE content
    skipped: list[Block] = field(default_factory=list)
    renames: dict[str, str] = field(default_factory=dict)
    identical: dict[int, _Definition] = field(default_factory=dict)  # skipped block index -> the definition kept
    contributed: int = 0

    @property
    def name(self) -> str:
        """The fragment's MODULE name (a bare fragment: its file name without suffix)."""
        if self.module is not None:
            return self.module.name or ""
        return self.doc.path.stem if self.doc.path is not None else self.doc.name

    @property
    def position(self) -> tuple[int, int]:
        return self.module.position[1:] if self.module is not None else (1, 1)

    def children(self) -> list[tuple[int, str, str | None]]:
        return _children(self.doc, self.module.index if self.module is not None else -1)


def load_fragment(path: str | Path) -> A2lDocument:
    """Read and validate a fragment: a whole A2L file (PROJECT and MODULE), or one written for
    ``/include`` (MODULEs without a PROJECT, or module-level blocks only). Raises as
    :func:`~workbench.a2l.document.load_a2l` does."""
    doc = load_a2l(path, validate=False)
    validate_document(doc, within=doc.included_in())
    return doc


def merge_documents(master: A2lDocument, fragments: list[A2lDocument], *, module: str | None = None,
                    policy: ConflictPolicy = ConflictPolicy.ERROR, keep_includes: bool = False,
                    progress: Progress | None = None) -> MergeResult:
    """Merge ``fragments`` into ``master``'s MODULE (see the module docstring); ``module`` names
    it when the master has several (a fragment with several MODULEs gives the one of that name).

    The result is self-contained: the text of every ``/include`` is written inline, unless
    ``keep_includes`` keeps the master's own ``/include`` lines (a fragment's included text
    is always inlined: its duplicates must be left out). Raises :class:`MergeFailed` on
    conflicts under ``ConflictPolicy.ERROR``, :class:`InputError` when the MODULE to merge into
    (or a fragment's) is not clear, :class:`A2lParseError` when a fragment cannot be
    written in the master's encoding, and :class:`InputError` when ``keep_includes`` would
    need a change inside a file the master includes.
    """
    report = Report("merge")
    merger = _Merger(master, _master_module(master, module), policy, report)
    for number, fragment in enumerate(fragments, start=1):
        report_progress(progress, number - 1, len(fragments), "merging fragments")
        merger.add(fragment, number)
    report_progress(progress, len(fragments), len(fragments), "merging fragments")
    if report.of_kind("conflict"):  # under any policy: a rename can meet one it cannot make
        raise MergeFailed(report, policy)
    edits = merger.edits()
    if keep_includes:
        return MergeResult(_master_file_text(master, edits), report)
    if master.include_count:
        report.add(Finding("includes-inlined", master.name, f"{master.include_count} /include(s) of the master "
                           "written inline: the output is self-contained", master.name, 1, 1))
    return MergeResult(edits.apply(master.data), report)


def merge_files(master: str | Path, fragments: list[str | Path], output: str | Path, *, module: str | None = None,
                policy: ConflictPolicy = ConflictPolicy.ERROR, keep_includes: bool = False,
                progress: Progress | None = None) -> Report:
    """Load (and validate) the inputs, merge, and write ``output`` atomically. The output's block
    structure is parsed again before writing, as a guard against a merge that broke it."""
    master_doc = load_a2l(master)
    result = merge_documents(master_doc, [load_fragment(path) for path in fragments], module=module, policy=policy,
                             keep_includes=keep_includes, progress=progress)
    A2lDocument.from_source(_as_source(master_doc, result.data), validate=False)
    write_source(master_doc.source, result.data, output)
    if keep_includes:
        result.report.extend(includes_not_found_from(master_doc, Path(output)))
    return result.report


def _master_file_text(master: A2lDocument, edits: Edits) -> bytes:
    """The master's own file with the edits, its /include lines kept."""
    data = master.source.data
    for source, file_edits in edits.by_file(master.source_map):
        if source is not master.source:
            line, column = source.position(min(file_edits.starts))
            raise InputError(f"{source.name}:{line}:{column}: the merge must change this file, which the master "
                             "includes; merge without keeping the master's includes")
        data = file_edits.apply(data)
    return data


class _Merger:
    """The names defined so far and what happens to each fragment's blocks."""

    def __init__(self, master: A2lDocument, module: Block, policy: ConflictPolicy, report: Report):
        self.master = master
        self.module = module
        self.policy = policy
        self.report = report
        self.plans: list[_Plan] = []
        self.definitions: dict[tuple[str, str], _Definition] = {}
        for index, keyword, name in _children(master, self.module.index):
            if keyword in NAMESPACES and name:
                self.definitions.setdefault((NAMESPACES[keyword], name), _Definition(master, index, 0))
        self.masters_own = dict(self.definitions)  # (namespace, name) -> the master's definition
        self.replacements: dict[tuple[str, str], Edit] = {}  # keep-last: the master's definition rewritten
        self.taken = {name for _, name in self.definitions}

    def add(self, fragment: A2lDocument, origin: int) -> None:
        plan = _Plan(fragment, _fragment_module(fragment, self.module.name))
        self.plans.append(plan)
        for index, keyword, name in plan.children():
            self._decide(plan, origin, index, keyword, name)
        self._rename_what_renames_changed(plan, origin)
        for index, existing in plan.identical.items():
            block = Block(fragment, index)
            self.report.add(finding_at(fragment, block.keyword_token, "duplicate-identical", block.name,
                                       f"{block.keyword} {block.name} of {_short(fragment)} is identical to the one "
                                       f"in {_short(existing.doc)}: merged", block.keyword))
        self.report.add(Finding("merged", plan.name, f"{plan.contributed} block(s) merged from "
                                f"{_short(fragment)}", fragment.name, *plan.position, "MODULE"))

    def _rename_what_renames_changed(self, plan: _Plan, origin: int) -> None:
        """A block that matched an earlier definition may differ from it once the fragment's renames
        apply (a COMPU_METHOD whose COMPU_VTAB was renamed): it is renamed too, until nothing changes."""
        changed = bool(plan.renames)
        while changed:
            changed = False
            for index, existing in list(plan.identical.items()):
                block = Block(plan.doc, index)
                if self._signature(block, plan) != self._signature(existing.block, self._plan_of(existing)):
                    del plan.identical[index]
                    plan.skipped.remove(block)
                    key = (NAMESPACES[block.keyword], block.name)
                    self._duplicate(plan, origin, block, key, existing)
                    changed = True

    def edits(self) -> Edits:
        """The master's edits: replaced definitions, and the fragments before its /end MODULE."""
        master = self.master
        end_line = master.data.rfind(b"\n", 0, master.tokens.starts_list[self.module.end_token]) + 1
        edits = Edits(self.replacements.values())
        edits.append(Edit(end_line, end_line, b"".join(_render(plan, master) for plan in self.plans)))
        return edits

    def _decide(self, plan: _Plan, origin: int, index: int, keyword: str, name: str | None) -> None:
        if keyword in MASTER_ONLY:
            self._master_only(plan, Block(plan.doc, index))
            return
        namespace = NAMESPACES.get(keyword)
        if namespace is None or not name:
            plan.contributed += 1
            return
        key = (namespace, name)
        existing = self.definitions.get(key)
        if existing is None:  # the common case: a new name
            self.definitions[key] = _Definition(plan.doc, index, origin)
            self.taken.add(name)
            plan.contributed += 1
            return
        self._duplicate(plan, origin, Block(plan.doc, index), key, existing)

    def _plan_of(self, definition: _Definition) -> _Plan | None:
        return self.plans[definition.origin - 1] if definition.origin else None

    @staticmethod
    def _signature(block: Block, plan: _Plan | None) -> list[bytes]:
        """The block's tokens as they are written out (comments and layout do not count)."""
        tokens = block.doc.tokens.raw_many(range(block.begin_token, block.end_token + 2))
        if plan is None or not plan.renames:
            return tokens
        renames = {old.encode(block.doc.encoding): new.encode(block.doc.encoding) for old, new in plan.renames.items()}
        return [renames.get(token, token) for token in tokens]

    def _master_only(self, plan: _Plan, block: Block) -> None:
        plan.skipped.append(block)
        if block.keyword == "MOD_COMMON":
            _compare_mod_common(self.master, self.module, block, self.report)
            return
        doc, keyword = plan.doc, block.keyword
        self.report.add(finding_at(doc, block.keyword_token, "ignored", keyword,
                                   f"{keyword} of {_short(doc)} ignored: the master's applies", keyword))

    def _duplicate(self, plan: _Plan, origin: int, block: Block, key: tuple[str, str], existing: _Definition) -> None:
        """A second definition of a name: identical ones merge, different ones follow the policy."""
        doc, report, keyword, (namespace, name) = plan.doc, self.report, block.keyword, key
        mine, theirs = self._signature(block, plan), self._signature(existing.block, self._plan_of(existing))
        if mine == theirs:
            plan.skipped.append(block)
            plan.identical[block.index] = existing
            return
        where = ":".join(map(str, existing.block.position[:2]))
        if self.policy is ConflictPolicy.RENAME and existing.origin == origin and origin:
            # one fragment's own references cannot tell its two definitions apart: a rename would rename both
            report.add(finding_at(doc, block.keyword_token, "conflict", name,
                                  f"{keyword} {name} is defined twice in {_short(doc)}, differently, also at {where} "
                                  f"({_first_difference(block, mine, theirs)}): a rename cannot tell which of the "
                                  "fragment's references mean which; correct the fragment, or merge with "
                                  "--on-conflict keep-first/keep-last", keyword, Severity.ERROR))
        elif self.policy is ConflictPolicy.ERROR:
            report.add(finding_at(doc, block.keyword_token, "conflict", name,
                                  f"{keyword} {name} differs from the definition at {where} "
                                  f"({_first_difference(block, mine, theirs)})", keyword, Severity.ERROR))
        elif self.policy is ConflictPolicy.KEEP_FIRST:
            plan.skipped.append(block)
            report.add(finding_at(doc, block.keyword_token, "kept-first", name,
                                  f"{keyword} {name}: kept the definition at {where}, dropped this one", keyword,
                                  Severity.WARNING))
        elif self.policy is ConflictPolicy.KEEP_LAST:
            if key in self.masters_own:  # the last definition takes the master's place (the latest one wins)
                start, end = self.masters_own[key].block.span
                self.replacements[key] = Edit(start, end, _fit(doc, self.master, doc.data[slice(*block.span)]))
                plan.skipped.append(block)
            else:
                earlier = self.plans[existing.origin - 1]
                earlier.skipped.append(existing.block)
                earlier.contributed -= 1
                plan.contributed += 1
            self.definitions[key] = _Definition(doc, block.index, origin)
            report.add(finding_at(doc, block.keyword_token, "kept-last", name,
                                  f"{keyword} {name}: this definition replaces the one at {where}", keyword,
                                  Severity.WARNING))
        else:
            new_name = _unique(f"{name}_{plan.name}", self.taken)
            self.taken.add(new_name)
            plan.renames[name] = new_name
            self.definitions[(namespace, new_name)] = _Definition(doc, block.index, origin)
            plan.contributed += 1
            report.add(finding_at(doc, block.keyword_token, "renamed", name,
                                  f"{keyword} {name} of {_short(doc)} renamed to {new_name} (differs from {where})",
                                  keyword, Severity.WARNING))


def _children(doc: A2lDocument, parent: int) -> list[tuple[int, str, str | None]]:
    """(block index, keyword, name) of a block's children (-1: the top level), names read in one pass."""
    children = doc.blocks.children(parent)
    keywords = doc.blocks.keyword
    return [(index, keywords[index], name) for index, name in zip(children.tolist(), doc.block_names(children))]


def _render(plan: _Plan, master: A2lDocument) -> bytes:
    """The fragment's MODULE content as it goes into the master."""
    doc, module = plan.doc, plan.module
    if module is None:  # a bare fragment: all of it, but for top-level keywords such as ASAP2_VERSION
        start, end = 0, len(doc.data)
        edits = [replace_token(doc, token, b"") for token in doc.own_tokens(-1)]
    else:
        args = module.args
        header_end = doc.tokens.ends_list[args[-1] if args else module.keyword_token]
        start = doc.data.find(b"\n", header_end) + 1 or header_end
        end = doc.data.rfind(b"\n", 0, doc.tokens.starts_list[module.end_token]) + 1
        end = max(end, start)
        edits = []
    edits += [remove_block(doc, block) for block in plan.skipped] + _rename_edits(plan, start, end)
    body = apply_edits(doc.data[start:end], [Edit(e.start - start, e.end - start, e.text)
                                             for e in edits if start <= e.start and e.end <= end])
    newline = newline_bytes(master)
    header = f"    /* ---- merged from {_short(doc)} ---- */".encode("ascii")
    return newline + header + newline + _fit(doc, master, body)


def _first_difference(block: Block, mine: list[bytes], theirs: list[bytes]) -> str:
    """Where two definitions of a name part first: ``first difference at line 23: '99' here, '100' there``."""
    index = next((i for i, (a, b) in enumerate(zip(mine, theirs)) if a != b), min(len(mine), len(theirs)))
    line = block.doc.token_position(block.begin_token + min(index, len(mine) - 1))[1]

    def token(tokens: list[bytes]) -> str:
        if index >= len(tokens):
            return "nothing more"
        return shown(tokens[index]) if tokens[index][:1] == b'"' else f"'{shown(tokens[index])}'"

    return f"first difference at line {line}: {token(mine)} here, {token(theirs)} there"


def _fit(doc: A2lDocument, master: A2lDocument, data: bytes) -> bytes:
    """Fragment bytes in the master's encoding and newline style."""
    if doc.encoding != master.encoding:
        data = transcoded(SourceFile(doc.path, data, doc.encoding), master.encoding).data
    if doc.source.newline != master.source.newline:
        data = data.replace(newline_bytes(doc), b"\n").replace(b"\n", newline_bytes(master))
    return data


def _rename_edits(plan: _Plan, start: int, end: int) -> list[Edit]:
    """Every use of a renamed name in the fragment's copied text (outside the blocks left out)."""
    if not plan.renames:
        return []
    doc = plan.doc
    left_out = sorted(block.span for block in plan.skipped)
    left_out_starts = [span[0] for span in left_out]
    edits = []
    for old, new in plan.renames.items():
        for token in doc.tokens.matching(old.encode(doc.encoding)).tolist():
            offset = doc.tokens.starts_list[token]
            inside = bisect.bisect_right(left_out_starts, offset) - 1
            if start <= offset < end and not (inside >= 0 and offset < left_out[inside][1]):
                edits.append(replace_token(doc, token, new.encode(doc.encoding)))
    return edits + _keep_symbol_links(plan, start, end)


def _keep_symbol_links(plan: _Plan, start: int, end: int) -> list[Edit]:
    """A renamed object without SYMBOL_LINK gets one naming its old name, so update still finds it."""
    doc = plan.doc
    left_out = {block.index for block in plan.skipped}  # a duplicate left out takes its SYMBOL_LINK with it
    edits = []
    for index, _, _ in plan.children():
        if index in left_out:
            continue
        block = Block(doc, index)
        if block.keyword in grammar.ADDRESSED_OBJECTS and block.name in plan.renames and block.option("SYMBOL_LINK") is None:
            anchor = doc.tokens.ends_list[block.args[-1]]
            edits.append(Edit(anchor, anchor, f' SYMBOL_LINK "{block.name}" 0'.encode(doc.encoding)))
    return edits


def _compare_mod_common(master: A2lDocument, module: Block, block: Block, report: Report) -> None:
    doc = block.doc
    master_common = module.first("MOD_COMMON")
    if master_common is None:
        return
    ours = {name: [doc.raw(t) for t in params] for name, params in block.layout()[1]}
    theirs = {name: [master.raw(t) for t in params] for name, params in master_common.layout()[1]}
    differing = sorted(name for name in ours if name in theirs and ours[name] != theirs[name])
    if differing:
        report.add(finding_at(doc, block.keyword_token, "mod-common-differs", "MOD_COMMON",
                              f"MOD_COMMON of {_short(doc)} differs from the master's in {', '.join(differing)}; "
                              "the master's applies", "MOD_COMMON", Severity.WARNING))
    else:
        report.add(finding_at(doc, block.keyword_token, "ignored", "MOD_COMMON",
                              f"MOD_COMMON of {_short(doc)} agrees with the master's", "MOD_COMMON"))


def _master_module(master: A2lDocument, name: str | None) -> Block:
    """The master's MODULE called ``name``, or its only one; raises :class:`InputError` naming the
    MODULEs when that is not clear."""
    modules = master.modules
    names = ", ".join(module.name or "?" for module in modules)
    if name is not None:
        for module in modules:
            if module.name == name:
                return module
        raise InputError(f"{master.name}: no MODULE named {name} (its MODULEs: {names or 'none'})")
    if len(modules) != 1:
        what = f"{len(modules)} MODULEs ({names}): choose one with --module NAME" if modules else "no MODULE"
        raise InputError(f"{master.name}: {what}")
    return modules[0]


def _fragment_module(doc: A2lDocument, name: str | None) -> Block | None:
    """The fragment's MODULE (in a PROJECT or not): its only one, or the one called ``name`` (the
    master's); None for a bare fragment of module-level blocks. Raises :class:`InputError` when it has several and none is called ``name``."""
    within = doc.included_in()
    if within == "MODULE":
        return None
    modules = doc.modules if within is None else [block for block in doc.top_blocks() if block.keyword == "MODULE"]
    if len(modules) == 1:
        return modules[0]
    for module in modules:
        if module.name == name:
            return module
    raise InputError(f"{doc.name}: {len(modules)} MODULEs ({', '.join(m.name or '?' for m in modules)}), none "
                     f"named {name} like the master's: merge a fragment with one MODULE")


def _unique(name: str, taken: set[str]) -> str:
    candidate, counter = name, 2
    while candidate in taken:
        candidate = f"{name}_{counter}"
        counter += 1
    return candidate


def _short(doc: A2lDocument) -> str:
    return doc.path.name if doc.path is not None else doc.name


def _as_source(master: A2lDocument, data: bytes) -> SourceFile:
    return SourceFile(master.path, data, master.encoding, master.source.bom, master.source.newline)
