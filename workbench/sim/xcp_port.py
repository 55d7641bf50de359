"""What every XCP front end of the simulated ECU shares, whatever carries its packets.

An :class:`XcpPort` takes command packets off its medium and hands them to
:meth:`XcpPort.on_command`; that applies the ECU's fault plan (``"rx"``), lets the ECU answer
under the simulator's lock, and passes each response through the ``"tx"`` faults to the
front end's :meth:`XcpPort._transmit_response`. The ECU's DTOs (one DAQ list sample per call)
go the same way to :meth:`XcpPort._transmit_dtos`. The front ends are XCP on CAN
(:mod:`workbench.sim.can_port`) and XCP on UDP/TCP (:mod:`workbench.sim.eth_port`): they only
frame, send and receive.
"""

from __future__ import annotations

import math
import threading
import time
from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any

from workbench.sim.ecu import SimulatedEcu
from workbench.sim.faults import FrameAction
from workbench.xcp_protocol import EV_CMD_PENDING, PID_EV, Cmd

__all__ = ["XcpPort"]


class XcpPort(ABC):
    """One XCP transport of a :class:`~workbench.sim.ecu.SimulatedEcu`; ``lock`` serialises the ECU."""

    transport = "XCP"  # "CAN", "UDP" or "TCP"

    def __init__(self, ecu: SimulatedEcu, lock: threading.RLock):
        self.ecu = ecu
        self.lock = lock
        self._timers: list[threading.Timer] = []
        self._answers = 0  # commands answered (for a slow slave's pace)
        self._waiting: list[list[bytes]] | None = None  # answers held back behind a slow one
        self._late_lock = threading.Lock()

    # --- life cycle, implemented by the front ends ---------------------------------------------

    @abstractmethod
    def start(self) -> None:
        """Open the medium and start receiving; :class:`~workbench.errors.WorkbenchError` when it cannot."""

    def close(self) -> None:
        """Stop receiving and drop delayed packets not sent yet; safe to call twice."""
        for timer in self._timers:
            timer.cancel()

    @abstractmethod
    def describe(self) -> dict[str, Any]:
        """Where and how this port serves XCP (for the CLI and logs)."""

    @abstractmethod
    def _transmit_response(self, packet: bytes) -> None:
        """Send a response (or a packet the fault plan delayed); it goes before any DTO still queued."""

    @abstractmethod
    def _transmit_dtos(self, packets: list[bytes]) -> bool:
        """Send one sample's DTOs, all or none; False when they did not fit the transmit buffer (a DAQ overload)."""

    # --- the packet path -----------------------------------------------------------------------

    def on_command(self, cto: bytes) -> None:
        """A command packet from the master: the ``"rx"`` fault, the ECU's answer, each response out."""
        fault = self.ecu.faults.on_frame("rx")
        if fault is not None and fault.action is FrameAction.DROP:
            return
        if fault is not None and fault.action is FrameAction.DELAY:
            time.sleep(fault.delay_s)
        for _ in range(2 if fault is not None and fault.action is FrameAction.DUPLICATE else 1):
            with self.lock:
                packets = self._command_answer(cto)
            self._answer(cto[0] if cto else 0, packets)

    def _command_answer(self, cto: bytes) -> list[bytes]:
        """The ECU's answer to one command (under the lock); a front end answers its transport's own commands."""
        return self.ecu.handle_cto(cto)

    def _answer(self, command: int, packets: list[bytes]) -> None:
        """Send a command's answers; a slow slave's (or one the fault plan delays) leave late, and the answers
        after them wait their turn (a slave answers its commands in order: SYNCH after the command it interrupts)."""
        with self._late_lock:
            busy_s = self._busy(command) if packets else 0.0
            late_s = max(self._pace(), self.ecu.faults.on_answer(command), busy_s) if packets else 0.0
            pending_s = self.ecu.params.pgm.pending_s
            for n in range(1, math.ceil(busy_s / pending_s) if pending_s else 0):  # "restart your timeout" meanwhile
                self._later(n * pending_s, self._respond, [bytes((PID_EV, EV_CMD_PENDING))])
            if self._waiting is not None:
                self._waiting.append(packets)
            elif late_s:
                self._waiting = [packets]
                self._later(late_s, self._send_waiting, None)
            else:
                self._respond(packets)

    def send_event(self, code: int) -> None:
        """Send an EV packet of the ECU's own (EV_SESSION_TERMINATED ...), after any answer still waiting."""
        with self._late_lock:
            if self._waiting is not None:
                self._waiting.append([bytes((PID_EV, code))])
                return
        self._respond([bytes((PID_EV, code))])

    def _send_waiting(self, _) -> None:
        with self._late_lock:
            waiting, self._waiting = self._waiting or [], None
            for packets in waiting:
                self._respond(packets)

    def _pace(self) -> float:
        """How late this answer of a slow slave leaves (every ``delayed_every``-th one is)."""
        params = self.ecu.params
        if not params.response_delay_s:
            return 0.0
        self._answers += 1
        return params.response_delay_s if self._answers % params.delayed_every == 0 else 0.0

    def _busy(self, command: int) -> float:
        """How long the ECU works on ``command`` before it answers (a flash erases for a while)."""
        return self.ecu.params.pgm.erase_s if command == Cmd.PROGRAM_CLEAR else 0.0

    def _respond(self, packets: list[bytes]) -> None:
        for packet in packets:
            for now in self._faulted(packet, self._transmit_response):
                self._transmit_response(now)

    def _later(self, delay_s: float, send: Callable[[Any], object], what: Any) -> None:
        timer = threading.Timer(delay_s, send, (what,))
        timer.daemon = True
        self._timers = [t for t in self._timers if t.is_alive()] + [timer]
        timer.start()

    def send_dtos(self, packets: list[bytes]) -> None:
        """The ECU's ``dto_sink``: one DAQ list sample, its DTOs through the ``"tx"`` faults."""
        now: list[bytes] = []
        for packet in packets:
            now += self._faulted(packet, lambda late: self._transmit_dtos([late]))
        if now:
            self._transmit_dtos(now)

    def _faulted(self, packet: bytes, send_later: Callable[[bytes], object]) -> list[bytes]:
        """The packets to send now for ``packet`` after the next ``"tx"`` fault (a delay sends it later)."""
        fault = self.ecu.faults.on_frame("tx")
        if fault is None:
            return [packet]
        if fault.action is FrameAction.DUPLICATE:
            return [packet, packet]
        if fault.action is FrameAction.DELAY:
            self._later(fault.delay_s, send_later, packet)
        return []
