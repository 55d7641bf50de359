"""The ``/begin KEYWORD ... /end KEYWORD`` block tree over a token table.

Blocks are rows of a few numpy arrays (document order); pairing begins with ends is
done with a sort by nesting level instead of a Python stack walk over every event.
When the file is malformed a plain stack walk finds the first problem in file order
and reports it with its position.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from workbench.a2l.grammar import BLOCKS, BlockSpec
from workbench.a2l.source import SourceMap
from workbench.a2l.tokens import Tokens, shown

__all__ = ["BlockTable", "find_directives", "first_of_each", "parse_blocks"]

_IDENT_START = np.zeros(256, dtype=bool)
_IDENT_START[list(b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_")] = True


@dataclass
class BlockTable:
    """Block ``b`` spans tokens ``begin[b]`` (``/begin``) to ``end[b] + 1`` (the keyword after ``/end``)."""

    begin: np.ndarray
    end: np.ndarray
    keyword_id: np.ndarray  # per block: the index of its keyword in ``keyword_names``
    keyword_names: list[str]  # the distinct keywords
    parent: np.ndarray  # -1 for a top-level block
    _child_order: np.ndarray
    _child_offsets: np.ndarray
    _keywords: list[str] | None = None

    def __len__(self) -> int:
        return len(self.begin)

    @property
    def keyword(self) -> list[str]:
        """The keyword of every block (made on first use: an update never needs them all)."""
        if self._keywords is None:
            names = self.keyword_names
            self._keywords = [names[number] for number in self.keyword_id.tolist()]
        return self._keywords

    def keyword_of(self, block: int) -> str:
        """The keyword of one block (without :attr:`keyword`'s list of every block's)."""
        return self.keyword_names[self.keyword_id[block]]

    def children_having_keyword(self, block: int, keyword: str) -> np.ndarray:
        """:meth:`children` with this keyword (a MODULE has one child per object: a vectorized pick)."""
        children = self.children(block)
        if keyword not in self.keyword_names:
            return children[:0]
        return children[self.keyword_id[children] == self.keyword_names.index(keyword)]

    def having_keyword(self, keyword: str) -> np.ndarray:
        """Indices of the blocks with this keyword, in document order."""
        if keyword not in self.keyword_names:
            return np.zeros(0, dtype=np.int64)
        return np.flatnonzero(self.keyword_id == self.keyword_names.index(keyword))

    def children(self, block: int) -> np.ndarray:
        """Indices of the direct children of ``block`` (-1: the top level), in document order."""
        slot = block + 1
        return self._child_order[self._child_offsets[slot] : self._child_offsets[slot + 1]]


def find_directives(tokens: Tokens, source_map: SourceMap) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Token indices of ``/begin``, ``/end`` and ``/include``; any other ``/word`` is an error."""
    slash = np.flatnonzero(tokens.first_bytes() == ord("/"))
    begins = tokens.matching(b"/begin", slash)
    ends = tokens.matching(b"/end", slash)
    includes = tokens.matching(b"/include", slash)
    if len(begins) + len(ends) + len(includes) != len(slash):
        known = np.concatenate((begins, ends, includes))
        stray = int(np.setdiff1d(slash, known)[0])
        raise source_map.error(
            f"unexpected '{shown(tokens.raw(stray))}' (expected /begin, /end or /include)",
            tokens.starts_list[stray],
        )
    return begins, ends, includes


def parse_blocks(tokens: Tokens, begins: np.ndarray, ends: np.ndarray, source_map: SourceMap) -> BlockTable:
    """Pair every ``/begin X`` with its ``/end X``; raises :class:`A2lParseError` at the first mismatch."""
    _check_keywords_follow(tokens, begins, "/begin", source_map)
    _check_keywords_follow(tokens, ends, "/end", source_map)
    events = np.concatenate((begins, ends))
    signs = np.concatenate((np.ones(len(begins), np.int64), -np.ones(len(ends), np.int64)))
    by_position = np.argsort(events, kind="stable")
    events, signs = events[by_position], signs[by_position]
    depth = np.cumsum(signs)
    if len(depth) and (depth.min() < 0 or depth[-1] != 0):
        _diagnose(tokens, events, signs, source_map)
    # A begin at level L is closed by the next end at level L (depth before that end).
    level = np.where(signs > 0, depth, depth + 1)
    paired = np.lexsort((events, level))  # by level, then position: each begin is followed by its end
    partner = np.empty(len(events), dtype=np.int64)
    partner[paired[0::2]] = paired[1::2]
    opens = np.flatnonzero(signs > 0)  # the begins in document order
    closes = partner[opens]
    begin, end, block_level = events[opens], events[closes], level[opens]
    keys, exact = tokens.keys(events + 1)  # the keywords after every /begin and /end
    opening, closing = keys[:, opens], keys[:, closes]
    opening_exact, both = exact[opens], exact[opens] & exact[closes]
    same = np.array_equal(opening, closing) if both.all() else (opening[:, both] == closing[:, both]).all() \
        and tokens.raw_many((begin + 1)[~both]) == tokens.raw_many((end + 1)[~both])
    if not same:
        _diagnose(tokens, events, signs, source_map)
    keyword_id, names = _keyword_numbers(tokens, begin + 1, opening, opening_exact)
    parent = _parents(begin, block_level)
    child_order = np.argsort(parent, kind="stable")
    child_offsets = np.concatenate(([0], np.cumsum(np.bincount(parent + 1, minlength=len(begin) + 1))))
    return BlockTable(begin, end, keyword_id, names, parent, child_order, child_offsets)


def _keyword_numbers(tokens: Tokens, keywords: np.ndarray, keys: np.ndarray, exact: np.ndarray
                     ) -> tuple[np.ndarray, list[str]]:
    """Number the keyword tokens by their text, in order of first appearance: (numbers, texts). A few
    dozen distinct keywords for a hundred thousand blocks: grouped by their :meth:`Tokens.keys`."""
    if not len(keywords):
        return np.zeros(0, np.int64), []
    if not exact.all():  # a keyword longer than 24 bytes, or one at the very end: by their bytes
        numbers: dict[bytes, int] = {}
        found = np.array([numbers.setdefault(raw, len(numbers)) for raw in tokens.raw_many(keywords)], np.int64)
        return found, [raw.decode("latin-1") for raw in numbers]
    hashed = _hashes(keys)  # sorted by one number per key: equal keywords are neighbours
    order = np.argsort(hashed, kind="stable")
    ordered = hashed[order]
    starts_group = np.ones(len(order), dtype=bool)
    starts_group[1:] = ordered[1:] != ordered[:-1]
    group = np.cumsum(starts_group) - 1  # per position in ``order``
    first_rows = order[starts_group]  # the first row of each group (the sort is stable)
    if not np.array_equal(keys[:, order], keys[:, first_rows[group]]):  # two keywords with one number
        order = np.lexsort(keys[::-1])
        ordered = keys[:, order]
        starts_group[1:] = (ordered[:, 1:] != ordered[:, :-1]).any(axis=0)
        group = np.cumsum(starts_group) - 1
        first_rows = order[starts_group]
    rank = np.empty(len(first_rows), dtype=np.int64)
    rank[np.argsort(first_rows)] = np.arange(len(first_rows))  # groups by first appearance
    numbers = np.empty(len(order), dtype=np.int64)
    numbers[order] = rank[group]
    names = [raw.decode("latin-1") for raw in tokens.raw_many(keywords[np.sort(first_rows)])]
    return numbers, names


def _hashes(keys: np.ndarray) -> np.ndarray:
    """One number per column of :meth:`Tokens.keys` (unequal keys may share one: the caller checks)."""
    return keys[0] ^ keys[1] * np.uint64(0x9E3779B97F4A7C15) ^ keys[2] * np.uint64(0xC2B2AE3D27D4EB4F) \
        ^ keys[3] * np.uint64(0x165667B19E3779F9)


def first_of_each(keys: np.ndarray) -> np.ndarray:
    """Where each distinct value of ``keys`` first occurs, ordered by value: ``np.unique``'s
    ``return_index`` without its import of ``numpy.ma`` (7 ms, on a path that is timed)."""
    order = np.argsort(keys, kind="stable")
    ordered = keys[order]
    first = np.ones(len(keys), dtype=bool)
    first[1:] = ordered[1:] != ordered[:-1]
    return order[first]


def _parents(begin: np.ndarray, level: np.ndarray) -> np.ndarray:
    """The enclosing block of each block: the last one a level up that began before it."""
    parent = np.full(len(begin), -1, dtype=np.int64)
    for depth in range(2, int(level.max(initial=1)) + 1):
        outer = np.flatnonzero(level == depth - 1)
        inner = np.flatnonzero(level == depth)
        parent[inner] = outer[np.searchsorted(begin[outer], begin[inner]) - 1]
    return parent


def _check_keywords_follow(tokens: Tokens, directives: np.ndarray, name: str, source_map: SourceMap) -> None:
    after = directives + 1
    bad = after >= len(tokens)
    ok = ~bad
    bad[ok] = ~_IDENT_START[tokens.first_bytes(after[ok])]
    if bad.any():
        where = int(directives[np.argmax(bad)])
        raise source_map.error(f"{name} must be followed by a block keyword", tokens.starts_list[where])


_FREE = BlockSpec(free=True)  # a block the table does not know: anything may stand inside


def _check_placed(keyword: str, offset: int, stack: list[tuple[str, int]], source_map: SourceMap) -> None:
    """A known block that cannot stand inside the open one (a MEASUREMENT in a CHARACTERISTIC) is where a
    missing /end shows: said there, not at the end of the MODULE (IF_DATA and A2ML hold anything)."""
    if not stack or keyword not in BLOCKS or any(BLOCKS.get(open_, _FREE).free for open_, _ in stack):
        return
    parent, parent_offset = stack[-1]
    if keyword not in BLOCKS[parent].blocks:
        file, line, column = source_map.position(parent_offset)
        if source_map.position(offset)[0] != file:  # an included file's block: the mistake is the includer's
            return
        raise source_map.error(f"/begin {keyword} cannot stand inside /begin {parent} (line {line}, column {column}): "
                               f"is its /end {parent} missing?", offset)


def _diagnose(tokens: Tokens, events: np.ndarray, signs: np.ndarray, source_map: SourceMap) -> None:
    """Walk the begin/end events with a stack and raise at the first problem in file order."""
    stack: list[tuple[str, int]] = []
    for token, sign in zip(events.tolist(), signs.tolist()):
        keyword = tokens.raw(token + 1).decode("latin-1")
        offset = tokens.starts_list[token]
        if sign > 0:
            _check_placed(keyword, offset, stack, source_map)
            stack.append((keyword, offset))
            continue
        if not stack:
            raise source_map.error(f"/end {keyword} without a matching /begin {keyword}", offset)
        open_keyword, open_offset = stack.pop()
        if open_keyword != keyword:
            _, line, column = source_map.position(open_offset)
            raise source_map.error(
                f"/end {keyword} found while /begin {open_keyword} (line {line}, column {column}) is still open",
                offset,
            )
    if stack:
        keyword, offset = stack[-1]
        raise source_map.error(f"/begin {keyword} is never closed (missing /end {keyword})", offset)
