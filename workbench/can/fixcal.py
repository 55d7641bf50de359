"""The fix calibrations the thesis's CAN library creates for one node (chapter 6.3.3–6.3.4).

For every signal of a message the node sends or receives:

* ``cf<SIGNAL>_EN`` — ``uint8_T`` 0/1, initially 0: while 1 the signal is replaced by
* ``cf<SIGNAL>_VALUE`` — the signal's *raw* value in the integer type of its width
  (:func:`~workbench.can.naming.raw_c_type`), shown in physical units through a linear
  conversion with the signal's factor/offset; limits are the DBC min/max (the full raw
  range when the DBC gives none); initially the raw value nearest to physical 0;

and for every message the node sends, ``cs<Message>_En`` — ``uint8_T`` 0/1, initially 1.
All of them live in CAL RAM (``.cal_ram``). Two signals that map to the same name (``Sgn1``
in two messages, ``Level`` and ``LEVEL``) would define one calibration twice:
:func:`fixcal_collisions` finds them and :func:`fix_calibrations` refuses them. With
``qualified=True`` the names carry the message (``cfC3RXAAA_SGN1_EN``, see
:mod:`workbench.can.naming`), which keeps signals of different messages apart.
"""

from __future__ import annotations

import enum
import math
from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass

from workbench.can.model import Message, Role, SignalOfMsg
from workbench.can.naming import FIX_ENABLE_SUFFIX, FIX_VALUE_SUFFIX, fix_enable_name, fix_value_name, tx_enable_name
from workbench.errors import InputError

__all__ = [
    "FixCalibration", "FixKind", "collision_remedy", "describe_owners", "fix_calibrations", "fixcal_collisions",
    "format_number", "raw_range",
]

_FLOAT32_MAX = 3.4028234663852886e38
_FLOAT64_MAX = 1.7976931348623157e308
_RAW_EPSILON = 1e-9  # (limit - offset) / factor of 0.07 / 0.01 is 6.999999...


class FixKind(str, enum.Enum):
    TX_ENABLE = "tx_enable"
    FIX_ENABLE = "fix_enable"
    FIX_VALUE = "fix_value"


@dataclass(frozen=True)
class FixCalibration:
    """One calibration scalar: its C declaration and its A2L description."""

    name: str
    kind: FixKind
    c_type: str
    """rtwtypes name: ``uint8_T``, ``uint16_T``, ``int8_T``, ``real32_T`` ..."""
    initial_raw: int | float
    message: Message
    signal: SignalOfMsg | None = None
    """The signal of a ``_EN``/``_VALUE`` pair; ``None`` for a TX enable."""
    lower: float = 0.0
    """Physical lower limit (phys = raw · factor + offset for a ``_VALUE``)."""
    upper: float = 1.0

    @property
    def description(self) -> str:
        """The A2L long identifier and C comment, worded as the demo ECU's A2L does."""
        if self.kind is FixKind.TX_ENABLE:
            return f"Transmission enable of {self.message.name}"
        signal = self.signal
        if self.kind is FixKind.FIX_ENABLE:
            value_name = self.name.removesuffix(FIX_ENABLE_SUFFIX) + FIX_VALUE_SUFFIX
            return f"Fix switch of CAN signal {signal.name} (1: use {value_name})"
        what = f": {signal.comment}" if signal.comment else ""
        resolution = "" if signal.factor == 1 else f", {format_number(signal.factor)} {signal.unit}".rstrip() + "/bit"
        return f"Fixed raw value of CAN signal {signal.name}{what} ({signal.length} bit{resolution})"


def format_number(value: float) -> str:
    """``1``, ``0.01``, ``-40``, ``1e-06``: integral values without a decimal point."""
    return str(int(value)) if float(value).is_integer() else repr(float(value))


def fixcal_collisions(messages: Iterable[Message], *, qualified: bool = False,
                      ) -> dict[str, list[tuple[Message, SignalOfMsg]]]:
    """Fix-calibration names claimed by more than one signal: name → the (message, signal)s.

    :param qualified: with message-qualified names (``cf<MESSAGE>_<SIGNAL>_…``).
    """
    claims: dict[str, list[tuple[Message, SignalOfMsg]]] = defaultdict(list)
    for message in messages:
        for signal in message.signals:
            claims[fix_value_name(signal.name, message.name if qualified else None)].append((message, signal))
    return {name: owners for name, owners in claims.items() if len(owners) > 1}


def describe_owners(owners: list[tuple[Message, SignalOfMsg]], listed: int = 3) -> str:
    """``M1.S, M2.S, M3.S and 5 more`` for a collision's signals."""
    text = ", ".join(f"{m.name}.{s.name}" for m, s in owners[:listed])
    return text + (f" and {len(owners) - listed} more" if len(owners) > listed else "")


def collision_remedy(messages: list[Message], qualified: bool) -> str:
    """``message-qualified names (--qualified) avoid this`` when they would, else ``""``."""
    if qualified or fixcal_collisions(messages, qualified=True):
        return ""
    return "message-qualified names (--qualified) avoid this"


def fix_calibrations(messages: Iterable[Message], *, qualified: bool = False) -> list[FixCalibration]:
    """The calibrations of the messages in a node's table (messages without a role are skipped).

    Per message in the given order: the TX enable (TX only), then ``_EN``/``_VALUE`` per signal.

    :param qualified: message-qualified fix names, ``cf<MESSAGE>_<SIGNAL>_EN``/``_VALUE``.
    :raises InputError: two signals map to the same calibration name, or a signal's raw value
        fits no C type (longer than 64 bits, a float of other than 32/64 bits).
    """
    messages = [m for m in messages if m.role is not None]
    collisions = fixcal_collisions(messages, qualified=qualified)
    if collisions:
        name, owners = next(iter(collisions.items()))
        more = f" (and {len(collisions) - 1} more names)" if len(collisions) > 1 else ""
        remedy = collision_remedy(messages, qualified)
        raise InputError(f"{owners[1][0].where(owners[1][1].name)}: {name} would be defined by "
                         f"{describe_owners(owners)}{more}{'; ' + remedy if remedy else ''}")
    calibrations: list[FixCalibration] = []
    for message in messages:
        if message.role is Role.TX:
            calibrations.append(FixCalibration(tx_enable_name(message.name), FixKind.TX_ENABLE, "uint8_T", 1, message))
        qualifier = message.name if qualified else None
        for signal in message.signals:
            calibrations.append(FixCalibration(
                fix_enable_name(signal.name, qualifier), FixKind.FIX_ENABLE, "uint8_T", 0, message, signal,
            ))
            calibrations.append(_fix_value(message, signal, fix_value_name(signal.name, qualifier)))
    return calibrations


def raw_range(signal: SignalOfMsg) -> tuple[float, float]:
    """The smallest and largest raw value the signal's bits can carry."""
    if signal.is_float:
        limit = _FLOAT32_MAX if signal.length == 32 else _FLOAT64_MAX
        return -limit, limit
    if signal.is_signed:
        return -(1 << (signal.length - 1)), (1 << (signal.length - 1)) - 1
    return 0, (1 << signal.length) - 1


def _fix_value(message: Message, signal: SignalOfMsg, name: str) -> FixCalibration:
    raw_low, raw_high = raw_range(signal)
    physical = sorted((raw_low * signal.factor + signal.offset, raw_high * signal.factor + signal.offset))
    lower = physical[0] if signal.minimum is None else min(max(signal.minimum, physical[0]), physical[1])
    upper = physical[1] if signal.maximum is None else min(max(signal.maximum, physical[0]), physical[1])
    try:
        c_type = signal.raw_c_type
    except ValueError as exc:
        raise InputError(f"{message.where(signal.name)}: {message.name}.{signal.name}: {exc}") from exc
    return FixCalibration(
        name, FixKind.FIX_VALUE, c_type,
        _initial_raw(signal, lower, upper, raw_low, raw_high), message, signal, lower, upper,
    )


def _initial_raw(signal: SignalOfMsg, lower: float, upper: float, raw_low: float, raw_high: float) -> int | float:
    """The raw value nearest to physical 0 within the limits."""
    physical = min(max(0.0, lower), upper)
    if signal.is_float or not signal.factor:
        return (physical - signal.offset) / (signal.factor or 1.0) if signal.is_float else 0
    inside = sorted(((lower - signal.offset) / signal.factor, (upper - signal.offset) / signal.factor))
    raw = round((physical - signal.offset) / signal.factor)
    raw = min(max(raw, math.ceil(inside[0] - _RAW_EPSILON)), math.floor(inside[1] + _RAW_EPSILON))
    return int(min(max(raw, raw_low), raw_high))
