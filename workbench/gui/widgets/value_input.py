"""One rule for typing a calibration value, in every editor of the window.

- What is typed is what is written: the field takes any text (no range that drops a keystroke);
  Enter hands it on as typed, and the session's write checks it (limits, EXTENDED_LIMITS only when
  the user chose them) and refuses it with the limit named, before anything is sent.
- Enter writes, Esc restores what the ECU holds, leaving the field (Tab, a click elsewhere)
  restores it too: nothing is written without Enter (or a choice from the drop-down).
- A verbal value (TAB_VERB) is typed by its text (``Low``, any case) or its number, or chosen
  from the drop-down the field offers (the arrow at its right, or Alt+Down).
- Ctrl+Z while typing takes the typing back; with nothing typed it is the window's Undo (the last write).

:class:`ValueEdit` is the field (a scalar editor uses it as it is); :class:`ValueDelegate` puts the
same field into table cells (curves, maps, the fix panel) with the same keys.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from PySide6.QtCore import QEvent, QModelIndex, QPersistentModelIndex, Qt, Signal
from PySide6.QtGui import QAction, QKeyEvent, QKeySequence
from PySide6.QtWidgets import QCompleter, QLineEdit, QMenu, QStyle, QStyledItemDelegate, QWidget

from workbench.gui import theme
from workbench.gui.formatting import parse_typed

__all__ = ["ValueDelegate", "ValueEdit"]

_ENTER = (Qt.Key_Return, Qt.Key_Enter)
HINT = "Enter writes, Esc restores; leaving the field writes nothing"


class ValueEdit(QLineEdit):
    """A value's field: shows what the ECU holds, emits ``committed(value)`` on Enter (a float, or
    a state's text) or ``refused(reason)`` when the text is no value at all."""

    committed = Signal(object)
    refused = Signal(str)

    def __init__(self, states: Sequence[str] = (), parent: QWidget | None = None):
        super().__init__(parent)
        self.states = tuple(states)
        self.shown = ""  # the text of what the ECU holds
        self.typing = False  # typed since the value was shown, not yet handed on (Enter) or restored (Esc)
        self.setFont(theme.mono_font())
        self.setToolTip(HINT)
        self.textEdited.connect(self._typed)
        if self.states:
            completer = QCompleter(list(self.states), self)
            completer.setCaseSensitivity(Qt.CaseInsensitive)
            completer.setCompletionMode(QCompleter.InlineCompletion)  # no popup that would take the Enter
            self.setCompleter(completer)
            self.choices = QMenu(self)
            for state in self.states:
                self.choices.addAction(state, lambda s=state: self._chosen(s))
            self.drop_down = QAction(self.style().standardIcon(QStyle.SP_ArrowDown), "choose", self)
            self.drop_down.setToolTip(f"choose: {', '.join(self.states)} (Alt+Down)")
            self.drop_down.triggered.connect(self.open_choices)
            self.addAction(self.drop_down, QLineEdit.TrailingPosition)

    def show_value(self, text: str) -> None:
        """Show what the ECU holds (``committed`` does not follow); what is being typed stays until Enter/Esc."""
        self.shown = text
        if not self.typing:
            self.setText(text)
        self._mark()

    def open_choices(self) -> None:
        """The drop-down of every state (choosing one commits it)."""
        self.choices.popup(self.mapToGlobal(self.rect().bottomLeft()))

    @property
    def pending(self) -> bool:
        """Text typed that differs from what the ECU holds."""
        return self.text() != self.shown

    def commit(self) -> None:
        """Enter: the typed value to ``committed``, or why it is none to ``refused`` (unchanged text: nothing)."""
        if not self.pending:
            return
        try:
            value = parse_typed(self.text(), self.states)
        except ValueError as exc:
            self.refused.emit(str(exc))
            return
        self.typing = False  # handed on: the ECU's answer (read back, or the old value) replaces it
        self.committed.emit(value)

    def restore(self) -> None:
        """Esc or leaving: back to what the ECU holds."""
        self.typing = False
        self.setText(self.shown)
        self._mark()

    def _typed(self, *_) -> None:
        self.typing = True
        self._mark()

    def _chosen(self, text: str) -> None:
        self.setText(text)
        self.commit()

    def _mark(self, *_) -> None:
        self.setProperty("pending", self.pending)
        self.setStyleSheet(f"border: 1px solid {theme.WARN};" if self.pending else "")

    def event(self, event: QEvent) -> bool:
        """Ctrl+Z with nothing typed is not the field's: the window's Undo writes the value before the last write."""
        if (event.type() == QEvent.ShortcutOverride and not self.typing
                and (event.matches(QKeySequence.Undo) or event.matches(QKeySequence.Redo))):
            event.ignore()
            return False
        return super().event(event)

    def keyPressEvent(self, event: QKeyEvent) -> None:
        if event.key() in _ENTER:
            self.commit()
            return
        if event.key() == Qt.Key_Escape:
            self.restore()
            return
        if event.key() == Qt.Key_Down and event.modifiers() & Qt.AltModifier and self.states:
            self.open_choices()
            return
        super().keyPressEvent(event)

    def focusOutEvent(self, event) -> None:
        super().focusOutEvent(event)
        if event.reason() not in (Qt.PopupFocusReason, Qt.ActiveWindowFocusReason):
            self.restore()


class ValueDelegate(QStyledItemDelegate):
    """Table cells edited with a :class:`ValueEdit`: Enter hands the value to ``setData`` (the model
    asks the ECU), Esc and leaving the cell close it unwritten. ``states(index)`` gives a cell's
    verbal values (none: numbers). A text that is no value stays open with ``refused(reason)``."""

    refused = Signal(str)

    def __init__(self, parent=None, states: Callable[[QModelIndex], Sequence[str]] | None = None):
        super().__init__(parent)
        self.states = states or (lambda index: ())

    def createEditor(self, parent, option, index) -> ValueEdit:
        editor = ValueEdit(self.states(index), parent)
        editor.setFrame(False)
        editor.index = QPersistentModelIndex(index)
        editor.committed.connect(lambda value, e=editor: self._commit(e, value))
        editor.refused.connect(self.refused)
        return editor

    def setEditorData(self, editor: ValueEdit, index) -> None:
        editor.show_value(str(index.data(Qt.DisplayRole) or ""))  # what is being typed stays

    def setModelData(self, editor, model, index) -> None:
        """Qt's own commits (focus out, Tab) write nothing: only :meth:`_commit` (Enter) does."""

    def _commit(self, editor: ValueEdit, value) -> None:
        index = editor.index
        if index.isValid():
            index.model().setData(QModelIndex(index), value, Qt.EditRole)
        self.closeEditor.emit(editor, QStyledItemDelegate.NoHint)

    def updateEditorGeometry(self, editor, option, index) -> None:
        editor.setGeometry(option.rect)

    def eventFilter(self, editor, event) -> bool:
        if isinstance(editor, ValueEdit):
            if event.type() == QEvent.KeyPress:
                if event.key() == Qt.Key_Escape or (event.key() in _ENTER and not editor.pending):
                    self.closeEditor.emit(editor, QStyledItemDelegate.RevertModelCache)
                    return True
                if event.key() in _ENTER:
                    return False  # the field commits it through _commit
                if event.key() in (Qt.Key_Tab, Qt.Key_Backtab):
                    self.closeEditor.emit(editor, QStyledItemDelegate.RevertModelCache)
                    return True
            if event.type() == QEvent.FocusOut:
                if event.reason() not in (Qt.PopupFocusReason, Qt.ActiveWindowFocusReason):
                    self.closeEditor.emit(editor, QStyledItemDelegate.RevertModelCache)
                return False
        return super().eventFilter(editor, event)
