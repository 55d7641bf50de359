"""Start and stop triggers of a recording, as CANape's trigger conditions: a condition on a recorded signal
(``zsRailPressure > 20``, ``zsRailPressure > 20 bar`` in its own unit, ``zsSensVolt[2] < 0.5`` on an array's
element, ``xsTankCtrlState == TANK2_ON``), and the seconds kept from before the start.

:class:`TriggerGate` stands between the recording's records and its file: until the start condition is met it
holds what comes (only the last ``pre_s`` seconds of it: memory stays bounded), from the start it lets everything
through (what it held first, from ``pre_s`` before the start on), and after the stop condition nothing. Times are
the recording's axis (s); a condition is judged on the DAQ samples of its signal, in physical units.
"""

from __future__ import annotations

import operator
import re
from collections import deque
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from workbench.errors import InputError, UnknownSymbolError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel

__all__ = ["Condition", "Trigger", "TriggerGate", "checked_trigger"]

_OPERATORS = {">=": operator.ge, "<=": operator.le, "==": operator.eq, "!=": operator.ne, ">": operator.gt,
              "<": operator.lt}
_CONDITION = re.compile(r"^\s*(?P<name>[^\s<>=!]+)\s*(?P<op>>=|<=|==|!=|>|<)\s*(?P<value>[^\s<>=!].*?)\s*$")
_WITH_UNIT = re.compile(r"(?P<number>[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?)\s*(?P<unit>[^\d\s.+-].*)")  # 25 bar, 2.5V
_ELEMENT = re.compile(r"(?P<name>.+?)(?P<index>(\[\s*\d+\s*\])+)")  # zsSensVolt[2], m[1][0]


@dataclass(frozen=True)
class Condition:
    """``name op value``: a recorded signal compared with a number, or with a text of its value table."""

    name: str  # as written: a signal, or one element of an array signal (zsSensVolt[2])
    op: str
    value: float | str
    text: str = field(default="", compare=False)  # as the user wrote it: what a refusal quotes
    unit: str = ""  # the unit the number was written with (25 bar), checked against the signal's
    signal: str = ""  # the recorded signal the condition judges ("": ``name``); an element's array
    index: tuple[int, ...] = ()  # the element of ``signal`` it judges (() the whole value)

    @classmethod
    def parse(cls, text: str) -> Condition:
        """``"NAME OP VALUE"`` (OP one of > >= < <= == !=). :raises InputError: it is not that."""
        found = _CONDITION.match(text)
        if found is None:
            raise InputError(f"trigger condition {text!r}: write NAME OP VALUE, OP one of > >= < <= == != "
                             "(e.g. 'zsRailPressure > 20')")
        value: float | str = found["value"].strip("'\"")
        unit = ""
        try:
            value = float(value)
        except ValueError:
            with_unit = _WITH_UNIT.fullmatch(value)
            if with_unit is not None:
                value, unit = float(with_unit["number"]), with_unit["unit"].strip()
            elif found["op"] not in ("==", "!="):
                raise InputError(f"trigger condition {text!r}: {found['op']} compares with a number") from None
        return cls(found["name"], found["op"], value, text.strip(), unit)

    def column(self, values: dict[str, np.ndarray]) -> np.ndarray | None:
        """Its signal's (or element's) samples among ``values`` (name -> physical values, one row a sample);
        None: not among them."""
        found = values.get(self.signal or self.name)
        if found is None:
            return None
        return np.asarray(found)[(slice(None), *self.index)] if self.index else np.asarray(found)

    def first(self, values: np.ndarray) -> int | None:
        """The first of ``values`` (physical: numbers, or texts of a value table) that meets it; None: none does."""
        values = np.asarray(values)
        if isinstance(self.value, str):
            values = np.array([value.decode() if isinstance(value, bytes) else str(value) for value in values.tolist()])
        met = np.flatnonzero(_OPERATORS[self.op](values, self.value))
        return int(met[0]) if len(met) else None

    @property
    def said(self) -> str:
        """The condition as the user wrote it (else as :meth:`__str__` writes it)."""
        return self.text or str(self)

    def __str__(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        return f"{self.name} {self.op} {self.value:g}{unit}" if isinstance(self.value, float) else \
            f"{self.name} {self.op} {self.value}"


@dataclass(frozen=True)
class Trigger:
    """``start``: record from when it is met (None: from the beginning), keeping ``pre_s`` seconds from before;
    ``stop``: end the recording when it is met after the start (the sample that met it is the last)."""

    start: Condition | None = None
    stop: Condition | None = None
    pre_s: float = 0.0

    @property
    def names(self) -> set[str]:
        """The recorded signals the conditions judge (an element's array)."""
        return {condition.signal or condition.name for condition in (self.start, self.stop) if condition is not None}

    def describe(self) -> str:
        parts = []
        if self.start is not None:
            parts.append(f"start when {self.start}" + (f" ({self.pre_s:g} s before kept)" if self.pre_s else ""))
        if self.stop is not None:
            parts.append(f"stop when {self.stop}")
        return ", ".join(parts)


def checked_trigger(trigger: Trigger, model: A2lModel) -> Trigger:
    """``trigger`` with each condition's signal found (an array's element: ``zsSensVolt[2]``), its unit checked and its
    text as the signal's value table writes it (``off``: ``OFF``).

    :raises UnknownSymbolError: a condition names no object of ``model`` (the closest are suggested).
    :raises InputError: an element the array does not have, a number in another unit than the signal's, a text the
        signal's table lacks, or a text for a signal without one: the condition would never be met, and a recording
        waiting for it would stay empty (or never stop).
    """
    checked = {}
    for role in ("start", "stop"):
        condition = getattr(trigger, role)
        if condition is None:
            continue
        found, index = _signal(model, condition, role)
        condition = replace(condition, signal=found.name, index=index)
        conversion = model.conversion(found)
        verbal = getattr(conversion, "verbal", False)
        if condition.unit and verbal and condition.op in ("==", "!="):  # a text that starts with a digit: '2WD'
            condition = replace(condition, value=condition.said.split(condition.op, 1)[1].strip().strip("'\""),
                                unit="")
        if condition.unit and condition.unit != model.unit_of(found):
            number = condition.said.split(condition.op, 1)[1].strip()
            raise InputError(f"trigger condition '{condition.said}': '{number}' is in {condition.unit}, {found.name} "
                             f"in {model.unit_of(found) or 'no unit'} (no unit conversion)")
        if isinstance(condition.value, str):
            if not verbal:
                raise InputError(f"trigger condition '{condition.said}': {found.name} has no value table; compare it "
                                 "with a number")
            text = conversion.text_of(condition.value)
            if text is None:
                raise InputError(f"trigger condition '{condition.said}': {condition.value!r} is not one of its values "
                                 f"({conversion.allowed_shown})")
            condition = replace(condition, value=text)
        checked[role] = condition
    return replace(trigger, **checked)


def _signal(model: A2lModel, condition: Condition, role: str):
    """The object a condition judges and the element of it (() for its whole value).

    :raises UnknownSymbolError: no such object (named with the condition: start and stop may name different ones).
    :raises InputError: an element the array does not have, or an array named whole.
    """
    element = _ELEMENT.fullmatch(condition.name)
    name = condition.name if element is None or condition.name in model else element["name"]
    try:
        found = model.object(name)
    except UnknownSymbolError as error:
        raise UnknownSymbolError(error.name, f"{error.where} ({role} condition '{condition.said}')",
                                 error.suggestions) from None
    shape = tuple(getattr(found, "shape", ()))
    if name == condition.name:
        if shape:  # judged whole, a row of its elements would count as samples
            last = "][".join(str(size - 1) for size in shape)
            raise InputError(f"trigger condition '{condition.said}': {name} has {'x'.join(map(str, shape))} elements: "
                             f"compare one of them ({name}[{']['.join('0' * len(shape))}] ... {name}[{last}])")
        return found, ()
    index = tuple(int(number) for number in re.findall(r"\d+", element["index"]))
    if len(index) != len(shape) or any(i >= size for i, size in zip(index, shape)):
        has = "no elements" if not shape else f"{'x'.join(map(str, shape))} elements"
        raise InputError(f"trigger condition '{condition.said}': {name} has {has}")
    return found, index


class TriggerGate:
    """What of the records reaches the file (see the module docstring); ``trigger`` None lets everything through."""

    def __init__(self, trigger: Trigger | None):
        self.trigger = trigger or Trigger()
        self.started_s: float | None = None if self.trigger.start is not None else -np.inf
        self.stopped_s: float | None = None
        self._held: deque = deque()  # (group, times, columns, counts) before the start
        self._latest = -np.inf

    def observe(self, times: np.ndarray, values: dict[str, np.ndarray]) -> None:
        """Judge the conditions on DAQ samples (``values``: name -> physical values, one per time)."""
        start, stop = self.trigger.start, self.trigger.stop
        started = start.column(values) if self.started_s is None and start is not None else None
        if started is not None:
            index = start.first(started)
            if index is not None:
                self.started_s = float(times[index])
        stopping = stop.column(values) if self.started_s is not None and self.stopped_s is None and stop else None
        if stopping is not None:
            after = np.flatnonzero(np.asarray(times) > self.started_s)
            index = stop.first(stopping[after]) if len(after) else None
            if index is not None:
                self.stopped_s = float(times[after[index]])

    def passed(self, group: int, times: np.ndarray, columns: list, counts: dict[str, int]) -> list[tuple]:
        """The records to write now, as (group, times, columns, counts per record); held ones first."""
        self._latest = max(self._latest, float(times[-1]))
        entry = (group, times, columns, counts)
        if self.started_s is None:
            self._held.append(entry)
            while self._held and float(self._held[0][1][-1]) < self._latest - self.trigger.pre_s:
                self._held.popleft()
            return []
        held, self._held = list(self._held), deque()
        upper = np.inf if self.stopped_s is None else self.stopped_s
        out = []
        for group, times, columns, counts in [*held, entry]:
            keep = (times >= self.started_s - self.trigger.pre_s) & (times <= upper)
            if keep.all():
                out.append((group, times, columns, counts))
            elif keep.any():
                out.append((group, times[keep], [column[keep] for column in columns], counts))
        return out

    @property
    def done(self) -> bool:
        """The stop condition was met: nothing more is written."""
        return self.stopped_s is not None
