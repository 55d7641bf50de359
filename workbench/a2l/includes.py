"""``/include`` handling: included files are spliced into one buffer, their positions kept.

``/include "file.a2l"`` (or an unquoted name) names a path relative to the including
file; includes nest. The spliced buffer is what the document parses; its source map
says which file every byte came from, so that an update can write its changes back
into the file that holds them and keep the ``/include`` lines.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from workbench.a2l.reports import IncludeMode
from workbench.a2l.source import Segment, SourceFile, SourceMap, read_source, transcoded
from workbench.a2l.tokens import Tokens, tokenize
from workbench.a2l.tree import find_directives
from workbench.a2l.values import parse_string
from workbench.errors import InputError
from workbench.findings import Finding, Report, Severity
from workbench.progress import Progress, report as report_progress

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument
    from workbench.a2l.edits import Edits

__all__ = ["A2ML_SUFFIX", "Include", "IncludedChange", "Spliced", "cannot_include", "edited_texts", "flatten_file",
           "flatten_summary", "includes_not_found_from", "left_out", "load_a2l_to_work", "splice_includes"]

A2ML_SUFFIX = ".aml"  # an A2ML file: the syntax of the IF_DATA blocks, which the reader knows without it


class Include(NamedTuple):
    """One ``/include`` directive of a file."""

    name: str  # as written (relative to the including file's folder)
    path: Path  # the file it names
    offset: int  # of the directive in the including file


class Spliced(NamedTuple):
    data: bytes  # the file with every /include replaced by the included text
    source_map: SourceMap
    tokens: Tokens  # of ``data``
    includes: list[Include]  # the file's own directives (not those of included files)
    count: int  # directives met, nested ones included
    begins: np.ndarray  # token indices of the /begin and /end directives of ``data``
    ends: np.ndarray


def splice_includes(source: SourceFile, encoding: str | None = None, _chain: tuple[Path, ...] = (), *,
                    missing: list[tuple[Include, SourceFile, str]] | None = None) -> Spliced:
    """The bytes of ``source`` with every ``/include`` replaced by the included file.

    ``encoding`` is the encoding of the buffer the result goes into (default: the
    source's own); included files in another encoding are converted to it.
    Raises :class:`A2lParseError` (located at the directive) when an included file is
    missing, includes itself, or cannot be expressed in the including file's encoding;
    with a ``missing`` list, a file that cannot be read is added to it (with the file whose directive
    names it, and why) and its directive left out, so that the rest can be checked.
    """
    encoding = encoding or source.encoding
    if source.encoding != encoding:
        source = transcoded(source, encoding)
    source_map = SourceMap.single(source)
    tokens = tokenize(source.data, source_map)
    begins, ends, directives = find_directives(tokens, source_map)
    if not len(directives):
        return Spliced(source.data, source_map, tokens, [], 0, begins, ends)
    chain = _chain + ((source.path.resolve(),) if source.path is not None else ())
    pieces: list[bytes] = []
    segments: list[Segment] = []
    includes: list[Include] = []
    position = 0  # in source.data
    length = 0  # of the output so far
    count = 0
    for directive in directives.tolist():
        offset = tokens.starts_list[directive]
        if directive + 1 >= len(tokens):
            raise source_map.error("/include must be followed by a file name", offset)
        name = _include_name(source, tokens.raw(directive + 1))
        target = (source.path.parent if source.path is not None else Path.cwd()) / name
        if target.resolve() in chain:
            raise source_map.error(f"/include of {target} includes itself (a cycle)", offset)
        try:
            included = read_source(target)
        except InputError as exc:
            why = str(exc).removeprefix(f"{target}: ")
            if missing is None:
                raise source_map.error(cannot_include(target, why), offset) from None
            missing.append((Include(name, target, offset), source, why))
            included = SourceFile(target, b"", encoding)
        inner = splice_includes(included, encoding, chain, missing=missing)
        includes.append(Include(name, target, offset))
        segments.append(Segment(length, offset - position, source, position))
        pieces.append(source.data[position:offset])
        length += offset - position
        segments.extend(Segment(s.offset + length, s.length, s.source, s.source_offset) for s in inner.source_map.segments)
        pieces.append(inner.data)
        length += len(inner.data)
        position = tokens.ends_list[directive + 1]
        count += 1 + inner.count
    segments.append(Segment(length, len(source.data) - position, source, position))
    pieces.append(source.data[position:])
    buffer = b"".join(pieces)
    spliced_map = SourceMap(segments)
    spliced_tokens = tokenize(buffer, spliced_map)
    begins, ends, _ = find_directives(spliced_tokens, spliced_map)
    return Spliced(buffer, spliced_map, spliced_tokens, includes, count, begins, ends)


def cannot_include(target: Path, why: str) -> str:
    """The one text for an ``/include`` whose file cannot be read (``why``: "no such file" ...), wherever it is said."""
    return f"cannot include {target}: {why}"


def _include_name(source: SourceFile, raw: bytes) -> str:
    return parse_string(raw, source.encoding) if raw[:1] == b'"' else raw.decode(source.encoding)


class IncludedChange(NamedTuple):
    """An included file that edits change."""

    source: SourceFile
    count: int  # edits in it
    data: bytes  # its new bytes, as the file stores them (BOM, encoding)
    first: tuple[str, int, int]  # file, line and column of its first change


def edited_texts(doc: "A2lDocument", edits: "Edits", includes: IncludeMode,
                 report: Report) -> tuple[bytes, list[IncludedChange]]:
    """The main file's text with ``edits`` applied, and the included files they change: under
    ``IncludeMode.MERGE`` the whole buffer (every ``/include`` inline, a finding says so) and none; under
    ``UPDATE`` each included file that changes is a finding ("include-updated"); under ``KEEP`` the caller says
    what changes it does not write mean. Raises :class:`InputError` for an edit across an ``/include``."""
    if includes is IncludeMode.MERGE:
        if doc.include_count:
            report.add(Finding("includes-inlined", doc.name, f"{doc.include_count} /include(s) written inline: the "
                               "output is self-contained", doc.name, 1, 1))
        return edits.apply(doc.data), []
    data, changed = doc.source.data, []
    for source, file_edits in edits.by_file(doc.source_map):
        if source is doc.source:
            data = file_edits.apply(source.data)
            continue
        first = (source.name, *source.position(min(file_edits.starts)))
        changed.append(IncludedChange(source, len(file_edits), source.file_bytes(file_edits.apply(source.data)), first))
        if includes is IncludeMode.UPDATE:
            report.add(Finding("include-updated", source.name, f"{source.name}: {len(file_edits)} change(s) written "
                               "into the included file", *first))
    return data, changed


def includes_not_found_from(doc: "A2lDocument", output: Path) -> list[Finding]:
    """Warnings for the ``/include`` lines of ``doc``'s main file that do not find their file from
    ``output``'s folder (an output written elsewhere than its input keeps relative include paths)."""
    findings = []
    for include in doc.includes:
        from_output = output.parent / include.name
        if from_output.exists() and from_output.resolve() == include.path.resolve():
            continue
        line, column = doc.source.position(include.offset)
        findings.append(Finding("include-not-found-from-output", include.name,
                                f'{output}: /include "{include.name}" does not find {include.path} from the output\'s '
                                "folder; write the output beside its input, or the includes inline",
                                doc.source.name, line, column, "", Severity.WARNING))
    return findings


def load_a2l_to_work(path: str | Path) -> A2lDocument:
    """:func:`~workbench.a2l.document.load_a2l` for work with the ECU (a session, an image, a flash): an ``/include``
    of an A2ML file (``.aml``, XCPlite's ``XCP_104.aml`` beside the A2L an ECU uploads) that is not there is left
    out with a warning (logged; :func:`left_out` says it, as ``a2l check`` finds it), for A2ML only describes the
    syntax of IF_DATA. The document's :attr:`~workbench.a2l.document.A2lDocument.missing_includes` lists it.

    :raises InputError: ``path`` cannot be read; :raises A2lParseError: malformed, or an include of another
        kind is missing (file:line:column of the directive, as load_a2l says it).
    """
    from workbench.a2l.document import A2lDocument

    doc = A2lDocument.from_source(read_source(path), missing_ok=True)
    for include, holder, why in doc.missing_includes:
        if include.path.suffix.lower() != A2ML_SUFFIX:
            raise holder.error(cannot_include(include.path, why), include.offset)
    if doc.missing_includes:
        from workbench.logs import logger

        for line in left_out(doc):
            logger(__name__).warning("%s", line)
    return doc


def left_out(doc: A2lDocument) -> list[str]:
    """``file:line:column: /include "NAME" left out: why`` for each include a tolerant load left out."""
    said = []
    for include, holder, why in doc.missing_includes:
        line, column = holder.position(include.offset)
        said.append(f'{holder.name}:{line}:{column}: /include "{include.name}" left out: {why}')
    return said


def flatten_file(a2l: str | Path, output: str | Path | None, progress: Progress | None = None) -> Report:
    """a2ltool's ``--merge-includes``: ``a2l`` with the text of every ``/include`` (nested ones too) in place
    of the directive, written to ``output`` atomically (None: a dry run). Included files in another encoding
    are converted to the main file's; everything else stays as written. One finding per directive.

    :raises InputError: ``a2l`` cannot be read; :raises A2lParseError: it or an included file is malformed or
        missing (file:line:column of the directive); :raises Cancelled: ``progress`` was cancelled (nothing
        written).
    """
    from workbench.a2l.document import load_a2l
    from workbench.a2l.edits import write_source

    report_progress(progress, 0, 2, f"reading {Path(a2l).name}")
    doc = load_a2l(a2l, validate=False)
    report_progress(progress, 1, 2, "writing")  # the last check point: nothing is written before it
    report = Report("flatten")
    for include in doc.includes:
        line, column = doc.source.position(include.offset)
        report.add(Finding("include-inlined", include.name, f'/include "{include.name}" written inline',
                           doc.source.name, line, column))
    if doc.include_count > len(doc.includes):
        report.add(Finding("include-inlined", doc.name, f"{doc.include_count - len(doc.includes)} nested /include(s) "
                           "written inline", doc.source.name, 1, 1))
    if output is not None:
        write_source(doc.source, doc.data, output)
    return report


def flatten_summary(report: Report, output: str | Path) -> str:
    """The one line after :func:`flatten_file` wrote ``output`` (the CLI's and the window's)."""
    inlined = len(report.of_kind("include-inlined"))
    return f"wrote {output}: " + (f"{inlined} /include(s) written inline" if inlined else "it has no /include")
