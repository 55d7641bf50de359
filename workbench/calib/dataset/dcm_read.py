"""Read DCM files (DAMOS Konservierungsformat 2.0) into a :class:`~workbench.calib.dataset.model.Dataset`.

What CANape, INCA and MATLAB write is read: any number of values per WERT/ST/X/ST/Y line,
WERT and TEXT lines mixed, quoted or bare FUNKTION and DISPLAYNAME names, ``*SSTX``/``*SSTY``
naming the STUETZSTELLENVERTEILUNG of a group curve or map, comments (``*``, ``!``, ``.``)
anywhere, empty lines, trailing spaces, any line end, a BOM, UTF-8 or Windows-1252.

``WERT true`` / ``WERT false`` (booleans as some tools write them) are read as 1 and 0, each with
a warning in ``Dataset.notes``.

Strict where a guess could change a value: an unknown keyword, a keyword in a block that cannot
hold it, a count that does not match the values, a text where a number belongs, a block without
END — each is a :class:`~workbench.errors.DatasetParseError` naming ``file:line:column`` and what
was expected. Nothing is skipped: comments are kept (inside a block with the object, outside
with the file), MODULKOPF, FUNKTIONEN, VARIANTENKODIERUNG and VAR too.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

import numpy as np

from workbench.calib.dataset.dcm_lines import Line, Token, decode, split_lines, tokenize
from workbench.calib.dataset.model import Dataset, FunctionInfo, ObjectInfo, value_runs
from workbench.calib.dataset.numbers import NumberError, parse_number, scalar, to_array
from workbench.calib.values import Axis, CalValue
from workbench.errors import DatasetParseError
from workbench.findings import Finding, Severity

__all__ = ["read"]

_INFO = ("LANGNAME", "DISPLAYNAME", "FUNKTION", "VAR")
_VALUES = ("WERT", "TEXT")
_X = ("ST/X", "ST_TX/X")
_Y = ("ST/Y", "ST_TX/Y")


@dataclass(frozen=True)
class _Kind:
    """What one object keyword declares and may contain."""

    kind: str  # CalValue kind
    counts: int  # numbers after the name (FESTWERTEBLOCK: 1, and "@ ny" optionally)
    keywords: tuple[str, ...]
    axis_kind: str = ""


_CURVE_KEYS = _INFO + ("EINHEIT_X", "EINHEIT_W") + _X + _VALUES
_MAP_KEYS = _INFO + ("EINHEIT_X", "EINHEIT_Y", "EINHEIT_W") + _X + _Y + _VALUES
OBJECT_KEYWORDS: dict[str, _Kind] = {
    "FESTWERT": _Kind("VALUE", 0, _INFO + ("EINHEIT_W",) + _VALUES),
    "TEXTSTRING": _Kind("ASCII", 0, _INFO + ("TEXT",)),
    "FESTWERTEBLOCK": _Kind("VAL_BLK", 1, _INFO + ("EINHEIT_W",) + _VALUES),
    "KENNLINIE": _Kind("CURVE", 1, _CURVE_KEYS, "STD_AXIS"),
    "FESTKENNLINIE": _Kind("CURVE", 1, _CURVE_KEYS, "FIX_AXIS"),
    "GRUPPENKENNLINIE": _Kind("CURVE", 1, _CURVE_KEYS, "COM_AXIS"),
    "KENNFELD": _Kind("MAP", 2, _MAP_KEYS, "STD_AXIS"),
    "FESTKENNFELD": _Kind("MAP", 2, _MAP_KEYS, "FIX_AXIS"),
    "GRUPPENKENNFELD": _Kind("MAP", 2, _MAP_KEYS, "COM_AXIS"),
    "STUETZSTELLENVERTEILUNG": _Kind("AXIS_PTS", 1, _INFO + ("EINHEIT_X",) + _X),
}
_FILE_KEYWORDS = ("KONSERVIERUNG_FORMAT", "FUNKTIONEN", "VARIANTENKODIERUNG", "MODULKOPF")
_ALL_BLOCK_KEYWORDS = set(_MAP_KEYS) | {"END"}
_SINGLE = ("LANGNAME", "DISPLAYNAME", "FUNKTION", "VAR", "EINHEIT_W", "EINHEIT_X", "EINHEIT_Y")
_INLINE_COMMENT = " (a comment takes a line of its own, starting with *, ! or .)"
_SST = re.compile(r"SST([XY])\s+(\S+)\Z")
_NAME = re.compile(r"[A-Za-z_][\w.\[\]]*\Z")
_COUNT = re.compile(r"\d+\Z")
_BOOLEANS = {"true": 1, "false": 0}


def read(data: bytes, path: str = "<string>") -> Dataset:
    """The dataset a DCM file holds.

    :raises DatasetParseError: the file is not DCM as described in the module docstring.
    """
    return _Reader(split_lines(decode(data, path)), path).read()


@dataclass
class _Block:
    """The lines of one object between its header and END, sorted by role."""

    header: Line
    keyword: str
    name: str
    counts: list[int]
    lines: list[Line] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)
    axis_names: dict[str, str] = field(default_factory=dict)  # "X"/"Y" -> *SSTX/*SSTY name


class _Reader:
    def __init__(self, lines: list[Line], path: str):
        self.lines = lines
        self.path = path
        self.at = 0
        self.dataset = Dataset(source=path, format="dcm")
        self.format_line = 0
        self.current = ""  # the object being read, for the notes
        self.value_lines: list[int] = []  # the line of each of its WERT/TEXT values

    def error(self, message: str, line: Line | int, column: int = 0) -> DatasetParseError:
        number = line if isinstance(line, int) else line.number
        return DatasetParseError(message, self.path, number, column)

    def tokens(self, line: Line) -> list[Token]:
        return tokenize(line, self.path)

    def read(self) -> Dataset:
        while self.at < len(self.lines):
            line = self.lines[self.at]
            self.at += 1
            if line.keyword is None:
                self.dataset.comments.append(line.rest)
            elif line.keyword in OBJECT_KEYWORDS:
                self.object(self.block(line))
            elif line.keyword == "KONSERVIERUNG_FORMAT":
                self.format_version(line)
            elif line.keyword == "FUNKTIONEN":
                self.functions(line)
            elif line.keyword == "VARIANTENKODIERUNG":
                self.variant_coding(line)
            elif line.keyword == "MODULKOPF":
                self.module_header(line)
            elif line.keyword == "END":
                raise self.error("END without a block to close", line, line.column)
            else:
                raise self.error(f"unknown keyword {line.keyword!r} (expected an object such as FESTWERT or "
                                 f"KENNLINIE, {', '.join(_FILE_KEYWORDS)}, or a comment)", line, line.column)
        return self.dataset

    # ---- file-level statements ----

    def format_version(self, line: Line) -> None:
        if self.format_line:
            raise self.error(f"KONSERVIERUNG_FORMAT again (first at line {self.format_line})", line)
        if line.rest != "2.0":
            raise self.error(f"KONSERVIERUNG_FORMAT {line.rest or '(nothing)'} is not supported (expected 2.0)",
                             line, line.rest_column)
        self.format_line = line.number

    def section(self, opener: Line, entry: str) -> list[Line]:
        """The ``entry`` lines of a FUNKTIONEN/VARIANTENKODIERUNG section up to its END (comments go to the file)."""
        entries = []
        while True:
            line = self.next_in_block(opener, opener.keyword)
            if line.keyword is None:
                self.dataset.comments.append(line.rest)
            elif line.keyword == "END":
                return entries
            elif line.keyword == entry:
                entries.append(line)
            else:
                raise self.error(f"{line.keyword} in {opener.keyword} (expected {entry} lines and END)", line)

    def next_in_block(self, opener: Line, what: str) -> Line:
        if self.at >= len(self.lines):
            last = self.lines[-1].number if self.lines else opener.number
            raise self.error(f"{what} (line {opener.number}) is not closed by END", last)
        line = self.lines[self.at]
        self.at += 1
        return line

    def functions(self, opener: Line) -> None:
        for line in self.section(opener, "FKT"):
            tokens = self.tokens(line)
            if not 1 <= len(tokens) <= 3 or tokens[0].quoted:
                raise self.error('FKT expects a function name, its version and long name: FKT name "1.0" "text"', line)
            name = tokens[0].text
            if name in self.dataset.functions:
                raise self.error(f"function {name} listed twice", line, tokens[0].column)
            texts = [t.text for t in tokens[1:]] + ["", ""]
            self.dataset.functions[name] = FunctionInfo(version=texts[0], long_name=texts[1])

    def variant_coding(self, opener: Line) -> None:
        for line in self.section(opener, "KRITERIUM"):
            tokens = self.tokens(line)
            if not tokens or tokens[0].quoted:
                raise self.error("KRITERIUM expects a criterion name and its values", line)
            self.dataset.variant_criteria[tokens[0].text] = tuple(t.text for t in tokens[1:])

    def module_header(self, line: Line) -> None:
        tokens = self.tokens(line)
        if len(tokens) == 2 and not tokens[0].quoted and tokens[1].quoted:
            self.dataset.module_header.append((tokens[0].text, tokens[1].text))
        elif len(tokens) == 1 and tokens[0].quoted:
            self.dataset.module_header.append(("", tokens[0].text))
        else:
            raise self.error('MODULKOPF expects a name and a text (MODULKOPF Name "text") or a continuation text', line)

    # ---- objects ----

    def block(self, header: Line) -> _Block:
        spec = OBJECT_KEYWORDS[header.keyword]
        tokens = self.tokens(header)
        counts = self.header_counts(header, tokens, spec)
        name = tokens[0].text if tokens else ""
        block = _Block(header, header.keyword, name, counts)
        groups = spec.axis_kind == "COM_AXIS"
        while True:
            line = self.next_in_block(header, f"{header.keyword} {name}")
            if line.keyword is None:
                match = _SST.match(line.rest) if groups and line.marker == "*" else None
                if match:
                    block.axis_names[match.group(1)] = match.group(2)
                else:
                    block.comments.append(line.rest)
            elif line.keyword == "END":
                if line.rest:
                    raise self.error("END takes nothing after it", line, line.rest_column)
                return block
            elif line.keyword not in _ALL_BLOCK_KEYWORDS:
                raise self.error(f"{header.keyword} {name} (line {header.number}) is not closed by END before "
                                 f"{line.keyword!r}" if line.keyword in OBJECT_KEYWORDS or line.keyword in _FILE_KEYWORDS
                                 else f"unknown keyword {line.keyword!r} in {header.keyword} {name}", line)
            elif line.keyword not in spec.keywords:
                raise self.error(f"{line.keyword} does not belong in {header.keyword} (expected "
                                 f"{', '.join(spec.keywords)} or END)", line)
            else:
                block.lines.append(line)

    def header_counts(self, header: Line, tokens: list[Token], spec: _Kind) -> list[int]:
        expected = spec.counts
        if header.keyword == "FESTWERTEBLOCK" and len(tokens) == 4 and tokens[2].text == "@" and not tokens[2].quoted:
            tokens[2:3] = []  # nx @ ny
            expected = 2
        usage = {0: "a name", 1: "a name and the number of values", 2: "a name and the numbers of X and Y points"}
        if len(tokens) != expected + 1 or tokens[0].quoted or not _NAME.match(tokens[0].text):
            extra = " (and '@ ny' for a 2-D block)" if header.keyword == "FESTWERTEBLOCK" else ""
            raise self.error(f"{header.keyword} expects {usage[spec.counts]}{extra}", header, header.rest_column)
        counts = []
        for token in tokens[1:]:
            if token.quoted or not _COUNT.match(token.text) or int(token.text) == 0:
                raise self.error(f"{header.keyword} {tokens[0].text}: {token.text!r} is not a count above 0", header,
                                 token.column)
            counts.append(int(token.text))
        return counts

    def object(self, block: _Block) -> None:
        name, header = block.name, block.header
        if name in self.dataset:
            first = self.dataset.info_of(name).line
            raise self.error(f"{name} is defined twice (first at line {first})", header, header.rest_column)
        single = self.single_lines(block)
        texts = {keyword: self.one_text(line) for keyword, line in single.items() if keyword not in ("FUNKTION", "VAR")}
        info = ObjectInfo(
            display_name=texts.get("DISPLAYNAME", ""),
            functions=tuple(t.text for t in self.tokens(single["FUNKTION"])) if "FUNKTION" in single else (),
            comments=tuple(block.comments),
            variants=self.variants(single.get("VAR")),
            category=block.keyword,
            line=header.number,
            value_line=_first(block, _VALUES) or _first(block, _X),
        )
        self.current = name
        self.value_lines = []
        try:
            value = _BUILDERS[OBJECT_KEYWORDS[block.keyword].kind](self, block, texts)
        except NumberError as exc:
            raise self.error(f"{block.keyword} {name}: {exc}", header) from None
        self.dataset.add(value, replace(info, value_runs=value_runs(self.value_lines)))

    def single_lines(self, block: _Block) -> dict[str, Line]:
        single: dict[str, Line] = {}
        for line in block.lines:
            if line.keyword in _SINGLE:
                if line.keyword in single:
                    raise self.error(f"{line.keyword} again in {block.keyword} {block.name} "
                                     f"(first at line {single[line.keyword].number})", line)
                single[line.keyword] = line
        if "FUNKTION" in single and not single["FUNKTION"].rest:
            raise self.error("FUNKTION expects one or more function names", single["FUNKTION"])
        return single

    def one_text(self, line: Line) -> str:
        tokens = self.tokens(line)
        if len(tokens) != 1:
            raise self.error(f'{line.keyword} expects one text in quotes, e.g. {line.keyword} "text"', line,
                             line.rest_column)
        return tokens[0].text

    def variants(self, line: Line | None) -> tuple[tuple[str, str], ...]:
        if line is None:
            return ()
        pairs = []
        for part in line.rest.split(","):
            criterion, equals, value = part.partition("=")
            if not equals or not criterion.strip() or not value.strip():
                raise self.error("VAR expects criterion=value pairs separated by commas", line, line.rest_column)
            pairs.append((criterion.strip(), value.strip().strip('"')))
        return tuple(pairs)

    def values(self, lines: list[Line]) -> list:
        """The values of WERT/TEXT (or ST/X, ST_TX/X ...) lines, in file order."""
        items: list = []
        for line in lines:
            tokens = self.tokens(line)
            if not tokens:
                raise self.error(f"{line.keyword} without values", line, line.column)
            if line.keyword in _VALUES:  # where each value is, for a refusal of one element
                self.value_lines += [line.number] * len(tokens)
            for token in tokens:
                if line.keyword in ("TEXT", "ST_TX/X", "ST_TX/Y"):
                    items.append(token.text)
                elif token.quoted:
                    text_keyword = {"WERT": "TEXT", "ST/X": "ST_TX/X", "ST/Y": "ST_TX/Y"}[line.keyword]
                    raise self.error(f"{line.keyword} takes numbers; the text {token.text!r} belongs on a "
                                     f"{text_keyword} line", line, token.column)
                elif line.keyword == "WERT" and token.text.lower() in _BOOLEANS:
                    items.append(self.boolean(line, token))
                else:
                    try:
                        items.append(parse_number(token.text))
                    except NumberError as exc:
                        hint = _INLINE_COMMENT if token.text.startswith(("*", "!")) else ""
                        raise self.error(f"{line.keyword}: {exc}{hint}", line, token.column) from None
        return items

    def boolean(self, line: Line, token: Token) -> int:
        number = _BOOLEANS[token.text.lower()]
        self.dataset.notes.append(Finding("read-as", self.current, f"{self.current}: WERT {token.text} read as {number}",
                                          self.path, line.number, token.column, severity=Severity.WARNING))
        return number

    def lines_of(self, block: _Block, keywords: tuple[str, ...]) -> list[Line]:
        return [line for line in block.lines if line.keyword in keywords]

    def count_error(self, block: _Block, what: str, declared: int, found: int) -> DatasetParseError:
        return self.error(f"{block.keyword} {block.name}: {declared} {what} declared, {found} found", block.header,
                          block.header.rest_column)

    # ---- one builder per kind ----

    def value(self, block: _Block, texts: dict[str, str]) -> CalValue:
        items = self.values(self.lines_of(block, _VALUES))
        if len(items) != 1:
            raise self.error(f"FESTWERT {block.name}: expects one WERT or TEXT, found {len(items)} values",
                             block.header, block.header.rest_column)
        item = items[0] if isinstance(items[0], str) else scalar(items[0])
        return CalValue(block.name, "VALUE", item, unit=texts.get("EINHEIT_W", ""), comment=texts.get("LANGNAME", ""))

    def ascii(self, block: _Block, texts: dict[str, str]) -> CalValue:
        items = self.values(self.lines_of(block, ("TEXT",)))
        if len(items) != 1:
            raise self.error(f"TEXTSTRING {block.name}: expects one TEXT, found {len(items)}", block.header,
                             block.header.rest_column)
        return CalValue(block.name, "ASCII", items[0], comment=texts.get("LANGNAME", ""))

    def val_blk(self, block: _Block, texts: dict[str, str]) -> CalValue:
        items = self.values(self.lines_of(block, _VALUES))
        size = int(np.prod(block.counts))
        if len(items) != size:
            raise self.count_error(block, "values", size, len(items))
        # 2-D: one WERT row per y, x along the row (x varies fastest)
        array = to_array(items, tuple(reversed(block.counts))).T.copy()
        return CalValue(block.name, "VAL_BLK", array, unit=texts.get("EINHEIT_W", ""), comment=texts.get("LANGNAME", ""))

    def axis(self, block: _Block, texts: dict[str, str], letter: str, points: list) -> Axis:
        spec = OBJECT_KEYWORDS[block.keyword]
        return Axis(to_array(points), kind=spec.axis_kind, name=block.axis_names.get(letter),
                    unit=texts.get(f"EINHEIT_{letter}", ""))

    def curve(self, block: _Block, texts: dict[str, str]) -> CalValue:
        (nx,) = block.counts
        xs = self.values(self.lines_of(block, _X))
        items = self.values(self.lines_of(block, _VALUES))
        if len(xs) != nx:
            raise self.count_error(block, "X points", nx, len(xs))
        if len(items) != nx:
            raise self.count_error(block, "values", nx, len(items))
        return CalValue(block.name, "CURVE", to_array(items), axes=(self.axis(block, texts, "X", xs),),
                        unit=texts.get("EINHEIT_W", ""), comment=texts.get("LANGNAME", ""))

    def map(self, block: _Block, texts: dict[str, str]) -> CalValue:
        nx, ny = block.counts
        xs = self.values(self.lines_of(block, _X))
        ys: list = []
        rows: list[list] = []
        for line in block.lines:
            if line.keyword in _Y:
                y = self.values([line])
                if len(y) != 1:
                    raise self.error(f"{line.keyword} carries one Y point, then that row's WERT lines", line,
                                     line.rest_column)
                ys.extend(y)
                rows.append([])
            elif line.keyword in _VALUES:
                if not rows:
                    raise self.error(f"{line.keyword} before the first ST/Y of {block.keyword} {block.name}", line)
                rows[-1].extend(self.values([line]))
        if len(xs) != nx:
            raise self.count_error(block, "X points", nx, len(xs))
        if len(ys) != ny:
            raise self.count_error(block, "Y points (ST/Y lines)", ny, len(ys))
        for y, row in zip(ys, rows):
            if len(row) != nx:
                raise self.error(f"{block.keyword} {block.name}: the row of Y point {y} has {len(row)} values, "
                                 f"{nx} declared", block.header, block.header.rest_column)
        array = to_array([v for row in rows for v in row], (ny, nx)).T.copy()
        axes = (self.axis(block, texts, "X", xs), self.axis(block, texts, "Y", ys))
        return CalValue(block.name, "MAP", array, axes=axes, unit=texts.get("EINHEIT_W", ""),
                        comment=texts.get("LANGNAME", ""))

    def axis_pts(self, block: _Block, texts: dict[str, str]) -> CalValue:
        (nx,) = block.counts
        xs = self.values(self.lines_of(block, _X))
        if len(xs) != nx:
            raise self.count_error(block, "points", nx, len(xs))
        return CalValue(block.name, "AXIS_PTS", to_array(xs), unit=texts.get("EINHEIT_X", ""),
                        comment=texts.get("LANGNAME", ""))


def _first(block: _Block, keywords: tuple[str, ...]) -> int:
    return next((line.number for line in block.lines if line.keyword in keywords), 0)


_BUILDERS = {"VALUE": _Reader.value, "ASCII": _Reader.ascii, "VAL_BLK": _Reader.val_blk, "CURVE": _Reader.curve,
             "MAP": _Reader.map, "AXIS_PTS": _Reader.axis_pts}
