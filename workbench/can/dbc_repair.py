"""What CANdb++ reads and cantools refuses, repaired in the text before cantools parses it.

Each problem is repaired where it stands and reported once, as a warning located at its
``file:line`` (a :class:`~workbench.findings.Finding` of the kind in brackets):

* a ``BO_`` id above 0x7FF without the extended flag is read as the extended id it spells,
  as CANdb++ does; its references (``CM_``, ``BA_``, ``VAL_`` ...) follow (``id-format``);
* a message whose id is no CAN id (more than 29 bits, or beyond 32) is skipped with its
  references (``id-range``); CANdb++'s placeholder ``VECTOR__INDEPENDENT_SIG_MSG`` (signals
  that belong to no message) is skipped whatever its id, without a warning;
* names that start with a digit (``2017_5``, ``64_BIT_LE``) are kept as written (``name-syntax``);
* a number written without its leading zero (``.25``) is read as written (``number-syntax``);
* a ``CM_`` without text is an empty comment; one without an object (``CM_ 145 "..."``), a
  ``CM_ SG_`` without a signal name or a ``CM_`` of anything else is ignored (``comment-syntax``);
* a ``VAL_``, ``SIG_VALTYPE_``, ``SG_MUL_VAL_``, ``CM_``, ``BA_`` or ``BO_TX_BU_`` that names a
  message or signal the file does not define is ignored (``unknown-reference``);
* a ``VAL_`` value without its text gets an empty one (``value-description``);
* a statement without its closing ``;`` is closed (``missing-semicolon``);
* a ``BA_`` of an attribute that no ``BA_DEF_`` defines is read with a definition made from its
  values, ``VFrameFormat`` with CANdb++'s (``attribute-definition``); an attribute type DBC does
  not have (canmatrix's ``BOOL``) is read as ``STRING`` (``attribute-type``); an ``ENUM`` value
  out of its range, or one of the wrong type, and a default of a numeric attribute that is no
  number are ignored, an ``ENUM`` value given by name is read as its index (``attribute-value``);
* signal receivers separated by spaces instead of commas (``receivers``), a signal of 0 bits
  (``signal-length``) or outside any message (``orphan-signal``), the obsolete bit timing in
  ``BS_:`` (``bit-timing``) and statements cantools cannot read (``SGTYPE_``, ``CAT_DEF_``,
  ``BA_DEF_REL_ BU_EV_REL_`` ...: ``unsupported-statement``).

Every value cantools then reads is the one the file gives. Lines are kept: an ignored
statement leaves its newlines behind and inserted text has none, so cantools' own syntax
errors still point into the user's file.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Iterable
from dataclasses import dataclass, field

from workbench.can.dbc_repair_attributes import AttributeRepairs
from workbench.can.dbc_text import LAYOUT, LAYOUT_PATTERN, NUMBER, STRING, WORD, DbcText, Statement, Token
from workbench.findings import Finding, Severity

__all__ = ["EXTENDED_ID_FLAG", "PLACEHOLDER_MESSAGE", "Repaired", "repair"]

EXTENDED_ID_FLAG = 0x80000000  # bit 31 of a BO_ id: the message has a 29-bit (extended) id
PLACEHOLDER_MESSAGE = "VECTOR__INDEPENDENT_SIG_MSG"
_STANDARD_ID_MAX = 0x7FF
_EXTENDED_ID_MAX = 0x1FFFFFFF
_ID_BITS_MAX = 0xFFFFFFFF
_TERMINATED = frozenset({"CM_", "BA_DEF_", "BA_DEF_DEF_", "BA_", "BA_REL_", "BA_DEF_REL_", "BA_DEF_DEF_REL_", "VAL_",
                         "VAL_TABLE_", "SIG_VALTYPE_", "SG_MUL_VAL_", "BO_TX_BU_", "SIG_GROUP_", "EV_", "ENVVAR_DATA_"})
_READ_BY_CANTOOLS = _TERMINATED | {"VERSION", "NS_", "BS_", "BU_", "BO_", "SG_"}
_COMMENT_OBJECT_TOKENS = {"SG_": 2, "BO_": 1, "BU_": 1, "EV_": 1}
# Statements that name a message by id (token index) and signals (token indexes).
_REFERENCES = {"SIG_VALTYPE_": (1, (2,)), "SG_MUL_VAL_": (1, (2, 3)), "BO_TX_BU_": (1, ()),
               "SIG_GROUP_": (1, ())}
_NAME_PREFIX = "wb_digit_"
_POINTED_NUMBER = re.compile(r"(?<![\w.])[-+]?\.\d+(?:[eE][+-]?\d+)?")  # .25, -.5
_UNREADABLE = -1  # a BO_ cantools will refuse: no warnings about its signals


@dataclass(frozen=True)
class Repaired:
    """The text for cantools and what was repaired in it."""

    text: str
    warnings: tuple[Finding, ...]
    name_prefix: str
    """Prefix put before each name that starts with a digit; :meth:`original_name` takes it off."""
    message_lines: dict[str, tuple[int, ...]]
    """Message name → 1-based lines of the ``BO_`` s cantools reads (more than one when the name is doubled)."""
    signal_lines: dict[tuple[int, str], int]
    """(line of the message's ``BO_``, signal name) → 1-based line of the signal's ``SG_``."""

    def original_name(self, name: str) -> str:
        """A name as the file writes it."""
        return name[len(self.name_prefix):] if name.startswith(self.name_prefix) else name


@dataclass
class _Message:
    name: str
    signals: set[str] = field(default_factory=set)


def repair(dbc: DbcText, path: str) -> Repaired:
    """The DBC text of the file ``path`` with every problem above repaired, and a warning for each.

    The statements it ignores are marked :attr:`~workbench.can.dbc_text.Statement.dropped`: repair a text once.
    """
    return _Repairer(dbc, path).run()


class _Repairer:
    def __init__(self, dbc: DbcText, path: str) -> None:
        self.dbc = dbc
        self.path = path
        self.warnings: list[Finding] = []
        self.edits: list[tuple[int, int, int, str]] = []  # start, order, end, replacement
        self.replaced: set[int] = set()  # starts of tokens an edit replaces
        self.messages: dict[int, _Message] = {}  # by the id cantools will read
        self.converted: dict[int, int] = {}  # standard id above 0x7FF -> extended id
        self.gone_ids: set[int] = set()  # skipped messages: their references go without a warning
        self.gone_signals: set[tuple[int, str]] = set()
        self.dropped_relations: set[str] = set()
        self.message_lines: dict[str, tuple[int, ...]] = {}
        self.signal_lines: dict[tuple[int, str], int] = {}
        self.prefix = _NAME_PREFIX
        while self.prefix in dbc.text:
            self.prefix = "x" + self.prefix

    def run(self) -> Repaired:
        statements = self.dbc.statements
        self._read_messages(statements)
        self.attributes = AttributeRepairs(self, statements)
        for statement in statements:
            if not statement.dropped:
                self._repair(statement)
        for statement in statements:
            if not statement.dropped:
                self._rename_digit_names(statement)
                self._close(statement)
        appended = self.attributes.appended()
        return Repaired(self._edited_text() + appended, tuple(self.warnings), self.prefix, self.message_lines,
                        self.signal_lines)

    # -- bookkeeping -------------------------------------------------------------------------

    def warn(self, kind: str, statement: Statement, name: str, message: str, at: Token | None = None) -> None:
        """A warning about ``name``, located at the token ``at`` (line and column), else at the statement's keyword."""
        line, column = statement.line, 0
        if at is not None:
            line, column = self.dbc.line_of(at.start), at.start - self.dbc.text.rfind("\n", 0, at.start)
        self.warnings.append(Finding(kind, name, message, self.path, line, column, statement.keyword,
                                     Severity.WARNING))

    def _edit(self, start: int, end: int, replacement: str) -> None:
        self.edits.append((start, len(self.edits), end, replacement))

    def replace(self, token: Token, replacement: str) -> None:
        self.replaced.add(token.start)
        self._edit(token.start, token.end, replacement)

    def erase(self, tokens: list[Token]) -> None:
        """Remove consecutive tokens (and the space between them) from what cantools sees."""
        if tokens:
            self.replaced.update(t.start for t in tokens)
            self._edit(tokens[0].start, tokens[-1].end, "")

    def _insert_after(self, token: Token, text: str) -> None:
        self._edit(token.end, token.end, text)

    def drop(self, statement: Statement) -> None:
        """Ignore a statement: cantools sees only its newlines."""
        statement.dropped = True
        self._edit(statement.start, statement.end, "\n" * self.dbc.text.count("\n", statement.start, statement.end))

    def _edited_text(self) -> str:
        if not self.edits:
            return self.dbc.text
        text, parts, position = self.dbc.text, [], 0
        for start, _order, end, replacement in sorted(self.edits):
            if start < position:  # inside a dropped statement
                continue
            parts += [text[position:start], replacement]
            position = end
        parts.append(text[position:])
        return "".join(parts)

    # -- messages and signals ----------------------------------------------------------------

    def _read_messages(self, statements: list[Statement]) -> None:
        current: int | None = None  # id of the message whose SG_ lines may follow
        message_line = 0  # the line of its BO_
        for statement in statements:
            if statement.keyword == "BO_":
                current = self._read_message(statement)
                if not statement.dropped and statement.token(2) is not None:
                    name = statement.tokens[2].text
                    self.message_lines[name] = self.message_lines.get(name, ()) + (statement.line,)
                    message_line = statement.line
            elif statement.keyword == "SG_":
                self._read_signal(statement, current)
                if not statement.dropped and current not in (None, _UNREADABLE):
                    self.signal_lines.setdefault((message_line, statement.tokens[1].text), statement.line)
            else:
                current = None

    def _read_message(self, statement: Statement) -> int:
        id_token, name_token = statement.token(1), statement.token(2)
        frame_id = _integer(id_token)
        if frame_id is None or name_token is None:
            return _UNREADABLE  # cantools reports the syntax error
        name = name_token.text
        extended = frame_id & EXTENDED_ID_FLAG
        bits = frame_id & ~EXTENDED_ID_FLAG
        if name == PLACEHOLDER_MESSAGE:
            return self._skip_message(statement, frame_id)
        if not 0 <= frame_id <= _ID_BITS_MAX or bits > _EXTENDED_ID_MAX:
            spelled = f" (0x{bits:X}{', extended' if extended else ''})" if frame_id >= 0 else ""
            self.warn("id-range", statement, name,
                      f"message {name}: id {frame_id}{spelled} is no CAN id (those have 11 or 29 bits): message "
                      "skipped with its signals and references")
            return self._skip_message(statement, frame_id)
        if len(statement.tokens) == 5 and statement.tokens[3].text == ":":
            self._insert_after(statement.tokens[4], " Vector__XXX")
            self.warn("statement-syntax", statement, name,
                      f"message {name}: no sender after the DLC: read as none (Vector__XXX, as CANdb++ writes it)")
        if not extended and bits > _STANDARD_ID_MAX:
            self.converted[frame_id] = frame_id | EXTENDED_ID_FLAG
            self.replace(id_token, str(frame_id | EXTENDED_ID_FLAG))
            self.warn("id-format", statement, name,
                      f"message {name}: id 0x{bits:X} does not fit in 11 bits but the BO_ id lacks the extended "
                      f"flag: read as extended id 0x{bits:X}, as CANdb++ does (write {frame_id | EXTENDED_ID_FLAG})")
            frame_id |= EXTENDED_ID_FLAG
        self.messages.setdefault(frame_id, _Message(name))
        return frame_id

    def _skip_message(self, statement: Statement, frame_id: int) -> int:
        self.gone_ids.add(frame_id)
        self.drop(statement)
        return frame_id

    def _read_signal(self, statement: Statement, frame_id: int | None) -> None:
        name_token = statement.token(1)
        name = name_token.text if name_token is not None else "?"
        if frame_id is None:
            self.warn("orphan-signal", statement, name, f"signal {name} follows no BO_: ignored")
            self.drop(statement)
            return
        if frame_id == _UNREADABLE:
            return
        if frame_id in self.gone_ids:
            self.drop(statement)
            return
        message = self.messages[frame_id]
        layout = next((i for i, token in enumerate(statement.tokens) if token.kind == LAYOUT), None)
        if layout is None:
            return  # cantools reports the syntax error
        if int(LAYOUT_PATTERN.match(statement.tokens[layout].text).group(2)) == 0:
            self.warn("signal-length", statement, f"{message.name}.{name}",
                      f"{message.name}.{name}: a signal of 0 bits carries nothing: ignored with its references")
            self.gone_signals.add((frame_id, name))
            self.drop(statement)
            return
        message.signals.add(name)
        self._join_receivers(statement, layout, f"{message.name}.{name}")

    def _join_receivers(self, statement: Statement, layout: int, name: str) -> None:
        unit = statement.token(layout + 1)
        if unit is None or unit.kind != STRING:
            return
        receivers = statement.tokens[layout + 2:]
        gaps = [first for first, second in itertools.pairwise(receivers) if first.kind == second.kind == WORD]
        if gaps:
            for token in gaps:
                self._insert_after(token, ",")
            self.warn("receivers", statement, name,
                      f"{name}: receivers separated by spaces instead of commas: read as "
                      f"{', '.join(t.text for t in receivers if t.kind == WORD)}")

    # -- statements --------------------------------------------------------------------------

    def _repair(self, statement: Statement) -> None:
        keyword = statement.keyword
        if keyword not in _READ_BY_CANTOOLS:
            self.warn("unsupported-statement", statement, keyword,
                      f"{keyword} statements are not read (cantools has no support for them): ignored")
            self.drop(statement)
        elif keyword == "CM_":
            self._repair_comment(statement)
        elif keyword == "BA_":
            self.attributes.repair_value(statement)
        elif keyword == "BA_DEF_REL_" and self._token_text(statement, 1) == "BU_EV_REL_":
            self.dropped_relations.add(self._token_text(statement, 2))
            self.warn("unsupported-statement", statement, self._token_text(statement, 2),
                      "BA_DEF_REL_ BU_EV_REL_ (node-environment variable relation attributes) is not read "
                      "(cantools has no support for it): ignored with its BA_REL_ values")
            self.drop(statement)
        elif keyword == "BA_REL_" and self._token_text(statement, 1) in self.dropped_relations:
            self.drop(statement)
        elif keyword == "BA_REL_":
            self.attributes.repair_relation_value(statement)
        elif keyword == "BS_":
            self._repair_bit_timing(statement)
        elif keyword in _REFERENCES:
            if self.reference_kept(statement, *_REFERENCES[keyword]) and keyword == "SIG_VALTYPE_":
                self._repair_value_type_colon(statement)
        elif keyword == "VAL_" and self._kind_at(statement, 1) == NUMBER:  # of a signal
            if self.reference_kept(statement, 1, (2,)):
                self._repair_value_descriptions(statement, 3)
        elif keyword in ("VAL_", "VAL_TABLE_"):  # of an environment variable, a value table
            self._repair_value_descriptions(statement, 2)
        if not statement.dropped:
            self._repair_numbers(statement)

    @staticmethod
    def _token_text(statement: Statement, index: int) -> str:
        token = statement.token(index)
        return token.value if token is not None else ""

    def reference_kept(self, statement: Statement, id_index: int, signal_indexes: Iterable[int]) -> bool:
        """Whether the message (and signals) a statement names exist; ignores the statement if not."""
        id_token = statement.token(id_index)
        written = _integer(id_token)
        if written is None:
            return True  # cantools reports the syntax error
        frame_id = self.converted.get(written, written)
        signals = [t for t in (statement.token(i) for i in signal_indexes) if t is not None and t.kind == WORD]
        if frame_id in self.gone_ids or any((frame_id, s.text) in self.gone_signals for s in signals):
            self.drop(statement)
            return False
        message = self.messages.get(frame_id)
        what = " ".join(t.text for t in statement.tokens[:id_index + 1 + len(signals)])
        if message is None:
            self.warn("unknown-reference", statement, id_token.text,
                      f"{what}: no BO_ has id {frame_id & ~EXTENDED_ID_FLAG:#x}"
                      f"{' (extended)' if frame_id & EXTENDED_ID_FLAG else ''}: ignored")
            self.drop(statement)
            return False
        missing = [s.text for s in signals if s.text not in message.signals]
        if missing:
            self.warn("unknown-reference", statement, f"{message.name}.{missing[0]}",
                      f"{what}: message {message.name} has no signal {missing[0]}: ignored")
            self.drop(statement)
            return False
        if id_token.text != str(frame_id):
            self.replace(id_token, str(frame_id))
        return True

    def _repair_value_type_colon(self, statement: Statement) -> None:
        if self._kind_at(statement, 3) == NUMBER:
            self._insert_after(statement.tokens[2], " :")
            self.warn("statement-syntax", statement, self._token_text(statement, 2),
                      f"{' '.join(t.text for t in statement.tokens[:4])}: no ':' before the value type: read as "
                      f"type {statement.tokens[3].text}")

    def _repair_comment(self, statement: Statement) -> None:
        kind = statement.token(1)
        if kind is None or kind.kind == STRING:
            return
        preview = " ".join(t.text for t in statement.tokens[:2])
        if kind.text not in _COMMENT_OBJECT_TOKENS:
            self.warn("comment-syntax", statement, kind.text,
                      f"{preview} ...: a comment belongs to BU_, BO_, SG_ or EV_ (or to the file): ignored")
            self.drop(statement)
            return
        count = _COMMENT_OBJECT_TOKENS[kind.text]
        if kind.text == "SG_" and self._kind_at(statement, 3) == STRING:
            self.warn("comment-syntax", statement, self._token_text(statement, 2),
                      f"{preview} ...: a signal comment without the signal's name: ignored")
            self.drop(statement)
            return
        if kind.text in ("SG_", "BO_") and not self.reference_kept(statement, 2, (3,) if kind.text == "SG_" else ()):
            return
        text = statement.token(2 + count)
        if text is None or text.text == ";":
            last = statement.tokens[1 + count] if len(statement.tokens) > 1 + count else statement.tokens[-1]
            self._insert_after(last, ' ""')
            self.warn("comment-syntax", statement, self._token_text(statement, 2),
                      f"{' '.join(t.text for t in statement.tokens[:2 + count])}: comment without text: "
                      f"read as an empty comment")

    @staticmethod
    def _kind_at(statement: Statement, index: int) -> str | None:
        token = statement.token(index)
        return token.kind if token is not None else None

    def _repair_value_descriptions(self, statement: Statement, first: int) -> None:
        bare = []
        index = first
        while index < len(statement.tokens) and statement.tokens[index].kind == NUMBER:
            following = statement.token(index + 1)
            if following is not None and following.kind == STRING:
                index += 2
                continue
            bare.append(statement.tokens[index])
            self._insert_after(statement.tokens[index], ' ""')
            index += 1
        if bare:
            self.warn("value-description", statement, self._token_text(statement, first - 1),
                      f"{' '.join(t.text for t in statement.tokens[:first])}: value"
                      f"{'s' if len(bare) > 1 else ''} {', '.join(t.text for t in bare)} without text: "
                      f"read with an empty one")

    def _repair_bit_timing(self, statement: Statement) -> None:
        colon = statement.index_of(":")
        if colon is not None and colon + 1 < len(statement.tokens):
            timing = statement.tokens[colon + 1:]
            self._edit(timing[0].start, timing[-1].end, "")
            self.warn("bit-timing", statement, "BS_",
                      f"BS_: {' '.join(t.text for t in timing)}: the obsolete bit timing is not read")

    def _repair_numbers(self, statement: Statement) -> None:
        pointed = []
        for token in statement.tokens:
            if token.kind in (NUMBER, LAYOUT) and _POINTED_NUMBER.search(token.text):
                pointed += _POINTED_NUMBER.findall(token.text)
                self.replace(token, _POINTED_NUMBER.sub(lambda m: m[0].replace(".", "0.", 1), token.text))
        if pointed:
            self.warn("number-syntax", statement, statement.keyword,
                      f"{', '.join(pointed)} written without a leading 0: read as "
                      f"{', '.join(number.replace('.', '0.', 1) for number in pointed)}")

    def _close(self, statement: Statement) -> None:
        if statement.keyword in _TERMINATED and statement.tokens[-1].text != ";":
            self._insert_after(statement.tokens[-1], ";")
            self.warn("missing-semicolon", statement, statement.keyword,
                      f"{' '.join(t.text for t in statement.tokens[:3])} ...: no closing ';': closed at the end of "
                      f"line {self.dbc.line_of(statement.end)}")

    def _rename_digit_names(self, statement: Statement) -> None:
        for position, token in enumerate(statement.tokens):
            if token.kind != WORD or not token.text[0].isdigit() or token.start in self.replaced:
                continue
            self.replace(token, self.prefix + token.text)
            what = _defined_name(statement, position)
            if what:
                self.warn("name-syntax", statement, token.text,
                          f"{what} name {token.text} starts with a digit, which DBC names may not: kept as written")


def _integer(token: Token | None) -> int | None:
    """The integer a number token spells (``None`` for anything else: cantools reports it)."""
    if token is None or token.kind != NUMBER:
        return None
    try:
        return int(token.text)
    except ValueError:
        return None


def _defined_name(statement: Statement, position: int) -> str | None:
    """What the name at ``position`` of ``statement`` defines (``message``, ``signal`` ...), or ``None``."""
    keyword = statement.keyword
    if keyword == "BO_" and position == 2:
        return "message"
    if keyword == "SG_" and position == 1:
        return "signal"
    if keyword == "BU_" and position >= 2:
        return "node"
    if (keyword, position) in (("VAL_TABLE_", 1), ("EV_", 1), ("SIG_GROUP_", 2)):
        return {"VAL_TABLE_": "value table", "EV_": "environment variable", "SIG_GROUP_": "signal group"}[keyword]
    return None
