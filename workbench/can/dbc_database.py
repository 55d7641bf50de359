"""The :class:`~workbench.can.model.DbcContent` of a cantools database.

:func:`workbench.can.dbc_file.load_dbc` reads a DBC's content from its statements
(:mod:`workbench.can.dbc_read`); where that reader is not sure to read as cantools would, the
load asks cantools and takes the content from its database through this module. The tests hold
the reader to this one: for every DBC both must give the same content.
"""

from __future__ import annotations

from cantools.database.can import Database
from cantools.database.can import Message as CantoolsMessage
from cantools.database.can import Signal as CantoolsSignal

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

__all__ = ["content_of_database"]


def content_of_database(database: Database, message_lines: dict[str, tuple[int, ...]]) -> DbcContent:
    """The content of a cantools database; ``message_lines``: the lines of the ``BO_`` s it read, by name.

    The database's messages are those ``BO_`` s in file order (whatever their long names).
    """
    definitions = database.dbc.attribute_definitions if database.dbc else {}
    value_tables = {name: _sorted_choices(table)
                    for name, table in ((database.dbc.value_tables if database.dbc else None) or {}).items()}
    lines = sorted(line for lines in message_lines.values() for line in lines)
    messages = []
    frame_formats: dict[str, str] = {}
    for index, message in enumerate(database.messages):
        messages.append(_message(message, definitions, value_tables, lines[index] if index < len(lines) else 0))
        frame_format = _frame_format(message, definitions.get(FRAME_FORMAT_ATTRIBUTE))
        if frame_format is not None:
            frame_formats.setdefault(message.name, frame_format)
    return DbcContent(tuple(node.name for node in database.nodes), tuple(messages), frozenset(definitions),
                      frame_formats)


def _attribute(message: CantoolsMessage, definitions: dict, name: str):
    """A message attribute's value, or its definition's default (``None`` without either)."""
    attributes = message.dbc.attributes if message.dbc else {}
    if name in attributes:
        return attributes[name].value
    definition = definitions.get(name)
    return definition.default_value if definition is not None else None


def _frame_format(message: CantoolsMessage, definition) -> str | None:
    """The ``VFrameFormat`` set on the message: its ENUM choice's name, or the value as text."""
    if not message.dbc or FRAME_FORMAT_ATTRIBUTE not in message.dbc.attributes:
        return None
    value = message.dbc.attributes[FRAME_FORMAT_ATTRIBUTE].value
    choices = definition.choices if definition is not None and definition.choices else None
    if isinstance(value, int) and choices and 0 <= value < len(choices):
        return choices[value]
    return str(value)


def _message(message: CantoolsMessage, definitions: dict, value_tables: dict[str, tuple[tuple[int, str], ...]],
             line: int) -> Message:
    period, timeout, timeout_is_default = period_and_timeout(_attribute(message, definitions, PERIOD_ATTRIBUTE),
                                                             _attribute(message, definitions, TIMEOUT_ATTRIBUTE))
    return Message(
        name=message.name,
        frame_id=message.frame_id,
        network=None,
        dlc=message.length,
        period_ms=period,
        timeout_ms=timeout,
        timeout_is_default=timeout_is_default,
        extended=message.is_extended_frame,
        role=None,
        signals=tuple(_signal(signal, value_tables) for signal in message.signals),
        senders=tuple(message.senders),
        comment=_comment(message.comment),
        line=line,
    )


def _sorted_choices(choices) -> tuple[tuple[int, str], ...]:
    return tuple(sorted((int(value), str(text)) for value, text in (choices or {}).items()))


def _signal(signal: CantoolsSignal, value_tables: dict[str, tuple[tuple[int, str], ...]]) -> SignalOfMsg:
    choices = _sorted_choices(signal.choices)
    return SignalOfMsg(
        name=signal.name,
        bit_start=signal.start,
        length=signal.length,
        byte_order="Intel" if signal.byte_order == "little_endian" else "Motorola",
        is_signed=signal.is_signed,
        is_float=signal.is_float,
        factor=signal.scale,
        offset=signal.offset,
        minimum=signal.minimum,
        maximum=signal.maximum,
        unit=signal.unit or "",
        comment=_comment(signal.comment),
        receivers=tuple(signal.receivers),
        multiplexer_ids=tuple(signal.multiplexer_ids) if signal.multiplexer_ids is not None else None,
        choices=choices,
        value_table=value_table_of(choices, value_tables),
    )


def _comment(comment) -> str:
    """cantools gives a str, or a dict of language → str for multilingual (ARXML-style) comments."""
    if isinstance(comment, dict):
        comment = next(iter(comment.values()), "")
    return comment or ""
