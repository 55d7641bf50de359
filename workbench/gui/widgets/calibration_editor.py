"""A calibration editor: one CHARACTERISTIC, its value on the ECU's page, edited in physical units.

Every edit is written at once through the session (which checks the limits and reads the value
back) and the editor then shows what the ECU holds. Values that differ from the reference page
(the flashed CAL ROM) are marked. Each write is an undo step: undo writes the previous value back.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import Signal
from PySide6.QtGui import QUndoCommand, QUndoStack
from PySide6.QtWidgets import QHBoxLayout, QLabel, QToolButton, QVBoxLayout, QWidget

from workbench.gui import theme
from workbench.gui.a2l_info import CalibrationInfo
from workbench.gui.formatting import format_value
from workbench.gui.widgets.scalar_field import ScalarField
from workbench.gui.widgets.table_field import TableField

__all__ = ["CalibrationEditor"]


class _Write(QUndoCommand):
    def __init__(self, editor: "CalibrationEditor", old, new):
        super().__init__(f"{editor.info.name} = {_short(new)}")
        self.editor, self.old, self.new = editor, old, new

    def redo(self) -> None:
        self.editor.write(self.new)

    def undo(self) -> None:
        self.editor.write(self.old)


def _short(value) -> str:
    return format_value(value) if np.ndim(value) == 0 else f"{np.shape(value)} values"


class CalibrationEditor(QWidget):
    """Edits ``info.name`` through ``controller`` (an :class:`~workbench.gui.ecu.EcuController`)."""

    loaded = Signal(object)  # the value read (after every read-back)
    error = Signal(object)  # a refused write or failed read

    def __init__(self, controller, info: CalibrationInfo, parent: QWidget | None = None):
        super().__init__(parent)
        self.controller = controller
        self.info = info
        self.value = None  # the CalValue shown
        self.reference = None  # the reference page's value (physical), None when unknown
        self.undo_stack = QUndoStack(self)
        self._build()
        controller.written.connect(self._written_elsewhere)
        controller.page_changed.connect(lambda _: self.reload())
        controller.connected.connect(lambda _: self.reload())

    def _build(self) -> None:
        info = self.info
        layout = QVBoxLayout(self)
        layout.setContentsMargins(8, 6, 8, 6)
        head = QHBoxLayout()
        title = QLabel(f"<b>{info.name}</b> <span style='color:{theme.MUTED}'>{info.type}"
                       f"{' · ' + ', '.join(info.functions) if info.functions else ''}</span>")
        head.addWidget(title)
        head.addStretch(1)
        self.modified_badge = QLabel("modified")
        self.modified_badge.setObjectName("badge")
        self.modified_badge.setStyleSheet(f"background: {theme.WARN}; color: #1b1b1b;")
        self.modified_badge.setToolTip("differs from the reference page (the flashed calibration)")
        self.modified_badge.hide()
        head.addWidget(self.modified_badge)
        undo = QToolButton()
        undo.setText("Undo")
        undo.clicked.connect(self.undo_stack.undo)
        self.undo_stack.canUndoChanged.connect(undo.setEnabled)
        undo.setEnabled(False)
        redo = QToolButton()
        redo.setText("Redo")
        redo.clicked.connect(self.undo_stack.redo)
        self.undo_stack.canRedoChanged.connect(redo.setEnabled)
        redo.setEnabled(False)
        head.addWidget(undo)
        head.addWidget(redo)
        layout.addLayout(head)
        if info.description:
            description = QLabel(info.description)
            description.setStyleSheet(f"color: {theme.MUTED};")
            description.setWordWrap(True)
            layout.addWidget(description)
        if info.type in ("CURVE", "MAP", "VAL_BLK", "AXIS_PTS"):
            self.field = TableField(unit=info.unit, x_label=info.axis_labels[0] if info.axis_labels else "index",
                                    y_label=info.axis_labels[1] if len(info.axis_labels) > 1 else None)
            self.field.refused.connect(lambda reason: self.error.emit(ValueError(f"{info.name}: {reason}")))
            layout.addWidget(self.field, 1)
        else:
            self.field = ScalarField(unit=info.unit, limits=info.limits, decimals=info.decimals, step=info.step,
                                     states=list(info.states) or None, writable=info.writable)
            layout.addWidget(self.field)
            self.reference_label = QLabel()
            self.reference_label.setStyleSheet(f"color: {theme.MUTED};")
            layout.addWidget(self.reference_label)
            layout.addStretch(1)
        self.field.committed.connect(self.edit)
        self.status = QLabel()
        self.status.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(self.status)

    # --- reading --------------------------------------------------------------------------------

    def reload(self) -> None:
        """Read the value (and the reference page's) from the ECU."""
        self.controller.call("read_value", self.info.name, on_done=self._show, on_error=self._failed)
        self.controller.call("read", self.info.name, page="reference", on_done=self._show_reference,
                             on_error=lambda _: self._show_reference(None))

    def _written_elsewhere(self, name: str) -> None:
        if name == self.info.name:
            self.reload()

    def _show(self, value) -> None:
        self.value = value
        session = self.controller.session
        writable = self.info.writable and not (session is not None and session.read_only)
        if isinstance(self.field, TableField):
            axes = [a.values for a in value.axes]
            x = axes[0] if axes else np.arange(np.shape(value.value)[0])
            y = axes[1] if len(axes) > 1 else None
            self.field.show_value(np.asarray(value.value, dtype=np.float64), x, y, decimals=self.info.decimals,
                                  limits=self.info.limits, writable=writable)
            self.field.set_reference(self.reference)
        else:
            self.field.show_value(value.value)
            self.field.input.setEnabled(writable)
        self.status.setText("read-only: " + ("the ECU's EPK differs from the A2L's" if self.info.writable
                                             else "the A2L forbids calibrating it") if not writable else "")
        self._mark()
        self.loaded.emit(value)

    def _show_reference(self, reference) -> None:
        self.reference = reference
        if isinstance(self.field, TableField):
            self.field.set_reference(None if reference is None else np.asarray(reference, dtype=np.float64))
        else:
            self.reference_label.setText("" if reference is None else
                                         f"reference page: {format_value(reference, self.info.decimals)}"
                                         + (f" {self.info.unit}" if self.info.unit and not self.info.states else ""))
        self._mark()

    def _mark(self) -> None:
        if self.value is None or self.reference is None:
            self.modified_badge.hide()
            return
        current, reference = self.value.value, self.reference
        if isinstance(current, np.ndarray) or isinstance(reference, np.ndarray):
            same = np.shape(current) == np.shape(reference) and np.array_equal(
                np.asarray(current, dtype=np.float64), np.asarray(reference, dtype=np.float64), equal_nan=True)
        else:
            same = current == reference
        self.modified_badge.setVisible(not same)

    def _failed(self, exc: BaseException) -> None:
        self.status.setText(f"⚠ {exc}")
        self.error.emit(exc)

    # --- writing --------------------------------------------------------------------------------

    def edit(self, new) -> None:
        """The user's new value: written as an undo step."""
        if self.value is None:
            return
        self.undo_stack.push(_Write(self, self.value.value, new))

    def write(self, value) -> None:
        self.status.setText("writing …")
        self.controller.write(self.info.name, value, on_done=lambda _: self.status.setText(""),
                              on_error=self._refused)

    def _refused(self, exc: BaseException) -> None:
        self._failed(exc)
        self.reload()  # show what the ECU really holds
