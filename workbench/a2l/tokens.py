"""Split A2L bytes into tokens without making an object per token.

One compiled regex finds the strings and comments (the only places where whitespace
does not separate tokens); numpy then finds every token's start and end offset. A
10 MB file becomes two int32 arrays in a few hundred milliseconds; the bytes of a
token are sliced out only when someone asks for them.
"""

from __future__ import annotations

import itertools
import re
from array import array

import numpy as np

from workbench.a2l.source import SourceMap

__all__ = ["Tokens", "opaque_spans", "shown", "tokenize"]

# A string ("..." with \x escapes or "" for a quote), a block comment or a line
# comment. The trailing '"?' and '\Z' let an unterminated one match so that it can
# be reported at its start instead of silently swallowing the file.
_OPAQUE = re.compile(rb'"[^"\\]*(?:(?:\\.|"")[^"\\]*)*"?|/\*.*?(?:\*/|\Z)|//[^\n]*', re.S)


class Tokens:
    """Token ``i`` is ``data[starts[i]:ends[i]]``; strings keep their quotes."""

    __slots__ = ("data", "starts", "ends", "_starts_list", "_ends_list", "_matches", "_first_bytes")

    def __init__(self, data: bytes, starts: np.ndarray, ends: np.ndarray):
        self.data = data
        self.starts = starts
        self.ends = ends
        self._starts_list: array | None = None
        self._ends_list: array | None = None
        self._matches: dict[bytes, np.ndarray] = {}
        self._first_bytes: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.starts)

    @property
    def starts_list(self) -> array:
        """``starts`` for indexing from Python: an ``array.array`` gives an int per index as fast as
        a list, without a list's 36 bytes per element (a 10 MB file has over a million tokens)."""
        if self._starts_list is None:
            self._starts_list = _as_array(self.starts)
        return self._starts_list

    @property
    def ends_list(self) -> array:
        if self._ends_list is None:
            self._ends_list = _as_array(self.ends)
        return self._ends_list

    def span(self, index: int) -> tuple[int, int]:
        """(start, end) byte offsets of one token."""
        if self._starts_list is None:
            return int(self.starts[index]), int(self.ends[index])
        return self._starts_list[index], self.ends_list[index]

    def raw(self, index: int) -> bytes:
        starts = self._starts_list
        if starts is None:  # a few tokens need no list of every token's offsets (8 MB each for 10 MB)
            return self.data[self.starts[index] : self.ends[index]]
        return self.data[starts[index] : self.ends_list[index]]

    def raw_many(self, indices) -> list[bytes]:
        """The bytes of many tokens (``indices``: an integer array or sequence)."""
        indices = np.asarray(indices, dtype=np.int64)
        data = self.data
        return [data[start:end] for start, end in zip(self.starts[indices].tolist(), self.ends[indices].tolist())]

    def joined(self, indices: np.ndarray, cut: int = 0) -> bytes:
        """The bytes of many tokens joined by NUL bytes, without ``cut`` bytes at either end of each
        (1: a string's quotes): one gather for the lot."""
        starts = self.starts[indices] + cut
        lengths = self.ends[indices] - cut - starts + 1  # with the separator after each
        if len(indices) < 1000:  # fewer slices than the gather's set-up costs
            data = self.data
            return b"\0".join([data[start : start + length - 1]
                                for start, length in zip(starts.tolist(), lengths.tolist())])
        ends = np.cumsum(lengths)
        positions = np.arange(int(ends[-1])) - np.repeat(ends - lengths - starts, lengths)
        buffer = np.frombuffer(self.data, np.uint8)
        joined = buffer[np.minimum(positions, len(buffer) - 1)]
        joined[ends - 1] = 0
        return joined[:-1].tobytes()

    def first_bytes(self, indices: np.ndarray | None = None) -> np.ndarray:
        """The first byte of every token (``"`` for strings, ``/`` for directives ...), or of ``indices``."""
        if indices is not None:
            return np.frombuffer(self.data, np.uint8)[self.starts[indices]]
        if self._first_bytes is None:
            self._first_bytes = np.frombuffer(self.data, np.uint8)[self.starts] if len(self.starts) \
                else np.zeros(0, np.uint8)
        return self._first_bytes

    def keys(self, indices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per token of ``indices``: a (4, n) uint64 key (length, then the bytes in three 64-bit words)
        that equals another token's exactly when their bytes are equal, and whether it could be made
        (False for tokens longer than 24 bytes or within the file's last 24: compare their bytes)."""
        starts = self.starts[indices]
        lengths = self.ends[indices] - starts
        exact = (lengths <= 24) & (starts <= len(self.data) - 24)
        keys = np.zeros((4, len(indices)), dtype=np.uint64)
        keys[0] = lengths
        rows = np.flatnonzero(exact)
        if len(rows):
            words = np.ndarray((len(self.data) - 7,), "<u8", self.data, 0, (1,))
            for part in range(3):  # the words after a token's end are 0: most keywords need two
                rows = rows[lengths[rows] > 8 * part]
                keys[1 + part, rows] = words[starts[rows] + 8 * part] & _MASKS[np.minimum(lengths[rows] - 8 * part, 8)]
        return keys, exact

    def matching(self, word: bytes, candidates: np.ndarray | None = None) -> np.ndarray:
        """Indices of the tokens (among ``candidates``, default all) whose bytes equal ``word``."""
        if candidates is None:
            found = self._matches.get(word)
            if found is None:
                candidates = np.flatnonzero(self.first_bytes() == word[0]) if word else np.zeros(0, np.int64)
                lengths = self.ends[candidates] - self.starts[candidates]
                found = self._matches[word] = self._compare(word, candidates[lengths == len(word)])
            return found
        lengths = self.ends[candidates] - self.starts[candidates]
        return self._compare(word, candidates[lengths == len(word)])

    def _compare(self, word: bytes, indices: np.ndarray) -> np.ndarray:
        """The ``indices`` (tokens of ``len(word)`` bytes, in order) whose bytes are ``word``: compared
        eight bytes at a time, through an unaligned 64-bit view of the data."""
        if not len(indices) or not word:
            return indices
        starts = self.starts[indices]
        size, data = len(word), self.data
        # the last few tokens of the file have no eight bytes after their start: compared byte by byte
        near_end = int(np.searchsorted(starts, len(data) - max(size, 8), side="right"))
        keep = np.ones(len(indices), dtype=bool)
        if near_end:
            words = np.ndarray((len(data) - 7,), "<u8", data, 0, (1,))
            head = starts[:near_end]
            if size < 8:
                mask = (1 << 8 * size) - 1
                keep[:near_end] = words[head] & np.uint64(mask) == int.from_bytes(word, "little")
            else:
                for offset in sorted({*range(0, size - 7, 8), size - 8}):
                    keep[:near_end] &= words[head + offset] == int.from_bytes(word[offset : offset + 8], "little")
        for row, start in enumerate(starts[near_end:].tolist(), near_end):
            keep[row] = data[start : start + size] == word
        return indices[keep]


_MASKS = np.array([(1 << 8 * size) - 1 for size in range(9)], dtype=np.uint64)  # the low ``size`` bytes


def _as_array(values: np.ndarray) -> array:
    converted = array("q")
    converted.frombytes(values.astype(np.int64, copy=False).tobytes())
    return converted


def tokenize(data: bytes, source_map: SourceMap) -> Tokens:
    """Tokenize ``data``; raises :class:`A2lParseError` at an unterminated string or comment."""
    size = len(data)
    if size == 0:
        empty = np.zeros(0, dtype=np.int64)
        return Tokens(data, empty, empty)
    buffer = np.frombuffer(data, np.uint8)
    spans = opaque_spans(data, buffer)
    is_string = buffer[spans[:, 0]] == 0x22
    _check_terminated(data, buffer, spans[:, 0], spans[:, 1], is_string, source_map)
    strings, comments = spans[is_string], spans[~is_string]
    solid = buffer > 0x20  # every A2L blank (space, tab, CR, LF, FF, VT) is a control character or space
    _mark(solid, comments, False)
    _mark(solid, strings, True)
    # a token boundary is a change between solid and blank, or either end of a string
    boundary = np.ones(size + 1, dtype=bool)
    np.not_equal(solid[1:], solid[:-1], out=boundary[1:size])
    boundary[strings[:, 0]] = True
    boundary[strings[:, 1]] = True
    cuts = np.flatnonzero(boundary)
    # offsets as int32 where they fit: half the memory of the two largest arrays of a document (a 10 MB
    # file's peak 22 MiB lower, ~5,000 fewer page faults per update)
    offset_type = np.int32 if size < 2**31 else np.int64
    head = cuts[:-1] if cuts[-1] == size else cuts
    tail = cuts[1:] if cuts[0] == 0 else cuts
    if len(strings) and (solid[strings[:, 0] - 1].any() or solid[np.minimum(strings[:, 1], size - 1)].any()):
        # a string that touches another token: a solid stretch between two cuts may be followed by another
        return Tokens(data, head[solid[head]].astype(offset_type), tail[solid[tail - 1]].astype(offset_type))
    # solid and blank stretches alternate between the cuts: every other cut starts a token, the next ends it
    first = 0 if solid[0] else 1
    ends = cuts[first + 1 :: 2].astype(offset_type)
    return Tokens(data, cuts[first::2][: len(ends)].astype(offset_type), ends)


def _mark(solid: np.ndarray, spans: np.ndarray, value: bool) -> None:
    """Set ``solid`` to ``value`` over the spans (a slice each when they are few, else one mask)."""
    if len(spans) <= 64:
        for start, end in spans.tolist():
            solid[start:end] = value
        return
    edges = np.empty(2 * len(spans) + 2, dtype=np.int64)
    edges[0], edges[-1] = 0, len(solid)
    edges[1:-1] = spans.ravel()
    # True over the spans to set, or over the stretches between the spans to clear (no inverted copy)
    marked = np.zeros(len(edges) - 1, dtype=bool)
    marked[(1 if value else 0)::2] = True
    mask = np.repeat(marked, np.diff(edges))
    if value:
        solid |= mask
    else:
        solid &= mask


def opaque_spans(data: bytes, buffer: np.ndarray) -> np.ndarray:
    """(start, end) of every string and comment, in order, as an (n, 2) array."""
    spans = _simple_opaque_spans(data, buffer)
    if spans is None:
        flat = itertools.chain.from_iterable(match.span() for match in _OPAQUE.finditer(data))
        spans = np.fromiter(flat, dtype=np.int64).reshape(-1, 2)
    return spans


def _simple_opaque_spans(data: bytes, buffer: np.ndarray) -> np.ndarray | None:
    """The spans found with numpy alone, valid when the file is simple: each quote closes the
    string the one before opened (no escaped or doubled quotes, no quote inside a comment).
    None when the file is not that simple; the regex then decides (and reports problems)."""
    marks = buffer == 0x22
    marks |= buffer == 0x2F
    marks = np.flatnonzero(marks)  # quotes and slashes: one pass over the file finds both
    is_quote = buffer[marks] == 0x22
    quotes = marks[is_quote]
    if len(quotes) % 2 or (len(quotes) and (buffer[quotes[quotes > 0] - 1] == 0x5C).any()):
        return None
    opens, closes = quotes[0::2], quotes[1::2] + 1
    if len(opens) > 1 and (opens[1:] == closes[:-1]).any():  # "" inside a string, or strings that touch
        return None
    slashes = marks[~is_quote]
    slashes = slashes[: len(slashes) - (len(slashes) and slashes[-1] == len(buffer) - 1)]  # one ends the file
    following = buffer[slashes + 1]
    candidates = slashes[(following == 0x2A) | (following == 0x2F)]
    if len(candidates) and len(opens):  # a comment start inside a string is text
        owner = np.searchsorted(opens, candidates, side="right") - 1
        inside = (owner >= 0) & (candidates < closes[np.maximum(owner, 0)])
        candidates = candidates[~inside]
    comments = []
    reached = 0
    for start in candidates.tolist():
        if start < reached:  # inside the previous comment
            continue
        if data[start + 1] == 0x2A:
            end = data.find(b"*/", start + 2)
            if end < 0:
                return None
            end += 2
        else:
            end = data.find(b"\n", start)
            end = len(data) if end < 0 else end
        comments.append((start, end))
        reached = end
    strings = np.stack((opens, closes), axis=1) if len(opens) else np.zeros((0, 2), dtype=np.int64)
    if not comments:
        return strings.astype(np.int64)
    comments = np.asarray(comments, dtype=np.int64)
    if (np.searchsorted(quotes, comments[:, 1]) > np.searchsorted(quotes, comments[:, 0])).any():
        return None  # a quote inside a comment
    # both are in order and disjoint: the comments go between the strings
    return np.insert(strings.astype(np.int64), np.searchsorted(strings[:, 0], comments[:, 0]), comments, axis=0)


def _check_terminated(data: bytes, buffer: np.ndarray, starts: np.ndarray, ends: np.ndarray,
                      is_string: np.ndarray, source_map: SourceMap) -> None:
    """Raise at the first string or block comment that runs to the end of the file."""
    last = buffer[ends - 1]
    length = ends - starts
    bad_string = is_string & ((length < 2) | (last != 0x22))
    is_block_comment = ~is_string & (buffer[np.minimum(starts + 1, len(buffer) - 1)] == 0x2A)
    bad_comment = is_block_comment & ((length < 4) | (last != 0x2F) | (buffer[ends - 2] != 0x2A))
    # a string whose closing quote is escaped (\" at the end of the file)
    suspicious = np.flatnonzero(is_string & ~bad_string & (buffer[ends - 2] == 0x5C) & (length > 2))
    for index in suspicious.tolist():
        bad_string[index] = _escaped_quote_at_end(data, int(starts[index]), int(ends[index]))
    bad = np.flatnonzero(bad_string | bad_comment)
    if len(bad):
        first = int(bad[0])
        what = "string (no closing '\"')" if is_string[first] else "comment (no closing '*/')"
        raise source_map.error(f"unterminated {what}", int(starts[first]))


def shown(raw: bytes, limit: int = 40) -> str:
    """A token as an error message quotes it: decoded byte for byte, cut to ``limit`` characters."""
    text = raw.decode("latin-1")
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _escaped_quote_at_end(data: bytes, start: int, end: int) -> bool:
    """True when the closing quote the regex stopped at is really an escaped one (``\\"`` at EOF)."""
    backslashes = 0
    position = end - 2
    while position > start and data[position] == 0x5C:
        backslashes += 1
        position -= 1
    return backslashes % 2 == 1
