"""Cache synchronisation (thesis figure 39): the ECU's calibrations differ from the project's
reference (an s19's CAL ROM, a dataset). The user chooses to *keep* both as they are (the default:
nothing is written, so Enter or Escape never loses a value), *download* (reference -> ECU, overwrites
the ECU's working page) or *upload* (ECU -> a file the user picks). A few differing objects are listed
at once with both values in the A2L's format; many behind the expert view."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np
from PySide6.QtCore import Qt
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
from workbench.gui.a2l_info import value_decimals
from workbench.gui.models.compare import describe_value

__all__ = ["SHOWN_AT_ONCE", "SyncChoice", "SyncDialog", "SyncDifference", "sync_differences"]

SHOWN_AT_ONCE = 10  # up to these differing objects are listed without opening the expert view


class SyncChoice(Enum):
    KEEP = "keep"  # write nothing: work with the ECU's values, the reference stays as it is
    DOWNLOAD = "download"  # the reference's values into the ECU
    UPLOAD = "upload"  # the ECU's values into a file


@dataclass(frozen=True)
class SyncDifference:
    name: str
    ecu: str  # the value as text
    reference: str


def sync_differences(report, model=None) -> list[SyncDifference]:
    """The rows of a :class:`~workbench.sync.SyncReport`: each differing object with the ECU's and the reference's
    value as the other views show them (the A2L's decimals of ``model``, the unit; an array by its kind and shape
    and how many of its values differ), then the bytes that differ outside every object."""
    rows = []
    for diff in report.diff.objects:
        if diff.status == "equal":
            continue
        places = value_decimals(model, diff.name) if model is not None else None
        ecu, reference = describe_value(diff.b, places), describe_value(diff.a, places)
        if diff.b is not None and isinstance(diff.b.value, np.ndarray):
            count = len(diff.differences)
            ecu += f" ({count} value{'s differ' if count != 1 else ' differs'})"
        rows.append(SyncDifference(diff.name, ecu, reference))
    rows += [SyncDifference(f"{d.span.size} bytes at {d.span.start:06X}h", d.ecu.hex(" ").upper(),
                            d.reference.hex(" ").upper()) for d in report.outside]
    return rows


class SyncDialog(QDialog):
    def __init__(self, ecu_name: str, reference_name: str, differences: list[SyncDifference], parent=None):
        super().__init__(parent)
        self.setWindowTitle("Cache synchronization")
        layout = QVBoxLayout(self)
        count = len(differences)
        layout.addWidget(QLabel(f"<b>The data in the ECU “{ecu_name}” differs from “{reference_name}”</b>"
                                f"<br>{count} object{'s differ' if count != 1 else ' differs'}"
                                f"{':' if count <= SHOWN_AT_ONCE else ' (listed in the expert view).'}"))
        self.table = QTableWidget(count, 3)
        self.table.setHorizontalHeaderLabels(["object", "ECU", reference_name])
        self.table.verticalHeader().hide()
        self.table.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.table.setSelectionMode(QAbstractItemView.NoSelection)
        self.table.setFocusPolicy(Qt.NoFocus)  # Enter and the arrows stay with the choices
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.Stretch)  # the two values alike wide
        header.setSectionResizeMode(0, QHeaderView.ResizeToContents)
        for row, diff in enumerate(differences):
            for column, text in enumerate((diff.name, diff.ecu, diff.reference)):
                item = QTableWidgetItem(text)
                if column:
                    item.setFont(theme.mono_font())
                self.table.setItem(row, column, item)
        widest = max((self.table.sizeHintForColumn(c) for c in (1, 2)), default=0)
        self.table.setMinimumWidth(min(900, self.table.sizeHintForColumn(0) + 2 * widest + 24))
        if count <= SHOWN_AT_ONCE:  # all rows visible, no scrolling
            self.table.setFixedHeight(header.height() + self.table.verticalHeader().length()
                                      + 2 * self.table.frameWidth())
        layout.addWidget(self.table)
        layout.addWidget(QLabel("What should happen?"))
        self.keep = QRadioButton(f"Keep: work with the ECU's values, write nothing (the ECU and “{reference_name}” "
                                 "stay as they are)")
        self.download = QRadioButton(f"Download: write the values of “{reference_name}” into the ECU (overwrites "
                                     f"the ECU's value{'s' if count != 1 else ''} shown above)")
        self.upload = QRadioButton(f"Upload: save the ECU's values in a copy of “{reference_name}” (you choose the "
                                   "file, the project then uses it)")
        self.keep.setChecked(True)  # the default overwrites nothing: Enter or Escape never loses a value
        for button in (self.keep, self.download, self.upload):
            layout.addWidget(button)
            button.toggled.connect(self._name_ok)
        self.expert = QToolButton()
        self.expert.setText("Expert view ▸")
        self.expert.setCheckable(True)
        self.expert.setVisible(count > SHOWN_AT_ONCE)
        self.expert.toggled.connect(self.table.setVisible)
        self.expert.toggled.connect(lambda on: self.expert.setText("Expert view ▾" if on else "Expert view ▸"))
        self.table.setVisible(count <= SHOWN_AT_ONCE)
        layout.addWidget(self.expert)
        self.buttons = QDialogButtonBox(QDialogButtonBox.Ok | QDialogButtonBox.Cancel)
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        layout.addWidget(self.buttons)
        self._name_ok()

    @property
    def choice(self) -> SyncChoice:
        if self.download.isChecked():
            return SyncChoice.DOWNLOAD
        return SyncChoice.UPLOAD if self.upload.isChecked() else SyncChoice.KEEP

    def _name_ok(self) -> None:
        """The OK button says what it does."""
        self.buttons.button(QDialogButtonBox.Ok).setText(
            {SyncChoice.KEEP: "Keep", SyncChoice.DOWNLOAD: "Download into the ECU",
             SyncChoice.UPLOAD: "Upload into a file…"}[self.choice])
