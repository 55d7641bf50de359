"""Cache synchronisation (thesis figure 39): the ECU's calibrations differ from the project's
reference (an s19's CAL ROM, a dataset). The user chooses *download* (reference -> ECU) or *upload*
(ECU -> reference); the expert view lists every differing object with both values."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from PySide6.QtWidgets import (
    QAbstractItemView,
    QDialog,
    QDialogButtonBox,
    QHeaderView,
    QLabel,
    QRadioButton,
    QTableWidget,
    QTableWidgetItem,
    QToolButton,
    QVBoxLayout,
)

from workbench.gui import theme

__all__ = ["SyncChoice", "SyncDialog", "SyncDifference"]


class SyncChoice(Enum):
    DOWNLOAD = "download"  # the reference's values into the ECU
    UPLOAD = "upload"  # the ECU's values into the reference


@dataclass(frozen=True)
class SyncDifference:
    name: str
    ecu: str  # the value as text
    reference: str


class SyncDialog(QDialog):
    def __init__(self, ecu_name: str, reference_name: str, differences: list[SyncDifference], parent=None):
        super().__init__(parent)
        self.setWindowTitle("Cache synchronization")
        layout = QVBoxLayout(self)
        layout.addWidget(QLabel(f"<b>The data in the ECU “{ecu_name}” differs from “{reference_name}”</b>"
                                f"<br>{len(differences)} object(s) differ. How do you want to proceed?"))
        self.download = QRadioButton(f"Download: write the values of “{reference_name}” into the ECU")
        self.upload = QRadioButton(f"Upload: take the ECU's values into “{reference_name}”")
        self.download.setChecked(True)
        layout.addWidget(self.download)
        layout.addWidget(self.upload)
        self.expert = QToolButton()
        self.expert.setText("Expert view ▸")
        self.expert.setCheckable(True)
        layout.addWidget(self.expert)
        self.table = QTableWidget(len(differences), 3)
        self.table.setHorizontalHeaderLabels(["object", "ECU", reference_name])
        self.table.verticalHeader().hide()
        self.table.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.Stretch)
        for row, diff in enumerate(differences):
            for column, text in enumerate((diff.name, diff.ecu, diff.reference)):
                item = QTableWidgetItem(text)
                if column:
                    item.setFont(theme.mono_font())
                self.table.setItem(row, column, item)
        self.table.setVisible(False)
        self.expert.toggled.connect(self.table.setVisible)
        self.expert.toggled.connect(lambda on: self.expert.setText("Expert view ▾" if on else "Expert view ▸"))
        layout.addWidget(self.table)
        buttons = QDialogButtonBox(QDialogButtonBox.Ok | QDialogButtonBox.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        layout.addWidget(buttons)

    @property
    def choice(self) -> SyncChoice:
        return SyncChoice.DOWNLOAD if self.download.isChecked() else SyncChoice.UPLOAD
