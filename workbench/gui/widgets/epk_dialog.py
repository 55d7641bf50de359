"""The software version check (thesis figure 37): the A2L's EPK differs from the ECU's. The user
chooses to flash the software that matches the A2L, to work read-only, or to disconnect. Where the A2L names
an EPK address in each part of the software (CALIB, APPLICATIVE), each part's EPK has a row of its own: a
calibration flashed onto another application shows as the one part that differs, and the flash dialog opens with
that part selected (the others stay: the flash compares the file with the EPK of what stays)."""

from __future__ import annotations

from collections.abc import Sequence
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING

from PySide6.QtWidgets import QDialog, QDialogButtonBox, QGridLayout, QLabel, QPushButton, QVBoxLayout

from workbench.errors import epk_text
from workbench.gui import theme
from workbench.gui.widgets.elided_label import ElidedLabel

if TYPE_CHECKING:
    from workbench.session.epk import EpkPart

__all__ = ["EpkChoice", "EpkDialog"]


class EpkChoice(Enum):
    FLASH = "flash"
    READ_ONLY = "read-only"
    DISCONNECT = "disconnect"


class EpkDialog(QDialog):
    def __init__(self, a2l_name: str, ecu_name: str, epk_a2l: str, epk_ecu: str, parent=None,
                 parts: Sequence[EpkPart] = ()):
        super().__init__(parent)
        self.setWindowTitle("Software version check")
        self.choice = EpkChoice.DISCONNECT
        layout = QVBoxLayout(self)
        # the parts of another build: what "Flash software…" selects (none named: the whole software)
        self.differing_parts = differing = [part.segment for part in parts if part.matches is False]
        what = (f"{' and '.join(differing)} in the ECU {'is' if len(differing) == 1 else 'are'} another build's"
                if differing and len(differing) < len(parts) else "The software in the ECU differs from the database")
        head = QLabel(f"<b>{what}.</b><br>What would you like to do?")
        layout.addWidget(head)
        grid = QGridLayout()
        for column, text in enumerate(("", "Database (A2L)", "ECU")):
            label = QLabel(f"<span style='color:{theme.MUTED}'>{text}</span>")
            grid.addWidget(label, 0, column)
        # the A2L by its file's name, the path in the tooltip: a whole path made the dialog ~1,200 px wide
        for column, (text, tip) in ((1, (Path(a2l_name).name, a2l_name)), (2, (ecu_name, ""))):
            name = ElidedLabel(minimum=120)
            name.setText(text or "—", tip if tip != text else "")
            name.setFont(theme.mono_font(11))
            grid.addWidget(name, 1, column)
        grid.addWidget(QLabel("name"), 1, 0)
        rows = [("EPK (EPROM identifier)", epk_a2l, epk_ecu)]
        rows += [(f"EPK in {part.segment} ({part.address:X}h)", part.a2l, part.ecu or "") for part in parts]
        for row, (caption, left, right) in enumerate(rows, 2):
            grid.addWidget(QLabel(caption), row, 0)
            for column, text in ((1, left), (2, right)):
                value = QLabel(epk_text(text) if text else "—")  # erased: not "ÿÿÿ"
                value.setFont(theme.mono_font(11))
                same = left.rstrip("\0 ") == right.rstrip("\0 ")
                value.setStyleSheet(f"color: {theme.GOOD if same else theme.BAD};")
                grid.addWidget(value, row, column)
        layout.addLayout(grid)
        explain = QLabel("Flash the software that matches the A2L, or work read-only: you can measure, but no "
                         "calibration is written to an ECU whose software the A2L does not describe.")
        explain.setWordWrap(True)
        explain.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(explain)
        buttons = QDialogButtonBox()
        self.flash_button = QPushButton("Flash software…")
        self.flash_button.setToolTip("open the flash dialog with " + (" and ".join(differing) if differing and len(
            differing) < len(parts) else "the whole software") + " selected")
        self.read_only_button = QPushButton("Work read-only")
        self.disconnect_button = QPushButton("Disconnect")
        buttons.addButton(self.flash_button, QDialogButtonBox.AcceptRole)
        buttons.addButton(self.read_only_button, QDialogButtonBox.AcceptRole)
        buttons.addButton(self.disconnect_button, QDialogButtonBox.RejectRole)
        self.flash_button.clicked.connect(lambda: self._choose(EpkChoice.FLASH))
        self.read_only_button.clicked.connect(lambda: self._choose(EpkChoice.READ_ONLY))
        self.disconnect_button.clicked.connect(lambda: self._choose(EpkChoice.DISCONNECT))
        self.read_only_button.setDefault(True)
        layout.addWidget(buttons)

    def _choose(self, choice: EpkChoice) -> None:
        self.choice = choice
        self.done(QDialog.Accepted if choice is not EpkChoice.DISCONNECT else QDialog.Rejected)
