"""Long signal names cut so that the part that tells them apart stays: in a narrow column
``zsTank1Pressure``, ``zsTank2Pressure`` and ``zsManifoldPressure`` read ``zsTank1P…``, ``zsTank2P…`` and
``zsManifol…``, not ``zs…Pressure`` three times; ``CANRX_PCM_TO_FLCU_001_Pdu.DlcError`` reads
``CANRX_…001…Error`` beside its ``002`` twin, not ``CANRX_….DlcError`` twice.

A name is compared with the others its view shows: the characters where it leaves its neighbours in the
order of their beginnings and where its neighbours in the order of their ends join it are kept first, then
its first word (a storage class, a module, a message), then the word of the first of them and its end, as
much as fits; every gap is one "…". A name that still reads like another keeps other such characters.
Alone it keeps its first word and as much of its end as fits. The cell's tooltip (the model's) has the
whole name.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from PySide6.QtCore import QModelIndex
from PySide6.QtGui import QFontMetrics
from PySide6.QtWidgets import QAbstractItemView, QStyle, QStyledItemDelegate, QStyleOptionViewItem

__all__ = ["NameDelegate", "distinct_positions", "elide_name", "elide_names"]

ELLIPSIS = "…"
HEAD_MAX = 8  # characters: a first word up to here is kept (CANRX_, csPCM_, PRVCtrl_), else two (zs…)
_SEPARATORS = "_."
_SAFETY = 3  # px: the style draws in a little less than its text rectangle (it would cut the text again)


def distinct_positions(names: Iterable[str]) -> dict[str, tuple[int, ...]]:
    """For each of ``names``: the positions of the characters that tell it from its neighbours, the most alike
    first (where it leaves the names next to it in order of their beginnings, and where the names next to it
    in order of their ends join it)."""
    unique = sorted(set(names))
    backwards = sorted(unique, key=lambda name: name[::-1])
    found: dict[str, list[tuple[int, int]]] = {name: [] for name in unique}  # (overlap, position)
    for ordered, overlap, position in (
            (unique, _common_prefix, lambda name, n: min(n, len(name) - 1)),
            (backwards, lambda a, b: _common_prefix(a[::-1], b[::-1]), lambda name, n: max(len(name) - n - 1, 0))):
        for index, name in enumerate(ordered):
            for other in ordered[max(index - 1, 0):index + 2]:
                if other != name:
                    shared = overlap(name, other)
                    found[name].append((shared, position(name, shared)))
    return {name: tuple(dict.fromkeys(p for _, p in sorted(pairs, reverse=True))) for name, pairs in found.items()}


def elide_names(names: Sequence[str], metrics: QFontMetrics, width: int) -> dict[str, str]:
    """Each of ``names`` cut to ``width`` pixels by :func:`elide_name` so that, as far as the room allows, no two
    read alike: a name that reads like another keeps other characters that tell them apart."""
    positions = distinct_positions(names)
    shown = {name: elide_name(name, metrics, width, positions[name][:2]) for name in positions}
    readers: dict[str, int] = {}
    for text in shown.values():
        readers[text] = readers.get(text, 0) + 1
    for name, text in shown.items():
        if readers[text] < 2:
            continue
        kept = positions[name]
        for first in kept:
            other = elide_name(name, metrics, width, (first, max(kept)))
            if other not in readers:
                readers[text] -= 1
                readers[other] = 1
                shown[name] = other
                break
    return shown


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


class NameDelegate(QStyledItemDelegate):
    """Draws a column of names cut by :func:`elide_names`, each told from the others its view shows."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self._model = None
        self._shown: dict[tuple, dict[str, str]] = {}  # (column, rows shown, width) -> name -> text

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
        shown = self._texts(index, widget, option.fontMetrics, room)
        option.text = shown.get(option.text) or elide_name(option.text, option.fontMetrics, room)
        style.drawControl(QStyle.CE_ItemViewItem, option, painter, widget)

    def sizeHint(self, option, index):
        """The style's size and the room paint keeps spare: a column fitted to its contents cuts no name."""
        size = super().sizeHint(option, index)
        size.setWidth(size.width() + _SAFETY)
        return size

    def _texts(self, index: QModelIndex, view, metrics: QFontMetrics, width: int) -> dict[str, str]:
        """The names of ``index``'s column in the rows ``view`` shows, cut to ``width``: found once per scroll,
        resize or change of the rows."""
        model = index.model()
        if model is not self._model:
            if self._model is not None:
                self._connect(self._model, False)
            self._model = model
            self._connect(model, True)
            self._shown = {}
        top, bottom = 0, model.rowCount() - 1
        if isinstance(view, QAbstractItemView):
            viewport = view.viewport().rect()
            top = max(view.indexAt(viewport.topLeft()).row(), 0)
            last = view.indexAt(viewport.bottomLeft()).row()
            bottom = last if last >= 0 else bottom
        key = (index.column(), top, bottom, width)
        if key not in self._shown:
            if len(self._shown) > 64:
                self._shown = {}
            texts = (model.index(row, index.column()).data() for row in range(top, bottom + 1))
            self._shown[key] = elide_names([str(text) for text in texts if text], metrics, width)
        return self._shown[key]

    def _connect(self, model, on: bool) -> None:
        for signal, slot in ((model.modelReset, self._forget), (model.rowsInserted, self._forget),
                             (model.rowsRemoved, self._forget), (model.layoutChanged, self._forget),
                             (model.dataChanged, self._data_changed)):
            signal.connect(slot) if on else signal.disconnect(slot)

    def _forget(self, *_) -> None:
        self._shown = {}

    def _data_changed(self, top_left: QModelIndex, bottom_right: QModelIndex, *_) -> None:
        """Values change often (a legend's, 6 times a second), names seldom: only a names' column is forgotten."""
        columns = range(top_left.column(), bottom_right.column() + 1)
        self._shown = {key: texts for key, texts in self._shown.items() if key[0] not in columns}
