"""A curve's or map's operating point, as CANape marks it: where the live values of its axes' inputs (the A2L's
INPUT_QUANTITY, measured while its editor is open) fall between the breakpoints, shown by the editor's
:class:`~workbench.gui.widgets.table_field.TableField` (the cells around it framed, a cross on the heat map, the
3D view or the curve).
"""

from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import QObject, QTimer

__all__ = ["OperatingPoint", "axis_position"]

REFRESH_MS = 100  # ten times a second: the point moves as the engine does, the table is not repainted more often


def axis_position(points, value: float) -> float | None:
    """Where ``value`` lies on the breakpoints ``points`` as a fractional index (2.5: halfway between the third and
    the fourth), held at the axis' ends as a lookup holds it; None for a value that is no number."""
    points = np.asarray(points, dtype=np.float64)
    if not len(points) or value is None or not math.isfinite(value):
        return None
    index = np.arange(len(points), dtype=np.float64)
    if points[-1] < points[0]:  # a falling axis
        points, index = points[::-1], index[::-1]
    return float(np.interp(value, points, index))


class OperatingPoint(QObject):
    """Has ``hub`` measure ``inputs`` (the MEASUREMENT of each axis, X first) from :meth:`start` to :meth:`stop`
    and hands ``field.show_operating_point`` where they are on its breakpoints every :data:`REFRESH_MS`: a
    fractional index per axis, or None while nothing is measured or an input has no sample yet."""

    def __init__(self, hub, inputs: tuple[str, ...], field, parent: QObject | None = None):
        super().__init__(parent)
        self.hub, self.inputs, self.field = hub, tuple(inputs), field
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)

    def start(self) -> None:
        self.hub.show(self, self.inputs)
        self.timer.start()

    def stop(self) -> None:
        self.timer.stop()
        self.hub.hide(self)
        self.field.show_operating_point(None)

    def refresh(self) -> None:
        self.field.show_operating_point(self.position())

    def values(self) -> tuple[float, ...] | None:
        """The inputs' last values while they are measured (None: not measured, or one has no sample yet)."""
        if self.hub.acquisition is None:
            return None
        last = [self.hub.buffer(name).last() for name in self.inputs]
        return None if any(sample is None for sample in last) else tuple(float(value) for _, value in last)

    def position(self) -> tuple[float, ...] | None:
        values = self.values()
        model = self.field.model
        axes = (model.x_points, model.y_points)[:len(self.inputs)]
        if values is None or any(points is None for points in axes):
            return None
        position = tuple(axis_position(points, value) for points, value in zip(axes, values))
        return None if None in position else position
