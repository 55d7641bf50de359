"""DCM text as located lines and tokens: encodings, line ends, comments, quoted texts.

A DCM file is line-oriented: a keyword, then whitespace-separated tokens (numbers, names, texts
in double quotes). Lines whose first character is ``*``, ``!`` or ``.`` are comments. Texts
escape a quote as ``\\"`` (and a backslash as ``\\\\``); a doubled quote ``""`` inside a text,
as some spreadsheet-made files have it, is read as one quote too. Any other backslash is kept as
it is: Windows paths in comments and long names are common.
"""

from __future__ import annotations

import codecs
import re
from dataclasses import dataclass

from workbench.errors import DatasetParseError

__all__ = ["Line", "Token", "decode", "split_lines", "tokenize"]

COMMENT_MARKERS = "*!."
_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_SPACE = " \t\f\v"


@dataclass(frozen=True)
class Token:
    text: str
    column: int  # 1-based
    quoted: bool


@dataclass(frozen=True)
class Line:
    """One non-blank line: a comment (``keyword`` is None) or a keyword and the rest of the line."""

    number: int  # 1-based
    keyword: str | None
    rest: str  # after the keyword (a comment: its text after the marker, stripped)
    rest_column: int  # 1-based column where ``rest`` starts in the line
    column: int = 1  # 1-based column of the keyword (or comment marker)
    marker: str = ""  # the comment marker: "*", "!" or "."

    @property
    def comment(self) -> str | None:
        return self.rest if self.keyword is None else None


def decode(data: bytes, path: str) -> str:
    """The text of a DCM file: UTF-8 (with or without BOM), UTF-16 with BOM, else Windows-1252/Latin-1.

    Tools on Windows write DCM in the ANSI code page; a file that is valid UTF-8 is taken as
    UTF-8, anything else as Windows-1252 (Latin-1 for the five bytes Windows-1252 leaves undefined).

    :raises DatasetParseError: a file that declares UTF-8 or UTF-16 by its BOM but is not.
    """
    for bom, codec in ((codecs.BOM_UTF8, "utf-8"), (codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be")):
        if data.startswith(bom):
            body = data[len(bom):]
            try:
                return body.decode(codec)
            except UnicodeDecodeError as exc:
                line = body[:exc.start].count(b"\n") + 1
                raise DatasetParseError(f"not valid {codec.upper()} although it starts with a {codec.upper()} byte order mark",
                                        path, line) from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        pass
    try:
        return data.decode("cp1252")
    except UnicodeDecodeError:
        return data.decode("latin-1")


def split_lines(text: str) -> list[Line]:
    """The non-blank lines of ``text`` (any line end: CRLF, LF, CR), comments and keyword lines."""
    lines = []
    for number, raw in enumerate(_LINE_BREAK.split(text), start=1):
        stripped = raw.strip()
        if not stripped:
            continue
        indent = len(raw) - len(raw.lstrip())
        if stripped[0] in COMMENT_MARKERS:
            lines.append(Line(number, None, stripped[1:].strip(), indent + 2, indent + 1, stripped[0]))
            continue
        parts = stripped.split(maxsplit=1)
        keyword = parts[0]
        rest = parts[1] if len(parts) > 1 else ""
        rest_column = indent + 1 + (stripped.index(rest, len(keyword)) if rest else len(stripped))
        lines.append(Line(number, keyword, rest, rest_column, indent + 1))
    return lines


def tokenize(line: Line, path: str) -> list[Token]:
    """The tokens of ``line.rest``: bare words and numbers, and texts in double quotes.

    :raises DatasetParseError: a text whose closing quote is missing.
    """
    text, base = line.rest, line.rest_column
    tokens: list[Token] = []
    i, n = 0, len(text)
    while i < n:
        if text[i] in _SPACE:
            i += 1
            continue
        if text[i] != '"':
            j = i
            while j < n and text[j] not in _SPACE and text[j] != '"':
                j += 1
            tokens.append(Token(text[i:j], base + i, False))
            i = j
            continue
        chars, j = [], i + 1
        while True:
            if j >= n:
                raise DatasetParseError("text without its closing quote", path, line.number, base + i)
            c = text[j]
            if c == "\\" and j + 1 < n and text[j + 1] in '"\\':
                chars.append(text[j + 1])
                j += 2
            elif c == '"' and j + 1 < n and text[j + 1] == '"':
                chars.append('"')
                j += 2
            elif c == '"':
                break
            else:
                chars.append(c)
                j += 1
        tokens.append(Token("".join(chars), base + i, True))
        i = j + 1
    return tokens


def quote(text: str) -> str:
    """``text`` as a DCM text token (quotes and backslashes escaped)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'
