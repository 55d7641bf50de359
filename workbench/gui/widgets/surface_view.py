"""A map as a 3D surface, painted with QPainter: the grid of values projected (azimuth, elevation),
its quads filled in the table's colours and drawn back to front, axes labelled with the breakpoints.
Drag to turn it. No OpenGL, so it renders the same on every platform, offscreen screenshots included.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QSizePolicy, QWidget

from workbench.gui import theme
from workbench.gui.formatting import format_value
from workbench.gui.models.calibration_table import shade

__all__ = ["SurfaceView"]


class SurfaceView(QWidget):
    """``set_surface(values[x, y], x_points, y_points)``; ``azimuth``/``elevation`` in degrees."""

    def __init__(self, x_label: str = "X", y_label: str = "Y", unit: str = "", parent: QWidget | None = None):
        super().__init__(parent)
        self.x_label, self.y_label, self.unit = x_label, y_label, unit
        self.values = np.zeros((0, 0))
        self.x_points = self.y_points = np.zeros(0)
        self.point_text = lambda axis, point: format_value(float(point))
        self.value_text = lambda value: format_value(float(value))
        self.azimuth, self.elevation = 35.0, 28.0  # the corner of the first breakpoints in front
        self.operating_point: tuple[float, float] | None = None  # fractional indices (x, y) of the breakpoints
        self._drag: QPointF | None = None
        self.setMinimumSize(160, 120)
        self.setSizePolicy(QSizePolicy.Expanding, QSizePolicy.Expanding)
        self.setToolTip("drag to turn the map")

    def set_surface(self, values: np.ndarray, x_points, y_points, *, point_text=None, value_text=None) -> None:
        """``point_text(axis, point)`` and ``value_text(value)``: the labels' texts (the A2L's decimals; default
        six significant digits)."""
        self.values = np.asarray(values, dtype=np.float64)
        self.x_points = np.asarray(x_points, dtype=np.float64)
        self.y_points = np.asarray(y_points, dtype=np.float64)
        self.point_text = point_text or (lambda axis, point: format_value(float(point)))
        self.value_text = value_text or (lambda value: format_value(float(value)))
        self.update()

    def set_operating_point(self, position: tuple[float, float] | None) -> None:
        """A cross on the surface at ``position`` (fractional indices of the X and Y breakpoints; None: none)."""
        self.operating_point = position
        self.update()

    # --- geometry -------------------------------------------------------------------------------

    def _unit_cube(self) -> np.ndarray:
        """Grid points scaled into [-1, 1] on each axis: shape (nx, ny, 3)."""
        nx, ny = self.values.shape
        x = np.linspace(-1, 1, nx) if nx > 1 else np.zeros(1)
        y = np.linspace(-1, 1, ny) if ny > 1 else np.zeros(1)
        low, high = np.nanmin(self.values), np.nanmax(self.values)
        z = np.zeros_like(self.values) if high == low else (self.values - low) / (high - low) * 1.4 - 0.7
        gx, gy = np.meshgrid(x, y, indexing="ij")
        return np.stack([gx, gy, z], axis=-1)

    def _project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Screen x/y and depth of points (..., 3)."""
        a, e = np.radians(self.azimuth), np.radians(self.elevation)
        x, y, z = points[..., 0], points[..., 1], points[..., 2]
        rx = x * np.cos(a) - y * np.sin(a)
        ry = x * np.sin(a) + y * np.cos(a)
        depth = ry * np.cos(e) - z * np.sin(e)  # seen from above, looking along ry: larger is farther
        up = z * np.cos(e) + ry * np.sin(e)
        scale = min(self.width(), self.height()) * 0.3
        centre = np.array([self.width() / 2, self.height() / 2 + 6])
        screen = np.stack([centre[0] + rx * scale, centre[1] - up * scale], axis=-1)
        return screen, depth

    # --- painting -------------------------------------------------------------------------------

    def paintEvent(self, event) -> None:
        painter = QPainter(self)
        painter.setRenderHint(QPainter.Antialiasing)
        painter.fillRect(self.rect(), QColor(theme.PLOT_BACKGROUND))
        if self.values.ndim != 2 or min(self.values.shape) < 2:
            painter.setPen(QColor(theme.MUTED))
            painter.drawText(self.rect(), Qt.AlignCenter, "a 3D view needs a map")
            return
        grid = self._unit_cube()
        screen, depth = self._project(grid)
        floor = self._floor(grid)
        self._draw_floor(painter, floor)
        low, high = np.nanmin(self.values), np.nanmax(self.values)
        nx, ny = self.values.shape
        quads = [(i, j) for i in range(nx - 1) for j in range(ny - 1)]
        quads.sort(key=lambda q: depth[q[0]:q[0] + 2, q[1]:q[1] + 2].mean(), reverse=True)  # far ones first
        edge = QPen(QColor(theme.BACKGROUND), 1)
        for i, j in quads:
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            mean = np.mean([self.values[c] for c in corners])
            painter.setBrush(shade(0.5 if high == low else (mean - low) / (high - low)))
            painter.setPen(edge)
            painter.drawPolygon(QPolygonF([QPointF(*screen[c]) for c in corners]))
        self._draw_labels(painter, floor)
        at = self.operating_point_on_screen()
        if at is not None:  # over the surface, never hidden behind a hill: the user looks for it
            painter.setPen(QPen(QColor(theme.OPERATING_POINT), 2))
            painter.setBrush(Qt.NoBrush)
            painter.drawEllipse(at, 6, 6)
            painter.drawLine(at - QPointF(9, 0), at + QPointF(9, 0))
            painter.drawLine(at - QPointF(0, 9), at + QPointF(0, 9))

    def operating_point_on_screen(self) -> QPointF | None:
        """Where the operating point is drawn: on the surface, between the grid's points around it."""
        if self.operating_point is None or self.values.ndim != 2 or min(self.values.shape) < 2:
            return None
        grid = self._unit_cube()
        nx, ny = self.values.shape
        fx, fy = self.operating_point
        i, j = min(int(fx), nx - 2), min(int(fy), ny - 2)
        tx, ty = fx - i, fy - j
        point = ((1 - tx) * (1 - ty) * grid[i, j] + tx * (1 - ty) * grid[i + 1, j]
                 + (1 - tx) * ty * grid[i, j + 1] + tx * ty * grid[i + 1, j + 1])
        screen, _ = self._project(point[None])
        return QPointF(*screen[0])

    def _floor(self, grid: np.ndarray) -> np.ndarray:
        """The grid's points on the floor below the surface, on screen."""
        floor = grid.copy()
        floor[..., 2] = -0.8
        return self._project(floor)[0]

    def _draw_floor(self, painter: QPainter, floor: np.ndarray) -> None:
        nx, ny = self.values.shape
        painter.setPen(QPen(QColor(theme.BORDER), 1))
        for a, b in (((0, 0), (nx - 1, 0)), ((0, 0), (0, ny - 1)), ((nx - 1, 0), (nx - 1, ny - 1)),
                     ((0, ny - 1), (nx - 1, ny - 1))):
            painter.drawLine(QPointF(*floor[a]), QPointF(*floor[b]))

    def _draw_labels(self, painter: QPainter, floor: np.ndarray) -> None:
        painter.setPen(QColor(theme.MUTED))
        for rect, text in self.labels(floor, painter.fontMetrics()):
            painter.drawText(rect, Qt.AlignCenter, text)

    def labels(self, floor: np.ndarray | None = None, metrics=None) -> list[tuple[QRectF, str]]:
        """Where the labels go: the value range in the corner, the first and last breakpoint of each axis and
        its name outside the floor's edges (on top of the surface). One that would overlap another or leave the
        view is left out, the names first (the heat map's titles and the tooltip have them): on a small view the
        titles ran over the breakpoints."""
        if floor is None:
            floor = self._floor(self._unit_cube())
        metrics = metrics or self.fontMetrics()
        nx, ny = self.values.shape
        centre = floor.reshape(-1, 2).mean(axis=0)
        low, high = np.nanmin(self.values), np.nanmax(self.values)
        unit = f" {self.unit}" if self.unit else ""
        corner = f"{self.value_text(low)} … {self.value_text(high)}{unit}"
        wanted = [(QRectF(6, 2, metrics.horizontalAdvance(corner), metrics.height()), corner)]
        titles = []
        for axis, ends, points, title in ((0, ((0, 0), (nx - 1, 0)), self.x_points, self.x_label),
                                          (1, ((0, 0), (0, ny - 1)), self.y_points, self.y_label)):
            start, end = floor[ends[0]], floor[ends[1]]
            outward = (start + end) / 2 - centre
            outward = outward / (np.hypot(*outward) or 1.0)
            along = (end - start) / (np.hypot(*(end - start)) or 1.0)
            for at, index, inward in ((start, 0, along), (end, -1, -along)):  # off the corner the axes share
                text = self.point_text(axis, points[index]) if len(points) else ""
                shift = inward * (metrics.horizontalAdvance(text) / 2 * abs(inward[0]) + 4)
                wanted.append((self._centred(at + outward * 14 + shift, text, metrics), text))
            titles.append((self._centred((start + end) / 2 + outward * 32, title, metrics), title))
        placed: list[tuple[QRectF, str]] = []
        view = QRectF(self.rect())
        for rect, text in wanted + titles:
            if text and view.contains(rect) and not any(rect.intersects(other) for other, _ in placed):
                placed.append((rect, text))
        return placed

    @staticmethod
    def _centred(centre, text: str, metrics) -> QRectF:
        width, height = metrics.horizontalAdvance(text) + 2, metrics.height()
        return QRectF(centre[0] - width / 2, centre[1] - height / 2, width, height)

    # --- turning --------------------------------------------------------------------------------

    def mousePressEvent(self, event) -> None:
        self._drag = event.position()

    def mouseMoveEvent(self, event) -> None:
        if self._drag is None:
            return
        delta = event.position() - self._drag
        self._drag = event.position()
        self.azimuth = (self.azimuth + delta.x() * 0.5) % 360
        self.elevation = float(np.clip(self.elevation + delta.y() * 0.5, 5, 85))
        self.update()

    def mouseReleaseEvent(self, event) -> None:
        self._drag = None
