"""Table columns a user resizes and the project file remembers.

Until the user drags a column's edge, the columns share the table's width, so a table fits its dock on a
small screen as on a large one: a *fitted* column is as wide as its header and its texts (a kind, a unit),
the others share the rest by fixed proportions (the last one takes what is left), none narrower than its
header, so a header is never cut. A *capped* column takes no more than its texts need (the rest goes to the
others); an *optional* column (a description) is left out while it would be too narrow to read, its text
being in the rows' tooltips. Once the user resized a column, the widths are theirs and
:func:`column_widths` / :func:`set_column_widths` carry them through the project file.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence

from PySide6.QtCore import QEvent, QObject
from PySide6.QtWidgets import QAbstractItemView, QHeaderView

__all__ = ["column_widths", "refit_columns", "set_column_widths", "share_columns", "wanted_width"]

OPTIONAL_MIN = 120  # px: an optional column narrower than this tells nothing (its header aside)
_SLACK = 6  # px beyond the texts' own width: the cell's margins


class _Sharer(QObject):
    def __init__(self, view: QAbstractItemView, weights: Sequence[float], fit: Collection[int],
                 capped: Collection[int], optional: Collection[int], measure_on_change: bool):
        super().__init__(view)
        self.view, self.weights = view, tuple(weights)
        self.fit, self.capped, self.optional = set(fit), set(capped), tuple(optional)
        self.user_sized = False
        self.dropped: set[int] = set()  # optional columns this sharer hid (the owner hides others itself)
        self.texts: dict[int, int] = {}  # column -> its widest text, until the rows change
        self._setting = False
        model = view.model()
        for changed in (model.modelReset, model.rowsInserted, model.rowsRemoved, model.layoutChanged):
            if measure_on_change:
                changed.connect(lambda *_: self.texts.clear())
        header = view.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.Interactive)
        header.setStretchLastSection(True)
        header.setMinimumSectionSize(28)
        header.setDefaultSectionSize(40)  # a stretched last section never gets narrower than this
        header.sectionResized.connect(self._resized)
        header.sortIndicatorChanged.connect(lambda *_: self.share())  # the sorted header shows an arrow
        view.viewport().installEventFilter(self)

    def _resized(self, column: int, old: int, new: int) -> None:
        header = self.view.horizontalHeader()
        in_order = (header.logicalIndex(visual) for visual in range(header.count()))
        shown = [c for c in in_order if not header.isSectionHidden(c)]
        last = shown[-1] if shown else -1  # the one Qt stretches when the table resizes
        shown_or_hidden = not old or not new
        if not self._setting and column != last and not shown_or_hidden and self.view.isVisible():
            self.user_sized = True

    def share(self) -> None:
        if self.user_sized:
            return
        header = self.view.horizontalHeader()
        columns = [c for c in range(min(len(self.weights), header.count()))
                   if not header.isSectionHidden(c) or c in self.dropped]
        widths = self._widths(columns, self.view.viewport().width())
        self._setting = True
        try:
            for column in columns:
                dropped = column not in widths
                if dropped != header.isSectionHidden(column):
                    header.setSectionHidden(column, dropped)
                (self.dropped.add if dropped else self.dropped.discard)(column)
            shown = [c for c in columns if c in widths]
            for column in shown[:-1]:
                self.view.setColumnWidth(column, widths[column])
            if shown:  # the last takes what is left (Qt's stretch never shrinks it below its first size)
                self.view.setColumnWidth(shown[-1], max(widths[shown[-1]], self.view.viewport().width()
                                                        - sum(widths[c] for c in shown[:-1])))
        finally:
            self._setting = False

    def _widths(self, columns: list[int], width: int) -> dict[int, int]:
        """column -> width for ``columns`` in ``width`` pixels; the optional columns left out have none."""
        heads = {c: self._header_width(c) for c in columns}
        texts = {c: self._text_width(c) for c in columns if c in self.fit or c in self.capped}
        for dropping in range(len(self.optional) + 1):
            left_out = set(self.optional[:dropping])
            shown = [c for c in columns if c not in left_out]
            widths = {c: max(heads[c], texts[c]) for c in shown if c in self.fit}
            shared = [c for c in shown if c not in self.fit]
            room = width - sum(widths.values())
            while shared:  # by weight; a column below its header gets the header, a capped one above its texts
                total = sum(self.weights[c] for c in shared) or 1.0  # the texts: the others share the rest
                share = {c: room * self.weights[c] / total for c in shared}
                settled = ({c: heads[c] for c in shared if share[c] < heads[c]}
                           or {c: max(heads[c], texts[c]) for c in shared if c in self.capped and share[c] >= texts[c]})
                if not settled:
                    widths.update((c, int(share[c])) for c in shared)
                    break
                widths.update(settled)
                room -= sum(settled.values())
                shared = [c for c in shared if c not in settled]
            narrow = [c for c in self.optional[dropping:dropping + 1] if c in widths
                      and widths[c] < max(heads[c], OPTIONAL_MIN)]
            if not narrow:
                return widths
        return widths

    def _header_width(self, column: int) -> int:
        """The header's text in full; with room for the sort arrow only where it is shown."""
        header = self.view.horizontalHeader()
        width = header.sectionSizeFromContents(column).width()
        if header.isSortIndicatorShown() and header.sortIndicatorSection() != column:
            width -= header.sectionSizeFromContents(column).height()  # Qt's room for the arrow, on every section
        return width

    def _text_width(self, column: int) -> int:
        """The widest text of ``column`` (Qt looks at the rows in view and around, up to a thousand)."""
        if column not in self.texts:
            self.texts[column] = self.view.sizeHintForColumn(column) + _SLACK
        return self.texts[column]

    def eventFilter(self, watched, event) -> bool:
        if event.type() == QEvent.Resize:
            self.share()
        return False


def share_columns(view: QAbstractItemView, weights: Sequence[float], *, fit: Collection[int] = (),
                  capped: Collection[int] = (), optional: Sequence[int] = (), measure_on_change: bool = True) -> None:
    """``view``'s columns share its width by ``weights`` (one per column) until the user resizes one; ``fit``
    columns are as wide as their header and texts, ``capped`` ones no wider than their texts, ``optional``
    ones left out (in this order) while narrower than :data:`OPTIONAL_MIN`. The texts are measured again when the
    rows change, or (``measure_on_change`` False: a list the user filters, whose columns should not jump at each
    letter typed, nor measure a thousand rows then) only at :func:`refit_columns`."""
    view._column_sharer = _Sharer(view, weights, fit, capped, optional, measure_on_change)
    view._column_sharer.share()


def wanted_width(view: QAbstractItemView, caps: dict[int, int] | None = None) -> int:
    """The width ``view`` needs to show every shown column's header and texts (column -> at most ``caps``),
    frame and vertical scroll bar included: what a splitter may give it."""
    sharer, header = view._column_sharer, view.horizontalHeader()
    caps = caps or {}
    width = sum(min(max(sharer._header_width(c), sharer._text_width(c)), caps.get(c, 1 << 20))
                for c in range(header.count()) if not header.isSectionHidden(c))
    scroll = view.verticalScrollBar()
    return width + 2 * view.frameWidth() + (scroll.sizeHint().width() if scroll.isVisible() else 0)


def refit_columns(view: QAbstractItemView) -> None:
    """The texts of ``view`` changed (or which columns it shows): its shared widths again."""
    sharer = view._column_sharer
    sharer.texts.clear()
    sharer.share()


def column_widths(view: QAbstractItemView) -> list[int]:
    """The widths of ``view``'s columns the user gave them (for the project file); none while they are shared
    (kept, they would stop following the window: a project saved on a small screen opens on a large one)."""
    sharer = getattr(view, "_column_sharer", None)
    if sharer is not None and not sharer.user_sized:
        return []
    header = view.horizontalHeader()
    return [header.sectionSize(column) for column in range(header.count())]


def set_column_widths(view: QAbstractItemView, widths: Sequence[int]) -> None:
    """The widths a user chose (from the project file); the shared proportions no longer apply."""
    sharer = getattr(view, "_column_sharer", None)
    if sharer is not None:
        sharer.user_sized = True
        for column in sharer.dropped:  # the user's widths say what is shown
            view.horizontalHeader().setSectionHidden(column, False)
        sharer.dropped.clear()
    header = view.horizontalHeader()
    for column, width in enumerate(widths[: header.count()]):
        if isinstance(width, int) and width > 0:
            header.resizeSection(column, width)
