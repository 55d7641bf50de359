"""The variable browser: search and filter every A2L object and CAN2 signal, drag them to views,
double-click (or Enter) to open the fitting view (a calibration editor, or a plot for a signal).
Down and Up in the search field go into the results, Up on the first result back to the search."""

from __future__ import annotations

from PySide6.QtCore import QEvent, QObject, Qt, Signal
from PySide6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QGridLayout,
    QLabel,
    QLineEdit,
    QTableView,
    QVBoxLayout,
    QWidget,
)

from workbench.gui import theme
from workbench.gui.models.variables import ALL, KIND_LABELS, Variable, VariableModel
from workbench.gui.widgets.columns import refit_columns, share_columns
from workbench.gui.widgets.names import NameDelegate
from workbench.gui.widgets.search_combo import SearchCombo

__all__ = ["VariableBrowser"]


class VariableBrowser(QWidget):
    open_requested = Signal(object)  # the Variable double-clicked (or Enter)

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.model = VariableModel(self)  # filters and sorts its rows itself (fast on 50,000 objects)
        self.left_out: list[str] = []  # why parts of the A2L's INSTANCEs are not listed
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        self.search = QLineEdit()
        self.search.setPlaceholderText("search names and descriptions (words, or a glob: xs*THR)")
        self.search.setToolTip(self.search.placeholderText())
        self.search.setClearButtonEnabled(True)
        self.search.textChanged.connect(lambda text: self.model.set_filters(search=text))
        self.search.installEventFilter(self)
        layout.addWidget(self.search)
        filters = QGridLayout()
        # a real ECU's A2L has thousands of FUNCTIONs and hundreds of units: found by typing a part of the name
        self.kind_box, self.function_box, self.unit_box = QComboBox(), SearchCombo(), SearchCombo()
        for column, (label, box, key) in enumerate((("kind", self.kind_box, "kind"),
                                                    ("function", self.function_box, "function"),
                                                    ("unit", self.unit_box, "unit"))):
            caption = QLabel(label)
            caption.setStyleSheet(f"color: {theme.MUTED};")
            filters.addWidget(caption, 0, column)
            box.setSizeAdjustPolicy(QComboBox.AdjustToMinimumContentsLengthWithIcon)  # a narrow dock: no cut
            box.setMinimumContentsLength(4)
            box.setToolTip(f"show one {label} only" + ("" if box is self.kind_box else ": type any part of its name"))
            filters.addWidget(box, 1, column)
            filters.setColumnStretch(column, 1)
            box.currentIndexChanged.connect(lambda _, b=box, k=key: self.model.set_filters(**{k: b.currentData()}))
        layout.addLayout(filters)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setSortingEnabled(True)
        self.table.sortByColumn(-1, Qt.AscendingOrder)  # the A2L's order (its modules) until a header is clicked
        self.table.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.table.setDragEnabled(True)
        self.table.setDragDropMode(QAbstractItemView.DragOnly)
        self.table.setAlternatingRowColors(True)
        self.table.setShowGrid(False)
        self.table.setTextElideMode(Qt.ElideRight)
        self.table.setItemDelegateForColumn(0, NameDelegate(self.table))  # names keep their distinct ends
        self.table.verticalHeader().hide()
        self.table.verticalHeader().setDefaultSectionSize(22)
        # name, kind, type, unit, functions, description: the name as wide as it needs while there is room,
        # kind and unit as their texts (of all rows: the widths stay while the user filters), the description what
        # is left (none when that is too little to read)
        share_columns(self.table, (3, 1, 1, 1, 1, 2), fit=(1, 3), capped=(0,), optional=(5,), measure_on_change=False)
        self.table.doubleClicked.connect(self._open)
        self.table.installEventFilter(self)
        layout.addWidget(self.table, 1)
        self.count = QLabel()
        self.count.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(self.count)
        self.model.modelReset.connect(self._count)

    def set_variables(self, rows: list[Variable], left_out: list[str] | None = None) -> None:
        """``rows`` listed (with the objects INSTANCEs stand for); ``left_out``: why parts of INSTANCEs could not be
        placed (a pointer, a missing typedef: one line each), which the count says rather than hiding them."""
        self.left_out = list(left_out or [])
        self.model.set_rows(rows)
        self._fill(self.kind_box, sorted({r.kind for r in rows}), KIND_LABELS)
        self._fill(self.function_box, sorted({f for r in rows for f in r.functions}))
        self._fill(self.unit_box, sorted({r.unit for r in rows if r.unit}))
        for column in (2, 4):  # type and functions: filters and tooltips tell them, the width is the name's
            self.table.setColumnHidden(column, True)
        refit_columns(self.table)
        self._count()

    def add_variables(self, rows: list[Variable]) -> None:
        """More rows (a measurement file's channels), the filters kept."""
        known = {row.name for row in self.model.all_rows}
        kind, function, unit = (box.currentData() for box in (self.kind_box, self.function_box, self.unit_box))
        self.set_variables(self.model.all_rows + [row for row in rows if row.name not in known], self.left_out)
        for box, value in ((self.kind_box, kind), (self.function_box, function), (self.unit_box, unit)):
            box.setCurrentIndex(max(box.findData(value), 0))

    def _fill(self, box: QComboBox, values: list[str], labels: dict | None = None) -> None:
        entries = [("all", ALL), *(((labels or {}).get(value, value), value) for value in values)]
        if isinstance(box, SearchCombo):
            box.set_entries(entries)
            return
        box.blockSignals(True)
        box.clear()
        for text, value in entries:
            box.addItem(text, value)
        box.blockSignals(False)  # "all": as the model starts its rows

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:
        """The keys between the search and the results: Down/Up into the results, Up from the first row back,
        Enter opens the current row as a double-click does (Qt's own Enter only emits ``activated``)."""
        if event.type() != QEvent.KeyPress or event.modifiers() & ~Qt.KeypadModifier:
            return super().eventFilter(watched, event)
        key, rows = event.key(), self.model.rowCount()
        if watched is self.search and key in (Qt.Key_Down, Qt.Key_Up) and rows:
            self._go_to_row(0 if key == Qt.Key_Down else rows - 1)
            return True
        if watched is self.table and key == Qt.Key_Up and self.table.currentIndex().row() <= 0:
            self.search.setFocus(Qt.OtherFocusReason)
            return True
        if watched is self.table and key in (Qt.Key_Return, Qt.Key_Enter) and self.table.currentIndex().isValid():
            self._open(self.table.currentIndex())
            return True
        return super().eventFilter(watched, event)

    def _go_to_row(self, row: int) -> None:
        index = self.model.index(row, 0)
        self.table.setFocus(Qt.OtherFocusReason)
        self.table.setCurrentIndex(index)  # whole rows are selected: this one
        self.table.scrollTo(index)

    def _open(self, index) -> None:
        self.open_requested.emit(index.data(Qt.UserRole))

    def variable(self, name: str) -> Variable | None:
        return self.model.variable(name)

    def reading(self, name: str | None) -> None:
        """The A2L ``name`` is being read (a large one takes seconds): said where the objects will be; None: over."""
        if name is None:
            self._count()
        else:
            self.count.setText(f"reading {name} …")

    def _count(self, *_) -> None:
        count = f"{self.model.rowCount():,} of {len(self.model.all_rows):,} objects"
        if self.left_out:
            count += f" · {len(self.left_out):,} INSTANCE parts left out"
        self.count.setText(count)
        self.count.setToolTip("\n".join(self.left_out[:20] + (["…"] if len(self.left_out) > 20 else [])))
