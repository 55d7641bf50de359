"""A DBC text as located statements: what :mod:`workbench.can.dbc_repair` looks at before cantools parses.

Not a DBC parser: tokens are cut the way cantools' tokenizer cuts them (strings with ``\\"``
escapes, ``//`` comments, numbers, words), except that a word may start with a digit
(``2017_5``) and a number may start with a point (``.25``), so that the repairs can see
both. The layout of a signal (``0|8@1+ (1,0) [0|255]``) is one token of its own
(:data:`LAYOUT`): a DBC is mostly signals, and they need not be cut finer. A statement
starts at a DBC keyword that is the first token of its line or follows a ``;``, and runs
up to the next one; the keyword list of ``NS_ :`` is skipped as cantools skips it (up to
the first token followed by ``:``, normally ``BS_:``). The ``SG_`` lines
of a message are statements of their own.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass, field
from typing import NamedTuple

__all__ = [
    "KEYWORDS", "LAYOUT", "LAYOUT_PATTERN", "NUMBER", "NUMBER_PATTERN", "OTHER", "STRING", "WORD", "DbcText",
    "Statement", "Token",
]

# The keywords cantools' DBC tokenizer knows.
KEYWORDS = frozenset({
    "BA_", "BA_DEF_", "BA_DEF_DEF_", "BA_DEF_DEF_REL_", "BA_DEF_REL_", "BA_DEF_SGTYPE_", "BA_REL_", "BA_SGTYPE_",
    "BO_", "BO_TX_BU_", "BS_", "BU_", "BU_BO_REL_", "BU_EV_REL_", "BU_SG_REL_", "CAT_", "CAT_DEF_", "CM_",
    "ENVVAR_DATA_", "EV_", "EV_DATA_", "FILTER", "NS_", "NS_DESC_", "SG_", "SG_MUL_VAL_", "SGTYPE_", "SGTYPE_VAL_",
    "SIG_GROUP_", "SIG_TYPE_REF_", "SIG_VALTYPE_", "SIGTYPE_VALTYPE_", "VAL_", "VAL_TABLE_", "VERSION",
})
STRING, NUMBER, WORD, OTHER, LAYOUT = "string", "number", "word", "other", "layout"
NUMBER_PATTERN = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
# start|length@order sign (factor,offset) [minimum|maximum]
LAYOUT_PATTERN = re.compile(
    rf"(\d+)\s*\|\s*(\d+)\s*@\s*[01]\s*[-+]\s*\(\s*{NUMBER_PATTERN}\s*,\s*{NUMBER_PATTERN}\s*\)"
    rf"\s*\[\s*{NUMBER_PATTERN}\s*\|\s*{NUMBER_PATTERN}\s*\]")
# Space and // comments before a token, then the token. A string ends at the first '"' that is not
# part of a \" (cantools' "(\\"|[^"])*?" matches the same strings, more slowly). A run of space and a
# comment, and a run of characters in a string each match one way only (the whole run, the whole line):
# space at the end of the text, where no token follows, or a string without its closing quote must not
# be tried split in every way (that took minutes for 30 blank lines or 40 characters).
_TOKEN = re.compile(
    r"(?P<space>(?:\s+(?!\s)|//[^\n]*(?![^\n]))*)"
    r'(?:(?P<string>"(?:[^"\\]+(?![^"\\])|\\"|\\)*")'
    rf"|(?P<layout>{LAYOUT_PATTERN.pattern})"
    rf"|(?P<number>{NUMBER_PATTERN}(?![\w.]))"
    r"|(?P<word>\w+)"
    r"|(?P<other>\S))",
    re.DOTALL,
)


class Token(NamedTuple):
    kind: str
    """:data:`STRING`, :data:`NUMBER`, :data:`WORD`, :data:`LAYOUT` or :data:`OTHER` (punctuation)."""
    text: str
    start: int
    """Offset in the text."""
    first_on_line: bool

    @property
    def end(self) -> int:
        return self.start + len(self.text)

    @property
    def value(self) -> str:
        """A string's content without its quotes; the text of any other token."""
        return self.text[1:-1] if self.kind == STRING else self.text


@dataclass
class Statement:
    """One DBC statement: its keyword token first, its ``;`` last when it has one."""

    keyword: str
    tokens: list[Token]
    line: int
    """1-based line of the keyword."""
    dropped: bool = field(default=False, compare=False)
    """Set by a repair that removes the statement from what cantools sees."""

    @property
    def start(self) -> int:
        return self.tokens[0].start

    @property
    def end(self) -> int:
        return self.tokens[-1].end

    def token(self, index: int) -> Token | None:
        return self.tokens[index] if index < len(self.tokens) else None

    def index_of(self, text: str, start: int = 0) -> int | None:
        """Index of the first token ``text`` (outside strings) from ``start``, ``None`` if absent."""
        return next((i for i in range(start, len(self.tokens))
                     if self.tokens[i].kind != STRING and self.tokens[i].text == text), None)


class DbcText:
    """The statements of a DBC text and the line of any offset."""

    def __init__(self, text: str) -> None:
        self.text = text
        self._line_starts = [0] + [m.end() for m in re.finditer("\n", text)]
        self.statements = _statements(self, _tokens(text))

    def line_of(self, offset: int) -> int:
        """The 1-based line of an offset."""
        return bisect.bisect_right(self._line_starts, offset)


def _tokens(text: str) -> list[Token]:
    # the first token needs no line start: it always starts a statement
    return [Token(match.lastgroup, match[match.lastgroup], match.start(match.lastgroup), "\n" in match["space"])
            for match in _TOKEN.finditer(text)]


def _statements(text: DbcText, tokens: list[Token]) -> list[Statement]:
    statements: list[Statement] = []
    skip_namespace_until = -1
    for index, token in enumerate(tokens):
        if index < skip_namespace_until:
            statements[-1].tokens.append(token)
            continue
        follows_semicolon = index > 0 and tokens[index - 1].text == ";"
        starts = index == skip_namespace_until or (
            token.kind == WORD and token.text in KEYWORDS and (token.first_on_line or follows_semicolon))
        if starts or not statements:
            statements.append(Statement(token.text, [token], text.line_of(token.start)))
            if token.text == "NS_":
                skip_namespace_until = _namespace_end(tokens, index)
        else:
            statements[-1].tokens.append(token)
    return statements


def _namespace_end(tokens: list[Token], index: int) -> int:
    """Index of the token after ``NS_ :`` that is followed by ``:`` (where cantools ends the list)."""
    for later in range(index + 2, len(tokens) - 1):
        if tokens[later + 1].text == ":":
            return later
    return len(tokens)
