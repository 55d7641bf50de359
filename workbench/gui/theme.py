"""The workbench's look: one dark theme for Qt widgets and pyqtgraph, and the signal colours.

Dark like the instrument panels calibration engineers stare at all day: a blue-grey background,
light text, saturated trace colours that stay apart on it, and status colours (good, warning,
bad) used the same way everywhere.
"""

from __future__ import annotations

from PySide6.QtGui import QColor, QFont, QPalette
from PySide6.QtWidgets import QApplication

__all__ = ["ACCENT", "BAD", "DISABLED", "GOOD", "MUTED", "STYLE_SHEET", "TRACE_COLOURS", "WARN", "apply", "trace_colour"]

BACKGROUND = "#15191f"
PANEL = "#1c2129"
RAISED = "#252b35"
BORDER = "#323a46"
TEXT = "#d6dbe2"
MUTED = "#8a94a3"
DISABLED = "#5a6370"  # what cannot be used now: dimmer than MUTED, which is for secondary text that can be read
ACCENT = "#3d9df3"
GOOD = "#3fbf72"
WARN = "#f0b429"
BAD = "#ef5350"
PLOT_BACKGROUND = "#0f1216"
GRID = "#232a33"  # opaque grid lines: blending translucent ones over the plot costs a quarter of a frame
GRID_ALPHA = 0.18
OPERATING_POINT = "#ffffff"  # a map's operating point: clear on every shade of its cells, blue to red

# traces: distinct on a dark background, the first ones the most distinct (Tableau 10, brightened)
TRACE_COLOURS = ("#4ea8ff", "#ffa53d", "#52d273", "#ff5c6c", "#b48cff", "#ffd84d", "#3fd6d6", "#ff7fc8",
                 "#a3d65c", "#c7a27a", "#8fb3ff", "#f08a5d")


def trace_colour(index: int) -> str:
    return TRACE_COLOURS[index % len(TRACE_COLOURS)]


STYLE_SHEET = f"""
QMainWindow, QDialog {{ background: {BACKGROUND}; }}
QWidget {{ color: {TEXT}; }}
QWidget:disabled {{ color: {DISABLED}; }}
QMenu::item:disabled {{ color: {DISABLED}; }}
QDockWidget {{ titlebar-close-icon: none; }}
QDockWidget::title {{ background: {RAISED}; padding: 5px 8px; border-bottom: 1px solid {BORDER};
                      font-weight: 600; }}
QToolBar {{ background: {PANEL}; border: none; border-bottom: 1px solid {BORDER}; spacing: 4px; padding: 3px; }}
QToolButton {{ padding: 4px 8px; border-radius: 4px; }}
QToolButton:hover {{ background: {RAISED}; }}
QToolButton:checked {{ background: #24466b; }}
QToolButton:checked:disabled {{ background: {RAISED}; }}
QStatusBar {{ background: {PANEL}; border-top: 1px solid {BORDER}; }}
QStatusBar QLabel {{ padding: 0 8px; }}
QLabel#badge {{ border-radius: 3px; padding: 1px 8px; font-weight: 600; }}
QHeaderView::section {{ background: {RAISED}; color: {MUTED}; border: none; border-right: 1px solid {BORDER};
                        border-bottom: 1px solid {BORDER}; padding: 3px 6px; font-weight: 600; }}
QTableView, QTreeView, QListView {{ background: {PANEL}; alternate-background-color: #20262f;
                                    gridline-color: {BORDER}; border: 1px solid {BORDER};
                                    selection-background-color: #24466b; selection-color: white; }}
QLineEdit, QSpinBox, QDoubleSpinBox, QComboBox {{ background: {RAISED}; border: 1px solid {BORDER};
                                                  border-radius: 4px; padding: 3px 6px; }}
QLineEdit:focus, QSpinBox:focus, QDoubleSpinBox:focus, QComboBox:focus {{ border-color: {ACCENT}; }}
QLineEdit:disabled {{ background: {PANEL}; color: {MUTED}; }}
QPushButton {{ background: {RAISED}; border: 1px solid {BORDER}; border-radius: 4px; padding: 5px 14px; }}
QPushButton:hover {{ border-color: {ACCENT}; }}
QPushButton:default {{ background: #24466b; border-color: {ACCENT}; }}
QPushButton:disabled {{ color: {MUTED}; }}
QTabWidget::pane {{ border: 1px solid {BORDER}; }}
QTabBar::tab {{ background: {PANEL}; padding: 5px 12px; border: 1px solid {BORDER}; border-bottom: none; }}
QTabBar::tab:selected {{ background: {RAISED}; color: white; }}
QTabBar QToolButton {{ padding: 0; border-radius: 0; background: {RAISED}; border: 1px solid {BORDER}; }}
QTabBar::scroller {{ width: 40px; }}
QProgressBar {{ background: {RAISED}; border: 1px solid {BORDER}; border-radius: 4px; text-align: center; }}
QProgressBar::chunk {{ background: {ACCENT}; border-radius: 3px; }}
QGroupBox {{ border: 1px solid {BORDER}; border-radius: 4px; margin-top: 14px; padding-top: 6px; }}
QGroupBox::title {{ subcontrol-origin: margin; left: 8px; color: {MUTED}; }}
QTableView::indicator {{ width: 13px; height: 13px; border: 1px solid {MUTED}; border-radius: 3px;
                         background: {RAISED}; }}
QTableView::indicator:checked {{ background: {WARN}; border-color: {WARN}; }}
QToolTip {{ background: {RAISED}; color: {TEXT}; border: 1px solid {BORDER}; }}
QSplitter::handle {{ background: {BORDER}; }}
"""


def apply(app: QApplication) -> None:
    """Give ``app`` the workbench's style, palette, font and pyqtgraph defaults."""
    import pyqtgraph as pg

    app.setStyle("Fusion")
    palette = QPalette()
    for role, colour in ((QPalette.Window, BACKGROUND), (QPalette.WindowText, TEXT), (QPalette.Base, PANEL),
                         (QPalette.AlternateBase, "#20262f"), (QPalette.Text, TEXT), (QPalette.Button, RAISED),
                         (QPalette.ButtonText, TEXT), (QPalette.Highlight, "#24466b"),
                         (QPalette.HighlightedText, "#ffffff"), (QPalette.ToolTipBase, RAISED),
                         (QPalette.ToolTipText, TEXT), (QPalette.PlaceholderText, MUTED), (QPalette.Link, ACCENT)):
        palette.setColor(role, QColor(colour))
    palette.setColor(QPalette.Disabled, QPalette.Text, QColor(MUTED))
    palette.setColor(QPalette.Disabled, QPalette.ButtonText, QColor(MUTED))
    app.setPalette(palette)
    font = QFont("DejaVu Sans", 10)
    font.setStyleHint(QFont.SansSerif)
    app.setFont(font)
    app.setStyleSheet(STYLE_SHEET)
    pg.setConfigOptions(background=PLOT_BACKGROUND, foreground=TEXT, antialias=False)


def mono_font(size: int = 10) -> QFont:
    """The font for values: fixed-width digits keep a changing number from jittering."""
    font = QFont("DejaVu Sans Mono", size)
    font.setStyleHint(QFont.Monospace)
    return font
