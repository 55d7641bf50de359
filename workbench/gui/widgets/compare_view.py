"""The compare view (CANape's "compare" window): two sets of calibration values side by side - the
working page against the reference page, the ECU against a parameter set, two parameter sets - one
row per object, the differing ones first shown; the selected object's differing elements below.
Double-click opens the object's editor; a parameter set compared with the ECU can be applied from here.
"""

from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPushButton,
    QSplitter,
    QTableView,
    QVBoxLayout,
    QWidget,
)

from workbench.gui import theme
from workbench.gui.a2l_info import value_decimals
from workbench.gui.models.compare import CompareFilter, CompareModel, ElementModel, no_decimals
from workbench.gui.widgets.columns import share_columns
from workbench.gui.widgets.elided_label import ElidedLabel

__all__ = ["CompareView"]

NOTHING_COMPARED = "nothing compared yet: Calibration ▸ Compare …"


class CompareView(QWidget):
    open_requested = Signal(str)  # an object's name (double-click)
    apply_requested = Signal()  # apply B (a parameter set) to the ECU
    refresh_requested = Signal()  # compare again

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.diff = None
        self.model = CompareModel(self)
        self.proxy = CompareFilter(self)
        self.proxy.setSourceModel(self.model)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        head = QHBoxLayout()  # what is compared and how many differ; the filter and commands below it
        self.sides = ElidedLabel(NOTHING_COMPARED, mode=Qt.ElideMiddle)
        self.sides.setStyleSheet(f"color: {theme.MUTED};")
        head.addWidget(self.sides, 1)
        self.summary = QLabel()
        self.summary.setStyleSheet(f"color: {theme.MUTED};")
        head.addWidget(self.summary)
        layout.addLayout(head)
        bar = QHBoxLayout()
        self.search = QLineEdit()
        self.search.setPlaceholderText("filter by name")
        self.search.setClearButtonEnabled(True)
        # its placeholder whole beside the buttons (it was cut to "fi…" with "Apply B to the ECU…" shown)
        self.search.setMinimumWidth(self.search.fontMetrics().horizontalAdvance("filter by name") + 48)
        self.search.textChanged.connect(lambda text: self.proxy.set_filter(search=text))
        bar.addWidget(self.search, 1)
        self.show_equal = QCheckBox("equal ones too")
        self.show_equal.toggled.connect(lambda on: self.proxy.set_filter(show_equal=on))
        bar.addWidget(self.show_equal)
        self.refresh_button = QPushButton("Compare again")
        self.refresh_button.clicked.connect(self.refresh_requested)
        self.refresh_button.setEnabled(False)
        bar.addWidget(self.refresh_button)
        self.apply_button = QPushButton("Apply B to the ECU…")
        self.apply_button.setToolTip("write the parameter set's values into the ECU (checked first, as cal load)")
        self.apply_button.clicked.connect(self.apply_requested)
        self.apply_button.setVisible(False)
        bar.addWidget(self.apply_button)
        layout.addLayout(bar)
        splitter = QSplitter(Qt.Vertical)
        self.table = QTableView()
        self.table.setModel(self.proxy)
        self.table.setSortingEnabled(True)
        self.table.sortByColumn(-1, Qt.AscendingOrder)
        self.table.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SingleSelection)
        self.table.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.table.setTextElideMode(Qt.ElideMiddle)
        self.table.verticalHeader().hide()
        self.table.verticalHeader().setDefaultSectionSize(22)
        self.table.setAlternatingRowColors(True)
        self.table.setShowGrid(False)
        self.table.setFont(theme.mono_font())
        # room between cells: B's value right-aligned beside the difference read as one ("MAP 6 x 5 8 values")
        self.table.setStyleSheet("QTableView::item { padding: 0px 6px; }")
        self.table.doubleClicked.connect(lambda index: self.open_requested.emit(index.data(Qt.UserRole).name))
        self.table.selectionModel().currentRowChanged.connect(self._show_elements)
        share_columns(self.table, (3, 1.3, 1.8, 1.8, 2.4))
        splitter.addWidget(self.table)
        self.elements = ElementModel(self)
        self.element_table = QTableView()
        self.element_table.setModel(self.elements)
        self.element_table.verticalHeader().hide()
        self.element_table.verticalHeader().setDefaultSectionSize(20)
        self.element_table.setFont(theme.mono_font(9))
        self.element_table.setShowGrid(False)
        share_columns(self.element_table, (2.5, 1.5, 1.5, 1.5))
        splitter.addWidget(self.element_table)
        splitter.setStretchFactor(0, 3)
        splitter.setStretchFactor(1, 1)
        layout.addWidget(splitter, 1)

    def set_a2l(self, model) -> None:
        """Show numbers with the decimals of ``model``'s display formats (the project's A2L)."""
        decimals = (lambda name, where: value_decimals(model, name, where)) if model is not None else no_decimals
        self.model.decimals = self.elements.decimals = decimals
        self.model.layoutChanged.emit()

    def show_diff(self, diff, *, can_apply: bool = False) -> None:
        """Show ``diff`` (a :class:`~workbench.calib.dataset.DatasetDiff`); ``can_apply``: B is a parameter set
        that may be written into the ECU (A is the ECU)."""
        self.diff = diff
        self.model.set_diff(diff)
        self.elements.show("", [])
        self.sides.setText(f"A: {diff.a_label}   ·   B: {diff.b_label}")
        counts = diff.counts()
        differing = len(diff.objects) - counts["equal"]
        self.summary.setText(f"{differing} of {len(diff.objects)} objects differ")
        self.summary.setStyleSheet(f"color: {theme.MUTED};")
        self.summary.setToolTip("")
        self.apply_button.setVisible(can_apply)
        self.refresh_button.setEnabled(True)
        first = self.proxy.index(0, 0)
        if first.isValid():
            self.table.setCurrentIndex(first)

    def clear(self) -> None:
        """Nothing compared (another project opens: the rows were the objects of the A2L before)."""
        self.diff = None
        self.model.set_rows([])
        self.elements.show("", [])
        self.sides.setText(NOTHING_COMPARED)
        self.summary.setText("")
        self.summary.setToolTip("")
        self.apply_button.setVisible(False)
        self.refresh_button.setEnabled(False)

    def mark_outdated(self, reason: str) -> None:
        """The ECU changed since it was compared (``reason``): the rows shown are no longer what it holds."""
        if self.diff is None or "outdated" in self.summary.text():
            return
        self.summary.setText(f"{self.summary.text()} · outdated: {reason}")
        self.summary.setStyleSheet(f"color: {theme.WARN};")
        self.summary.setToolTip("Compare again to see what the ECU holds now")

    def _show_elements(self, current, _previous=None) -> None:
        diff = current.data(Qt.UserRole) if current.isValid() else None
        shown = diff is not None and diff.status != "equal"
        self.elements.show(diff.name if shown else "", diff.differences if shown else [])

    def rows_shown(self) -> list[str]:
        """The names of the rows the filter lets through, in their order."""
        return [self.proxy.index(row, 0).data(Qt.UserRole).name for row in range(self.proxy.rowCount())]
