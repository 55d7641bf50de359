"""A map as a 3D surface, painted with QPainter: the grid of values projected (azimuth, elevation),
its quads filled in the table's colours and drawn back to front, axes labelled with the breakpoints.
Drag to turn it. No OpenGL, so it renders the same on every platform, offscreen screenshots included.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, Qt
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
        self.azimuth, self.elevation = -55.0, 28.0
        self._drag: QPointF | None = None
        self.setMinimumSize(160, 120)
        self.setSizePolicy(QSizePolicy.Expanding, QSizePolicy.Expanding)
        self.setToolTip("drag to turn the map")

    def set_surface(self, values: np.ndarray, x_points, y_points) -> None:
        self.values = np.asarray(values, dtype=np.float64)
        self.x_points = np.asarray(x_points, dtype=np.float64)
        self.y_points = np.asarray(y_points, dtype=np.float64)
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
        depth = ry * np.cos(e) + z * np.sin(e)
        up = z * np.cos(e) - ry * np.sin(e)
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
        self._draw_axes(painter, grid)
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

    def _draw_axes(self, painter: QPainter, grid: np.ndarray) -> None:
        """The floor's two edges with the breakpoints, and the value range beside the vertical edge."""
        floor = grid.copy()
        floor[..., 2] = -0.8
        screen, _ = self._project(floor)
        painter.setPen(QPen(QColor(theme.BORDER), 1))
        nx, ny = self.values.shape
        for a, b in (((0, 0), (nx - 1, 0)), ((0, 0), (0, ny - 1)), ((nx - 1, 0), (nx - 1, ny - 1)),
                     ((0, ny - 1), (nx - 1, ny - 1))):
            painter.drawLine(QPointF(*screen[a]), QPointF(*screen[b]))
        painter.setPen(QColor(theme.MUTED))
        metrics = painter.fontMetrics()
        for i in (0, nx - 1):
            self._label(painter, screen[i, 0], format_value(float(self.x_points[i])) if i < len(self.x_points) else "",
                        metrics, below=True)
        for j in (ny - 1,):
            self._label(painter, screen[0, j], format_value(float(self.y_points[j])) if j < len(self.y_points) else "",
                        metrics, below=True)
        self._label(painter, (screen[nx - 1, 0] + screen[0, 0]) / 2, self.x_label, metrics, below=True, offset=16)
        self._label(painter, (screen[0, ny - 1] + screen[0, 0]) / 2, self.y_label, metrics, below=True, offset=16)
        low, high = np.nanmin(self.values), np.nanmax(self.values)
        unit = f" {self.unit}" if self.unit else ""
        painter.drawText(6, metrics.height(), f"{format_value(low)} … {format_value(high)}{unit}")

    @staticmethod
    def _label(painter: QPainter, at, text: str, metrics, below: bool, offset: int = 4) -> None:
        width = metrics.horizontalAdvance(text)
        y = at[1] + (metrics.ascent() + offset if below else -offset)
        painter.drawText(QPointF(at[0] - width / 2, y), text)

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
