"""A calibration object's value in physical units, as the session, datasets and the GUI exchange it.

One shape for every kind, so a dataset read from DCM, a value read from the ECU and an edit
in the GUI compare and convert without knowing where they came from:

* ``VALUE``: ``value`` is a number, or a text for a verbal conversion (COMPU_VTAB);
* ``ASCII``: ``value`` is a ``str``;
* ``VAL_BLK``: ``value`` is a numpy array of the MATRIX_DIM shape (x first);
* ``CURVE``: ``value`` has shape ``(nx,)``, ``axes[0]`` the X axis;
* ``MAP``: ``value`` has shape ``(nx, ny)`` and is indexed ``[x, y]`` whatever the memory order
  (ROW_DIR/COLUMN_DIR is the record layout's business, not the value's);
* ``CUBOID``, ``CUBE_4``, ``CUBE_5``: shape ``(nx, ny, nz[, n4[, n5]])``, one axis each, likewise;
* ``AXIS_PTS``: ``value`` holds the axis points (shape ``(n,)``).

Verbal values (TAB_VERB) in arrays are numpy ``object`` arrays of ``str``. Numbers are float64
or int64, which hold every raw value of the ASAP2 data types exactly, so writing ``repr`` of a
value to text and reading it back gives the same number.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

import numpy as np

__all__ = ["Axis", "CalValue", "Scalar"]

Scalar = Union[int, float, str]


@dataclass(frozen=True)
class Axis:
    """The points of one axis of a CURVE or MAP, physical."""

    values: np.ndarray
    kind: str = "STD_AXIS"  # STD_AXIS, FIX_AXIS, COM_AXIS, RES_AXIS, CURVE_AXIS
    name: str | None = None  # the AXIS_PTS (COM_AXIS, RES_AXIS) or CURVE (CURVE_AXIS) it comes from
    unit: str = ""
    input_quantity: str | None = None  # the MEASUREMENT the axis reads (NO_INPUT_QUANTITY: None)

    def __eq__(self, other) -> bool:
        return (isinstance(other, Axis) and (self.kind, self.name, self.unit, self.input_quantity)
                == (other.kind, other.name, other.unit, other.input_quantity) and _same(self.values, other.values))

    __hash__ = None  # an array is not hashable


@dataclass(frozen=True)
class CalValue:
    """A CHARACTERISTIC's (or AXIS_PTS') value, physical; see the module docstring for the shapes."""

    name: str
    kind: str  # VALUE, ASCII, VAL_BLK, CURVE, MAP, CUBOID, CUBE_4, CUBE_5, AXIS_PTS
    value: Scalar | np.ndarray
    axes: tuple[Axis, ...] = ()
    unit: str = ""
    comment: str = field(default="", compare=False)

    @property
    def shape(self) -> tuple[int, ...]:
        return np.shape(self.value) if isinstance(self.value, np.ndarray) else ()

    def same_values(self, other: "CalValue") -> bool:
        """Same value and axis points (names, units and comments aside)."""
        return (_same(self.value, other.value) and len(self.axes) == len(other.axes)
                and all(_same(a.values, b.values) for a, b in zip(self.axes, other.axes)))

    def __eq__(self, other) -> bool:
        return (isinstance(other, CalValue) and (self.name, self.kind, self.unit) == (other.name, other.kind, other.unit)
                and self.axes == other.axes and _same(self.value, other.value))

    __hash__ = None


def _same(a, b) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        if a.shape != b.shape:
            return False
        if a.dtype.kind in "fc" or b.dtype.kind in "fc":
            try:
                return bool(np.array_equal(a, b, equal_nan=True))
            except TypeError:  # numbers against texts
                return False
        return bool(np.array_equal(a, b))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True  # NaN equals NaN here: a value is the same as itself
    return type(a) is type(b) and a == b if isinstance(a, str) or isinstance(b, str) else a == b
