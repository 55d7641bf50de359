"""An A2L file held as its original bytes plus token and block indexes.

:func:`load_a2l` reads a file (splicing ``/include``\\ s), tokenizes, pairs the blocks and
validates them against the ASAP2 keyword table. Nothing is converted to objects up
front: a :class:`Block` is a light view (document + row number) and values are
parsed when asked for, so reading a 10 MB file costs a fraction of a second and
writing it back unchanged gives the same bytes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from workbench.a2l import grammar
from workbench.a2l.includes import Include, splice_includes
from workbench.a2l.source import SourceFile, SourceMap, read_source, source_from_text
from workbench.a2l.tokens import Tokens
from workbench.a2l.tree import BlockTable, first_of_each, parse_blocks
from workbench.a2l.values import is_int, is_number, parse_int, parse_number, parse_string
from workbench.errors import A2lParseError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel
    from workbench.a2l.objects import AxisPts, Characteristic, CompuMethod, Function, Measurement, RecordLayout

__all__ = ["A2lDocument", "Block", "EpkAddress", "MemorySegment", "load_a2l", "load_a2l_string"]


def load_a2l(path: str | Path, *, validate: bool = True) -> "A2lDocument":
    """Read the A2L file at ``path`` (with its ``/include``\\ s spliced in).

    ``validate`` checks every known block against the ASAP2 keyword table (parameter
    count and kinds, keywords in the right place). Raises :class:`InputError` when the
    file cannot be read and :class:`A2lParseError` (path, line, column) when it is malformed.
    """
    return A2lDocument.from_source(read_source(path), validate=validate)


def load_a2l_string(text: str, path: str | Path | None = None, *, validate: bool = True) -> "A2lDocument":
    """Parse A2L text; ``path`` names it in errors and anchors relative ``/include``\\ s."""
    return A2lDocument.from_source(source_from_text(text, path), validate=validate)


class MemorySegment(NamedTuple):
    """A MOD_PAR MEMORY_SEGMENT; ``address`` and ``size`` in bytes."""

    name: str
    long_identifier: str
    prg_type: str  # CODE, DATA, OFFLINE_DATA, VARIABLES, ...
    memory_type: str  # FLASH, RAM, EEPROM, ...
    attribute: str  # INTERN / EXTERN
    address: int
    size: int
    block: "Block"

    def contains(self, address: int, size: int = 1) -> bool:
        return self.address <= address and address + size <= self.address + self.size


class EpkAddress(NamedTuple):
    """One MOD_PAR ADDR_EPK: where a part of the software keeps its EPK string."""

    address: int
    segment: MemorySegment | None  # the MEMORY_SEGMENT it lies in (None: it lies in none)
    token: int  # the address's token, for a finding at its place

    @property
    def part(self) -> str:
        """The name of its MEMORY_SEGMENT ("" for none)."""
        return self.segment.name if self.segment is not None else ""


class A2lDocument:
    """One A2L file (includes spliced in): bytes, tokens and the block tree over them."""

    def __init__(self, data: bytes, source_map: SourceMap, tokens: Tokens, blocks: BlockTable,
                 includes: list[Include] | None = None, include_count: int = 0):
        self.data = data
        self.source_map = source_map
        self.tokens = tokens
        self.blocks = blocks
        self.includes = includes or []  # the main file's own /include directives
        self.include_count = include_count  # directives met, nested ones included
        # (directive, the file that has it, why) of each file that could not be read, when loaded to be checked
        self.missing_includes: list[tuple[Include, SourceFile, str]] = []
        self.block_begin: list[int] = blocks.begin.tolist()  # per block: its /begin token
        self.block_end: list[int] = blocks.end.tolist()  # per block: its /end token
        self._models: dict[int, "A2lModel"] = {}  # MODULE block -> its object model

    @classmethod
    def from_source(cls, source: SourceFile, *, validate: bool = True, missing_ok: bool = False) -> "A2lDocument":
        """``missing_ok``: an ``/include`` whose file cannot be read is left out and listed in
        :attr:`missing_includes` instead of an error (``check`` reports it and checks the rest)."""
        missing = [] if missing_ok else None
        spliced = splice_includes(source, missing=missing)
        blocks = parse_blocks(spliced.tokens, spliced.begins, spliced.ends, spliced.source_map)
        document = cls(spliced.data, spliced.source_map, spliced.tokens, blocks, spliced.includes, spliced.count)
        document.missing_includes = missing or []
        if validate:
            from workbench.a2l.validate import validate_document

            validate_document(document)
        return document

    # -- the file as a whole -------------------------------------------------------
    @property
    def source(self) -> SourceFile:
        """The main file (the one loaded; included files are in :attr:`source_map`)."""
        return self.source_map.main

    @property
    def path(self) -> Path | None:
        return self.source.path

    @property
    def name(self) -> str:
        return self.source.name

    @property
    def encoding(self) -> str:
        return self.source.encoding

    def position(self, offset: int) -> tuple[str, int, int]:
        """(file, line, column) of a byte offset of :attr:`data`, in the file it came from."""
        return self.source_map.position(offset)

    def token_position(self, token: int) -> tuple[str, int, int]:
        return self.position(self.tokens.span(token)[0])

    def error(self, message: str, token: int) -> A2lParseError:
        """An :class:`A2lParseError` located at ``token`` (its buffer offset kept as ``offset`` for sorting)."""
        offset = self.tokens.span(token)[0]
        error = self.source_map.error(message, offset)
        error.offset = offset
        return error

    # -- token values --------------------------------------------------------------
    def raw(self, token: int) -> bytes:
        return self.tokens.raw(token)

    def text(self, token: int) -> str:
        """A token as text: a string without quotes, anything else as written."""
        raw = self.tokens.raw(token)
        if raw[:1] == b'"':
            return parse_string(raw, self.encoding)
        return raw.decode(self.encoding)

    def int_value(self, token: int) -> int:
        """An integer token; raises :class:`A2lParseError` at it when it is not one."""
        raw = self.tokens.raw(token)
        if not is_int(raw):
            raise self.error(f"expected an integer, found '{raw.decode(self.encoding)}'", token)
        return parse_int(raw)

    def value(self, token: int) -> int | float | str:
        """A number if the token is one, else its text."""
        raw = self.tokens.raw(token)
        if is_number(raw):
            return parse_number(raw)
        return self.text(token)

    def texts(self, tokens: np.ndarray, quoted: bool = False) -> list[str]:
        """Many tokens as text, decoded in one call (a document has no NUL byte to join them with);
        ``quoted``: string tokens, returned without their quotes and escapes."""
        if not len(tokens):
            return []
        joined = self.tokens.joined(tokens, 1 if quoted else 0)
        if quoted and (b"\\" in joined or b'""' in joined):  # escapes: resolve them one string at a time
            return [parse_string(raw, self.encoding) for raw in self.tokens.raw_many(tokens)]
        return joined.decode(self.encoding).split("\0")

    # -- blocks ----------------------------------------------------------------------
    def block_names(self, blocks: np.ndarray) -> list[str | None]:
        """:attr:`Block.name` of many blocks at once."""
        table = self.blocks
        named = np.array([_has_name(keyword) for keyword in table.keyword_names], dtype=bool)
        first = table.begin[blocks] + 2
        valid = named[table.keyword_id[blocks]] & (first < table.end[blocks])
        first_bytes = self.tokens.first_bytes()[np.minimum(first, len(self.tokens) - 1)] if len(blocks) else first
        valid &= (first_bytes != ord('"')) & (first_bytes != ord("/"))
        names: list[str | None] = [None] * len(blocks)
        for row, name in zip(np.flatnonzero(valid).tolist(), self.texts(first[valid])):
            names[row] = name
        return names

    def block(self, index: int) -> "Block":
        return Block(self, index)

    def top_blocks(self) -> list["Block"]:
        return [Block(self, int(i)) for i in self.blocks.children(-1)]

    def blocks_named(self, keyword: str) -> list["Block"]:
        """Every block with this keyword, anywhere, in document order."""
        return [Block(self, i) for i in self.block_indices(keyword)]

    def block_indices(self, keyword: str) -> list[int]:
        """Indices of every block with this keyword, in document order."""
        return self.blocks.having_keyword(keyword).tolist()

    def included_in(self) -> str | None:
        """Where a file without PROJECT was written to be included (``/include``): ``"PROJECT"``
        when its top level holds MODULEs, ``"MODULE"`` when it holds other blocks (MEASUREMENT ...);
        None for a whole file (one with a PROJECT) or one without blocks."""
        blocks = self.blocks
        keywords = {blocks.keyword_names[number] for number in np.unique(blocks.keyword_id[blocks.children(-1)]).tolist()}
        if not keywords or "PROJECT" in keywords:
            return None
        return "PROJECT" if keywords == {"MODULE"} else "MODULE"

    @property
    def project(self) -> "Block":
        for block in self.top_blocks():
            if block.keyword == "PROJECT":
                return block
        raise A2lParseError("no /begin PROJECT in the file", self.name, 1, 1)

    @property
    def modules(self) -> list["Block"]:
        return self.project.children_named("MODULE")

    def module(self, name: str | None = None) -> "Block":
        """The MODULE called ``name``, or the only one when ``name`` is None."""
        modules = self.modules
        if name is None:
            if len(modules) != 1:
                names = f" ({', '.join(module.name or '?' for module in modules)})" if modules else ""
                what = "; the workbench reads one ECU per A2L: open an A2L of one MODULE (its own file)" if modules else ""
                raise A2lParseError(f"expected exactly one MODULE, found {len(modules)}{names}{what}", self.name,
                                    *self.project.position[1:])
            return modules[0]
        for module in modules:
            if module.name == name:
                return module
        raise A2lParseError(f"no MODULE named {name!r}", self.name, *self.project.position[1:])

    def mod_par(self, module: str | None = None) -> "Block | None":
        return self.module(module).first("MOD_PAR")

    def mod_common(self, module: str | None = None) -> "Block | None":
        return self.module(module).first("MOD_COMMON")

    def epk_token(self, module: str | None = None) -> int | None:
        """The token of MOD_PAR's EPK string, if there is one."""
        mod_par = self.mod_par(module)
        option = mod_par.option("EPK") if mod_par is not None else None
        return option[0] if option else None

    def epk(self, module: str | None = None) -> str | None:
        """MOD_PAR EPK: the software identifier the ECU must report."""
        token = self.epk_token(module)
        return self.text(token) if token is not None else None

    def addr_epk(self, module: str | None = None) -> int | None:
        """MOD_PAR's first ADDR_EPK: where the ECU holds its EPK string (GET_ID type 5 reads it)."""
        mod_par = self.mod_par(module)  # not through the MEMORY_SEGMENTs: the check reads it where they are malformed
        params = mod_par.option("ADDR_EPK") if mod_par is not None else None
        return self.int_value(params[0]) if params else None

    def epk_addresses(self, module: str | None = None) -> tuple[EpkAddress, ...]:
        """Every MOD_PAR ADDR_EPK in order, each with the MEMORY_SEGMENT it lies in (ASAP2 allows several: e.g. one
        in the calibration data, one in the application's header, so that each part of the software says which
        build it belongs to)."""
        mod_par = self.mod_par(module)
        if mod_par is None:
            return ()
        tokens = [params[0] for params in mod_par.options("ADDR_EPK") if params]
        if not tokens:
            return ()
        segments = self.memory_segments(module)
        found = []
        for token in tokens:
            address = self.int_value(token)
            found.append(EpkAddress(address, next((s for s in segments if s.contains(address)), None), token))
        return tuple(found)

    def epk_parts(self, module: str | None = None) -> tuple[EpkAddress, ...]:
        """The ADDR_EPK of each part of the software that keeps its own EPK, when the ADDR_EPKs lie in more than
        one MEMORY_SEGMENT (the application's header, the calibration data); else empty: the one EPK address
        stands for the whole software."""
        addresses = self.epk_addresses(module)
        parts = tuple(epk for epk in addresses if epk.segment is not None)
        return parts if len({epk.segment.name for epk in parts}) > 1 else ()

    def memory_segments(self, module: str | None = None) -> list[MemorySegment]:
        mod_par = self.mod_par(module)
        if mod_par is None:
            return []
        segments = []
        for block in mod_par.children_named("MEMORY_SEGMENT"):
            args = block.args
            if len(args) < 7:
                raise self.error("MEMORY_SEGMENT needs name, description, type, memory, attribute, address, size",
                                 block.keyword_token)
            name, long_id, prg, memory, attribute = (self.text(t) for t in args[:5])
            segments.append(MemorySegment(name, long_id, prg, memory, attribute,
                                          self.int_value(args[5]), self.int_value(args[6]), block))
        return segments

    # -- the object model ----------------------------------------------------------------
    def model(self, module: str | None = None) -> "A2lModel":
        """The typed, read-only objects of a MODULE (:class:`~workbench.a2l.model.A2lModel`): names
        indexed once, each object read from its tokens when first asked for."""
        block = self.module(module)
        found = self._models.get(block.index)
        if found is None:
            from workbench.a2l.model import A2lModel

            found = self._models[block.index] = A2lModel(self, block.name)
        return found

    def characteristic(self, name: str, module: str | None = None) -> "Characteristic":
        """The CHARACTERISTIC ``name``; raises :class:`UnknownSymbolError` (closest names suggested)."""
        return self.model(module).characteristic(name)

    def measurement(self, name: str, module: str | None = None) -> "Measurement":
        return self.model(module).measurement(name)

    def axis_pts(self, name: str, module: str | None = None) -> "AxisPts":
        return self.model(module).axis_pts(name)

    def compu_method(self, name: str, module: str | None = None) -> "CompuMethod":
        return self.model(module).compu_method(name)

    def record_layout(self, name: str, module: str | None = None) -> "RecordLayout":
        return self.model(module).record_layout(name)

    def function(self, name: str, module: str | None = None) -> "Function":
        return self.model(module).function(name)

    def objects(self, keyword: str, module: str | None = None) -> list["Block"]:
        """The MODULE's direct children with this keyword (MEASUREMENT, CHARACTERISTIC ...)."""
        return self.module(module).children_named(keyword)

    def own_tokens(self, block: int) -> list[int]:
        """The tokens at a block's own level after its keyword, its child blocks left out; ``block``
        -1: the tokens outside every block (ASAP2_VERSION ...)."""
        position, stop = (self.block_begin[block] + 2, self.block_end[block]) if block >= 0 else (0, len(self.tokens))
        tokens: list[int] = []
        for child in self.blocks.children(block).tolist():
            tokens.extend(range(position, self.block_begin[child]))
            position = self.block_end[child] + 2
        tokens.extend(range(position, stop))
        return tokens

    def parameter_limits(self) -> np.ndarray:
        """Per block: the first token that cannot be one of its parameters (its first child or its /end)."""
        blocks = self.blocks
        limits = blocks.end.copy()
        has_parent = blocks.parent >= 0
        # blocks are in document order, so the first block naming a parent is its first child
        first = first_of_each(blocks.parent[has_parent])
        owners = blocks.parent[has_parent][first]
        limits[owners] = np.minimum(limits[owners], blocks.begin[has_parent][first])
        return limits

    def option_tokens(self, block_keyword: str, option: str) -> tuple[np.ndarray, np.ndarray]:
        """(blocks, tokens): every ``block_keyword`` block that has the keyword ``option`` at its own
        level, and the token of its first one, in document order. Found with vectorized searches."""
        owners, tokens = self.option_occurrences(block_keyword, option)
        first = first_of_each(owners)
        return owners[first], tokens[first]

    def option_occurrences(self, block_keyword: str, option: str) -> tuple[np.ndarray, np.ndarray]:
        """(blocks, tokens) of every ``option`` keyword at the own level of a ``block_keyword`` block, in
        document order (a block that has it twice is there twice)."""
        tokens = self.tokens.matching(option.encode("ascii"))
        blocks = self.blocks.having_keyword(block_keyword)
        if not len(tokens) or not len(blocks):
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        owners = self._innermost_blocks(tokens)
        slot = np.minimum(np.searchsorted(blocks, owners), len(blocks) - 1)
        skip = len(grammar.BLOCKS[block_keyword].params) if block_keyword in grammar.BLOCKS else 0
        # a token among the positional parameters is a name that happens to spell the keyword
        keep = (blocks[slot] == owners) & (tokens >= self.blocks.begin[np.maximum(owners, 0)] + 2 + skip)
        return owners[keep], tokens[keep]

    def _innermost_blocks(self, tokens: np.ndarray) -> np.ndarray:
        """The innermost block containing each token (-1: top level)."""
        begin, end, parent = self.blocks.begin, self.blocks.end, self.blocks.parent
        owner = np.searchsorted(begin, tokens, side="right") - 1
        while True:
            valid = owner >= 0
            outside = np.zeros(len(owner), dtype=bool)
            outside[valid] = end[owner[valid]] < tokens[valid]
            if not outside.any():
                return owner
            owner[outside] = parent[owner[outside]]


class Block:
    """A view of one ``/begin KEYWORD ... /end KEYWORD`` block of a document."""

    __slots__ = ("doc", "index")

    def __init__(self, doc: A2lDocument, index: int):
        self.doc = doc
        self.index = index

    def __eq__(self, other) -> bool:
        return isinstance(other, Block) and other.doc is self.doc and other.index == self.index

    def __hash__(self) -> int:
        return hash((id(self.doc), self.index))

    def __repr__(self) -> str:
        name = self.name
        return f"<Block {self.keyword}{' ' + name if name else ''} at {self.position[1]}:{self.position[2]}>"

    @property
    def keyword(self) -> str:
        return self.doc.blocks.keyword_of(self.index)

    @property
    def spec(self) -> grammar.BlockSpec | None:
        return grammar.BLOCKS.get(self.keyword)

    @property
    def begin_token(self) -> int:
        """The ``/begin`` token."""
        return self.doc.block_begin[self.index]

    @property
    def keyword_token(self) -> int:
        return self.doc.block_begin[self.index] + 1

    @property
    def end_token(self) -> int:
        """The ``/end`` token (the closing keyword is the next one)."""
        return self.doc.block_end[self.index]

    @property
    def span(self) -> tuple[int, int]:
        """Byte offsets from ``/begin`` to the end of the closing keyword."""
        tokens = self.doc.tokens
        return tokens.span(self.begin_token)[0], tokens.span(self.end_token + 1)[1]

    @property
    def position(self) -> tuple[str, int, int]:
        """(file, line, column) of the ``/begin``."""
        return self.doc.token_position(self.begin_token)

    @property
    def parent(self) -> "Block | None":
        parent = int(self.doc.blocks.parent[self.index])
        return Block(self.doc, parent) if parent >= 0 else None

    @property
    def children(self) -> list["Block"]:
        return [Block(self.doc, i) for i in self.doc.blocks.children(self.index).tolist()]

    def children_named(self, keyword: str) -> list["Block"]:
        return [Block(self.doc, i) for i in self.doc.blocks.children_having_keyword(self.index, keyword).tolist()]

    def first(self, keyword: str) -> "Block | None":
        found = self.children_named(keyword)
        return found[0] if found else None

    @property
    def own_tokens(self) -> list[int]:
        """Tokens at this block's level after its keyword (child blocks left out)."""
        return self.doc.own_tokens(self.index)

    @property
    def args(self) -> list[int]:
        """The positional parameters (name first) as the keyword table defines them;
        every own token for a block the table does not know."""
        return self.layout()[0]

    @property
    def name(self) -> str | None:
        """The first parameter when the block has a name or tag (MEASUREMENT x, IF_DATA XCP)."""
        if not _has_name(self.keyword):
            return None
        first = self.keyword_token + 1
        if first >= self.end_token:
            return None
        raw = self.doc.tokens.raw(first)
        return None if raw[:1] in (b'"', b"/") else raw.decode(self.doc.encoding)

    @property
    def name_token(self) -> int:
        return self.keyword_token + 1

    def layout(self) -> tuple[list[int], list[tuple[str, list[int]]]]:
        """(positional parameter tokens, [(option keyword, its parameter tokens), ...]).

        Lenient: a keyword the table does not know takes the tokens up to the next
        known keyword. :mod:`workbench.a2l.validate` is the strict counterpart.
        """
        own = self.own_tokens
        spec = self.spec
        if spec is None or spec.free:
            return own, []
        count = len(spec.params)
        if spec.repeat and len(own) >= count:
            raw = self.doc.raw(own[count - 1])
            if is_int(raw):
                count += parse_int(raw) * len(spec.repeat)
        if spec.items:
            count = len(own)
            for i, token in enumerate(own):
                if self.doc.raw(token).decode("latin-1") in spec.options:
                    count = i
                    break
        return own[:count], _options(self.doc, own[count:])

    def option(self, keyword: str) -> list[int] | None:
        """The parameter tokens of the first ``keyword`` option at this level, or None."""
        for name, params in self.layout()[1]:
            if name == keyword:
                return params
        return None

    def options(self, keyword: str) -> list[list[int]]:
        return [params for name, params in self.layout()[1] if name == keyword]

    def text(self) -> str:
        start, end = self.span
        return self.doc.data[start:end].decode(self.doc.encoding)


def _has_name(keyword: str) -> bool:
    """Whether a block's first parameter is its name or tag (unknown blocks: maybe, if it is a word)."""
    spec = grammar.BLOCKS.get(keyword)
    return spec is None or spec.free or (bool(spec.params) and spec.params[0] == "ident")


def _options(doc: A2lDocument, tokens: list[int]) -> list[tuple[str, list[int]]]:
    options: list[tuple[str, list[int]]] = []
    i = 0
    while i < len(tokens):
        keyword = doc.raw(tokens[i]).decode("latin-1")
        kinds = grammar.OPTIONS.get(keyword)
        i += 1
        if kinds == ("int*",):
            start = i
            while i < len(tokens) and is_int(doc.raw(tokens[i])):
                i += 1
            options.append((keyword, tokens[start:i]))
        elif kinds is not None and kinds != ("ident*",):
            options.append((keyword, tokens[i : i + len(kinds)]))
            i += len(kinds)
        else:  # a list of names, or a keyword the table does not know: up to the next known keyword
            start = i
            while i < len(tokens) and doc.raw(tokens[i]).decode("latin-1") not in grammar.OPTIONS:
                i += 1
            options.append((keyword, tokens[start:i]))
    return options
