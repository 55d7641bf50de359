"""A drop-down to type in: a real ECU's A2L has thousands of FUNCTIONs, too many to scroll through."""

from __future__ import annotations

import heapq
from collections.abc import Iterable

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QComboBox, QCompleter, QWidget

__all__ = ["SearchCombo"]


class SearchCombo(QComboBox):
    """A QComboBox whose entries are found by typing any part of them, in any case: the list under the field
    narrows to the entries that contain the text (a click or Enter takes one). Enter takes the entry named whole,
    or the only one left; a text that names none goes back to the chosen entry when the field is left, so the
    field always shows what is chosen. Choosing works as in a plain QComboBox (``currentIndexChanged``)."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setEditable(True)
        self.setInsertPolicy(QComboBox.NoInsert)  # typing only searches: no entry is added
        completer = QCompleter(self.model(), self)
        completer.setCompletionMode(QCompleter.PopupCompletion)
        completer.setFilterMode(Qt.MatchContains)
        completer.setCaseSensitivity(Qt.CaseInsensitive)
        completer.setMaxVisibleItems(15)
        self.setCompleter(completer)
        for view in (completer.popup(), self.view()):
            view.setTextElideMode(Qt.ElideMiddle)  # a name too long for the list keeps both ends
            view.setUniformItemSizes(True)  # not each of thousands of entries measured when the list shows
        self.lineEdit().editingFinished.connect(self._take_typed)

    def set_entries(self, entries: Iterable[tuple[str, object]]) -> None:
        """The entries (text, data) instead of those before, the first chosen, no signal emitted."""
        completer = self.completer()
        self.blockSignals(True)
        completer.setModel(None)  # else it follows each of thousands of insertions (2,600: 14 ms instead of 4)
        self.clear()
        for text, data in entries:
            self.addItem(text, data)
        completer.setModel(self.model())
        self.blockSignals(False)
        self._fit_lists()

    def _fit_lists(self, limit: int = 480) -> None:
        """The lists as wide as the longest entry, up to ``limit`` pixels: the field may be narrow in a dock, and
        FUNCTION names often differ only at their end."""
        metrics = self.fontMetrics()
        # the longest texts measured, not every one (each of 2,700 FUNCTIONs took 30 ms)
        longest = heapq.nlargest(20, (self.itemText(row) for row in range(self.count())), key=len)
        widest = max(map(metrics.horizontalAdvance, longest), default=0)
        width = min(widest + 2 * metrics.averageCharWidth() + self.view().verticalScrollBar().sizeHint().width(), limit)
        for view in (self.completer().popup(), self.view()):
            view.setMinimumWidth(width)

    def chosen_text(self) -> str:
        """The chosen entry's text (``currentText()`` is what the field shows, maybe a search)."""
        return self.itemText(self.currentIndex())

    def _take_typed(self) -> None:
        text = self.lineEdit().text()
        if text == self.chosen_text():
            return
        index = self.findText(text, Qt.MatchFixedString)  # the whole name, in any case
        if index < 0:
            completer = self.completer()
            completer.setCompletionPrefix(text)
            if completer.completionCount() == 1:
                index = self.findText(completer.currentCompletion(), Qt.MatchFixedString | Qt.MatchCaseSensitive)
        if index >= 0:
            self.setCurrentIndex(index)
        self.lineEdit().setText(self.chosen_text())
