"""A pyqtgraph axis whose tick labels never run together: pyqtgraph picks the spacing of its major ticks from the
axis' length alone and writes every major label, so a narrow plot's time axis read "142144146148"."""

from __future__ import annotations

import math

import pyqtgraph as pg
from PySide6.QtGui import QFontMetrics

__all__ = ["SpacedAxis"]

GAP_PX = 12  # between two labels along the axis
_STEPS = (1.0, 2.0, 5.0)


class SpacedAxis(pg.AxisItem):
    """Major ticks at 1, 2 or 5 times a power of ten, the smallest such spacing (from pyqtgraph's finest) whose
    labels stay :data:`GAP_PX` apart; only major ticks are labelled (the minor ones are grid lines)."""

    def __init__(self, orientation: str, **kwargs):
        super().__init__(orientation, **kwargs)
        self.setStyle(maxTextLevel=0)

    def tickSpacing(self, minVal, maxVal, size):  # noqa: N802 - pyqtgraph's name
        levels = super().tickSpacing(minVal, maxVal, size)
        span = maxVal - minVal
        if not levels or span <= 0 or size <= 0:
            return levels
        major = levels[-1][0]  # pyqtgraph's finest, then coarser until the labels have their room
        metrics = QFontMetrics(self.style["tickFont"] or self.font())
        horizontal = self.orientation in ("top", "bottom")
        for _ in range(30):  # a few steps up at most; bounded for absurd ranges
            if horizontal:
                texts = self.tickStrings([minVal, maxVal], 1.0, major)
                room = max(metrics.horizontalAdvance(text) for text in texts)
            else:
                room = metrics.height()
            if major * size / span >= room + GAP_PX:
                break
            major = _next_step(major)
        return [(major, 0), (major / (5.0 if _leading(major) == 5 else 2.0), 0)]


def _next_step(spacing: float) -> float:
    """The next of 1, 2, 5, 10, 20, ... times a power of ten above ``spacing``."""
    power = 10.0 ** math.floor(math.log10(spacing))
    for step in (*_STEPS, 10.0):
        if step * power > spacing * (1 + 1e-9):
            return step * power
    return 10.0 * power


def _leading(spacing: float) -> int:
    """1, 2 or 5: the digit of a spacing :func:`_next_step` gives."""
    return round(spacing / 10.0 ** math.floor(math.log10(spacing) + 1e-9))
