"""Long signal names cut so that the part that tells them apart stays: in a narrow column
``zsTank1Pressure``, ``zsTank2Pressure`` and ``zsManifoldPressure`` read ``zsTank1Pr…``, ``zsTank2Pr…``,
``zs…foldPressure``, not ``zs…Pressure`` three times; ``CANRX_PCM_TO_FLCU_001_Pdu.DlcError`` reads
``CANRX_…1_Pdu.D…Error`` beside its ``002`` twin and its ``…Pdu.Dlc`` sibling.

A name is compared with the others of its column (the rows shown): the first character where it leaves
the name sharing most of its beginning, and the last before the end it shares most with another, are
kept first; then its first word (a storage class, a module, a message), then its end and the context of
those characters, as much as fits; every gap is one "…". Without other names it keeps its first word and
as much of its end as fits. The cell's tooltip (the model's) has the whole name.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from PySide6.QtCore import QModelIndex
from PySide6.QtGui import QFontMetrics
from PySide6.QtWidgets import QStyle, QStyledItemDelegate, QStyleOptionViewItem

__all__ = ["NameDelegate", "distinct_positions", "elide_name"]

ELLIPSIS = "…"
HEAD_MAX = 8  # characters: a first word up to here is kept (CANRX_, csPCM_, PRVCtrl_), else two (zs…)
_SEPARATORS = "_."
_SAFETY = 3  # px: the style draws in a little less than its text rectangle (it would cut the text again)


def distinct_positions(names: Iterable[str]) -> dict[str, tuple[int, ...]]:
    """For each of ``names``: the positions of the characters that tell it from the others (where it leaves
    the one that shares most of its beginning, and where the one that shares most of its end joins it)."""
    unique = sorted(set(names))
    if len(unique) < 2:
        return {name: () for name in unique}
    prefix = _neighbour_overlap(unique, lambda a, b: _common_prefix(a, b))
    backwards = sorted(unique, key=lambda name: name[::-1])
    suffix = _neighbour_overlap(backwards, lambda a, b: _common_prefix(a[::-1], b[::-1]))
    positions = {}
    for name in unique:
        first = min(prefix[name], len(name) - 1)
        last = max(len(name) - suffix[name] - 1, 0)
        positions[name] = tuple(sorted({first, last}))
    return positions


def elide_name(name: str, metrics: QFontMetrics, width: int, distinct: Sequence[int] = ()) -> str:
    """``name`` as it fits ``width`` pixels: whole; else its head, "…" and the longest end that fits, when that
    end keeps its characters at ``distinct`` (:func:`distinct_positions`); else its head, the word of the first
    of them, and its end from the last of them on, each gap one "…" (``CANRX_…001_…cError``)."""
    if metrics.horizontalAdvance(name) <= width:
        return name

    def fits(text: str) -> bool:
        return metrics.horizontalAdvance(text) <= width

    cuts = [name.find(separator) for separator in _SEPARATORS]
    head = name[:min((c for c in cuts if 0 < c < HEAD_MAX), default=1) + 1]
    first, last = (min(distinct), max(distinct)) if distinct else (len(name), len(name))
    word_start, word_end = _word(name, first)
    end = last if last >= word_end else len(name)  # the end kept from here (none: the word tells it)
    for lead in (head, ""):
        tail = _longest(len(lead), len(name), lambda t, lead=lead: fits(_cut(name, lead, t, t, t)))
        if tail <= first and fits(_cut(name, lead, tail, tail, tail)):
            return _cut(name, lead, tail, tail, tail)  # one gap: the end tells it
        for start in (max(word_start, len(lead)), max(first, len(lead))):
            middle = first + 1
            if not fits(_cut(name, lead, start, middle, end)):
                continue
            while middle < min(word_end, end) and fits(_cut(name, lead, start, middle + 1, end)):
                middle += 1  # the rest of the word first
            grown = True
            while grown:  # then the end and the middle by turns
                grown = False
                if end - 1 >= middle and fits(_cut(name, lead, start, middle, end - 1)):
                    end, grown = end - 1, True
                if middle + 1 <= end and fits(_cut(name, lead, start, middle + 1, end)):
                    middle, grown = middle + 1, True
            return _cut(name, lead, start, middle, end)
    tail = _longest(0, len(name), lambda t: fits(_cut(name, "", t, t, t)))
    return _cut(name, "", tail, tail, tail)


def _cut(name: str, lead: str, start: int, middle: int, end: int) -> str:
    """``lead``, ``name[start:middle]`` and ``name[end:]``, a "…" for each gap between them."""
    text = lead + (ELLIPSIS if start > len(lead) else "") + name[start:middle]
    return text + (ELLIPSIS if middle < end else "") + name[max(end, middle):]


def _longest(low: int, high: int, fits) -> int:
    """The smallest start in ``low..high`` whose end fits (``high`` when none)."""
    while low < high:
        half = (low + high) // 2
        if fits(half):
            high = half
        else:
            low = half + 1
    return high


def _word(name: str, index: int) -> tuple[int, int]:
    """The word around ``index``: ``Tank1`` of ``zsTank1Pressure``, ``001`` of ``..._001_Pdu``."""
    def boundary(i: int) -> bool:  # a word starts at i
        return i <= 0 or i >= len(name) or name[i - 1] in _SEPARATORS or name[i] in _SEPARATORS or (
            name[i].isupper() and name[i - 1].islower())

    start = index
    while not boundary(start):
        start -= 1
    end = index + 1
    while not boundary(end):
        end += 1
    return max(start, 0), min(end, len(name))


def _common_prefix(a: str, b: str) -> int:
    n = 0
    for x, y in zip(a, b):
        if x != y:
            break
        n += 1
    return n


def _neighbour_overlap(ordered: list[str], overlap) -> dict[str, int]:
    """For each name of ``ordered`` (sorted so that the most alike are neighbours): its largest overlap."""
    result = {}
    for index, name in enumerate(ordered):
        before = overlap(name, ordered[index - 1]) if index else 0
        after = overlap(name, ordered[index + 1]) if index + 1 < len(ordered) else 0
        result[name] = max(before, after)
    return result


class NameDelegate(QStyledItemDelegate):
    """Draws a column of names cut by :func:`elide_name`, each told from the others of its column."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self._model = None
        self._positions: dict[int, dict[str, tuple[int, ...]]] = {}  # column -> name -> distinct positions

    def paint(self, painter, option, index) -> None:
        option = QStyleOptionViewItem(option)
        self.initStyleOption(option, index)
        widget = option.widget
        style = widget.style() if widget is not None else None
        if style is None or not option.text:
            super().paint(painter, option, index)
            return
        text_rect = style.subElementRect(QStyle.SE_ItemViewItemText, option, widget)
        margin = style.pixelMetric(QStyle.PM_FocusFrameHMargin, None, widget) + 1
        room = text_rect.width() - 2 * margin - _SAFETY
        option.text = elide_name(option.text, option.fontMetrics, room, self._distinct(index).get(option.text, ()))
        style.drawControl(QStyle.CE_ItemViewItem, option, painter, widget)

    def _distinct(self, index: QModelIndex) -> dict[str, tuple[int, ...]]:
        """The distinct positions of the names in ``index``'s column, found again when its rows change."""
        model = index.model()
        if model is not self._model:
            if self._model is not None:
                self._connect(self._model, False)
            self._model = model
            self._connect(model, True)
            self._positions = {}
        column = index.column()
        if column not in self._positions:
            texts = (model.index(row, column).data() for row in range(model.rowCount()))
            self._positions[column] = distinct_positions(str(text) for text in texts if text)
        return self._positions[column]

    def _connect(self, model, on: bool) -> None:
        for signal, slot in ((model.modelReset, self._forget), (model.rowsInserted, self._forget),
                             (model.rowsRemoved, self._forget), (model.layoutChanged, self._forget),
                             (model.dataChanged, self._data_changed)):
            signal.connect(slot) if on else signal.disconnect(slot)

    def _forget(self, *_) -> None:
        self._positions = {}

    def _data_changed(self, top_left: QModelIndex, bottom_right: QModelIndex, *_) -> None:
        """Values change often (a legend's, 6 times a second), names seldom: only a names' column is forgotten."""
        for column in range(top_left.column(), bottom_right.column() + 1):
            self._positions.pop(column, None)
