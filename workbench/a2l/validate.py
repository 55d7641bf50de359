"""Strict check of a parsed document against the ASAP2 keyword table.

Raises :class:`A2lParseError` at the first problem in file order: a block where its
parent does not allow it, a missing or malformed parameter (``bad number``), a
keyword that does not exist or is not allowed in its block. Free-form content
(IF_DATA, A2ML) is skipped.

Where blocks may stand is checked once per (parent keyword, keyword) pair; the
parameters block by block, with each distinct spelling matched against its pattern
once (a 10 MB file has a million tokens but far fewer distinct numbers and keywords).
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

import numpy as np

from workbench.a2l import grammar
from workbench.a2l.tokens import shown
from workbench.a2l.tree import first_of_each
from workbench.a2l.values import FLOAT_RE, IDENT_RE, INT_RE, int_or_none
from workbench.errors import A2lParseError

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

__all__ = ["validate_document"]

_KIND_NAMES = {"ident": "a name", "str": "a string", "int": "an integer", "float": "a number", "int*": "an integer",
               "ident*": "a name"}


def _kind_name(kind: str) -> str:
    """What a parameter of this kind is, for messages: "an integer", "a data type" ..."""
    enumeration = grammar.ENUMS.get(kind)
    return enumeration.what if enumeration is not None else _KIND_NAMES[kind]
_PATTERNS = {"ident": IDENT_RE, "int": INT_RE, "float": FLOAT_RE, "int*": INT_RE, "ident*": IDENT_RE}
_ENUM_BYTES = {kind: frozenset(word.encode("ascii") for word in enumeration.words)
               for kind, enumeration in grammar.ENUMS.items()}  # the words as a file spells them


def validate_document(doc: "A2lDocument", errors: list[A2lParseError] | None = None, *,
                      within: str | None = None, options_once: bool = False) -> None:
    """Raise :class:`A2lParseError` at the first violation of the keyword table (in file
    order, saying how many more there are), or, when ``errors`` is a list, append every
    violation (one per block) to it.
    An error inside a block has that block's index as ``block``. ``within`` is the block the
    file's top level stands in: None for a whole file (PROJECT), ``"MODULE"`` for a bare
    fragment of module-level blocks (a file written for ``/include``). ``options_once`` also
    reports an option given twice in a block where ASAP2 allows it once (``check`` does; loading
    does not refuse such a file, as other tools read it), as an error whose ``kind`` is
    ``"option-twice"``."""
    found: list[A2lParseError] = []
    _Validator(doc, found, within, options_once).run()
    found.sort(key=lambda error: getattr(error, "offset", 0))
    if errors is not None:
        errors.extend(found)
    elif len(found) == 1:
        raise found[0]
    elif found:  # the first, and how many more a check would list
        first = found[0]
        raise A2lParseError(f"{first.reason} (and {len(found) - 1} more problem(s): `workbench a2l check` lists "
                            "them all)", first.path, first.line, first.column)


class _Validator:
    def __init__(self, doc: "A2lDocument", errors: list[A2lParseError], within: str | None = None,
                 options_once: bool = False):
        self.doc = doc
        self.within = within
        self.options_once = options_once
        self.twice: list[A2lParseError] = []  # the options given twice in the block being checked
        self.errors = errors
        self.data = doc.data
        self.starts = doc.tokens.starts_list
        self.ends = doc.tokens.ends_list
        # kind -> spelling -> verdict
        self.fits: dict[str, dict[bytes, bool]] = {kind: {} for kind in (*_PATTERNS, *grammar.ENUMS)}

    def raw(self, token: int) -> bytes:
        return self.data[self.starts[token] : self.ends[token]]

    def run(self) -> None:
        doc = self.doc
        blocks = doc.blocks
        checked = self._check_placements()
        params_ok = self._positional_parameters_fit(checked)
        begin, end = doc.block_begin, doc.block_end
        child_offsets, child_order = blocks._child_offsets.tolist(), blocks._child_order.tolist()
        for block, skip_params in zip(np.flatnonzero(checked).tolist(), params_ok[checked].tolist()):
            first, last = child_offsets[block + 1], child_offsets[block + 2]
            own = range(begin[block] + 2, end[block]) if first == last else self._own_tokens(
                begin[block] + 2, end[block], child_order[first:last])
            try:
                self._check_block(block, own, skip_params)
            except A2lParseError as exc:
                self.twice.append(exc)
            for exc in self.twice:  # every option given twice, and the block's first other problem
                exc = self._named(exc, block)
                exc.block = block
                self.errors.append(exc)
            self.twice.clear()
        try:
            self._check_top_level(self._own_tokens(0, len(doc.tokens), child_order[child_offsets[0] : child_offsets[1]]))
        except A2lParseError as exc:
            self.errors.append(exc)

    def _named(self, error: A2lParseError, block: int) -> A2lParseError:
        """``error`` of a named block (MEASUREMENT m, COMPU_METHOD cm ...) saying which object it is: in a large
        file's log the line alone does not."""
        keyword, name_token = self.doc.blocks.keyword[block], self.doc.block_begin[block] + 2
        if name_token >= self.doc.block_end[block] or grammar.BLOCKS[keyword].params[:1] != ("ident",):
            return error
        name = self.raw(name_token)
        if not IDENT_RE.fullmatch(name):  # the name itself is what is wrong
            return error
        reason = error.reason.removeprefix(f"{keyword}: ")
        named = A2lParseError(f"{keyword} {name.decode('latin-1')}: {reason}", error.path, error.line, error.column)
        named.offset = getattr(error, "offset", 0)
        if hasattr(error, "kind"):
            named.kind = error.kind
        return named

    def _own_tokens(self, start: int, stop: int, children: list[int]) -> list[int]:
        """The tokens from ``start`` to ``stop`` that do not belong to one of the ``children`` blocks."""
        own: list[int] = []
        for child in children:
            own.extend(range(start, self.doc.block_begin[child]))
            start = self.doc.block_end[child] + 2
        own.extend(range(start, stop))
        return own

    def _check_placements(self) -> np.ndarray:
        """Report every block its parent does not allow; returns which blocks to check further
        (not free-form, not inside a free-form block)."""
        doc, blocks = self.doc, self.doc.blocks
        names = blocks.keyword_names
        parent_ids = np.where(blocks.parent >= 0, blocks.keyword_id[np.maximum(blocks.parent, 0)], -1)
        free = np.array([grammar.BLOCKS.get(name, grammar.BlockSpec()).free for name in names], dtype=bool)
        free_blocks = np.flatnonzero(free[blocks.keyword_id])
        # inside a free block: the free blocks that began before it reach beyond its begin
        reach = np.maximum.accumulate(blocks.end[free_blocks]) if len(free_blocks) else np.zeros(0, np.int64)
        before = np.searchsorted(blocks.begin[free_blocks], blocks.begin) - 1
        inside_free = (before >= 0) & (reach[np.maximum(before, 0)] > blocks.begin) if len(free_blocks) else \
            np.zeros(len(blocks), dtype=bool)
        pairs = parent_ids * len(names) + blocks.keyword_id
        kept = pairs[~inside_free]
        for pair in kept[first_of_each(kept)].tolist():
            parent_id, keyword_id = divmod(pair, len(names)) if pair >= 0 else (-1, pair + len(names))
            problem = _placement_problem(names[parent_id] if parent_id >= 0 else self.within, names[keyword_id])
            if problem is not None:
                for block in np.flatnonzero((pairs == pair) & ~inside_free).tolist():
                    error = doc.error(problem, doc.block_begin[block] + 1)
                    error.block = block
                    self.errors.append(error)
        return ~inside_free & ~free[blocks.keyword_id]

    def _positional_parameters_fit(self, checked: np.ndarray) -> np.ndarray:
        """Per block: True when its positional parameters are known to be there and of the right
        kinds, found column by column for all blocks of a keyword (most of a file's tokens)."""
        doc, blocks = self.doc, self.doc.blocks
        fit = np.zeros(len(blocks), dtype=bool)
        limits = doc.parameter_limits()
        first_bytes = doc.tokens.first_bytes()
        for number, keyword in enumerate(blocks.keyword_names):
            spec = grammar.BLOCKS.get(keyword)
            if spec is None or not spec.params:
                continue
            rows = np.flatnonzero(checked & (blocks.keyword_id == number))
            rows = rows[blocks.begin[rows] + 2 + len(spec.params) <= limits[rows]]  # no child among them
            good = np.ones(len(rows), dtype=bool)
            for index, kind in enumerate(spec.params):
                tokens = blocks.begin[rows] + 2 + index
                if kind == "str":
                    good &= first_bytes[tokens] == ord('"')
                else:
                    good &= np.array(self._fit_many(kind, tokens), dtype=bool)
            fit[rows[good]] = True
        return fit

    def _fit_many(self, kind: str, tokens: np.ndarray) -> list[bool]:
        data, starts, ends = self.data, self.doc.tokens.starts[tokens].tolist(), self.doc.tokens.ends[tokens].tolist()
        raws = [data[start:end] for start, end in zip(starts, ends)]
        fits, words = self.fits[kind], _ENUM_BYTES.get(kind)
        new = set(raws).difference(fits)  # a column of names: mostly spellings met once
        if words is not None:
            fits.update((raw, raw in words) for raw in new)
        else:
            fullmatch = _PATTERNS[kind].fullmatch
            fits.update((raw, fullmatch(raw) is not None) for raw in new)
        return [fits[raw] for raw in raws]

    def _check_block(self, block: int, own, params_fit: bool = False) -> None:
        keyword = self.doc.blocks.keyword[block]
        spec = grammar.BLOCKS.get(keyword)
        if spec is None:
            return
        end_token = self.doc.block_end[block]
        position = len(spec.params) if params_fit else self._check_params(keyword, spec.params, own, 0, end_token)
        if spec.repeat:
            groups = int_or_none(self.raw(own[len(spec.params) - 1])) or 0
            for _ in range(groups):  # stops at the first missing parameter, however large the count
                position = self._check_params(keyword, spec.repeat, own, position, end_token)
        if spec.items:
            while position < len(own) and self.raw(own[position]).decode("latin-1") not in spec.options:
                self._check_params(f"{keyword} entry", (spec.items,), own, position, end_token)
                position += 1
        self._check_options(keyword, spec, own, position, end_token)

    def _check_params(self, keyword: str, kinds, own, position: int, end_token: int) -> int:
        data, starts, ends, fits = self.data, self.starts, self.ends, self.fits
        for kind in kinds:
            if position >= len(own):
                raise self.doc.error(f"{keyword}: missing parameter ({_kind_name(kind)} expected)", end_token)
            token = own[position]
            raw = data[starts[token] : ends[token]]
            if kind == "str":
                ok = raw[:1] == b'"'
            else:
                ok = fits[kind].get(raw)
                if ok is None:
                    ok = fits[kind][raw] = _fits(kind, raw)
            if not ok:
                raise self._kind_error(kind, token, raw, keyword)
            position += 1
        return position

    def _check_options(self, keyword: str, spec: grammar.BlockSpec, own, position: int, end_token: int) -> None:
        allowed = _allowed_options(keyword)
        first_of: dict[bytes, int] | None = {} if self.options_once else None  # option -> its first token
        repeatable = grammar.REPEATABLE_OPTIONS.get(keyword, ())
        while position < len(own):
            token = own[position]
            raw = self.raw(token)
            kinds = allowed.get(raw)
            name = raw.decode("latin-1")
            if kinds is None:
                if name not in grammar.OPTIONS and not IDENT_RE.fullmatch(raw):
                    raise self.doc.error(f"unexpected '{shown(raw)}' in {keyword} (a keyword expected)", token)
                known = name in grammar.OPTIONS or name in grammar.TOP_LEVEL_OPTIONS
                what = "keyword" if known else "unknown keyword"
                raise self.doc.error(f"{what} {name} is not allowed in {keyword}", token)
            if first_of is not None and first_of.setdefault(raw, token) != token and name not in repeatable:
                self.twice.append(self._twice(keyword, name, first_of[raw], token))
            position += 1
            if kinds in (("int*",), ("ident*",)):
                position = self._check_list(name, kinds[0], allowed, own, position, end_token)
                continue
            position = self._check_params(name, kinds, own, position, end_token)

    def _twice(self, keyword: str, name: str, first: int, token: int) -> A2lParseError:
        """The error at the second ``name`` of a block, which ASAP2 allows once: which one a tool takes is not told."""
        line = self.doc.token_position(first)[1]
        error = self.doc.error(f"{keyword}: {name} is given twice (at most once; the first at line {line})", token)
        error.kind = "option-twice"
        return error

    def _check_list(self, name: str, kind: str, allowed: dict, own, position: int, end_token: int) -> int:
        """The one or more ``kind`` parameters of option ``name`` from ``position`` (a list of names
        ends at the next keyword the block allows); returns the position after them."""
        start = position
        pattern = _PATTERNS[kind]
        while position < len(own):
            raw = self.raw(own[position])
            if not pattern.fullmatch(raw) or raw in allowed:
                break
            position += 1
        if position == start:
            raise self.doc.error(f"{name}: at least one {'integer' if kind == 'int*' else 'name'} expected",
                                 own[position] if position < len(own) else end_token)
        return position

    def _kind_error(self, kind: str, token: int, raw: bytes, context: str) -> A2lParseError:
        found = "a string" if raw[:1] == b'"' else f"'{shown(raw)}'"
        enumeration = grammar.ENUMS.get(kind)
        if enumeration is not None:
            if raw[:1] == b'"':
                return self.doc.error(f"{context}: {enumeration.what} expected, found a string "
                                      f"(allowed: {', '.join(enumeration.words)})", token)
            return self.doc.error(f"{context}: {found} is not {enumeration.what} "
                                  f"(allowed: {', '.join(enumeration.words)})", token)
        if kind in ("int", "float") and raw[:1] != b'"' and _looks_numeric(raw):
            return self.doc.error(f"{context}: bad number {found} ({_KIND_NAMES[kind]} expected)", token)
        return self.doc.error(f"{context}: {_KIND_NAMES[kind]} expected, found {found}", token)

    def _check_top_level(self, own: list[int]) -> None:
        position = 0
        while position < len(own):
            token = own[position]
            raw = self.raw(token)
            kinds = grammar.TOP_LEVEL_OPTIONS.get(raw.decode("latin-1"))
            if kinds is None:
                raise self.doc.error(f"unexpected '{shown(raw)}' at the top level", token)
            position = self._check_params(raw.decode("latin-1"), kinds, own, position + 1, token)


@functools.cache
def _allowed_options(keyword: str) -> dict[bytes, tuple[str, ...]]:
    """The option keywords a block allows, as spelled in a file, with their parameter kinds."""
    return {name.encode("ascii"): grammar.OPTIONS[name] for name in grammar.BLOCKS[keyword].options}


def _placement_problem(parent: str | None, keyword: str) -> str | None:
    """Why a ``keyword`` block cannot stand in a ``parent`` block (None: top level); None when it can."""
    if parent is None:
        if keyword in grammar.TOP_LEVEL_BLOCKS:
            return None
        return f"/begin {keyword} is not allowed at the top level (expected PROJECT)"
    parent_spec = grammar.BLOCKS.get(parent)
    if parent_spec is None or keyword in parent_spec.blocks:
        return None
    what = "unknown block" if keyword not in grammar.BLOCKS else "block"
    return f"{what} /begin {keyword} is not allowed in {parent}"


def _fits(kind: str, raw: bytes) -> bool:
    """Whether a token's bytes ``raw`` are a parameter of this kind (any kind but ``str``)."""
    words = _ENUM_BYTES.get(kind)
    if words is not None:
        return raw in words
    return _PATTERNS[kind].fullmatch(raw) is not None


def _looks_numeric(raw: bytes) -> bool:
    return raw[:1] in b"0123456789+-." and len(raw) > 0
