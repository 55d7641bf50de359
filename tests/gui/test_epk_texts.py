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


def test_the_epk_dialog_names_the_a2l_by_its_file_and_fits_a_small_screen(qtbot):
    path = "/projects/hds9/" + "calibration-release-candidates/" * 12 + "FLCU.a2l"  # ~1,200 px written whole
    dialog = EpkDialog(path, "FLCU demo ECU", "10300020250301", "08493820231002")
    qtbot.addWidget(dialog)
    names = [label for label in dialog.findChildren(QLabel) if label.text().endswith("FLCU.a2l")]
    assert [name.text() for name in names] == ["FLCU.a2l"] and path in names[0].toolTip()
    assert dialog.sizeHint().width() <= 1366 and dialog.minimumSizeHint().width() <= 1366
