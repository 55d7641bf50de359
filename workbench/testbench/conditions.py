"""What an expectation or a wait asks of a signal: a band, a value, a bound, or "anything but".

::

    within(24.0, 26.0)          # 24 <= x <= 26
    equals("TANK1_ON")          # a verbal value by its text
    equals(33.33, tolerance=0.005)
    at_least(24.0), at_most(0.0)
    other_than("CAN_RX_TIMEOUT_ERR")

A plain value stands for :func:`equals`, a ``(low, high)`` tuple for :func:`within`. Conditions test
whole arrays of samples at once and describe themselves for the step log and the report.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from workbench.errors import InputError

__all__ = ["Condition", "as_condition", "at_least", "at_most", "equals", "other_than", "within"]


@dataclass(frozen=True)
class Condition:
    """``low <= x <= high`` (either bound may be None), or ``x == value`` (± ``tolerance`` for numbers);
    ``negate`` turns it into its opposite."""

    low: float | None = None
    high: float | None = None
    value: Any = None
    tolerance: float = 0.0
    negate: bool = False
    label: str | None = None  # the text a numeric value stands for (a CAN2 value table's), as it is shown

    @property
    def is_value(self) -> bool:
        return self.low is None and self.high is None

    @property
    def is_text(self) -> bool:
        return isinstance(self.value, str)

    def band(self) -> tuple[float, float] | None:
        """The numeric band a plot draws (None for text values; an open side is infinite)."""
        if self.is_text:
            return None
        if self.is_value:
            return float(self.value) - self.tolerance, float(self.value) + self.tolerance
        return (-np.inf if self.low is None else self.low), (np.inf if self.high is None else self.high)

    def test(self, values: np.ndarray) -> np.ndarray:
        """One bool per sample."""
        values = np.asarray(values)
        if self.is_value:
            if self.is_text or values.dtype.kind in "OUS":
                ok = np.array([_same(v, self.value) for v in values.ravel()], dtype=bool).reshape(values.shape)
            else:
                ok = np.abs(values.astype(float) - float(self.value)) <= self.tolerance
        else:
            numbers = values.astype(float)
            ok = np.ones(numbers.shape, dtype=bool)
            if self.low is not None:
                ok &= numbers >= self.low
            if self.high is not None:
                ok &= numbers <= self.high
        return ~ok if self.negate else ok

    def describe(self, unit: str = "") -> str:
        """``within [24, 26] bar``, ``= TANK1_ON``, ``>= 24 bar``, ``!= CAN_RX_TIMEOUT_ERR``."""
        unit = f" {unit}" if unit else ""
        if self.is_value:
            text = f"{'!=' if self.negate else '='} {self.label or _number(self.value)}"
            if self.tolerance:
                text += f" ± {_number(self.tolerance)}"
            return text + ("" if self.is_text or self.label else unit)
        if self.low is not None and self.high is not None:
            text = f"within [{_number(self.low)}, {_number(self.high)}]{unit}"
        elif self.low is not None:
            text = f">= {_number(self.low)}{unit}"
        else:
            text = f"<= {_number(self.high)}{unit}"
        return f"not {text}" if self.negate else text


def within(low: float, high: float) -> Condition:
    """:raises InputError: ``low`` above ``high`` (the test's mistake, not the ECU's: it would fail every sample)."""
    __tracebackhide__ = True  # pytest shows the test's line and the one-line error, not this function's
    if low > high:
        raise InputError(f"within({low}, {high}): the low bound is above the high one")
    return Condition(low=float(low), high=float(high))


def equals(value: Any, tolerance: float = 0.0) -> Condition:
    """:raises InputError: a negative ``tolerance`` (no sample could pass)."""
    __tracebackhide__ = True
    if not tolerance >= 0:
        raise InputError(f"equals({value!r}, tolerance={tolerance}): a tolerance is 0 or more")
    return Condition(value=value, tolerance=float(tolerance))


def at_least(low: float) -> Condition:
    return Condition(low=float(low))


def at_most(high: float) -> Condition:
    return Condition(high=float(high))


def other_than(value: Any) -> Condition:
    return Condition(value=value, negate=True)


def as_condition(wanted: Any) -> Condition:
    """A :class:`Condition`, a ``(low, high)`` tuple (:func:`within`) or a value (:func:`equals`)."""
    if isinstance(wanted, Condition):
        return wanted
    if isinstance(wanted, tuple) and len(wanted) == 2:
        return within(*wanted)
    return equals(wanted)


def _same(sample: Any, value: Any) -> bool:
    if isinstance(sample, bytes):
        sample = sample.decode(errors="replace")
    if isinstance(value, str) or isinstance(sample, str):
        return str(sample) == str(value)
    return sample == value


def _number(value: Any) -> str:
    return f"{value:g}" if isinstance(value, (int, float, np.number)) and not isinstance(value, bool) else str(value)
