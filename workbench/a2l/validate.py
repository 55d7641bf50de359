"""Strict check of a parsed document against the ASAP2 keyword table.

Raises :class:`A2lParseError` at the first problem in file order: a block where its
parent does not allow it, a missing or malformed parameter (``bad number``), a
keyword that does not exist or is not allowed in its block. Free-form content
(IF_DATA, A2ML) is skipped.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.a2l import grammar
from workbench.a2l.values import FLOAT_RE, IDENT_RE, INT_RE
from workbench.errors import A2lParseError

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument

_KIND_NAMES = {"ident": "a name", "str": "a string", "int": "an integer", "float": "a number", "int*": "an integer"}


def validate_document(doc: "A2lDocument", errors: list[A2lParseError] | None = None) -> None:
    """Raise :class:`A2lParseError` at the first violation of the keyword table (in file
    order), or, when ``errors`` is a list, append every violation (one per block) to it."""
    found: list[A2lParseError] = []
    _Validator(doc, found).run()
    found.sort(key=lambda error: getattr(error, "offset", 0))
    if errors is not None:
        errors.extend(found)
    elif found:
        raise found[0]


class _Validator:
    def __init__(self, doc: "A2lDocument", errors: list[A2lParseError]):
        self.doc = doc
        self.errors = errors
        self.data = doc.data
        self.starts = doc.tokens.starts_list
        self.ends = doc.tokens.ends_list

    def raw(self, token: int) -> bytes:
        return self.data[self.starts[token] : self.ends[token]]

    def run(self) -> None:
        doc = self.doc
        begin, end, keywords = doc.block_begin, doc.block_end, doc.blocks.keyword
        parent = doc.blocks.parent.tolist()
        skip_until = -1  # token index: everything before it is inside a free block
        # own tokens per block, collected in one pass over the blocks in document order
        gaps: dict[int, list[int]] = {-1: []}
        cursor = [0]  # cursor[-1]: next unassigned token of the innermost open block
        stack = [-1]
        for block, (b, e) in enumerate(zip(begin, end)):
            if b < skip_until:
                continue
            while stack[-1] != -1 and end[stack[-1]] < b:
                self._close(stack, cursor, gaps, end)
            gaps[stack[-1]].extend(range(cursor[-1], b))
            cursor[-1] = e + 2
            keyword = keywords[block]
            spec = grammar.BLOCKS.get(keyword)
            self._guarded(self._check_placement, block, keyword, parent[block], keywords)
            if spec is not None and spec.free:
                skip_until = e
                continue
            stack.append(block)
            cursor.append(b + 2)
            gaps[block] = []
        while len(stack) > 1:
            self._close(stack, cursor, gaps, end)
        gaps[-1].extend(range(cursor[-1], len(doc.tokens)))
        self._guarded(self._check_top_level, gaps[-1])

    def _guarded(self, check, *args) -> None:
        try:
            check(*args)
        except A2lParseError as exc:
            self.errors.append(exc)

    def _close(self, stack, cursor, gaps, end) -> None:
        block = stack.pop()
        start = cursor.pop()
        own = gaps.pop(block)
        own.extend(range(start, end[block]))
        self._guarded(self._check_block, block, own)

    def _check_placement(self, block: int, keyword: str, parent: int, keywords: list[str]) -> None:
        if parent < 0:
            if keyword not in grammar.TOP_LEVEL_BLOCKS:
                raise self.doc.error(f"/begin {keyword} is not allowed at the top level (expected PROJECT)",
                                     self.doc.block_begin[block] + 1)
            return
        parent_keyword = keywords[parent]
        parent_spec = grammar.BLOCKS.get(parent_keyword)
        if parent_spec is None or keyword in parent_spec.blocks:
            return
        what = "unknown block" if keyword not in grammar.BLOCKS else "block"
        raise self.doc.error(f"{what} /begin {keyword} is not allowed in {parent_keyword}", self.doc.block_begin[block] + 1)

    def _check_block(self, block: int, own: list[int]) -> None:
        keyword = self.doc.blocks.keyword[block]
        spec = grammar.BLOCKS.get(keyword)
        if spec is None:
            return
        position = self._check_params(keyword, spec.params, own, 0, self.doc.block_end[block])
        if spec.repeat:
            count_raw = self.raw(own[len(spec.params) - 1])
            groups = int(count_raw, 0) if INT_RE.fullmatch(count_raw) else 0
            position = self._check_params(keyword, spec.repeat * groups, own, position, self.doc.block_end[block])
        if spec.items:
            while position < len(own) and self.raw(own[position]).decode("latin-1") not in spec.options:
                self._check_kind(spec.items, own[position], f"{keyword} entry")
                position += 1
        self._check_options(keyword, spec, own, position, self.doc.block_end[block])

    def _check_params(self, keyword: str, kinds, own: list[int], position: int, end_token: int) -> int:
        for kind in kinds:
            if position >= len(own):
                raise self.doc.error(f"{keyword}: missing parameter ({_KIND_NAMES[kind]} expected)", end_token)
            self._check_kind(kind, own[position], keyword)
            position += 1
        return position

    def _check_options(self, keyword: str, spec: grammar.BlockSpec, own: list[int], position: int, end_token: int) -> None:
        while position < len(own):
            token = own[position]
            raw = self.raw(token)
            name = raw.decode("latin-1")
            kinds = grammar.OPTIONS.get(name)
            if kinds is None or name not in spec.options:
                if kinds is None and not IDENT_RE.fullmatch(raw):
                    raise self.doc.error(f"unexpected '{_shown(raw)}' in {keyword} (a keyword expected)", token)
                what = "unknown keyword" if kinds is None else "keyword"
                raise self.doc.error(f"{what} {name} is not allowed in {keyword}", token)
            position += 1
            if kinds == ("int*",):
                start = position
                while position < len(own) and INT_RE.fullmatch(self.raw(own[position])):
                    position += 1
                if position == start:
                    raise self.doc.error(f"{name}: at least one integer expected", own[position] if position < len(own) else end_token)
                continue
            position = self._check_params(name, kinds, own, position, end_token)

    def _check_kind(self, kind: str, token: int, context: str) -> None:
        raw = self.raw(token)
        if kind == "str":
            ok = raw[:1] == b'"'
        elif kind == "ident":
            ok = IDENT_RE.fullmatch(raw) is not None
        elif kind == "int":
            ok = INT_RE.fullmatch(raw) is not None
        else:
            ok = FLOAT_RE.fullmatch(raw) is not None
        if not ok:
            found = "a string" if raw[:1] == b'"' else f"'{_shown(raw)}'"
            problem = "bad number" if kind in ("int", "float") and raw[:1] != b'"' and _looks_numeric(raw) else "expected"
            if problem == "bad number":
                raise self.doc.error(f"{context}: bad number {found} ({_KIND_NAMES[kind]} expected)", token)
            raise self.doc.error(f"{context}: {_KIND_NAMES[kind]} expected, found {found}", token)

    def _check_top_level(self, own: list[int]) -> None:
        position = 0
        while position < len(own):
            token = own[position]
            raw = self.raw(token)
            kinds = grammar.TOP_LEVEL_OPTIONS.get(raw.decode("latin-1"))
            if kinds is None:
                raise self.doc.error(f"unexpected '{_shown(raw)}' at the top level", token)
            position = self._check_params(raw.decode("latin-1"), kinds, own, position + 1, token)


def _looks_numeric(raw: bytes) -> bool:
    return raw[:1] in b"0123456789+-." and len(raw) > 0


def _shown(raw: bytes, limit: int = 40) -> str:
    text = raw.decode("latin-1")
    return text if len(text) <= limit else text[: limit - 3] + "..."
