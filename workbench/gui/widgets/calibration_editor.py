"""A calibration editor: one CHARACTERISTIC, its value on the ECU's page, edited in physical units.

Every edit (Enter, see :mod:`~workbench.gui.widgets.value_input`) is written at once through the
session, which checks it before anything is sent and reads the value back; the editor then shows
what the ECU holds. A value the session refuses (beyond the limits, not one of the texts ...) is
said in the editor's status line, with the limit, and the ECU keeps its value. Values that differ
from the reference page (the flashed CAL ROM) are marked. Each write is an undo step: undo writes
the previous value back.

Before a connection, the editor shows the value the project's s19/hex holds (``offline``, a
:class:`~workbench.gui.file_values.FileValues`), its status line naming the file, and edits it there as CANape
edits an offline dataset: checked as online, written into the image in memory (``offline_written`` tells the
window, which marks the image modified and saves it with File > Save image); the ECU's value replaces it once
connected, and the editor is the ECU's from then on (after a disconnect it keeps the ECU's value, read-only).

While nothing can be written (not connected, the connection lost, the reference page active, a read-only
session) the editor is read-only and greyed, its tooltip and status line say why; a write tried then is
refused at once ("not written: not connected"). A write under way when the connection is lost ends with
"not written" in the editor (badge and status line, kept after reconnecting until the next write) while the
field shows what the ECU holds.
"""

from __future__ import annotations

import os

import numpy as np
from PySide6.QtCore import QRect, Qt, Signal
from PySide6.QtGui import QUndoCommand, QUndoStack
from PySide6.QtWidgets import QHBoxLayout, QLabel, QSizePolicy, QToolButton, QVBoxLayout, QWidget

from workbench.errors import LimitsError
from workbench.gui import theme
from workbench.gui.a2l_info import CalibrationInfo
from workbench.gui.ecu import IN_BOOT, READ_ONLY_PAGE, NotWrittenError, refusal
from workbench.gui.formatting import format_value
from workbench.gui.widgets.elided_label import ElidedLabel
from workbench.gui.widgets.operating_point import OperatingPoint
from workbench.gui.widgets.scalar_field import ScalarField
from workbench.gui.widgets.table_field import TableField
from workbench.gui.worker import run_task

__all__ = ["CalibrationEditor"]


class _Write(QUndoCommand):
    """A write the ECU took: undo writes the old value back, redo the new one again."""

    def __init__(self, editor: "CalibrationEditor", old, new):
        super().__init__(_change_text(editor.info.name, old, new))
        self.editor, self.old, self.new = editor, old, new
        self.written = True  # pushed after the write: the stack's first redo() must not write again

    def redo(self) -> None:
        if self.written:
            self.written = False
            return
        self.editor.write(self.new)

    def undo(self) -> None:
        self.editor.write(self.old)


def _short(value) -> str:
    return format_value(value) if np.ndim(value) == 0 else f"{np.shape(value)} values"


def _change_text(name: str, old, new) -> str:
    """An undo step as Edit > Undo names it: a scalar's new value, or how many of an array's values changed."""
    if np.ndim(new) == 0:
        return f"{name} = {_short(new)}"
    old, new = np.asarray(old, dtype=np.float64), np.asarray(new, dtype=np.float64)
    changed = np.count_nonzero(old != new) if old.shape == new.shape else new.size
    return f"{name}: {changed} of {new.size} values"


class CalibrationEditor(QWidget):
    """Edits ``info.name`` through ``controller`` (an :class:`~workbench.gui.ecu.EcuController`). With a ``hub``
    (:class:`~workbench.gui.signal_hub.SignalHub`), a curve or map whose every axis has an input measurement
    shows its operating point (:mod:`.operating_point`) until :meth:`release`."""

    loaded = Signal(object)  # the value read (after every read-back)
    error = Signal(object)  # a failed read or write the ECU is to blame for (the window shows a dialog)
    refused = Signal(str)  # a value not written: why (also in the status line)
    offline_written = Signal(str)  # a value written into the project's image offline (the object's name)

    def __init__(self, controller, info: CalibrationInfo, parent: QWidget | None = None, hub=None, offline=None):
        super().__init__(parent)
        self.controller = controller
        self.info = info
        self.offline = offline  # FileValues: the value shown before a connection (None: none)
        self.value = None  # the CalValue shown
        self.value_source = ""  # the file the value shown comes from ("": the ECU, or nothing shown)
        self.reference = None  # the reference page's value (physical), None when unknown
        self.undo_stack = QUndoStack(self)
        self.unwritten = ""  # a write the connection's loss cut off: what and why (until the next write)
        self._message = ("", theme.MUTED)  # a refusal or failure (until the next write or page change)
        self._writing = False
        self._build()
        self.operating_point: OperatingPoint | None = None
        if hub is not None and isinstance(self.field, TableField) and info.axis_inputs and all(info.axis_inputs):
            self.operating_point = OperatingPoint(hub, info.axis_inputs, self.field, self)
            self.operating_point.start()
        controller.written.connect(self._written_elsewhere)
        controller.page_changed.connect(self._page_changed)
        controller.connected.connect(self._connected)
        controller.disconnected.connect(self._update_writable)
        self._update_writable()

    def _build(self) -> None:
        info = self.info
        layout = QVBoxLayout(self)
        layout.setContentsMargins(8, 6, 8, 6)
        head = QHBoxLayout()
        kind_text = f"{info.type}{' · ' + ', '.join(info.functions) if info.functions else ''}"
        self.title = ElidedLabel(mode=Qt.ElideMiddle, minimum=60)
        self.title.setStyleSheet("font-weight: 600;")
        self.title.setText(info.name, "\n".join(t for t in (kind_text, info.description) if t))
        head.addWidget(self.title)
        kind = ElidedLabel(kind_text, mode=Qt.ElideRight, minimum=0)
        kind.setSizePolicy(QSizePolicy.Ignored, QSizePolicy.Preferred)  # gives way first: the name stays whole
        kind.setStyleSheet(f"color: {theme.MUTED};")
        head.addWidget(kind, 1)
        self.modified_badge = QLabel("modified")  # or "not written" (a write the connection's loss cut off)
        self.modified_badge.setObjectName("badge")
        keep_place = self.modified_badge.sizePolicy()
        keep_place.setRetainSizeWhenHidden(True)  # appearing must not move the buttons beside it
        self.modified_badge.setSizePolicy(keep_place)
        self.modified_badge.hide()
        head.addWidget(self.modified_badge)
        self.undo_button = undo = QToolButton()  # Edit > Undo/Redo of the window too (Ctrl+Z, Ctrl+Shift+Z)
        undo.setText("Undo")
        undo.setToolTip("write back the value before the last write (Ctrl+Z)")
        undo.clicked.connect(self.undo_stack.undo)
        self.undo_stack.canUndoChanged.connect(undo.setEnabled)
        undo.setEnabled(False)
        self.redo_button = redo = QToolButton()
        redo.setText("Redo")
        redo.setToolTip("write the value undone again (Ctrl+Shift+Z, Ctrl+Y)")
        redo.clicked.connect(self.undo_stack.redo)
        self.undo_stack.canRedoChanged.connect(redo.setEnabled)
        redo.setEnabled(False)
        head.addWidget(undo)
        head.addWidget(redo)
        layout.addLayout(head)
        table = info.type in ("CURVE", "MAP", "VAL_BLK", "AXIS_PTS")
        if info.description:
            if table:  # one line (all of it in the tooltip): a wrapped second line squeezed the table's rows
                description = ElidedLabel(info.description, mode=Qt.ElideRight, minimum=0)
            else:
                description = QLabel(info.description)
                description.setWordWrap(True)
            description.setMinimumWidth(0)
            description.setStyleSheet(f"color: {theme.MUTED};")
            layout.addWidget(description)
        if table:
            self.field = TableField(unit=info.unit, x_label=info.axis_labels[0] if info.axis_labels else "index",
                                    y_label=info.axis_labels[1] if len(info.axis_labels) > 1 else None,
                                    extended_limits=info.extended_limits)
            layout.addWidget(self.field, 1)
        else:
            self.field = ScalarField(unit=info.unit, limits=info.limits, decimals=info.decimals,
                                     states=list(info.states) or None, extended_limits=info.extended_limits)
            layout.addWidget(self.field)
            self.reference_label = QLabel()
            self.reference_label.setStyleSheet(f"color: {theme.MUTED};")
            layout.addWidget(self.reference_label)
            layout.addStretch(1)
        self.field.committed.connect(self.edit)
        self.field.refused.connect(self._say_refused)
        self.status = QLabel()
        self.status.setWordWrap(True)
        self.status.setStyleSheet(f"color: {theme.MUTED};")
        # two lines kept for it from the start: a refusal that wraps neither moves the table nor squeezes it (the
        # window's layout does not grow a dock for a label's second line; the heat map's tabs covered a row)
        self.status.setMinimumHeight(2 * self.status.fontMetrics().lineSpacing())
        self.status.setAlignment(Qt.AlignLeft | Qt.AlignTop)
        layout.addWidget(self.status)

    def release(self) -> None:
        """The editor is closed: its operating point's inputs are no longer measured for it."""
        if self.operating_point is not None:
            self.operating_point.stop()

    # --- reading --------------------------------------------------------------------------------

    def reload(self) -> None:
        """Read the value (and the reference page's) from the ECU; before any connection, from the project's file."""
        if self.controller.session is None:
            if self.offline is not None and (self.value is None or self.value_source):  # the image's, as edited
                run_task(self.offline.read_value, self.info.name, on_done=self._show_offline,
                         on_error=lambda exc: self._say(f"⚠ {exc}", theme.BAD))
            return
        if self.controller.in_boot:  # nothing to read (each editor's read was an error dialog): said in its line
            self._update_writable()
            return
        self.controller.call("read_value", self.info.name, on_done=self._show, on_error=self._failed)
        self.controller.call("read", self.info.name, page="reference", on_done=self._show_reference,
                             on_error=lambda _: self._show_reference(None))

    def _connected(self, _) -> None:
        self._writing = False  # what was under way on the session before is over with it (a cut-off write is said)
        if self.value_source:  # the file's value: no undo step or write starts from it; the ECU's replaces it
            self.value = None
        self._page_changed("working")

    def _page_changed(self, _page: str) -> None:
        self._message = ("", theme.MUTED)  # a refusal on the other page is no longer the news
        self._update_writable()
        self.reload()

    def read_only_reason(self) -> str:
        """Why nothing can be written now ("" when it can)."""
        session = self.controller.session
        if not self.info.writable:
            return "the A2L forbids calibrating it"
        if session is None:
            return "" if self.offline_editable() else self.controller.offline_reason
        if self.controller.in_boot:
            return IN_BOOT
        if session.read_only:
            return "the ECU's EPK differs from the A2L's"
        if self.controller.page == "reference":
            return READ_ONLY_PAGE
        return ""

    def offline_editable(self) -> bool:
        """Whether edits go into the project's image: no session (nor one being reconnected), and the value shown
        is the file's (not the last one an ECU had)."""
        return (self.offline is not None and self.controller.session is None and self.controller.lost_error is None
                and (self.value is None or bool(self.value_source)))

    def file_saved(self, name: str) -> None:
        """The project's image was saved as ``name``: the values shown are that file's."""
        if self.value_source:
            self.value_source = name
        self._update_status()

    def _update_writable(self) -> None:
        """Greyed and read-only with the reason in the tooltip while nothing can be written; the status line."""
        self.field.set_read_only(self.read_only_reason())
        self._update_status()

    def _written_elsewhere(self, name: str) -> None:
        if name == self.info.name:
            self.reload()

    def _show_offline(self, value) -> None:
        if self.controller.session is None and (self.value is None or self.value_source):  # an ECU's value stays
            self._show(value, self.offline.name)

    def _show(self, value, source: str = "") -> None:
        self.value, self.value_source = value, source
        if isinstance(self.field, TableField):
            axes = [a.values for a in value.axes]
            x = axes[0] if axes else np.arange(np.shape(value.value)[0])
            y = axes[1] if len(axes) > 1 else None
            self.field.show_value(np.asarray(value.value, dtype=np.float64), x, y, decimals=self.info.decimals,
                                  axis_decimals=self.info.axis_decimals if axes else ())
            self.field.set_reference(self.reference)
        else:
            self.field.show_value(value.value)
        self._update_writable()
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
        """The badge: "not written" while a write is cut off, else "modified" where the value differs from the
        reference page."""
        badge = self.modified_badge
        if self.unwritten:
            badge.setText("not written")
            badge.setStyleSheet(f"background: {theme.BAD}; color: #1b1b1b;")
            badge.setToolTip(self.unwritten)
            badge.show()
            return
        badge.setText("modified")
        badge.setStyleSheet(f"background: {theme.WARN}; color: #1b1b1b;")
        badge.setToolTip("differs from the reference page (the flashed calibration)")
        badge.setVisible(self._modified())

    def _modified(self) -> bool:
        if self.value_source and self.offline is not None:  # offline: differs from the file as opened or saved
            return self.info.name in self.offline.changed()
        if self.value is None or self.reference is None:
            return False
        current, reference = self.value.value, self.reference
        if isinstance(current, np.ndarray) or isinstance(reference, np.ndarray):
            return not (np.shape(current) == np.shape(reference) and np.array_equal(
                np.asarray(current, dtype=np.float64), np.asarray(reference, dtype=np.float64), equal_nan=True))
        return current != reference

    def _say(self, text: str, colour: str = theme.MUTED) -> None:
        self._message = (text, colour)
        self._update_status()

    def _update_status(self) -> None:
        """One line, the most important first: writing, a write cut off, a refusal or failure, why read-only."""
        reason = self.read_only_reason()
        text, colour = self._message
        if self._writing:
            text, colour = "writing …", theme.MUTED
        elif self.value_source and self.controller.session is not None and not self.controller.in_boot:
            text, colour = f"reading the ECU … (the values of {self.value_source} until then)", theme.MUTED
        elif self.unwritten:
            text, colour = f"⚠ {self.unwritten}; the field shows what the ECU holds", theme.BAD
        elif not text and self.offline_editable() and self.value_source:
            text = f"offline: the values of {self.value_source}; an edit changes the image (File ▸ Save image)"
        elif not text and reason:
            text, colour = f"read-only: {reason}", theme.MUTED
            if self.value_source:
                text += f"; the values of {self.value_source}"
            elif self.value is None and self.offline is None and self.controller.session is None:
                text += "; no values before connecting (the project names no s19/hex to show them from)"
        if text != self.status.text():
            self.status.setToolTip("")
        self.status.setText(text)
        self.status.setStyleSheet(f"color: {colour};")
        self._mark()

    def _say_refused(self, reason: str, *shorter: str) -> None:
        """A value not written: why, in the status line (no dialog: the user is typing; the editor's title names
        it); the first of ``shorter`` that fits where ``reason`` would take more than the line's two rows (all of
        it in the tooltip)."""
        texts = [f"not written: {text.removeprefix(self.info.name + ': ')}" for text in (reason, *shorter)]
        metrics, room = self.status.fontMetrics(), QRect(0, 0, max(self.status.width(), 1), 10_000)
        two_rows = metrics.boundingRect(room, Qt.TextWordWrap, "x\nx").height()
        fits = [t for t in texts if metrics.boundingRect(room, Qt.TextWordWrap, t).height() <= two_rows]
        self._say((fits or texts[-1:])[0], theme.BAD)
        self.status.setToolTip(reason)
        self.refused.emit(reason)

    def _failed(self, exc: BaseException) -> None:
        self._say(f"⚠ {exc}", theme.BAD)
        self.error.emit(exc)

    def _located(self, exc: LimitsError) -> list[str]:
        """A refusal's cell named by its breakpoints, as CANape does, not by the array's index: "at xaPRV_FF_TARGET
        10.00 bar / xaPRV_FF_MANIFOLD 200.00 bar", then shorter ("at TARGET 10.00 bar / MANIFOLD 200.00 bar",
        "at 10.00 bar / 200.00 bar") for a narrow editor."""
        model = getattr(self.field, "model", None)
        quantities = [quantity for quantity, _ in self.info.axis_quantities]
        if model is None or not quantities:
            return [str(exc)]
        common = os.path.commonprefix(quantities) if len(quantities) > 1 else ""
        names = [quantities, [q[len(common):] for q in quantities] if common else None, [""] * len(quantities)]
        points = (model.x_points, model.y_points)
        texts = []
        for shown in (n for n in names if n is not None):
            text = str(exc)
            for violation in exc.violations[:3]:
                index = violation.index
                if index is None or len(index) != len(quantities):
                    continue
                where = " / ".join(f"{name} {model.point_text(axis, points[axis][i])} {unit}".strip()
                                   for axis, (name, (_, unit), i) in
                                   enumerate(zip(shown, self.info.axis_quantities, index)))
                text = text.replace(f" at {list(index)}", f" at {where}", 1)
            texts.append(text)
        return texts

    # --- writing --------------------------------------------------------------------------------

    def edit(self, new) -> None:
        """The user's new value: written, and an undo step once the ECU took it."""
        old = None if self.value is None else self.value.value
        self.write(new, on_done=None if old is None else lambda _: self.undo_stack.push(_Write(self, old, new)))

    def write(self, value, on_done=None) -> None:
        def done(result) -> None:
            self._writing, self.unwritten = False, ""
            self._say("")
            if on_done is not None:
                on_done(result)

        self._writing = True
        self._message = ("", theme.MUTED)
        self._update_status()
        if self.offline_editable():
            def written(result) -> None:
                self._show(result, self.offline.name)
                done(result)
                self.offline_written.emit(self.info.name)

            run_task(self.offline.write, self.info.name, value, allow_extended_limits=self.field.allow_extended_limits,
                     on_done=written, on_error=lambda exc: self._not_written(value, exc))
            return
        self.controller.write(self.info.name, value, allow_extended_limits=self.field.allow_extended_limits,
                              on_done=done, on_error=lambda exc: self._not_written(value, exc))

    def _not_written(self, value, exc: BaseException) -> None:
        self._writing = False
        reason = refusal(exc)
        if isinstance(exc, NotWrittenError) and exc.lost:  # cut off: the ECU may hold the old value or the new
            shown = _short(value) if np.ndim(value) else format_value(value, self.info.decimals)
            self.unwritten = f"{shown} not written: {exc}"
            self._update_status()
        elif reason is not None:  # refused before anything was sent: the user's value, not the ECU
            self._say_refused(*(self._located(exc) if isinstance(exc, LimitsError) else [reason]))
        else:
            self._failed(exc)
        self.reload()  # show what the ECU really holds (on reconnecting when there is no session now)
