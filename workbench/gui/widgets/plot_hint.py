"""What the plot area shows while it holds no plot (an A2L opened on its own, the last plot closed): what to do, and
a place to drop signals that opens a plot of them."""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Qt
from PySide6.QtGui import QKeySequence
from PySide6.QtWidgets import QLabel

from workbench.gui import theme
from workbench.gui.mime import SignalDropTarget

__all__ = ["PlotHint"]


class PlotHint(SignalDropTarget, QLabel):
    """The hint; signals dropped on it (those ``hub`` knows) go to ``open_plot(names)``."""

    def __init__(self, hub, open_plot: Callable[[list[str]], object], new_plot_key: QKeySequence):
        QLabel.__init__(self, "Drop signals here from the variables (or double-click one) to plot them; New plot: "
                        f"{new_plot_key.toString(QKeySequence.NativeText)}")
        self.hub, self.open_plot = hub, open_plot
        self.setAlignment(Qt.AlignCenter)
        self.setWordWrap(True)
        self.setStyleSheet(f"color: {theme.MUTED};")
        self.setAcceptDrops(True)

    def add_signals(self, names: list[str]) -> None:
        self.open_plot(names)
