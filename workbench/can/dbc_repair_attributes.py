"""The attribute part of :mod:`workbench.can.dbc_repair`: ``BA_DEF_``, ``BA_``, ``BA_REL_`` cantools refuses.

* an attribute used without a ``BA_DEF_`` (``BA_DEF_REL_``) gets one, appended to the text,
  typed from its values: INT, FLOAT or STRING (``attribute-definition``);
* a type DBC does not have (canmatrix writes ``BOOL False True``) is read as STRING, its
  values as written (``attribute-type``); so is a ``GenMsgSendType`` of a numeric type,
  which cantools can only read as a name;
* an ``ENUM`` value outside its choices, or a number that is text, is ignored; an ``ENUM``
  value given by name is read as its index; a numeric value written as a string
  (``"100"``) is read as the number cantools makes of it (``attribute-value``);
* the default (``BA_DEF_DEF_``, ``BA_DEF_DEF_REL_``) of an INT, HEX or FLOAT attribute that
  is no number (``"abc"``, ``""``) is ignored: the attribute has no default (``attribute-value``);
  a number written as a string (``"10"``) is read as cantools reads it, without a warning;
* ``VFrameFormat`` as INT (cantools maps it onto CANdb++'s 16 frame formats): a value
  outside 0..15 is ignored, a missing ``BA_DEF_DEF_`` is its minimum, as in CANdb++; as
  STRING (or another type) it is read as the ENUM of those formats, its values by name;
  used without a ``BA_DEF_`` it is defined as CANdb++ defines it, that ENUM with the
  default ``StandardCAN`` (``attribute-definition``).
"""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal
from typing import Protocol

from workbench.can.dbc_text import NUMBER, STRING, WORD, Statement, Token

__all__ = ["FRAME_FORMAT", "FRAME_FORMATS", "AttributeRepairs", "Repairs"]

_TYPES = frozenset({"INT", "HEX", "FLOAT", "STRING", "ENUM"})
_NUMERIC_TYPES = frozenset({"INT", "HEX", "FLOAT"})
_OBJECT_KINDS = frozenset({"BO_", "SG_", "BU_", "EV_"})
_VALUE_INDEX = {"BO_": 4, "SG_": 5, "BU_": 4, "EV_": 4}  # BA_ "name" <object ...> value ;
_RELATION_VALUE_INDEX = {"BU_SG_REL_": 7, "BU_BO_REL_": 5, "BU_EV_REL_": 5}  # BA_REL_ "name" <kind> node ...
FRAME_FORMAT = "VFrameFormat"
# CANdb++'s frame formats, which an INT VFrameFormat indexes (cantools knows the same list)
FRAME_FORMATS = ("StandardCAN", "ExtendedCAN", "reserved", "J1939PG") + ("reserved",) * 10 + (
    "StandardCAN_FD", "ExtendedCAN_FD")
_FRAME_FORMAT_ENUM = "ENUM " + ",".join(f'"{name}"' for name in FRAME_FORMATS)
_FRAME_FORMATS_TEXT = "the ENUM of CANdb++'s frame formats (StandardCAN, ExtendedCAN, J1939PG, ...)"
_SEND_TYPE = "GenMsgSendType"


class Repairs(Protocol):
    """What the attribute repairs ask of :class:`workbench.can.dbc_repair` (edits, warnings, references)."""

    def warn(self, kind: str, statement: Statement, name: str, message: str, at: Token | None = None) -> None: ...

    def replace(self, token: Token, replacement: str) -> None: ...

    def erase(self, tokens: list[Token]) -> None: ...

    def drop(self, statement: Statement) -> None: ...

    def reference_kept(self, statement: Statement, id_index: int, signal_indexes: tuple[int, ...]) -> bool: ...


@dataclass
class _Definition:
    type: str
    choices: tuple[str, ...] = ()
    minimum: str = "0"
    has_default: bool = False
    statement: Statement | None = None
    by_name: bool = False
    """An ENUM the repair made from another type: its values are names, read as indexes without a warning."""


class AttributeRepairs:
    """Reads the definitions of a DBC's attributes, then repairs each ``BA_``/``BA_REL_`` it is given."""

    def __init__(self, repairs: Repairs, statements: list[Statement]) -> None:
        self.repairs = repairs
        self.definitions = self._read_definitions(statements, "BA_DEF_")
        self.relation_definitions = self._read_definitions(statements, "BA_DEF_REL_")
        self.undefined: dict[tuple[str, str], list[tuple[Statement, str, Token]]] = {}
        self.frame_format_appended = False  # VFrameFormat is used without a BA_DEF_: its definition is appended
        self._send_type_as_text()
        self._frame_format_as_enum()
        self._read_defaults(statements)

    def _read_definitions(self, statements: list[Statement], keyword: str) -> dict[str, _Definition]:
        definitions: dict[str, _Definition] = {}
        for statement in statements:
            if statement.keyword != keyword or statement.dropped:
                continue
            name_index = 1 if _kind(statement, 1) == STRING else 2
            name, type_token = _text(statement, name_index), statement.token(name_index + 1)
            if type_token is None:
                continue  # cantools reports the syntax error
            values = [t for t in statement.tokens[name_index + 2:] if t.text not in (";", ",")]
            if type_token.text not in _TYPES:
                self.repairs.replace(type_token, "STRING")
                self.repairs.erase(values)
                self.repairs.warn("attribute-type", statement, name,
                                  f"attribute {name}: type {type_token.text} is not a DBC attribute type: read as "
                                  "STRING (its values as written)")
                definitions[name] = _Definition("STRING", statement=statement)
                continue
            choices = tuple(t.value for t in values if t.kind == STRING)
            minimum = values[0].text if values and values[0].kind == NUMBER else "0"
            definitions[name] = _Definition(type_token.text, choices, minimum, statement=statement)
        return definitions

    def _read_defaults(self, statements: list[Statement]) -> None:
        """Marks the definitions that have a default; a numeric attribute's default that is no number is ignored."""
        definitions_of = {"BA_DEF_DEF_": self.definitions, "BA_DEF_DEF_REL_": self.relation_definitions}
        for statement in statements:
            definitions = definitions_of.get(statement.keyword)
            if definitions is None or statement.dropped:
                continue
            name, value = _text(statement, 1), statement.token(2)
            definition = definitions.get(name)
            if definition is None:
                continue
            if definition.type in _NUMERIC_TYPES and value is not None and (
                    value.kind == WORD or value.kind == STRING and _number(definition.type, value.value) is None):
                self.repairs.warn("attribute-value", statement, name,
                                  f"attribute {name} is {definition.type} but its default {value.text} is no number: "
                                  "ignored (no default)", at=value)
                self.repairs.drop(statement)
                continue
            definition.has_default = True

    def _send_type_as_text(self) -> None:
        definition = self.definitions.get(_SEND_TYPE)
        if definition is None or definition.type not in _NUMERIC_TYPES:
            return
        statement = definition.statement
        name_index = 1 if _kind(statement, 1) == STRING else 2
        self.repairs.replace(statement.tokens[name_index + 1], "STRING")
        self.repairs.erase([t for t in statement.tokens[name_index + 2:] if t.text != ";"])
        self.repairs.warn("attribute-type", statement, _SEND_TYPE,
                          f"attribute {_SEND_TYPE} is {definition.type}: cantools reads a send type only as a name, "
                          "so it is read as STRING (its values as written)")
        definition.type = "STRING"

    def _frame_format_as_enum(self) -> None:
        definition = self.definitions.get(FRAME_FORMAT)
        if definition is None or definition.type in ("INT", "ENUM"):
            return
        statement = definition.statement
        name_index = 1 if _kind(statement, 1) == STRING else 2
        self.repairs.replace(statement.tokens[name_index + 1], _FRAME_FORMAT_ENUM)
        self.repairs.erase([t for t in statement.tokens[name_index + 2:] if t.text != ";"])
        self.repairs.warn("attribute-type", statement, FRAME_FORMAT,
                          f"attribute {FRAME_FORMAT} is {definition.type}: read as {_FRAME_FORMATS_TEXT}, its values "
                          "by name")
        self.definitions[FRAME_FORMAT] = _Definition("ENUM", FRAME_FORMATS, statement=statement, by_name=True)

    def repair_value(self, statement: Statement) -> None:
        """A ``BA_`` statement: its object must exist, its value fit its definition."""
        name = _text(statement, 1)
        kind = _text(statement, 2) if _kind(statement, 2) == WORD else ""
        if kind in ("BO_", "SG_") and not self.repairs.reference_kept(statement, 3, (4,) if kind == "SG_" else ()):
            return
        value = statement.token(_VALUE_INDEX.get(kind, 2))
        if value is not None and value.text != ";":
            self._repair(statement, name, kind if kind in _OBJECT_KINDS else "", value, self.definitions, "BA_DEF_")

    def repair_relation_value(self, statement: Statement) -> None:
        """A ``BA_REL_`` statement (node-message and node-signal relations), as :meth:`repair_value`."""
        name, kind = _text(statement, 1), _text(statement, 2)
        if kind == "BU_SG_REL_" and not self.repairs.reference_kept(statement, 5, (6,)):
            return
        if kind == "BU_BO_REL_" and not self.repairs.reference_kept(statement, 4, ()):
            return
        value = statement.token(_RELATION_VALUE_INDEX.get(kind, 0))
        if value is not None and value.text != ";":
            self._repair(statement, name, kind, value, self.relation_definitions, "BA_DEF_REL_")

    def _repair(self, statement: Statement, name: str, kind: str, value: Token,
                definitions: dict[str, _Definition], definition_keyword: str) -> None:
        definition = definitions.get(name)
        if definition is None and name == FRAME_FORMAT and definition_keyword == "BA_DEF_":
            definition = self._define_frame_format(statement)
        if definition is None:
            self.undefined.setdefault((definition_keyword, name), []).append((statement, kind, value))
            if value.kind == WORD:
                self.repairs.replace(value, f'"{value.text}"')
        elif definition.type == "ENUM":
            self._repair_enum(statement, name, definition.choices, value, quiet=definition.by_name)
        elif definition.type == "STRING":
            if value.kind == WORD:
                self.repairs.replace(value, f'"{value.text}"')
        elif value.kind != NUMBER:
            self._repair_number(statement, name, definition, value)
        elif name == FRAME_FORMAT and definition.type == "INT":
            self._repair_enum(statement, name, FRAME_FORMATS, value)

    def _define_frame_format(self, statement: Statement) -> _Definition:
        """VFrameFormat used without a BA_DEF_ (cantools refuses an INT one without a default): CANdb++'s definition."""
        self.repairs.warn("attribute-definition", statement, FRAME_FORMAT,
                          f"attribute {FRAME_FORMAT} has no BA_DEF_: read as {_FRAME_FORMATS_TEXT} with the default "
                          f"{FRAME_FORMATS[0]}, as CANdb++ defines it, its values by index or name")
        self.frame_format_appended = True
        definition = self.definitions[FRAME_FORMAT] = _Definition("ENUM", FRAME_FORMATS, has_default=True,
                                                                  statement=statement, by_name=True)
        return definition

    def _repair_enum(self, statement: Statement, name: str, choices: tuple[str, ...], value: Token, *,
                     quiet: bool = False) -> None:
        if value.kind == NUMBER:
            index = float(value.text)
            if not choices or (index.is_integer() and 0 <= index < len(choices)):
                return
            problem = f"value {value.text} is none of its {len(choices)} choices (0..{len(choices) - 1})"
        elif value.value in choices:
            self.repairs.replace(value, str(choices.index(value.value)))
            if quiet:
                return
            self.repairs.warn("attribute-value", statement, name,
                              f"attribute {name}: ENUM value given by name {value.text}: read as its index "
                              f"{choices.index(value.value)}")
            return
        else:
            problem = f"value {value.text} is none of its choices ({', '.join(choices)})"
        self.repairs.warn("attribute-value", statement, name, f"attribute {name}: {problem}: ignored")
        self.repairs.drop(statement)

    def _repair_number(self, statement: Statement, name: str, definition: _Definition, value: Token) -> None:
        number = _number(definition.type, value.value)
        if number is None:
            self.repairs.warn("attribute-value", statement, name,
                              f"attribute {name} is {definition.type} but the value is {value.text}: ignored", at=value)
            self.repairs.drop(statement)
            return
        self.repairs.replace(value, repr(number))
        self.repairs.warn("attribute-value", statement, name,
                          f"attribute {name} is {definition.type} but the value is written as text {value.text}: "
                          f"read as {number!r}", at=value)

    def appended(self) -> str:
        """Lines for the end of the text: definitions of the attributes used without one, missing defaults."""
        lines = []
        for (keyword, name), uses in self.undefined.items():
            values = [value for _statement, _kind, value in uses]
            if any(v.kind != NUMBER for v in values):
                attribute_type = "STRING"
            elif any(not v.text.lstrip("+-").isdigit() for v in values):
                attribute_type = "FLOAT"
            else:
                attribute_type = "INT"
            first, kind, _value = uses[0]
            lines.append(f'{keyword} {kind} "{name}" {attribute_type};')
            self.repairs.warn("attribute-definition", first, name,
                              f"attribute {name} has no {keyword}: read as {attribute_type} "
                              f"({len(uses)} value{'s' if len(uses) > 1 else ''}, as written)")
        if self.frame_format_appended:
            lines += [f'BA_DEF_ BO_ "{FRAME_FORMAT}" {_FRAME_FORMAT_ENUM};',
                      f'BA_DEF_DEF_ "{FRAME_FORMAT}" "{FRAME_FORMATS[0]}";']
        frame_format = self.definitions.get(FRAME_FORMAT)
        if frame_format is not None and frame_format.type == "INT" and not frame_format.has_default:
            lines.append(f'BA_DEF_DEF_ "{FRAME_FORMAT}" {frame_format.minimum};')
            self.repairs.warn("attribute-definition", frame_format.statement, FRAME_FORMAT,
                              f"attribute {FRAME_FORMAT} is INT without a BA_DEF_DEF_: its default is its minimum "
                              f"{frame_format.minimum}, as in CANdb++")
        return "\n" + "\n".join(lines) + "\n" if lines else ""


def _number(attribute_type: str, text: str) -> int | float | None:
    """The number cantools makes of an INT, HEX or FLOAT attribute's text (``None``: none, or not finite)."""
    try:
        number = Decimal(text)
    except ArithmeticError:  # decimal.InvalidOperation: no number
        return None
    if not number.is_finite():
        return None
    return float(number) if attribute_type == "FLOAT" else int(number)


def _text(statement: Statement, index: int) -> str:
    token = statement.token(index)
    return token.value if token is not None else ""


def _kind(statement: Statement, index: int) -> str | None:
    token = statement.token(index)
    return token.kind if token is not None else None
