"""An EPK in the window reads as the CLI's messages show it (workbench.errors.epk_text): an erased ECU says
"erased (14 bytes FF)", not 'ÿÿÿÿÿÿÿÿÿÿÿÿÿÿ'."""

from __future__ import annotations

from PySide6.QtWidgets import QLabel

from workbench.gui.widgets.epk_dialog import EpkDialog


def test_the_epk_dialog_says_an_erased_epk_is_erased(qtbot):
    dialog = EpkDialog("FLCU.a2l", "FLCU", "10300020250301", "\xff" * 14)
    qtbot.addWidget(dialog)
    texts = [label.text() for label in dialog.findChildren(QLabel)]
    assert "erased (14 bytes FF)" in texts and "'10300020250301'" in texts
    assert not any("\xff" in text for text in texts)
