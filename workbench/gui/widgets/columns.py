"""Table columns a user resizes and the project file remembers.

Until the user drags a column's edge, the columns share the table's width by fixed proportions (the
last one takes what is left), so a table fits its dock on a small screen as on a large one; once the
user resized one, the widths are theirs and :func:`column_widths` / :func:`set_column_widths` carry
them through the project file.
"""

from __future__ import annotations

from collections.abc import Sequence

from PySide6.QtCore import QEvent, QObject
from PySide6.QtWidgets import QAbstractItemView, QHeaderView

__all__ = ["column_widths", "set_column_widths", "share_columns"]


class _Sharer(QObject):
    def __init__(self, view: QAbstractItemView, weights: Sequence[float]):
        super().__init__(view)
        self.view, self.weights = view, tuple(weights)
        self.user_sized = False
        self._setting = False
        header = view.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.Interactive)
        header.setStretchLastSection(True)
        header.setMinimumSectionSize(28)
        header.setDefaultSectionSize(40)  # a stretched last section never gets narrower than this
        header.sectionResized.connect(self._resized)
        view.viewport().installEventFilter(self)

    def _resized(self, column: int, old: int, new: int) -> None:
        header = self.view.horizontalHeader()
        last = header.logicalIndex(header.count() - 1)  # the one Qt stretches when the table resizes
        shown_or_hidden = not old or not new
        if not self._setting and column != last and not shown_or_hidden and self.view.isVisible():
            self.user_sized = True

    def share(self) -> None:
        if self.user_sized:
            return
        width = self.view.viewport().width()
        header = self.view.horizontalHeader()
        shown = [c for c in range(min(len(self.weights), header.count())) if not header.isSectionHidden(c)]
        total = sum(self.weights[c] for c in shown) or 1.0
        self._setting = True
        try:
            left = width
            for column in shown[:-1]:
                size = max(28, int(width * self.weights[column] / total))
                self.view.setColumnWidth(column, size)
                left -= size
            if shown:  # the last takes what is left (Qt's stretch never shrinks it below its first size)
                self.view.setColumnWidth(shown[-1], max(28, left))
        finally:
            self._setting = False

    def eventFilter(self, watched, event) -> bool:
        if event.type() == QEvent.Resize:
            self.share()
        return False


def share_columns(view: QAbstractItemView, weights: Sequence[float]) -> None:
    """``view``'s columns share its width by ``weights`` (one per column) until the user resizes one."""
    view._column_sharer = _Sharer(view, weights)
    view._column_sharer.share()


def column_widths(view: QAbstractItemView) -> list[int]:
    """The widths of ``view``'s columns (for the project file)."""
    header = view.horizontalHeader()
    return [header.sectionSize(column) for column in range(header.count())]


def set_column_widths(view: QAbstractItemView, widths: Sequence[int]) -> None:
    """The widths a user chose (from the project file); the shared proportions no longer apply."""
    sharer = getattr(view, "_column_sharer", None)
    if sharer is not None:
        sharer.user_sized = True
    header = view.horizontalHeader()
    for column, width in enumerate(widths[: header.count()]):
        if isinstance(width, int) and width > 0:
            header.resizeSection(column, width)
