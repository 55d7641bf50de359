"""The connection dialog's "Scan for slaves": GET_SLAVE_ID on the A2L's CAN_ID_BROADCAST of the bus entered
(:func:`workbench.detect_slaves` in the thread pool), each slave's ids shown against the A2L's."""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Signal
from PySide6.QtWidgets import QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from workbench.bus_defaults import BusSpec
from workbench.errors import WorkbenchError
from workbench.gui import theme
from workbench.gui.worker import run_task

__all__ = ["SlaveScan", "id_text"]


def id_text(can_id) -> str:
    """A CAN id as CANape writes it in its dialogs: ``7F0h`` (standard), ``12345x`` (extended)."""
    return f"{can_id.id:X}{'x' if can_id.extended else 'h'}"


class SlaveScan(QWidget):
    """A button that asks the bus ``bus()`` names which XCP slaves answer on ``can``'s CAN_ID_BROADCAST (``can``:
    the A2L's XCP_ON_CAN), and a line a slave below it; ``finished`` when the answers are shown."""

    finished = Signal()

    def __init__(self, can, bus: Callable[[], BusSpec], parent=None):
        super().__init__(parent)
        self.can = can
        self._bus = bus
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        row = QHBoxLayout()
        self.button = QPushButton("Scan for slaves")
        self.button.clicked.connect(self.scan)
        row.addWidget(self.button)
        row.addStretch(1)
        layout.addLayout(row)
        self.result = QLabel()
        self.result.setWordWrap(True)
        layout.addWidget(self.result)
        broadcast = getattr(can, "can_id_broadcast", None)
        self.button.setEnabled(broadcast is not None)
        self.button.setToolTip(f"GET_SLAVE_ID on the A2L's CAN_ID_BROADCAST {id_text(broadcast)}: every XCP slave "
                               "on the bus answers with its ids; nothing else is sent" if broadcast is not None else
                               "the A2L's XCP_ON_CAN names no CAN_ID_BROADCAST")

    def scan(self) -> None:
        from workbench.session.detect import detect_slaves

        try:
            bus = self._bus()
        except WorkbenchError as exc:
            self._show(str(exc), theme.BAD)
            return
        if bus.bitrate is None and not bus.software and self.can.baudrate:
            bus = bus.with_bitrate(self.can.baudrate)
        self.button.setEnabled(False)
        self._show(f"asking GET_SLAVE_ID on {id_text(self.can.can_id_broadcast)} ({bus.describe()}) …", theme.MUTED)
        run_task(detect_slaves, bus=bus, broadcast_id=self.can.can_id_broadcast, on_done=self._found,
                 on_error=lambda exc: self._done(str(exc), theme.BAD))

    def _found(self, detection) -> None:
        slaves = detection.slaves
        if not slaves:
            self._done(f"no slave answered GET_SLAVE_ID on {id_text(self.can.can_id_broadcast)} "
                       f"({detection.found.bus})", theme.BAD)
            return
        wanted = (self.can.can_id_master, self.can.can_id_slave)
        lines = [f"commands {id_text(slave.command_id)}, answers {id_text(slave.response_id)}"
                 + (": the A2L's ids" if (slave.command_id, slave.response_id) == wanted else "")
                 + ("" if slave.confirmed else " (no inverse echo)") for slave in slaves]
        if all((slave.command_id, slave.response_id) != wanted for slave in slaves):
            lines.append(f"none on the A2L's ids ({id_text(wanted[0])}, {id_text(wanted[1])}): correct "
                         "CAN_ID_MASTER/CAN_ID_SLAVE in the A2L")
            self._done("\n".join(lines), theme.BAD)
            return
        self._done("\n".join(lines), theme.MUTED)

    def _done(self, text: str, color: str) -> None:
        self._show(text, color)
        self.button.setEnabled(True)
        self.finished.emit()

    def _show(self, text: str, color: str) -> None:
        self.result.setStyleSheet(f"color: {color};")
        self.result.setText(text)
        # a long answer (an error naming the options) wraps; the connection dialog's pages (a QStackedWidget) do not
        # ask a label's height for its width: ask it here, so that the dialog grows to show it whole
        self.result.setMinimumHeight(self.result.heightForWidth(max(self.result.width(), 1)))
        window = self.window()
        if window is not self and window.isVisible():
            window.resize(window.width(), max(window.height(), window.sizeHint().height()))
