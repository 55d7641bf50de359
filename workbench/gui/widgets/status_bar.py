"""The status bar: who the ECU is, whether its EPK matches, whether another master talked to it before CONNECT,
what is locked, which page, bus load, DAQ, and - when the measurement stands still - why and since when
(flashing, reconnecting, connection lost).

Every text fits: the ECU's name and the link give way first (cut with "…", all of it in the tooltip),
the measurement's state is short and complete. A message (``showMessage``) stands beside the indicators,
not over them."""

from __future__ import annotations

import time

from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import QLabel, QStatusBar

from workbench.errors import epk_text
from workbench.gui import theme
from workbench.gui.widgets.elided_label import ElidedLabel

__all__ = ["EcuStatusBar", "clock"]

REFRESH_MS = 500


def clock(when: float) -> str:
    """``when`` (seconds since the epoch) as the wall-clock time a user compares with their watch."""
    return time.strftime("%H:%M:%S", time.localtime(when))


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
        self.pause: tuple[str, float] | None = None  # why the measurement stands still, since when
        self.link = ElidedLabel("not connected", mode=Qt.ElideRight, minimum=80)
        self.ecu = ElidedLabel(mode=Qt.ElideRight, minimum=60)
        self.epk = _badge("EPK —", theme.MUTED)
        self.other_master = _badge("⚠ other master?", theme.WARN)  # shown when the session heard one before CONNECT
        self.other_master.hide()
        self.protection = QLabel()
        self.page = QLabel()
        self.bus = QLabel()
        self.daq = QLabel()
        # the counts grow digit by digit: the room for long ones from the start (no cut "lost 0", no jumps)
        longest = "DAQ 99 signals · 9,999,999 samples · lost 99"
        self.daq.setMinimumWidth(self.daq.fontMetrics().horizontalAdvance(longest) + 16)
        self.recording = QLabel()
        self.recording.setStyleSheet(f"color: {theme.BAD}; font-weight: bold;")
        self.message = ElidedLabel(mode=Qt.ElideRight, minimum=60)
        self._message_timer = QTimer(self, singleShot=True)
        self._message_timer.timeout.connect(self.clearMessage)
        self.addWidget(self.link, 3)
        self.addWidget(self.ecu, 2)
        for widget in (self.epk, self.other_master, self.protection, self.page):
            self.addWidget(widget)
        self.addWidget(self.message, 4)
        for widget in (self.recording, self.bus, self.daq):
            self.addPermanentWidget(widget)
        self.timer = QTimer(self)
        self.timer.setInterval(REFRESH_MS)
        self.timer.timeout.connect(self.refresh)
        self.timer.start()

    def showMessage(self, text: str, timeout: int = 0) -> None:  # noqa: N802 - Qt's name
        """``text`` beside the indicators for ``timeout`` ms (0: until the next). QStatusBar's own message hides
        every widget but the permanent ones while it shows: after a connect, the link, the ECU, the EPK and the
        page vanished for 15 s behind "the data in the ECU equals ..." (user trial)."""
        self.message.setText(text)
        self._message_timer.stop()
        if timeout > 0:
            self._message_timer.start(timeout)

    def clearMessage(self) -> None:  # noqa: N802 - Qt's name
        self.message.setText("")

    def currentMessage(self) -> str:  # noqa: N802 - Qt's name
        return self.message.text()

    def show_connected(self, session, info) -> None:
        self.link.setText(f"● {info.link}")
        self.link.setStyleSheet(f"color: {theme.GOOD};")
        ident = info.identification or info.a2l_name or "ECU"
        self.ecu.setText(f"boot loader · {ident}" if info.boot else ident)  # first: a long ident is elided
        epk = session.epk
        if epk.matches is True:
            self._set_badge(self.epk, "EPK ✓", theme.GOOD, f"{epk_text(epk.ecu)}\n{epk.describe()}")
        elif epk.matches is False:
            parts = epk.mismatched_parts
            which = " ".join(p.segment for p in parts) + " " if parts and len(parts) < len(epk.parts) else ""
            self._set_badge(self.epk, f"EPK ✗ {which}" + ("read-only" if session.read_only else "writes allowed"),
                            theme.BAD, "\n".join([epk.describe(), *(p.describe() for p in epk.parts)]))
        else:
            self._set_badge(self.epk, "EPK not checked", theme.MUTED, epk.describe())
        self.show_other_master(session.other_master)
        locked = ", ".join(info.protected)
        self.protection.setText("seed & key" if locked else "no seed & key")
        self.protection.setToolTip("resources protected by seed & key at connect (unlocked on use): "
                                   + (locked or "none"))
        self.show_page("working")

    def show_other_master(self, heard: str) -> None:
        """What the session heard on the ECU's ids before CONNECT (another master, a DAQ nobody stopped; "" for
        nothing): a badge that stays while connected, the whole line in its tooltip. Not a message: the cache
        check's summary after a connect replaces one at once."""
        self.other_master.setToolTip(heard)
        self.other_master.setVisible(bool(heard))

    def show_page(self, page: str) -> None:
        colour = theme.ACCENT if page == "working" else theme.WARN
        self.page.setText(f"<span style='color:{colour}'>■</span> {page}")
        self.page.setToolTip(f"the ECU and XCP use the {page} page")

    def show_disconnected(self, closing: bool = False) -> None:
        """Not connected; ``closing``: the session closes still (DAQ stopped, DISCONNECT, the bus freed)."""
        self.link.setText("○ disconnecting …" if closing else "○ not connected")
        self.link.setStyleSheet(f"color: {theme.MUTED};")
        self.ecu.setText("")
        self._set_badge(self.epk, "EPK —", theme.MUTED, "")
        self.other_master.hide()
        self.protection.setText("")
        self.page.setText("")

    def show_offline_only(self, why: str | None) -> None:
        """The A2L describes no XCP connection (``why``, its reader's words) - or does again (None)."""
        if why is None:
            if self.link.text().startswith("○ offline"):  # another A2L, one with XCP: a connected link stays
                self.show_disconnected()
            return
        self.link.setText("○ offline: the A2L has no IF_DATA XCP", tip=f"{why}: offline work only (browse, "
                          "parameter sets, compare); connecting needs the ECU's IF_DATA XCP in the A2L")
        self.link.setStyleSheet(f"color: {theme.WARN};")

    def show_lost(self, exc) -> None:
        """The connection is lost: what and when, in red (the link keeps its place)."""
        self.link.setText(f"✕ connection lost at {clock(exc.when)}: {exc.reason}", tip=str(exc))
        self.link.setStyleSheet(f"color: {theme.BAD};")

    def set_pause(self, reason: str | None, since: float | None = None) -> None:
        """Why the measurement stands still (``flashing``, ``reconnecting`` ...), None when it runs again."""
        self.pause = None if reason is None else (reason, time.time() if since is None else since)
        self.refresh()

    @staticmethod
    def _set_badge(label: QLabel, text: str, colour: str, tip: str) -> None:
        label.setText(text)
        label.setStyleSheet(f"background: {colour}; color: #101214;")
        label.setToolTip(tip)

    def refresh(self) -> None:
        monitor = self.hub.can_monitor
        load = monitor.bus_load() if monitor is not None else None
        self.bus.setText("" if load is None else f"bus {load * 100:.1f} %")
        self.bus.setToolTip("CAN bus load over the last second")
        acquisition = self.hub.acquisition
        state = acquisition.state if acquisition is not None else None
        if state is not None and state.recording is not None:
            from workbench.record.recorder import size_text  # loaded already: it records

            name = state.recording.name
            name = name if len(name) <= 24 else "…" + name[-23:]
            self.recording.setText(f"● REC {name} · {state.recorded_s:.0f} s · {size_text(state.file_bytes)}")
            self.recording.setToolTip(f"recording to {state.recording}")
        else:
            self.recording.setText("")
        if self.pause is not None and (state is None or not state.running):
            reason, since = self.pause
            self.daq.setText(f"DAQ paused: {reason} since {clock(since)}")
            self.daq.setToolTip("the plots show a gap for the time nothing was measured")
            self.daq.setStyleSheet(f"color: {theme.WARN};")
            return
        if state is None or not state.running:
            self.daq.setText("DAQ idle")
            self.daq.setToolTip("")
            self.daq.setStyleSheet(f"color: {theme.MUTED};")
            return
        trouble = state.lost or state.overloads
        self.daq.setText(f"DAQ {len(state.signals)} signals · {state.samples:,} samples · lost {state.lost}"
                         + (f" · overloads {state.overloads}" if state.overloads else "")
                         + ("" if state.ecu_clock else " · receive time")
                         + (f" · {len(state.refused)} not measurable" if state.refused else ""))
        self.daq.setToolTip("samples received by DAQ since the measurement (re)started; lost: DTOs the ECU "
                            "sent that never arrived (by their counters); overloads: the ECU's DAQ overload "
                            f"indications ({state.overloads})" + (f"\ntimed by {state.clock}" if state.clock else "")
                            + ("" if state.ecu_clock else ": the plots show when the samples arrived (in bursts, "
                               "as the bus delivers them), not when the ECU took them")
                            + "".join(f"\nnot measured: {name}: {why}" for name, why in state.refused.items()))
        self.daq.setStyleSheet(f"color: {theme.WARN if trouble or state.refused else theme.GOOD};")
