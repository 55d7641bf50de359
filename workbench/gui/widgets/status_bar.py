"""The status bar: who the ECU is, whether its EPK matches, what is locked, which page, bus load, DAQ."""

from __future__ import annotations

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QLabel, QSizePolicy, QStatusBar

from workbench.gui import theme

__all__ = ["EcuStatusBar"]

REFRESH_MS = 500


def _badge(text: str, colour: str, tip: str = "") -> QLabel:
    label = QLabel(text)
    label.setObjectName("badge")
    label.setStyleSheet(f"background: {colour}; color: #101214;")
    label.setToolTip(tip)
    return label


class EcuStatusBar(QStatusBar):
    def __init__(self, hub, parent=None):
        super().__init__(parent)
        self.hub = hub
        self.link = QLabel("not connected")
        self.ecu = QLabel()
        self.epk = _badge("EPK —", theme.MUTED)
        self.protection = QLabel()
        self.page = QLabel()
        self.bus = QLabel()
        self.daq = QLabel()
        self.recording = QLabel()
        self.recording.setStyleSheet(f"color: {theme.BAD}; font-weight: bold;")
        for widget in (self.link, self.ecu):  # long texts: they give way (tooltip: all of it) before the window grows
            widget.setSizePolicy(QSizePolicy.Ignored, QSizePolicy.Preferred)
            widget.setMinimumWidth(60)
        self.addWidget(self.link, 3)
        self.addWidget(self.ecu, 2)
        for widget in (self.epk, self.protection, self.page):
            self.addWidget(widget)
        for widget in (self.recording, self.bus, self.daq):
            self.addPermanentWidget(widget)
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)
        self.timer.start()

    def show_connected(self, session, info) -> None:
        self.link.setText(f"● {info.link}")
        self.link.setToolTip(info.link)
        self.link.setStyleSheet(f"color: {theme.GOOD};")
        ident = info.identification or info.a2l_name or "ECU"
        self.ecu.setText(f"{ident}{'  (boot loader)' if info.boot else ''}")
        self.ecu.setToolTip(self.ecu.text())
        epk = session.epk
        if epk.matches is True:
            self._set_badge(self.epk, f"EPK ✓ {epk.ecu}", theme.GOOD, epk.describe())
        elif epk.matches is False:
            self._set_badge(self.epk, "EPK ✗ read-only" if session.read_only else "EPK ✗ writes allowed",
                            theme.BAD, epk.describe())
        else:
            self._set_badge(self.epk, "EPK not checked", theme.MUTED, epk.describe())
        locked = ", ".join(info.protected)
        self.protection.setText(f"seed & key: {locked}" if locked else "no seed & key")
        self.protection.setToolTip("resources protected by seed & key at connect (unlocked on use): "
                                   + (locked or "none"))
        self.show_page("working")

    def show_page(self, page: str) -> None:
        colour = theme.ACCENT if page == "working" else theme.WARN
        self.page.setText(f"<span style='color:{colour}'>■</span> {page} page")

    def show_disconnected(self) -> None:
        self.link.setText("○ not connected")
        self.link.setStyleSheet(f"color: {theme.MUTED};")
        self.ecu.setText("")
        self._set_badge(self.epk, "EPK —", theme.MUTED, "")
        self.protection.setText("")
        self.page.setText("")

    @staticmethod
    def _set_badge(label: QLabel, text: str, colour: str, tip: str) -> None:
        label.setText(text)
        label.setStyleSheet(f"background: {colour}; color: #101214;")
        label.setToolTip(tip)

    def refresh(self) -> None:
        monitor = self.hub.can_monitor
        load = monitor.bus_load() if monitor is not None else None
        self.bus.setText("" if load is None else f"bus load {load * 100:.1f} %")
        acquisition = self.hub.acquisition
        state = acquisition.state if acquisition is not None else None
        if state is not None and state.recording is not None:
            size = state.file_bytes / 2**20
            self.recording.setText(f"● REC {state.recording.name} · {state.recorded_s:.1f} s · {size:.1f} MiB")
            self.recording.setToolTip(f"recording to {state.recording}")
        else:
            self.recording.setText("")
        if state is None or not state.running:
            self.daq.setText("DAQ idle")
            self.daq.setStyleSheet(f"color: {theme.MUTED};")
            return
        trouble = state.lost or state.overloads
        self.daq.setText(f"DAQ {len(state.signals)} signals · {state.samples:,} samples · lost {state.lost} · "
                         f"overloads {state.overloads}")
        self.daq.setStyleSheet(f"color: {theme.WARN if trouble else theme.GOOD};")
