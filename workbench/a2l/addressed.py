"""The objects of a document that have an ECU address, as columns: MEASUREMENT, CHARACTERISTIC,
AXIS_PTS, BLOB and INSTANCE directly inside a MODULE.

Built with vectorized searches over the token and block tables (no walk over the
blocks), so a file with 65,000 objects costs a few milliseconds; ``update`` then works
on whole columns, and :meth:`AddressedObjects.target` gives one row as an object where
per-object work is needed anyway (type checks, reports).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from workbench.a2l import grammar
from workbench.a2l.tokens import shown
from workbench.a2l.values import FLOAT_RE, INT_RE, parse_int

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["KEYWORDS", "AddressedObjects", "Target"]

KEYWORDS = tuple(grammar.ADDRESSED_OBJECTS)
_POSITIONAL = np.array([len(grammar.BLOCKS[keyword].params) for keyword in KEYWORDS], dtype=np.int64)


class Target(NamedTuple):
    """One addressed object."""

    keyword: str
    block: int  # block index in the document
    name: str
    name_token: int
    symbol: str  # what to look up in the ELF: the SYMBOL_LINK name, else the object name
    symbol_offset: int  # SYMBOL_LINK offset in bytes
    address_token: int | None  # None: a MEASUREMENT without ECU_ADDRESS
    anchor_token: int  # the last positional parameter (an ECU_ADDRESS is inserted after it)


class AddressedObjects:
    """Every addressed object of ``doc`` in document order, one row each; the columns are integer
    arrays (``names``, ``symbols`` and ``symbol_offsets`` are lists).

    Raises :class:`A2lParseError` at an object that lacks positional parameters or has a
    malformed SYMBOL_LINK (the first in the file).
    """

    def __init__(self, doc: "A2lDocument"):
        self.doc = doc
        limits = doc.parameter_limits()
        parts = [_keyword_rows(doc, number, keyword) for number, keyword in enumerate(KEYWORDS)]
        columns = [np.concatenate(column) for column in zip(*parts)]
        order = np.argsort(columns[0], kind="stable")
        blocks, numbers, addresses, links = (column[order] for column in columns)
        name_tokens = doc.blocks.begin[blocks] + 2
        anchors = name_tokens + _POSITIONAL[numbers] - 1
        short = np.flatnonzero(anchors >= limits[blocks])
        if len(short):  # the address would be read from the wrong token
            row = int(short[0])
            raise doc.error(f"{KEYWORDS[numbers[row]]} {doc.raw(int(name_tokens[row])).decode(doc.encoding)}: "
                            f"missing parameter(s), {_POSITIONAL[numbers[row]]} expected", int(name_tokens[row]) - 1)
        _check_parameters(doc, blocks, numbers, name_tokens, limits)
        self.blocks = blocks
        self.keyword_numbers = numbers  # index into KEYWORDS
        self.name_tokens = name_tokens
        self.address_token_array = addresses  # -1: a MEASUREMENT without ECU_ADDRESS
        self.anchor_tokens = anchors
        self.names: list[str] = doc.texts(name_tokens)
        self.symbols: list[str] = list(self.names)
        self.symbol_offsets: list[int] = [0] * len(self.names)
        linked = np.flatnonzero(links >= 0)
        if len(linked):
            self._read_symbol_links(linked, links[linked], doc.blocks.end[blocks[linked]])

    def __len__(self) -> int:
        return len(self.blocks)

    def keyword(self, row: int) -> str:
        return KEYWORDS[self.keyword_numbers[row]]

    def target(self, row: int) -> Target:
        address = int(self.address_token_array[row])
        return Target(self.keyword(row), int(self.blocks[row]), self.names[row], int(self.name_tokens[row]),
                      self.symbols[row], self.symbol_offsets[row], address if address >= 0 else None,
                      int(self.anchor_tokens[row]))

    def _read_symbol_links(self, rows: np.ndarray, links: np.ndarray, ends: np.ndarray) -> None:
        """Take the symbol name and offset of the rows with a SYMBOL_LINK "name" offset (an option may
        stand anywhere among the block's own tokens, before or after its child blocks: ``ends`` are
        the blocks' ``/end`` tokens)."""
        doc = self.doc
        first_bytes = np.frombuffer(doc.data, np.uint8)[doc.tokens.starts[np.minimum(links + 1, len(doc.tokens) - 1)]]
        offset_raws = doc.tokens.raw_many(np.minimum(links + 2, len(doc.tokens) - 1))
        offsets = {raw: parse_int(raw) for raw in set(offset_raws) if INT_RE.fullmatch(raw)}  # mostly "0"
        bad = (links + 2 >= ends) | (first_bytes != ord('"'))
        bad |= np.array([raw not in offsets for raw in offset_raws], dtype=bool)
        if bad.any():
            row, link = int(rows[np.argmax(bad)]), int(links[np.argmax(bad)])
            raise doc.error(f"{self.keyword(row)} {self.names[row]}: SYMBOL_LINK needs a string and an integer "
                            "offset", link)
        names = doc.texts(links + 1, quoted=True)
        for row, name, raw in zip(rows.tolist(), names, offset_raws):
            self.symbols[row] = name
            self.symbol_offsets[row] = offsets[raw]


def _check_parameters(doc: "A2lDocument", blocks: np.ndarray, numbers: np.ndarray, name_tokens: np.ndarray,
                      limits: np.ndarray) -> None:
    """Raise :class:`A2lParseError` at the first object whose numbers and strings are not where its
    positional parameters have them, or that has a parameter too many: a parameter missing shifts the next
    keyword into the parameters (an upper limit ``ECU_ADDRESS``), where an update would read and write the
    wrong tokens. Checked by each token's first byte, column by column (a few ms for 65,000 objects); a
    token that looks wrong (``NaN`` for a number) is then matched exactly."""
    first = doc.tokens.first_bytes()
    suspects: list[tuple[int, int, str]] = []  # (token, row, what was expected there)
    for number, keyword in enumerate(KEYWORDS):
        rows = np.flatnonzero(numbers == number)
        if not len(rows):
            continue
        params = grammar.BLOCKS[keyword].params
        for index, kind in enumerate(params):
            if kind in ("str", "int", "float"):
                tokens = name_tokens[rows] + index
                wrong = first[tokens] != _QUOTE if kind == "str" else ~_NUMBER_START[first[tokens]]
                suspects += [(token, row, kind) for token, row in zip(tokens[wrong].tolist(), rows[wrong].tolist())]
        after = name_tokens[rows] + len(params)  # an option keyword, unless a child block or /end comes first
        extra = (after < limits[blocks[rows]]) & (_NUMBER_START[first[after]] | (first[after] == _QUOTE))
        suspects += [(token, row, "") for token, row in zip(after[extra].tolist(), rows[extra].tolist())]
    for token, row, kind in sorted(suspects):
        raw = doc.raw(token)
        if kind == "str" or (kind and not (INT_RE if kind == "int" else FLOAT_RE).fullmatch(raw)):
            expected = {"str": "a string", "int": "an integer", "float": "a number"}[kind]
            what = f"{expected} expected, found '{shown(raw)}'"
        elif not kind:
            what = f"unexpected '{shown(raw)}' after its {len(grammar.BLOCKS[KEYWORDS[numbers[row]]].params)} " \
                   "parameters (a keyword expected)"
        else:
            continue
        keyword, name = KEYWORDS[numbers[row]], doc.raw(int(name_tokens[row])).decode(doc.encoding)
        raise doc.error(f"{keyword} {name}: {what}", token)


_QUOTE = ord('"')
_NUMBER_START = np.zeros(256, dtype=bool)  # by first byte: may start a number (NaN and INF are matched exactly)
_NUMBER_START[list(b"0123456789+-.")] = True


def _keyword_rows(doc: "A2lDocument", number: int, keyword: str) -> tuple[np.ndarray, ...]:
    """(blocks, keyword number, address token, SYMBOL_LINK token) of one keyword's objects (-1: none)."""
    blocks = doc.blocks.having_keyword(keyword)
    blocks = blocks[np.isin(doc.blocks.parent[blocks], doc.blocks.having_keyword("MODULE"))]
    address_index = grammar.ADDRESSED_OBJECTS[keyword]
    if address_index is None:
        address_tokens = _aligned(blocks, *_once(doc, keyword, "ECU_ADDRESS"))
        address_tokens[address_tokens >= 0] += 1
    else:
        address_tokens = doc.blocks.begin[blocks] + 2 + address_index
    link_tokens = _aligned(blocks, *_once(doc, keyword, "SYMBOL_LINK"))
    return blocks, np.full(len(blocks), number, dtype=np.int64), address_tokens, link_tokens


def _once(doc: "A2lDocument", keyword: str, option: str) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`~workbench.a2l.document.A2lDocument.option_tokens`; raises :class:`A2lParseError` at an
    object that has ``option`` twice (which one the update should write cannot be told)."""
    owners, tokens = doc.option_occurrences(keyword, option)
    twice = np.flatnonzero(owners[1:] == owners[:-1])
    if len(twice):
        block = int(owners[twice[0]])
        name = doc.raw(doc.block_begin[block] + 2).decode(doc.encoding)
        raise doc.error(f"{keyword} {name}: {option} is given twice (at most once)", int(tokens[twice[0] + 1]))
    return owners, tokens


def _aligned(blocks: np.ndarray, found_blocks: np.ndarray, found_tokens: np.ndarray) -> np.ndarray:
    """Per block of ``blocks``: its token among (found_blocks, found_tokens), -1 where it has none."""
    aligned = np.full(len(blocks), -1, dtype=np.int64)
    if len(blocks) and len(found_blocks):
        slot = np.minimum(np.searchsorted(blocks, found_blocks), len(blocks) - 1)
        hit = blocks[slot] == found_blocks
        aligned[slot[hit]] = found_tokens[hit]
    return aligned
