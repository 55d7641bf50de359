"""A DBC's content read from its statements, as cantools reads it, without building cantools' database.

What the commands need of a DBC (nodes, messages, signals, comments, value descriptions,
the period and timeout attributes) is read here from the statements :mod:`workbench.can.dbc_text`
cut (those of the repaired text, :mod:`workbench.can.dbc_repair`), with cantools' rules: its
grammar, its conversions of numbers and attribute values, how it picks a message's multiplexer
(``SG_MUL_VAL_`` included), which ``VAL_`` a signal takes, CANdb++'s long names
(``System{Message,Signal,Node}LongSymbol``). The statements are cut once, for the repair and for this
reading; cantools would cut the text again, parse it with its grammar and build codecs for encoding
and decoding, which :attr:`DbcFile.database <workbench.can.dbc_file.DbcFile.database>` builds when
someone decodes.

The reader gives up (:class:`Unreadable`) wherever it is not sure to read as cantools does — a
statement outside cantools' grammar, a value cantools would refuse or convert in a way it does not
follow, space cantools' tokenizer does not skip — and the load then asks cantools, which reads the
file or names the problem. The tests hold it to :mod:`workbench.can.dbc_database`: both must give
the same content for every DBC, or refuse it alike.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from decimal import Decimal

from workbench.can.dbc_repair_attributes import FRAME_FORMATS
from workbench.can.dbc_text import (
    KEYWORDS,
    LAYOUT,
    NUMBER,
    NUMBER_PATTERN,
    OTHER,
    STRING,
    WORD,
    DbcText,
    Statement,
    Token,
)
from workbench.can.model import (
    FRAME_FORMAT_ATTRIBUTE,
    PERIOD_ATTRIBUTE,
    TIMEOUT_ATTRIBUTE,
    DbcContent,
    Message,
    SignalOfMsg,
    period_and_timeout,
    value_table_of,
)

__all__ = ["Unreadable", "read_content"]

_LAYOUT = re.compile(
    rf"(\d+)\s*\|\s*(\d+)\s*@\s*([01])\s*([-+])\s*\(\s*({NUMBER_PATTERN})\s*,\s*({NUMBER_PATTERN})\s*\)"
    rf"\s*\[\s*({NUMBER_PATTERN})\s*\|\s*({NUMBER_PATTERN})\s*\]")
# Space cantools' tokenizer does not skip (it skips only " \t\r\n" and // comments up to a newline)
_FOREIGN_SPACE = re.compile(r"[^\S \t\r\n]")
_COMMENT = re.compile(r"//[^\n]*")
_OBJECTS = ("BO_", "SG_", "BU_", "EV_")
# names longer than 32 characters, as CANdb++ writes them
_LONG_MESSAGE, _LONG_SIGNAL, _LONG_NODE = "SystemMessageLongSymbol", "SystemSignalLongSymbol", "SystemNodeLongSymbol"
_RANGE_MAX = 100_000  # SG_MUL_VAL_ values cantools lists one by one
_INTEGER_TYPES = ("INT", "HEX")
_FLOAT_SIGNAL_TYPES = (1, 2)  # SIG_VALTYPE_ 1: IEEE float, 2: double
_SEND_TYPE = "GenMsgSendType"
_NO_NODE = "Vector__XXX"


class Unreadable(Exception):
    """The reader is not sure to read the text as cantools does: the load asks cantools."""


def read_content(dbc: DbcText, original_name: Callable[[str], str]) -> DbcContent:
    """The content of the DBC text ``dbc`` (as repaired); ``original_name`` gives a name as the file writes it.

    :raises Unreadable: the reader is not sure to read the text as cantools does.
    """
    if _foreign_space(dbc) or "//" in dbc.text[dbc.text.rfind("\n") + 1:]:
        raise Unreadable("space cantools does not skip, or a // comment at the end of the text")
    try:
        return _Reader(original_name).read(dbc.statements)
    except (ValueError, ArithmeticError, IndexError, KeyError, TypeError) as exc:
        raise Unreadable(f"{type(exc).__name__}: {exc}") from exc


def _foreign_space(dbc: DbcText) -> bool:
    """Whether space between tokens holds a character cantools' tokenizer does not skip (in strings it may)."""
    if not _FOREIGN_SPACE.search(dbc.text):
        return False
    end = 0
    for statement in dbc.statements:
        for token in statement.tokens:
            if _FOREIGN_SPACE.search(_COMMENT.sub("", dbc.text[end:token.start])):
                return True
            end = token.end
    return bool(_FOREIGN_SPACE.search(_COMMENT.sub("", dbc.text[end:])))


@dataclass
class _Definition:
    type: str
    choices: list[str] | None = None
    default: object = None


@dataclass
class _Signal:
    name: str
    mux: str | None
    layout: re.Match
    unit: str
    receivers: list[str]


@dataclass
class _Message:
    frame_id: int
    name: str
    dlc: int
    sender: str
    line: int
    signals: list[_Signal]


class _Reader:
    """One pass over the statements collects what cantools collects; then the messages are built."""

    def __init__(self, original_name: Callable[[str], str]) -> None:
        self.original = original_name
        self.nodes: list[str] = []
        self.messages: list[_Message] = []
        self.message_comments: dict[int, str] = {}
        self.signal_comments: dict[tuple[int, str], str] = {}
        # BA_DEF_, BA_DEF_REL_, BA_, BA_REL_: read once the whole file is (a definition may follow its values)
        self.later: dict[str, list[list[Token]]] = {"BA_DEF_": [], "BA_DEF_REL_": [], "BA_": [], "BA_REL_": []}
        self.defaults: dict[str, str] = {}
        self.relation_defaults: dict[str, str] = {}
        self.value_tables: dict[str, dict[int, str]] = {}
        self.choices: dict[int, dict[str, dict[int, str]]] = {}
        self.senders: dict[int, list[str]] = {}
        self.signal_types: dict[int, dict[str, int]] = {}
        self.multiplexing: dict[int, dict[str, dict[str, list[int]]]] = {}
        # once every statement is read (_content)
        self.definitions: dict[str, _Definition] = {}
        self.attributes: dict[str | None, dict] = {}
        self.sorted_tables: dict[str, tuple[tuple[int, str], ...]] = {}

    # -- statements ------------------------------------------------------------------------------

    def read(self, statements: list[Statement]) -> DbcContent:
        if not statements:
            raise Unreadable("no statements")
        message: _Message | None = None
        for statement in statements:
            keyword, tokens = statement.keyword, statement.tokens
            if keyword == "SG_":
                if message is None:
                    raise Unreadable("a signal outside a message")
                message.signals.append(self._signal(tokens))
                continue
            message = None
            if keyword == "BO_":
                message = self._message(statement)
                self.messages.append(message)
            elif keyword == "CM_":
                self._comment(tokens)
            elif keyword in self.later:
                self.later[keyword].append(tokens)
            elif keyword == "VAL_":
                self._choices(tokens)
            elif keyword in _OTHER_STATEMENTS:
                _OTHER_STATEMENTS[keyword](self, tokens)
            else:
                raise Unreadable(f"{keyword} statement")
        if statements[-1].keyword == "NS_":  # cantools ends the list at a token followed by ':', not at the end
            raise Unreadable("NS_ up to the end")
        return self._content()

    def _message(self, statement: Statement) -> _Message:
        tokens = statement.tokens
        _expect(tokens, (NUMBER, WORD, ":", NUMBER, WORD))
        return _Message(int(tokens[1].text), _word(tokens[2]), int(tokens[4].text, 0), _word(tokens[5]),
                        statement.line, [])

    def _signal(self, tokens: list[Token]) -> _Signal:
        mux = _word(tokens[2]) if len(tokens) > 2 and tokens[2].kind == WORD else None
        at = 3 if mux is not None else 2
        if (len(tokens) < at + 4 or tokens[at].text != ":" or tokens[at + 1].kind != LAYOUT
                or tokens[at + 2].kind != STRING):
            raise Unreadable("signal syntax")
        layout = _LAYOUT.fullmatch(tokens[at + 1].text)
        if layout is None or any(number.lstrip("+-").startswith(".") for number in layout.groups()[4:]):
            raise Unreadable("signal layout")
        return _Signal(_word(tokens[1]), mux, layout, _string(tokens[at + 2]),
                       _delimited(tokens, at + 3, len(tokens), WORD))

    def _comment(self, tokens: list[Token]) -> None:
        kind = tokens[1].text if len(tokens) > 1 and tokens[1].kind == WORD else None
        if kind == "SG_":
            _expect(tokens, ("SG_", NUMBER, WORD, STRING, ";"))
            self.signal_comments[(int(tokens[2].text), _word(tokens[3]))] = _string(tokens[4])
        elif kind == "BO_":
            _expect(tokens, ("BO_", NUMBER, STRING, ";"))
            self.message_comments[int(tokens[2].text)] = _string(tokens[3])
        elif kind in ("BU_", "EV_"):
            _expect(tokens, (kind, WORD, STRING, ";"))
        else:
            _expect(tokens, (STRING, ";"))

    def _choices(self, tokens: list[Token]) -> None:
        has_id = len(tokens) > 1 and tokens[1].kind == NUMBER
        first = 3 if has_id else 2
        _expect(tokens[:first], (NUMBER, WORD) if has_id else (WORD,))
        pairs = _pairs(tokens, first)
        if has_id and pairs:  # a VAL_ of an environment variable, or one without values, is not read
            self.choices.setdefault(int(tokens[1].text), {})[_word(tokens[2])] = pairs

    def _version(self, tokens: list[Token]) -> None:
        _expect(tokens, (STRING,))

    def _namespace(self, tokens: list[Token]) -> None:
        # cantools skips the list up to the first token followed by ':', as dbc_text does
        if len(tokens) < 2 or tokens[1].text != ":" or any(
                t.kind != WORD or not (t.text.isascii() and t.text.isidentifier()) for t in tokens[2:]):
            raise Unreadable("NS_ syntax")

    def _bit_timing(self, tokens: list[Token]) -> None:
        _expect(tokens, (":",))

    def _nodes(self, tokens: list[Token]) -> None:
        if len(tokens) < 2 or tokens[1].text != ":":
            raise Unreadable("BU_ syntax")
        self.nodes = [_word(token) for token in tokens[2:]]  # the last BU_ counts

    def _value_table(self, tokens: list[Token]) -> None:
        _expect(tokens[:2], (WORD,))
        self.value_tables[_word(tokens[1])] = _pairs(tokens, 2)

    def _default(self, tokens: list[Token]) -> None:
        name, value = _name_and_value(tokens)
        self.defaults[name] = value

    def _relation_default(self, tokens: list[Token]) -> None:
        name, value = _name_and_value(tokens)
        self.relation_defaults[name] = value

    def _signal_type(self, tokens: list[Token]) -> None:
        _expect(tokens, (NUMBER, WORD, ":", NUMBER, ";"))
        self.signal_types.setdefault(int(tokens[1].text), {})[_word(tokens[2])] = int(tokens[4].text)

    def _add_senders(self, tokens: list[Token]) -> None:
        _expect(tokens[:3], (NUMBER, ":"))
        self.senders.setdefault(int(tokens[1].text), []).extend(_delimited(tokens, 3, len(tokens) - 1, WORD))
        _expect(tokens[-1:], (";",), first=0)

    def _signal_group(self, tokens: list[Token]) -> None:
        _expect(tokens[:5], (NUMBER, WORD, NUMBER, ":"))
        _expect(tokens[-1:], (";",), first=0)
        for token in tokens[5:-1]:
            _word(token)
        _converts(int, tokens[3].text)  # the repetitions

    def _environment_variable(self, tokens: list[Token]) -> None:
        _expect(tokens[:13], (WORD, ":", NUMBER, "[", NUMBER, "|", NUMBER, "]", STRING, NUMBER, NUMBER, WORD))
        _delimited(tokens, 13, len(tokens) - 1, WORD)
        _expect(tokens[-1:], (";",), first=0)
        _converts(int, tokens[3].text, tokens[11].text)  # type and id
        _converts(_number, tokens[5].text, tokens[7].text, tokens[10].text)  # minimum, maximum, initial value

    def _environment_data(self, tokens: list[Token]) -> None:
        _expect(tokens, (WORD, ":", NUMBER, ";"))
        _converts(int, tokens[3].text)  # the data size

    def _extended_multiplexing(self, tokens: list[Token]) -> None:
        """``SG_MUL_VAL_ id signal multiplexer 1-3, 5-5;``: ``1`` and ``-3`` are numbers to cantools."""
        _expect(tokens[:4], (NUMBER, WORD, WORD))
        _expect(tokens[-1:], (";",), first=0)
        ranges = tokens[4:-1]
        if len(ranges) % 3 != 2 or any(t.kind != NUMBER for t in ranges[0::3] + ranges[1::3]) or any(
                t.text != "," or t.kind != OTHER for t in ranges[2::3]):
            raise Unreadable("SG_MUL_VAL_ syntax")
        ids: list[int] = []
        for lower, upper in zip(ranges[0::3], ranges[1::3]):
            first, last = int(lower.text), int(upper.text[1:])
            if last - first > _RANGE_MAX:
                raise Unreadable("a huge SG_MUL_VAL_ range")
            ids.extend(range(first, last + 1))
        by_multiplexer = self.multiplexing.setdefault(int(tokens[1].text), {})
        by_multiplexer.setdefault(_word(tokens[3]), {})[_word(tokens[2])] = ids

    # -- what the statements say -----------------------------------------------------------------

    def _content(self) -> DbcContent:
        self.definitions = self._definitions(self.later["BA_DEF_"], self.defaults, relation=False)
        relation_definitions = self._definitions(self.later["BA_DEF_REL_"], self.relation_defaults, relation=True)
        self.attributes = self._attributes()
        self._relation_attributes(relation_definitions)
        self.sorted_tables = {self.original(name): tuple(sorted(table.items()))
                              for name, table in self.value_tables.items()}
        messages, frame_formats = [], {}
        for message in self.messages:
            attributes = self.attributes["BO_"].get(message.frame_id, {})
            frame_format = _frame_format(attributes, self.definitions.get(FRAME_FORMAT_ATTRIBUTE))
            _check_send_type(attributes, self.definitions.get(_SEND_TYPE))
            built = self._built(message, attributes)
            if frame_format is not None:
                frame_formats.setdefault(built.name, frame_format)
            messages.append(built)
        unused = [f"VAL_ {frame_id} {signal}" for frame_id, table in self.choices.items() for signal in table]
        unused += [f"SIG_VALTYPE_ {frame_id} {signal}" for frame_id, types in self.signal_types.items()
                   for signal in types]
        if unused:
            raise Unreadable(f"unused {', '.join(unused)}")
        return DbcContent(tuple(self.original(self._node(node)) for node in self.nodes), tuple(messages),
                          frozenset(self.definitions), frame_formats)

    def _definitions(self, statements: list[list[Token]], defaults: dict[str, str], *, relation: bool,
                     ) -> dict[str, _Definition]:
        kinds = ("BU_SG_REL_", "BU_BO_REL_", "BU_EV_REL_") if relation else _OBJECTS
        definitions = {}
        for tokens in statements:
            at = 2 if len(tokens) > 1 and tokens[1].kind == WORD and tokens[1].text in kinds else 1
            _expect(tokens[at - 1:at + 2], (STRING, WORD), first=1)
            name, definition = _string(tokens[at]), _Definition(_word(tokens[at + 1]))
            values_at = at + 2
            _expect(tokens[-1:], (";",), first=0)
            if values_at < len(tokens) - 1 and tokens[values_at].kind == STRING:
                values = _delimited(tokens, values_at, len(tokens) - 1, STRING)
            else:
                values = [token.text for token in tokens[values_at:-1]]
                if any(token.kind != NUMBER for token in tokens[values_at:-1]):
                    raise Unreadable("BA_DEF_ values")
            if values:
                if definition.type == "ENUM":
                    definition.choices = values
                elif definition.type in ("INT", "FLOAT", "HEX"):
                    _converts(lambda value: _converted(definition, value), values[0], values[1])  # limits
            if name in defaults:
                definition.default = _converted(definition, defaults[name])
            definitions[name] = definition
        return definitions

    def _attributes(self) -> dict[str | None, dict]:
        """The ``BA_`` values, converted as cantools converts them, by object kind (``None``: the file's).

        ``BO_``: frame id → name → value; ``SG_``: (frame id, signal) → ...; ``BU_``: node → ...
        """
        attributes: dict[str | None, dict] = {"BO_": {}, "SG_": {}, "BU_": {}, "EV_": {}, None: {}}
        for tokens in self.later["BA_"]:
            _expect(tokens[:2], (STRING,))
            _expect(tokens[-1:], (";",), first=0)
            name, kind = _string(tokens[1]), tokens[2].text if tokens[2].kind == WORD else None
            shape = {"BO_": (NUMBER,), "SG_": (NUMBER, WORD), "BU_": (WORD,), "EV_": (WORD,), None: ()}[kind]
            value_at = 2 + (len(shape) + 1 if kind else 0)
            if len(tokens) != value_at + 2 or tokens[value_at].kind not in (NUMBER, STRING):
                raise Unreadable("BA_ syntax")
            if kind:
                _expect(tokens[2:value_at], (kind, *shape), first=0)
            value = _attribute_value(self.definitions[name], _value(tokens[value_at]))
            if kind == "BO_":
                key = int(tokens[3].text)
            elif kind == "SG_":
                key = (int(tokens[3].text), _word(tokens[4]))
            else:
                key = tokens[3].text if kind else None
            attributes[kind].setdefault(key, {})[name] = value
        database = attributes[None].get(None, {})
        if "DBName" in database and not isinstance(database["DBName"], str):
            raise Unreadable("DBName is no text")
        if "Baudrate" in database:
            _converts(lambda value: int(float(value)), database["Baudrate"])
        return attributes

    def _relation_attributes(self, definitions: dict[str, _Definition]) -> None:
        for tokens in self.later["BA_REL_"]:
            if len(tokens) > 2 and tokens[2].text == "BU_SG_REL_":
                _expect(tokens, (STRING, "BU_SG_REL_", WORD, "SG_", NUMBER, WORD, None, ";"))
                frame_id = tokens[5]
            else:
                _expect(tokens, (STRING, "BU_BO_REL_", WORD, NUMBER, None, ";"))
                frame_id = tokens[4]
            _attribute_value(definitions[_string(tokens[1])], _value(tokens[-2]))
            _converts(int, frame_id.text)

    def _node(self, name: str) -> str:
        """A node's name: its ``SystemNodeLongSymbol`` when it has one (cantools' long names)."""
        long_name = self.attributes["BU_"].get(name, {}).get(_LONG_NODE)
        return str(long_name) if long_name is not None else name

    def _built(self, message: _Message, attributes: dict[str, object]) -> Message:
        frame_id, extended = message.frame_id & 0x7FFFFFFF, bool(message.frame_id & 0x80000000)
        if frame_id.bit_length() > (29 if extended else 11):
            raise Unreadable("frame id too long")
        senders = [self._node(message.sender)]
        added = (self._node(node) for node in self.senders.get(message.frame_id, ()))
        senders += [node for node in dict.fromkeys(added) if node not in senders]
        if senders == [_NO_NODE]:
            senders = []
        multiplexers = [s.name for s in message.signals if s.mux is not None and s.mux.endswith("M")]
        multiplexing = _Multiplexing(multiplexers[0] if len(multiplexers) == 1 else None,
                                     self.multiplexing.get(message.frame_id, {}))
        period, timeout, timeout_is_default = period_and_timeout(
            _attribute(attributes, self.definitions, PERIOD_ATTRIBUTE),
            _attribute(attributes, self.definitions, TIMEOUT_ATTRIBUTE))
        return Message(
            name=self.original(str(attributes.get(_LONG_MESSAGE, message.name))), frame_id=frame_id, network=None,
            dlc=message.dlc, period_ms=period, timeout_ms=timeout, timeout_is_default=timeout_is_default,
            extended=extended, role=None,
            signals=tuple(self._built_signal(signal, message.frame_id, multiplexing) for signal in message.signals),
            senders=tuple(self.original(sender) for sender in senders),
            comment=self.message_comments.get(message.frame_id) or "", line=message.line)

    def _built_signal(self, signal: _Signal, frame_id: int, multiplexing: _Multiplexing) -> SignalOfMsg:
        start, length, order, sign, factor, offset, minimum, maximum = signal.layout.groups()
        attributes = self.attributes["SG_"].get((frame_id, signal.name), {})
        if int(length) <= 0:
            raise Unreadable("a signal of no bits")
        if not isinstance(attributes.get("GenSigStartValue", 0), (int, float)):
            raise Unreadable("GenSigStartValue is no number")
        if "SPN" in attributes and not isinstance(attributes["SPN"], int):
            raise Unreadable("SPN is no integer")
        # the first signal of that name in a message with that id claims its VAL_ and SIG_VALTYPE_
        choices = self.choices.get(frame_id, {}).pop(signal.name, None)
        is_float = self.signal_types.get(frame_id, {}).pop(signal.name, None) in _FLOAT_SIGNAL_TYPES
        scale, offset = _conversion(_number(factor), _number(offset), choices is not None, is_float)
        receivers = signal.receivers if signal.receivers != [_NO_NODE] else []
        sorted_choices = tuple(sorted(choices.items())) if choices else ()
        return SignalOfMsg(
            name=self.original(str(attributes.get(_LONG_SIGNAL, signal.name))), bit_start=int(start),
            length=int(length), byte_order="Motorola" if order == "0" else "Intel", is_signed=sign == "-",
            is_float=is_float, factor=scale, offset=offset,
            minimum=None if minimum == maximum == "0" else _number(minimum),
            maximum=None if minimum == maximum == "0" else _number(maximum),
            unit=signal.unit, comment=self.signal_comments.get((frame_id, signal.name)) or "",
            receivers=tuple(self.original(self._node(receiver)) for receiver in receivers),
            multiplexer_ids=multiplexing.ids(signal), choices=sorted_choices,
            value_table=value_table_of(sorted_choices, self.sorted_tables))


@dataclass
class _Multiplexing:
    """The multiplexers of one message: its one ``M`` signal, and what ``SG_MUL_VAL_`` says."""

    multiplexer: str | None
    """The message's multiplexer signal (``None`` when it has none, or more than one)."""
    values: dict[str, dict[str, list[int]]]
    """``SG_MUL_VAL_``: multiplexer → signal → the multiplexer values that select it."""

    def ids(self, signal: _Signal) -> tuple[int, ...] | None:
        """The multiplexer values that select ``signal`` (``m3``: 3, and its ``SG_MUL_VAL_`` ranges), as cantools."""
        ids = []
        multiplexer = self.multiplexer
        if multiplexer is not None:
            if signal.mux is not None and not signal.mux.endswith("M"):
                if not signal.mux.startswith("m"):
                    raise Unreadable(f"multiplexer marker {signal.mux}")
                ids.append(int(signal.mux[1:]))
        else:
            multiplexer = next((name for name, signals in reversed(self.values.items()) if signal.name in signals),
                               None)
        if multiplexer is None:
            return None
        ids += self.values.get(multiplexer, {}).get(signal.name, ())
        return tuple(set(ids)) if ids else None  # cantools' order: list(set(ids))


_OTHER_STATEMENTS: dict[str, Callable[[_Reader, list[Token]], None]] = {
    "VERSION": _Reader._version, "NS_": _Reader._namespace, "BS_": _Reader._bit_timing, "BU_": _Reader._nodes,
    "VAL_TABLE_": _Reader._value_table, "BA_DEF_DEF_": _Reader._default, "BA_DEF_DEF_REL_": _Reader._relation_default,
    "SIG_VALTYPE_": _Reader._signal_type, "BO_TX_BU_": _Reader._add_senders,
    "SIG_GROUP_": _Reader._signal_group, "EV_": _Reader._environment_variable,
    "ENVVAR_DATA_": _Reader._environment_data, "SG_MUL_VAL_": _Reader._extended_multiplexing,
}


# -- tokens as cantools' grammar sees them ---------------------------------------------------------

def _expect(tokens: list[Token], shape: tuple, first: int = 1) -> None:
    """``tokens[first:]`` are exactly ``shape``: a token kind, a keyword or punctuation, or ``None`` (a value).

    :raises Unreadable: they are not.
    """
    if len(tokens) - first != len(shape):
        raise Unreadable("statement syntax")
    for token, expected in zip(tokens[first:], shape):
        if expected is None:
            ok = token.kind in (NUMBER, STRING)
        elif expected in (NUMBER, STRING, WORD):
            ok = token.kind == expected
            if ok and expected == WORD:
                _word(token)
            elif ok and expected == NUMBER:
                ok = not token.text.lstrip("+-").startswith(".")
        else:
            ok = token.text == expected and token.kind != STRING
        if not ok:
            raise Unreadable("statement syntax")


def _word(token: Token) -> str:
    """A name as cantools' tokenizer cuts it: ASCII letters, digits and ``_``, not a keyword, not led by a digit."""
    text = token.text
    if token.kind != WORD or not (text.isascii() and text.isidentifier()) or text in KEYWORDS:
        raise Unreadable(f"name {text}")
    return text


def _string(token: Token) -> str:
    if token.kind != STRING:
        raise Unreadable("string expected")
    return token.text[1:-1].replace('\\"', '"')


def _value(token: Token) -> str:
    """An attribute value as cantools keeps it: the number's text, or the string's content."""
    return _string(token) if token.kind == STRING else token.text


def _delimited(tokens: list[Token], start: int, end: int, kind: str) -> list[str]:
    """``tokens[start:end]``: one or more of ``kind`` separated by commas (cantools' DelimitedList)."""
    items = tokens[start:end:2]
    if not items or len(tokens[start:end]) % 2 == 0 or any(t.text != "," or t.kind != OTHER
                                                            for t in tokens[start + 1:end:2]):
        raise Unreadable("list syntax")
    return [_word(t) if kind == WORD else _string(t) for t in items]


def _pairs(tokens: list[Token], start: int) -> dict[int, str]:
    """``number "text"`` pairs from ``start`` up to the closing ``;`` (``VAL_``, ``VAL_TABLE_``)."""
    _expect(tokens[-1:], (";",), first=0)
    pairs = tokens[start:-1]
    if len(pairs) % 2 or any(t.kind != NUMBER for t in pairs[::2]):
        raise Unreadable("value description syntax")
    return {int(number.text): _string(text) for number, text in zip(pairs[::2], pairs[1::2])}


def _name_and_value(tokens: list[Token]) -> tuple[str, str]:
    _expect(tokens, (STRING, None, ";"))
    return _string(tokens[1]), _value(tokens[2])


def _converts(function: Callable[[str], object], *texts: str) -> None:
    """Convert as cantools does where the value is not kept: a text it cannot convert raises here too."""
    for text in texts:
        function(text)


def _index_exists(sequence: list | tuple | None, index: int) -> None:
    """:raises Unreadable: ``sequence[index]`` fails in cantools (no sequence, or no such index)."""
    if sequence is None or not -len(sequence) <= index < len(sequence):
        raise Unreadable(f"no choice {index}")


def _number(text: str) -> int | float:
    """cantools' ``num``: an int when the text is one, else a float."""
    try:
        return int(text)
    except ValueError:
        return float(text)


def _converted(definition: _Definition, value: str):
    """A definition's limit or default as cantools converts it."""
    if definition.type in _INTEGER_TYPES:
        return int(Decimal(value))
    if definition.type == "FLOAT":
        return float(Decimal(value))
    return value


def _attribute_value(definition: _Definition, value: str):
    """A ``BA_`` value as cantools converts it."""
    if definition.type in (*_INTEGER_TYPES, "ENUM"):
        return int(Decimal(value))
    if definition.type == "FLOAT":
        return float(Decimal(value))
    return value


def _attribute(attributes: dict[str, object], definitions: dict[str, _Definition], name: str):
    """A message attribute's value, or its definition's default (``None`` without either)."""
    if name in attributes:
        return attributes[name]
    definition = definitions.get(name)
    return definition.default if definition is not None else None


def _frame_format(attributes: dict[str, object], definition: _Definition | None) -> str | None:
    """The ``VFrameFormat`` set on a message (as :mod:`workbench.can.dbc_database` names it), with cantools' checks."""
    if definition is None:
        return None
    choices = definition.choices
    if definition.type == "INT":
        if definition.default is None:
            raise Unreadable("VFrameFormat INT without default")
        _index_exists(FRAME_FORMATS, int(definition.default))  # cantools maps the default onto them
        choices = list(FRAME_FORMATS)
    if FRAME_FORMAT_ATTRIBUTE not in attributes:
        return None
    value = attributes[FRAME_FORMAT_ATTRIBUTE]
    if not isinstance(value, int):
        raise Unreadable("VFrameFormat is no integer")
    _index_exists(choices, value)  # cantools takes the frame format's name
    named = definition.choices
    return named[value] if named and 0 <= value < len(named) else str(value)


def _check_send_type(attributes: dict[str, object], definition: _Definition | None) -> None:
    """cantools reads a message's send type as a name: the checks it makes on the way."""
    if definition is None:
        return
    value = attributes.get(_SEND_TYPE)
    if value is not None and definition.choices:
        _index_exists(definition.choices, int(value))
    elif value is not None and not isinstance(value, str):
        raise Unreadable("GenMsgSendType is no name")
    if value is None and definition.default is not None and not isinstance(definition.default, str):
        raise Unreadable("GenMsgSendType default is no name")


def _conversion(scale: int | float, offset: int | float, has_choices: bool, is_float: bool,
                ) -> tuple[int | float, int | float]:
    """Factor and offset as cantools' conversion keeps them (1 and 0 as ints, integral factors as ints)."""
    if has_choices:
        return scale, offset
    if scale == 1 and offset == 0:
        return 1, 0
    if _is_integer(scale) and _is_integer(offset) and not is_float:
        return int(scale), int(offset)
    return scale, offset


def _is_integer(value: int | float) -> bool:
    return isinstance(value, int) or value.is_integer()
