"""The calibration editors' tabs on a laptop's screen: more editors than the dock shows scroll, and the arrows that
scroll them can be seen (the theme's tool-button padding left them blank: tabs cut at the left edge, no cue)."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QTabWidget, QToolButton, QWidget

from workbench.gui import theme


def _colours(widget) -> int:
    image = widget.grab().toImage()
    return len({image.pixel(x, y) for x in range(image.width()) for y in range(image.height())})


def test_the_scroll_arrows_of_tabs_that_do_not_fit_are_drawn(qtbot):
    tabs = QTabWidget()
    qtbot.addWidget(tabs)
    tabs.setStyleSheet(theme.STYLE_SHEET)
    tabs.setTabsClosable(True)
    tabs.setDocumentMode(True)  # as the window's editor tabs
    for name in ("xsSWITCH_TANK_THR", "xvPRV_DC_FF", "zvRailPConv", "cfENABLEFLCU_VALUE", "xsPRV_PWM_PERIOD"):
        tabs.addTab(QWidget(), name)
    tabs.resize(420, 200)
    tabs.show()
    qtbot.waitExposed(tabs)
    arrows = {button.arrowType(): button for button in tabs.tabBar().findChildren(QToolButton) if button.isVisible()}
    assert set(arrows) == {Qt.LeftArrow, Qt.RightArrow}
    assert all(_colours(button) > 2 for button in arrows.values())  # an arrow on its background, not blank
