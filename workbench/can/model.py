"""The thesis's Message and SignalOfMsg classes (chapter 6.3.2), built from a loaded DBC.

Periods and timeouts come from the DBC message attributes ``GenMsgCycleTime`` and
``GenMsgTimeoutTime`` (milliseconds; an attribute's ``BA_DEF_DEF_`` default applies when
the message has none, and 0 counts as missing). A message without a timeout gets three
times its period, as the thesis's import does; :attr:`Message.timeout_is_default` says so
and the validation reports the missing attribute.

A loaded DBC holds its messages once, as :class:`DbcContent` (read by
:mod:`workbench.can.dbc_read`, or from cantools' database by :mod:`workbench.can.dbc_database`);
:func:`messages_of` gives them a network and a role.

A message's role is relative to one node of the DBC: the node sends it (TX), or the node
receives at least one of its signals (RX); any other message is not in that node's table
(role ``None``). Mailboxes are assigned later by :mod:`workbench.can.mailboxes`.
"""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass, field
from decimal import Decimal
from typing import TYPE_CHECKING

from workbench.can.naming import raw_c_type
from workbench.errors import InputError

if TYPE_CHECKING:
    from workbench.can.dbc_file import DbcFile

PERIOD_ATTRIBUTE = "GenMsgCycleTime"
TIMEOUT_ATTRIBUTE = "GenMsgTimeoutTime"
FRAME_FORMAT_ATTRIBUTE = "VFrameFormat"
DEFAULT_TIMEOUT_PERIODS = 3

__all__ = ["DEFAULT_TIMEOUT_PERIODS", "FRAME_FORMAT_ATTRIBUTE", "PERIOD_ATTRIBUTE", "TIMEOUT_ATTRIBUTE", "DbcContent",
           "Message", "Role", "SignalOfMsg", "check_node", "messages_of", "period_and_timeout", "role_of",
           "step_decimals", "value_table_of"]

MAX_STEP_DECIMALS = 9


class Role(str, enum.Enum):
    """Direction of a message seen from the chosen node."""

    TX = "TX"
    RX = "RX"


@dataclass(frozen=True)
class SignalOfMsg:
    """One signal of a message, with the thesis's SignalOfMsg properties."""

    name: str
    bit_start: int
    """The DBC start bit (Intel: the LSB; Motorola: the MSB in DBC bit numbering)."""
    length: int
    """Bits."""
    byte_order: str
    """``"Intel"`` (little endian) or ``"Motorola"`` (big endian)."""
    is_signed: bool
    is_float: bool
    factor: float
    offset: float
    minimum: float | None
    """Physical minimum from the DBC, ``None`` when the DBC gives none (``[0|0]``)."""
    maximum: float | None
    unit: str
    comment: str
    receivers: tuple[str, ...] = ()
    multiplexer_ids: tuple[int, ...] | None = None
    """The multiplexer values that select this signal; ``None`` for a plain signal."""
    choices: tuple[tuple[int, str], ...] = ()
    """The DBC value descriptions (``VAL_``), raw value → text, ascending."""
    value_table: str | None = None
    """The name of the DBC ``VAL_TABLE_`` whose entries equal :attr:`choices`, if any."""

    @property
    def value_type(self) -> str:
        """``unsigned``, ``signed`` or ``float<length>`` (IEEE: float32, float64)."""
        if self.is_float:
            return f"float{self.length}"
        return "signed" if self.is_signed else "unsigned"

    @property
    def raw_c_type(self) -> str:
        """The rtwtypes type of the raw value (``uint16_T``, ``int8_T``, ``real32_T`` ...)."""
        return raw_c_type(self.length, self.is_signed, self.is_float)

    def to_dict(self) -> dict:
        return {
            "Name": self.name,
            "BitStart": self.bit_start,
            "Length": self.length,
            "ByteOrder": self.byte_order,
            "ValueType": self.value_type,
            "Factor": self.factor,
            "Offset": self.offset,
            "Min": self.minimum,
            "Max": self.maximum,
            "Unit": self.unit,
            "Comment": self.comment,
        }


@dataclass(frozen=True)
class Message:
    """One CAN message with the thesis's Message properties."""

    name: str
    frame_id: int
    network: str | None
    """``CAN1`` … ``CAN4``; ``None`` where no network was chosen (fix calibrations, checks)."""
    dlc: int
    """Payload length in bytes."""
    period_ms: int | None
    """``None`` when the DBC gives no (or a zero) ``GenMsgCycleTime``."""
    timeout_ms: int | None
    timeout_is_default: bool
    """True when the timeout is the thesis's default (3 × period) for a missing attribute."""
    extended: bool
    role: Role | None
    signals: tuple[SignalOfMsg, ...]
    senders: tuple[str, ...] = ()
    comment: str = ""
    enable: bool = True
    """Whether the driver sends/receives the message; the DBC has no such flag, so always True."""
    mailbox: str | None = None
    """``CAN2_MSG_TX_000`` …, ``None`` for a message outside the node's table."""
    unique_id: bool = True
    """False when another message on the same network has the same id and format."""
    source: DbcFile | None = field(default=None, compare=False, repr=False)
    line: int = 0
    """1-based line of the message's ``BO_`` in :attr:`source` (0 when unknown)."""

    @property
    def type(self) -> str:
        return "ext" if self.extended else "std"

    @property
    def is_intel(self) -> bool:
        """True unless a signal is Motorola (big endian): picks the driver's PDU init data."""
        return all(signal.byte_order == "Intel" for signal in self.signals)

    def where(self, signal: str | None = None) -> str:
        """``file:line`` of the message's ``BO_`` (or of a signal's ``SG_``), for error messages."""
        if self.source is None:
            return self.name
        return self.source.where(self.source.signal_line(self.line, signal) if signal else self.line)

    def to_dict(self) -> dict:
        return {
            "Name": self.name,
            "ID": f"0x{self.frame_id:X}",
            "NetworkType": self.network,
            "UniqueID": self.unique_id,
            "DLC": self.dlc,
            "Period": self.period_ms,
            "Timeout": self.timeout_ms,
            "TimeoutIsDefault": self.timeout_is_default,
            "Enable": self.enable,
            "Type": self.type,
            "MboxId": self.mailbox,
            "Role": self.role.value if self.role else None,
            "Comment": self.comment,
            "Signals": [signal.to_dict() for signal in self.signals],
        }


@dataclass(frozen=True)
class DbcContent:
    """What the commands read from a DBC: its nodes, its messages in file order, attribute facts."""

    nodes: tuple[str, ...]
    """The ``BU_`` nodes."""
    messages: tuple[Message, ...]
    """Every message in file order, with its line; no network, role or source yet."""
    attributes: frozenset[str]
    """The names of the attributes the file defines (``BA_DEF_``)."""
    frame_formats: dict[str, str] = field(default_factory=dict)
    """Message name → the ``VFrameFormat`` set on it (its ENUM choice's name, or the value as text);
    of the first message of that name that sets one."""


def check_node(dbc: DbcFile, node: str) -> None:
    """:raises InputError: ``node`` is not one of the DBC's ``BU_`` nodes."""
    nodes = dbc.content.nodes
    if node not in nodes:
        raise InputError(f"{dbc.path}: node {node!r} is not in this DBC (nodes: {', '.join(nodes) or 'none'})")


def messages_of(dbc: DbcFile, network: str | None, node: str | None) -> list[Message]:
    """Every message of ``dbc`` in file order, with its role relative to ``node`` (no mailboxes yet).

    :raises InputError: ``node`` is given but not a node of the DBC.
    """
    if node is not None:
        check_node(dbc, node)
    return [dataclasses.replace(message, network=network, role=role_of(message, node), source=dbc)
            for message in dbc.content.messages]


def role_of(message: Message, node: str | None) -> Role | None:
    if node is None:
        return None
    if node in message.senders:
        return Role.TX
    if any(node in signal.receivers for signal in message.signals):
        return Role.RX
    return None


def period_and_timeout(period: object, timeout: object) -> tuple[int | None, int | None, bool]:
    """Period, timeout (ms) and whether the timeout is the default, from the attributes' values (or defaults).

    A value that is no positive integer (missing, 0, text) is no period or timeout; a missing timeout is
    :data:`DEFAULT_TIMEOUT_PERIODS` × period.
    """
    period, timeout = _positive_ms(period), _positive_ms(timeout)
    timeout_is_default = timeout is None
    if timeout is None and period is not None:
        timeout = DEFAULT_TIMEOUT_PERIODS * period
    return period, timeout, timeout_is_default


def _positive_ms(value) -> int | None:
    try:
        value = int(value)
    except (TypeError, ValueError):
        return None
    return value if value > 0 else None


def value_table_of(choices: tuple[tuple[int, str], ...], value_tables: dict[str, tuple[tuple[int, str], ...]],
                   ) -> str | None:
    """The name of the first value table whose entries are ``choices`` (both sorted by value), if any."""
    if not choices:
        return None
    return next((name for name, entries in value_tables.items() if entries == choices), None)


def step_decimals(factor: float, offset: float) -> int:
    """Decimals that show one raw step of a scaled signal: 2 for a factor of 0.01, 6 for 1e-06, 0 for whole
    factors and offsets (the display format of its fix calibration, its live value and its recorded channel)."""
    digits = [-Decimal(repr(float(number))).normalize().as_tuple().exponent for number in (factor, offset)]
    return min(max(0, *digits), MAX_STEP_DECIMALS)
