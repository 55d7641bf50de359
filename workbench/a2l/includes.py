"""``/include`` handling: included files are spliced into one buffer, their positions kept.

``/include "file.a2l"`` (or an unquoted name) names a path relative to the including
file; includes nest. The spliced buffer is what the document parses and what a
merge or update writes: the output of a file with includes is self-contained.
"""

from __future__ import annotations

from pathlib import Path

from workbench.a2l.source import Segment, SourceFile, SourceMap, read_source, transcoded
from workbench.a2l.tokens import Tokens, tokenize
from workbench.a2l.tree import find_directives
from workbench.a2l.values import parse_string
from workbench.errors import InputError


def splice_includes(source: SourceFile, encoding: str | None = None,
                    _chain: tuple[Path, ...] = ()) -> tuple[bytes, SourceMap, Tokens, int]:
    """The bytes of ``source`` with every ``/include`` replaced by the included file.

    Returns (buffer, source map, tokens of the buffer, number of include directives).
    ``encoding`` is the encoding of the buffer the result goes into (default: the
    source's own); included files in another encoding are converted to it.
    Raises :class:`A2lParseError` (located at the directive) when an included file is
    missing, includes itself, or cannot be expressed in the including file's encoding.
    """
    encoding = encoding or source.encoding
    if source.encoding != encoding:
        source = transcoded(source, encoding)
    source_map = SourceMap.single(source)
    tokens = tokenize(source.data, source_map)
    _, _, includes = find_directives(tokens, source_map)
    if not len(includes):
        return source.data, source_map, tokens, 0
    chain = _chain + ((source.path.resolve(),) if source.path is not None else ())
    pieces: list[bytes] = []
    segments: list[Segment] = []
    position = 0  # in source.data
    length = 0  # of the output so far
    count = 0
    for directive in includes.tolist():
        offset = tokens.starts_list[directive]
        if directive + 1 >= len(tokens):
            raise source_map.error("/include must be followed by a file name", offset)
        target = _include_path(source, tokens.raw(directive + 1), offset)
        if target.resolve() in chain:
            raise source_map.error(f"/include of {target} includes itself (a cycle)", offset)
        try:
            included = read_source(target)
        except InputError as exc:
            raise source_map.error(f"cannot include {target}: {exc}", offset) from None
        data, inner_map, _, inner_count = splice_includes(included, encoding, chain)
        segments.append(Segment(length, offset - position, source, position))
        pieces.append(source.data[position:offset])
        length += offset - position
        segments.extend(Segment(s.offset + length, s.length, s.source, s.source_offset) for s in inner_map.segments)
        pieces.append(data)
        length += len(data)
        position = tokens.ends_list[directive + 1]
        count += 1 + inner_count
    segments.append(Segment(length, len(source.data) - position, source, position))
    pieces.append(source.data[position:])
    buffer = b"".join(pieces)
    spliced_map = SourceMap(segments)
    return buffer, spliced_map, tokenize(buffer, spliced_map), count


def _include_path(source: SourceFile, raw: bytes, offset: int) -> Path:
    name = parse_string(raw, source.encoding) if raw[:1] == b'"' else raw.decode(source.encoding)
    base = source.path.parent if source.path is not None else Path.cwd()
    return base / name
