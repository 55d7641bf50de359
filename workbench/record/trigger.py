"""Start and stop triggers of a recording, as CANape's trigger conditions: a condition on a recorded signal
(``zsRailPressure > 20``, ``xsTankCtrlState == TANK2_ON``), and the seconds kept from before the start.

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


@dataclass(frozen=True)
class Condition:
    """``name op value``: a recorded signal compared with a number, or with a text of its value table."""

    name: str
    op: str
    value: float | str
    text: str = field(default="", compare=False)  # as the user wrote it: what a refusal quotes

    @classmethod
    def parse(cls, text: str) -> Condition:
        """``"NAME OP VALUE"`` (OP one of > >= < <= == !=). :raises InputError: it is not that."""
        found = _CONDITION.match(text)
        if found is None:
            raise InputError(f"trigger condition {text!r}: write NAME OP VALUE, OP one of > >= < <= == != "
                             "(e.g. 'zsRailPressure > 20')")
        value: float | str = found["value"].strip("'\"")
        try:
            value = float(value)
        except ValueError:
            if found["op"] not in ("==", "!="):
                raise InputError(f"trigger condition {text!r}: {found['op']} compares with a number") from None
        return cls(found["name"], found["op"], value, text.strip())

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
        return f"{self.name} {self.op} {self.value:g}" if isinstance(self.value, float) else \
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
        return {condition.name for condition in (self.start, self.stop) if condition is not None}

    def describe(self) -> str:
        parts = []
        if self.start is not None:
            parts.append(f"start when {self.start}" + (f" ({self.pre_s:g} s before kept)" if self.pre_s else ""))
        if self.stop is not None:
            parts.append(f"stop when {self.stop}")
        return ", ".join(parts)


def checked_trigger(trigger: Trigger, model: A2lModel) -> Trigger:
    """``trigger`` with each condition's text as the signal's value table writes it (``off``: ``OFF``).

    :raises UnknownSymbolError: a condition names no object of ``model`` (the closest are suggested).
    :raises InputError: a text the signal's table lacks, or a text for a signal without one: the condition
        would never be met, and a recording waiting for it would stay empty (or never stop).
    """
    checked = {}
    for role in ("start", "stop"):
        condition = getattr(trigger, role)
        if condition is None:
            continue
        try:
            found = model.object(condition.name)
        except UnknownSymbolError as error:  # named with the condition: start and stop may name different signals
            raise UnknownSymbolError(error.name, f"{error.where} ({role} condition '{condition.said}')",
                                     error.suggestions) from None
        if not isinstance(condition.value, str):
            continue
        conversion = model.conversion(found)
        if not getattr(conversion, "verbal", False):
            raise InputError(f"trigger condition '{condition.said}': {condition.name} has no value table; compare it "
                             "with a number")
        text = conversion.text_of(condition.value)
        if text is None:
            raise InputError(f"trigger condition '{condition.said}': {condition.value!r} is not one of its values "
                             f"({conversion.allowed_shown})")
        checked[role] = replace(condition, value=text)
    return replace(trigger, **checked)


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
        if self.started_s is None and start is not None and start.name in values:
            index = start.first(values[start.name])
            if index is not None:
                self.started_s = float(times[index])
        if self.started_s is not None and self.stopped_s is None and stop is not None and stop.name in values:
            after = np.flatnonzero(np.asarray(times) > self.started_s)
            index = stop.first(np.asarray(values[stop.name])[after]) if len(after) else None
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
