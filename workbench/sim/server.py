"""The simulated ECU on CAN buses: XCP on CAN1, the FLCU messages on CAN2, a clock.

:class:`Simulator` owns the threads around a :class:`~workbench.sim.ecu.SimulatedEcu`:
one receiver per bus, a transmitter per bus (paced with ``bitrate``), and a clock that
moves simulated time with real time (``time_scale`` 1.0), faster (e.g. 10.0), or not at
all (``None``: only :meth:`Simulator.advance` moves it, for tests and benchmarks). CAN1
and CAN2 may be one bus (the FLCU ids and the XCP ids do not collide) or two.

It is a context manager: ``start()`` opens the buses given as python-can settings
(buses passed as objects stay the caller's), ``close()`` is idempotent.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

import can

from workbench.errors import InputError, WorkbenchError
from workbench.sim.bus import ECHOING_INTERFACES, EchoFilter, Receiver, Transmitter
from workbench.sim.can2 import Can2Driver
from workbench.sim.can_timing import BusClock
from workbench.sim.ecu import EcuState, SimulatedEcu
from workbench.sim.faults import FrameAction
from workbench.sim.pcm import PcmNode
from workbench.sim.scheduler import US_PER_S
from workbench.xcp_protocol import CAN_ID_EXTENDED_FLAG

log = logging.getLogger(__name__)

MAX_DLC = 8  # classic CAN
MAX_LAG_S = 0.5  # a clock further behind than this skips ahead instead of catching up
_CLOCK_POLL_S = 0.05

BusSpec = can.BusABC | Mapping[str, Any]


def split_can_id(raw: int) -> tuple[int, bool]:
    """An A2L CAN id (bit 31 = extended) as ``(identifier, is_extended)``."""
    return raw & 0x1FFFFFFF, bool(raw & CAN_ID_EXTENDED_FLAG)


class Simulator:
    def __init__(
        self,
        ecu: SimulatedEcu,
        can1: BusSpec,
        can2: BusSpec | None = None,
        *,
        can2_driver: Can2Driver | None = None,
        pcm: PcmNode | None = None,
        bitrate: int | None = None,
        time_scale: float | None = 1.0,
    ):
        if time_scale is not None and time_scale <= 0:
            raise ValueError(f"time_scale must be positive or None, got {time_scale}")
        self.ecu = ecu
        self.can2_driver = can2_driver
        self.pcm = pcm
        self.bitrate = bitrate
        self.time_scale = time_scale
        self.lock = threading.RLock()
        self._specs = {"CAN1": can1, "CAN2": can2}
        self._buses: dict[str, can.BusABC] = {}
        self._owned: list[can.BusABC] = []
        self._transmitters: dict[str, Transmitter] = {}
        self._receivers: list[Receiver] = []
        self._timers: list[threading.Timer] = []
        self._stop = threading.Event()
        self._clock_thread: threading.Thread | None = None
        self._master_id = split_can_id(ecu.params.can_id_master)
        self._slave_id = split_can_id(ecu.params.can_id_slave)
        self._pcm_task = None
        self._short_frame_seen = False
        self.started = False
        self.closed = False

    # --- life cycle --------------------------------------------------------------------------

    def start(self) -> Simulator:
        """Open the buses, start the threads and power the ECU on; on failure everything started is closed.

        :raises WorkbenchError: a bus cannot be opened (the message names the interface).
        """
        if self.started:
            return self
        self.started = True
        try:
            self._open_buses()
            self._start_io()
            if self.pcm is not None:
                self._pcm_task = self.ecu.scheduler.add(self.pcm.period_s, self._pcm_cycle, "PCM", order=-1)
            with self.lock:
                self.ecu.power_on()
            if self.time_scale is not None:
                self._clock_thread = threading.Thread(target=self._run_clock, name="sim-clock", daemon=True)
                self._clock_thread.start()
        except BaseException:
            self.close()
            raise
        return self

    def _start_io(self) -> None:
        clocks = {name: BusClock(self.bitrate) if self.bitrate else None for name in self._buses}
        for name, bus in self._distinct_buses():
            echoes = EchoFilter() if self._echoes(name, bus) else None
            self._transmitters[name] = Transmitter(bus, clocks[name], name, echoes)
            self._receivers.append(Receiver(bus, self._receiver_for(name), clocks[name], name, echoes))
        if "CAN2" not in self._transmitters:
            self._transmitters["CAN2"] = self._transmitters["CAN1"]
        self.ecu.dto_sink = self._send_dtos
        if self.can2_driver is not None:
            self.can2_driver.transmit = self._transmitters["CAN2"].send

    def _open_buses(self) -> None:
        for name, spec in self._specs.items():
            if spec is None:
                continue
            if isinstance(spec, can.BusABC):
                self._buses[name] = spec
                continue
            interface = spec.get("interface")
            if interface not in can.interfaces.VALID_INTERFACES:
                raise InputError(f"{name}: unknown python-can interface {interface!r} "
                                 f"(known: {', '.join(sorted(can.interfaces.VALID_INTERFACES))})")
            try:
                bus = can.Bus(**dict(spec))
            except (can.CanError, OSError, ValueError, ImportError, TypeError) as exc:
                where = f"{spec.get('interface')} {spec.get('channel', '')}".strip()
                raise WorkbenchError(f"cannot open {name} bus ({where}): {exc}") from exc
            self._buses[name] = bus
            self._owned.append(bus)

    def _echoes(self, name: str, bus: can.BusABC) -> bool:
        spec = self._specs[name]
        interface = spec.get("interface") if isinstance(spec, Mapping) else type(bus).__name__
        return interface in ECHOING_INTERFACES or type(bus).__name__ == "UdpMulticastBus"

    def _distinct_buses(self) -> list[tuple[str, can.BusABC]]:
        seen: list[tuple[str, can.BusABC]] = []
        for name, bus in self._buses.items():
            if all(bus is not other for _, other in seen):
                seen.append((name, bus))
        return seen

    def close(self) -> None:
        """Stop every thread and close the buses this simulator opened; safe to call twice."""
        if self.closed:
            return
        self.closed = True
        self._stop.set()
        if self._clock_thread is not None:
            self._clock_thread.join(timeout=2)
        for timer in self._timers:
            timer.cancel()
        for receiver in self._receivers:
            receiver.stop()
        for transmitter in set(self._transmitters.values()):
            transmitter.close()
        if self._pcm_task is not None:
            self.ecu.scheduler.cancel(self._pcm_task)
        for bus in self._owned:
            bus.shutdown()

    def __enter__(self) -> Simulator:
        return self.start()

    def __exit__(self, *exc_info) -> None:
        self.close()

    # --- time --------------------------------------------------------------------------------

    def advance(self, seconds: float) -> None:
        """Move simulated time by ``seconds`` (only without a running clock)."""
        if self._clock_thread is not None:
            raise RuntimeError("the simulator's clock runs by itself (time_scale is set)")
        with self.lock:
            self.ecu.advance(seconds)

    @property
    def buses(self) -> dict[str, can.BusABC]:
        """The open buses by role (``CAN1``, and ``CAN2`` when it is a bus of its own)."""
        return dict(self._buses)

    def bus_clock(self, name: str = "CAN1") -> BusClock | None:
        """The timing model of a bus (``CAN1``/``CAN2``), None without ``bitrate`` or before :meth:`start`."""
        transmitter = self._transmitters.get(name)
        return transmitter.clock if transmitter is not None else None

    @property
    def now_s(self) -> float:
        return self.ecu.scheduler.now_s

    def _run_clock(self) -> None:
        scheduler = self.ecu.scheduler
        anchor_wall, anchor_us = time.perf_counter(), scheduler.now_us
        while not self._stop.is_set():
            target_us = anchor_us + int((time.perf_counter() - anchor_wall) * self.time_scale * US_PER_S)
            with self.lock:
                if target_us - scheduler.now_us > MAX_LAG_S * US_PER_S:
                    log.warning("simulated time is %.1f s behind; skipping ahead", (target_us - scheduler.now_us) / US_PER_S)
                    scheduler.now_us = target_us - int(MAX_LAG_S * US_PER_S)
                self._run_tasks(target_us)
                due = scheduler.next_due_us()
            wait = _CLOCK_POLL_S if due is None else (due - target_us) / US_PER_S / self.time_scale
            self._stop.wait(min(max(wait, 0.0), _CLOCK_POLL_S))

    def _run_tasks(self, target_us: int) -> None:
        try:
            self.ecu.scheduler.run_until(target_us)
        except Exception:  # an application bug stops the application, not the simulator
            log.exception("a task failed; the application is halted, XCP keeps answering")
            self.ecu.halt_application()

    # --- power -------------------------------------------------------------------------------

    def power_off(self) -> None:
        with self.lock:
            self.ecu.power_off()

    def power_on(self) -> EcuState:
        with self.lock:
            return self.ecu.power_on()

    # --- frames ------------------------------------------------------------------------------

    def _receiver_for(self, name: str):
        handles_xcp = name == "CAN1"
        handles_can2 = name == "CAN2" or self._specs["CAN2"] is None or self._buses.get("CAN2") is self._buses["CAN1"]

        def on_frame(message: can.Message) -> None:
            key = (message.arbitration_id, message.is_extended_id)
            if handles_xcp and key == self._master_id:
                self._on_xcp(message)
            elif handles_can2 and self.can2_driver is not None:
                with self.lock:
                    self.can2_driver.receive(message)

        return on_frame

    def _on_xcp(self, message: can.Message) -> None:
        if message.is_remote_frame or (self.ecu.params.max_dlc_required and message.dlc != MAX_DLC):
            # MAX_DLC_REQUIRED binds the master too: a shorter frame is no XCP packet (AUTOSAR CanXcp ignores it)
            level = logging.DEBUG if self._short_frame_seen else logging.WARNING
            self._short_frame_seen = True
            log.log(level, "XCP frame with DLC %d ignored: the A2L says MAX_DLC_REQUIRED, the master must pad to 8",
                    message.dlc)
            return
        fault = self.ecu.faults.on_frame("rx")
        if fault is not None and fault.action is FrameAction.DROP:
            return
        if fault is not None and fault.action is FrameAction.DELAY:
            time.sleep(fault.delay_s)
        for _ in range(2 if fault is not None and fault.action is FrameAction.DUPLICATE else 1):
            with self.lock:
                packets = self.ecu.handle_cto(bytes(message.data))
            for packet in packets:
                self._send_xcp(packet)

    def _send_xcp(self, packet: bytes) -> None:
        """A response: it waits for the bus, before any queued DTO."""
        transmitter = self._transmitters["CAN1"]
        for frame in self._faulted(packet, transmitter.send):
            transmitter.send(frame)

    def _send_dtos(self, packets: list[bytes]) -> None:
        """One DAQ list's sample: all its DTOs go, or (the DTO buffer being full) none."""
        transmitter = self._transmitters["CAN1"]
        frames = []
        for packet in packets:
            frames += self._faulted(packet, lambda frame: transmitter.send_dtos([frame]))
        transmitter.send_dtos(frames)

    def _faulted(self, packet: bytes, send_later: Callable[[can.Message], object]) -> list[can.Message]:
        """The frames to send for an XCP packet now, after the next ``"tx"`` frame fault (a delay sends it later)."""
        if self.ecu.params.max_dlc_required:
            packet = packet.ljust(MAX_DLC, b"\0")
        identifier, extended = self._slave_id
        frame = can.Message(arbitration_id=identifier, is_extended_id=extended, data=packet)
        fault = self.ecu.faults.on_frame("tx")
        if fault is None:
            return [frame]
        if fault.action is FrameAction.DUPLICATE:
            return [frame, frame]
        if fault.action is FrameAction.DELAY:
            timer = threading.Timer(fault.delay_s, send_later, (frame,))
            timer.daemon = True
            self._timers = [t for t in self._timers if t.is_alive()] + [timer]
            timer.start()
        return []

    def _pcm_cycle(self) -> None:
        for frame in self.pcm.frames():
            if self.can2_driver is not None:
                self.can2_driver.receive(frame)
            self._transmitters["CAN2"].send(frame)

    # --- what it serves ------------------------------------------------------------------------

    def describe(self) -> dict[str, Any]:
        """The buses, ids, bit rate and EPK this simulator serves (for the CLI and logs)."""
        params = self.ecu.params
        with self.lock:
            epk = self.ecu.read(params.epk_address, params.epk_length)
        buses = {}
        for name, spec in self._specs.items():
            bus = self._buses.get(name)
            if spec is None:
                continue
            buses[name] = dict(spec) if isinstance(spec, Mapping) else {"bus": str(bus)}
        return {
            "buses": buses,
            "can_id_master": params.can_id_master,
            "can_id_slave": params.can_id_slave,
            "bitrate": self.bitrate,
            "epk": epk.decode("ascii", "replace").rstrip("\0"),
            "state": self.ecu.state.value,
            "time_scale": self.time_scale,
        }
