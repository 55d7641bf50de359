"""Long signal names cut where they differ: ``CANRX_PCM_TO_FLCU_001_Pdu.DlcError`` in a narrow column reads
``CANRX_…001_Pdu.DlcError``, not ``CANRX_PCM…Pdu.DlcError`` (or ``CANRX_PCM_…``) like its neighbours.

Names of one ECU share their beginnings (a storage class, a module, a message) and differ at the end
(the signal, the element), so a name keeps its first word and as much of its end as fits. The cell's
tooltip (the model's) has the whole name.
"""

from __future__ import annotations

from PySide6.QtGui import QFontMetrics
from PySide6.QtWidgets import QStyle, QStyledItemDelegate, QStyleOptionViewItem

__all__ = ["NameDelegate", "elide_name"]

ELLIPSIS = "…"
HEAD_MAX = 8  # characters: a first word up to here is kept (CANRX_, csPCM_, PRVCtrl_), else two (zs…)
_SEPARATORS = "_."
_SAFETY = 3  # px: the style draws in a little less than its text rectangle (it would cut the text again)


def elide_name(name: str, metrics: QFontMetrics, width: int) -> str:
    """``name`` as it fits ``width`` pixels: whole, else its head, "…" and the longest tail that fits."""
    if metrics.horizontalAdvance(name) <= width:
        return name
    cuts = [name.find(separator) for separator in _SEPARATORS]
    cut = min((c for c in cuts if 0 < c < HEAD_MAX), default=1) + 1
    head = name[:cut]
    room = width - metrics.horizontalAdvance(head + ELLIPSIS)
    if room < metrics.horizontalAdvance(name[-4:]):  # no room for a head: the end is what tells names apart
        head, room = "", width - metrics.horizontalAdvance(ELLIPSIS)
    low, high = 0, len(name) - len(head)  # the longest tail within ``room``
    while low < high:
        middle = (low + high + 1) // 2
        if metrics.horizontalAdvance(name[-middle:]) <= room:
            low = middle
        else:
            high = middle - 1
    return head + ELLIPSIS + (name[-low:] if low else "")


class NameDelegate(QStyledItemDelegate):
    """Draws a column of names cut by :func:`elide_name`."""

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
        option.text = elide_name(option.text, option.fontMetrics, room)
        style.drawControl(QStyle.CE_ItemViewItem, option, painter, widget)
