"""The fix-calibration panel (thesis chapter 6): every signal with an ``_EN``/``_VALUE`` pair, its live
value, the override value and a switch. Switching on writes ``_VALUE`` then ``_EN`` = 1 through the
session; the table refreshes every second while it is visible. The override is typed as every value
of the window is (Enter writes, Esc restores, leaving writes nothing; a verbal value by its text or
from the drop-down); a value the session refuses is said below the table, the limit named. Values keep the
A2L's format all the time; while the ECU is not connected (or lost) they are greyed as not current and
nothing can be typed (on the reference page neither: XCP may not write it), the tooltip says why.

Before any connection, with the project's s19/hex open (:meth:`FixPanel.set_offline`), the panel lists the pairs as
the image holds them and edits them there, as the calibration editors do (``offline_written`` tells the window);
the live column is empty then: an image has no live values. Once an ECU connected the rows are its."""

from __future__ import annotations

from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtWidgets import QAbstractItemView, QLabel, QTableView, QVBoxLayout, QWidget

from workbench.gui import theme
from workbench.gui.a2l_info import value_decimals
from workbench.gui.ecu import IN_BOOT, READ_ONLY_PAGE, refusal
from workbench.gui.formatting import format_value
from workbench.gui.models.fixes import COLUMNS, FixModel
from workbench.gui.widgets.columns import share_columns
from workbench.gui.widgets.value_input import ValueDelegate
from workbench.gui.worker import run_task

__all__ = ["FixPanel"]

REFRESH_MS = 1000


class FixPanel(QWidget):
    refreshed = Signal()
    error = Signal(object)  # what the ECU is to blame for (a dialog)
    refused = Signal(str)  # a value not written, and why (said in the panel)
    offline_written = Signal()  # a pair written into the project's image offline

    def __init__(self, controller, hub=None, parent: QWidget | None = None):
        super().__init__(parent)
        self.controller = controller
        self.hub = hub
        self.offline = None  # the project's image (FileValues) edited before a connection; None: none
        self._ecu_rows = False  # the rows are an ECU's (connected once): never the image's again for this project
        self.a2l = None  # the A2L model of the last session: the values' formats stay when it is closed
        self.model = FixModel(self, value_format=self._format, bus_value=self._bus_value if hub is not None else None)
        self.model.override_requested.connect(self.override)
        self.model.enable_requested.connect(lambda fix: self._change("write", fix.pair.enable, 1,
                                                                     changes=(fix.pair.enable,)))
        self.model.release_requested.connect(self.release)
        self.model.value_requested.connect(lambda fix, value: self._change("write", fix.pair.value, value,
                                                                           changes=(fix.pair.value,)))
        controller.page_changed.connect(self._page_changed)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        hint = QLabel("Tick <b>on</b> to replace a signal by its override value (…_EN = 1); type the override and "
                      "press Enter to change it.")
        hint.setWordWrap(True)
        hint.setMinimumWidth(0)
        hint.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(hint)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setFont(theme.mono_font())
        self.table.verticalHeader().hide()
        self.table.verticalHeader().setDefaultSectionSize(22)
        self.table.setShowGrid(False)
        self.table.setAlternatingRowColors(True)
        self.table.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.table.setEditTriggers(QAbstractItemView.DoubleClicked | QAbstractItemView.AnyKeyPressed
                                   | QAbstractItemView.EditKeyPressed)
        self.delegate = ValueDelegate(self.table, states=self._states)
        self.delegate.refused.connect(self._say_refused)
        self.table.setItemDelegateForColumn(COLUMNS.index("override"), self.delegate)
        self.table.setTextElideMode(Qt.ElideMiddle)
        share_columns(self.table, (4.2, 2, 2, 0.8, 1.2))  # signal, live, override, on, kind
        layout.addWidget(self.table)
        self.message = QLabel()
        self.message.setWordWrap(True)
        self.message.setStyleSheet(f"color: {theme.BAD};")
        layout.addWidget(self.message)
        self._busy = False
        self._rows_of = 0  # counts the clears: a state read for the project before is not shown after one
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)
        controller.connected.connect(self._connected)
        controller.disconnected.connect(self._disconnected)
        controller.written.connect(lambda _: (self.message.setText(""), self.refresh()))
        self.model.set_read_only(controller.offline_reason, stale=True)

    def set_offline(self, values, a2l) -> None:
        """The project's image (a FileValues, None: none) and its A2L model: before a connection the panel lists and
        edits the pairs the image holds."""
        self.offline = values
        if self.offline_mode():
            self.a2l = a2l
            self.refresh()

    def offline_mode(self) -> bool:
        """Whether the rows are the image's and edits go into it (no ECU connected yet)."""
        return self.offline is not None and not self._ecu_rows and self.controller.session is None

    def _connected(self, result) -> None:
        self._ecu_rows = True
        self._busy = False  # a request on the session before (closed under it) is not waited for
        self.a2l = result.session.model
        self.message.setText("")
        self.model.set_read_only("", stale=True)  # greyed until the first refresh
        self.refresh()
        self.timer.start()

    def _disconnected(self) -> None:
        self.timer.stop()
        self.model.set_read_only(self.controller.offline_reason, stale=True)

    def clear(self) -> None:
        """No rows (another project opens: they were the pairs of the A2L before; a session lists the new ones)."""
        self.timer.stop()
        self._busy = False
        self._rows_of += 1
        self.a2l, self.offline, self._ecu_rows = None, None, False
        self.message.setText("")
        self.model.set_fixes([])

    def _page_changed(self, page: str) -> None:
        self.message.setText("")
        self.model.set_read_only(READ_ONLY_PAGE if page == "reference" else "", stale=self.model.stale)

    def _states(self, index) -> tuple[str, ...]:
        """The verbal values of a row's ``_VALUE`` (its drop-down), none for a number."""
        model = self.a2l
        if model is None or not 0 <= index.row() < len(self.model.rows):
            return ()
        conversion = model.conversion(model.object(self.model.rows[index.row()].pair.value))
        return tuple(conversion.allowed) if getattr(conversion, "verbal", False) else ()

    def _format(self, name: str, value) -> str:
        """A live or override value in the format and unit of ``_VALUE`` ``name`` (its A2L decimals), as ``cal fix
        --list`` prints it ("25.23 bar"); a verbal value by its text alone."""
        if self.a2l is None:
            return format_value(value)
        text = format_value(value, value_decimals(self.a2l, name))
        unit = self.a2l.unit_of(self.a2l.object(name)) if value is not None and not isinstance(value, str) else ""
        return f"{text} {unit}" if unit else text

    def _bus_value(self, fix) -> str | None:
        """A CAN signal's newest value as the CAN2 monitor decoded it (``Message.Signal`` of the same name)."""
        if fix.pair.kind != "CAN signal":
            return None
        name = self.hub.can2_signal(fix.pair.stem[2:])
        if name is None:
            return None
        last = self.hub.buffer(name).last()
        return None if last is None else self.hub.info(name).format(last[1])

    def refresh(self) -> None:
        """Read every fix's state (one request in flight at a time): the ECU's, or offline the image's."""
        if self._busy:
            return
        rows_of = self._rows_of

        def show(fixes) -> None:
            if rows_of == self._rows_of:
                self._show(fixes)

        if self.offline_mode():
            self._busy = True
            run_task(lambda: self.offline.image().fixes(), on_done=show, on_error=self._failed)
            return
        if not self.controller.is_connected:
            return
        if self.controller.in_boot:  # no fixes to read there (a dialog a second): greyed, the tooltip says why
            self.model.set_read_only(IN_BOOT, stale=True)
            return
        if self.model.read_only == IN_BOOT:  # the application runs again (flashed)
            self.model.set_read_only("", stale=True)
        self._busy = True
        task = self.controller.call("fixes", on_done=show, on_error=self._failed)
        if task is None:
            self._busy = False

    def _show(self, fixes) -> None:
        self._busy = False
        self.model.set_fixes(fixes)
        self.model.set_read_only("" if self.offline_mode() else self.model.read_only, stale=False)
        self.refreshed.emit()

    def _failed(self, exc) -> None:
        self._busy = False
        self.timer.stop()  # one dialog, not one a second
        self.error.emit(exc)

    def _say_refused(self, reason: str) -> None:
        self.message.setText(f"not written: {reason}")
        self.refused.emit(reason)

    def _not_written(self, exc: BaseException) -> None:
        reason = refusal(exc)
        if reason is not None:  # refused before anything was sent (or not sent at all): said here, not in a dialog
            self._say_refused(reason)
        else:
            self.error.emit(exc)
        self.refresh()

    def override(self, fix, value) -> None:
        self._change("override", fix.pair.stem, value, changes=(fix.pair.enable, fix.pair.value))

    def release(self, fix) -> None:
        self._change("release", fix.pair.stem, changes=(fix.pair.enable,))

    def _change(self, method: str, *args, changes: tuple[str, ...]) -> None:
        """``method`` (override, release, write) on the session, or offline on the project's image (whose methods
        have the same names)."""
        if not self.offline_mode():
            self.controller.change(method, *args, on_error=self._not_written, changes=changes)
            return

        def written(_) -> None:
            self.message.setText("")
            self.offline_written.emit()
            self.refresh()

        run_task(getattr(self.offline.image(), method), *args, on_done=written, on_error=self._not_written)
