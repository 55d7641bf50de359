"""The simulated ECU served: XCP on CAN or on Ethernet, the FLCU messages on CAN2, a clock.

:class:`Simulator` owns the threads around a :class:`~workbench.sim.ecu.SimulatedEcu`: the
XCP front end (XCP on CAN on the ``can1`` bus, or XCP on UDP/TCP at an ``ethernet`` endpoint),
the python-can buses (a receiver and a transmitter each, paced with ``bitrate``), and a clock
that moves simulated time with real time (``time_scale`` 1.0), faster (e.g. 10.0), or not at
all (``None``: only :meth:`Simulator.advance` moves it, for tests and benchmarks). CAN1 and
CAN2 may be one bus (the FLCU ids and the XCP ids do not collide) or two; with XCP on
Ethernet the FLCU messages go on ``can2`` if given, else nowhere.

It is a context manager: ``start()`` opens the buses given as python-can settings (buses
passed as objects stay the caller's) and the Ethernet socket, ``close()`` is idempotent.
"""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING, Any

import can

from workbench.logs import logger
from workbench.sim.can_port import BusSpec, CanBuses, CanXcpPort
from workbench.sim.ecu import EcuState, SimulatedEcu
from workbench.sim.eth_port import EthernetEndpoint, EthernetXcpPort
from workbench.sim.scheduler import US_PER_S
from workbench.sim.xcp_port import XcpPort
from workbench.xcp_protocol import EV_SESSION_TERMINATED, IdType

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument
    from workbench.sim.can2 import Can2Driver
    from workbench.sim.can_timing import BusClock
    from workbench.sim.pcm import PcmNode

__all__ = ["Simulator"]

log = logger(__name__)

MAX_LAG_S = 0.5  # a clock further behind than this skips ahead instead of catching up
_CLOCK_POLL_S = 0.05


def _unplugged(frame: can.Message) -> None:
    """Where CAN2 frames go without a CAN2 bus (XCP on Ethernet and no ``can2``): nowhere."""


class Simulator:
    def __init__(
        self,
        ecu: SimulatedEcu,
        can1: BusSpec | None = None,
        can2: BusSpec | None = None,
        *,
        ethernet: EthernetEndpoint | None = None,
        can2_driver: Can2Driver | None = None,
        pcm: PcmNode | None = None,
        bitrate: int | None = None,
        time_scale: float | None = 1.0,
        a2l: A2lDocument | None = None,
        profile: str = "demo",
    ):
        """
        :param can1: the bus of XCP on CAN (python-can settings or an open bus); it also carries CAN2
            unless ``can2`` is given.
        :param ethernet: serve XCP on UDP/TCP there instead (then ``can1`` stays None).
        :param bitrate: bit/s of the bus timing model of every bus (None: frames go at once).
        :param a2l: the A2L that describes this ECU to a master (kept as :attr:`a2l`); ``profile`` names the
            slave profile it was built with (for :meth:`describe`).
        :raises ValueError: not exactly one XCP transport, or a non-positive ``time_scale``.
        """
        if time_scale is not None and time_scale <= 0:
            raise ValueError(f"time_scale must be positive or None, got {time_scale}")
        if (can1 is None) == (ethernet is None):
            raise ValueError("XCP needs exactly one transport: can1 (XCP on CAN) or ethernet (XCP on UDP/TCP)")
        self.ecu = ecu
        self.a2l = a2l
        if a2l is not None:  # GET_ID 4 uploads it, as XCPlite's own A2L
            ecu.slave.files[IdType.ASAM_MC2_FILE] = bytes(a2l.data)
        self.profile = profile
        self.can2_driver = can2_driver
        self.pcm = pcm
        self.bitrate = bitrate
        self.time_scale = time_scale
        self.ethernet = ethernet
        self.lock = threading.RLock()
        self._can_specs = {"CAN1": can1, "CAN2": can2}
        self._can: CanBuses | None = None
        self.xcp: XcpPort | None = None
        self._stop = threading.Event()
        self._clock_thread: threading.Thread | None = None
        self._pcm_task = None
        self._send_can2 = _unplugged
        self.started = False
        self.closed = False

    # --- life cycle --------------------------------------------------------------------------

    def start(self) -> Simulator:
        """Open the buses and the XCP port, start the threads and power the ECU on; on failure
        everything started is closed.

        :raises InputError: an unknown python-can interface or host name.
        :raises WorkbenchError: a bus or the Ethernet address cannot be opened (the message names it).
        """
        if self.started:
            return self
        self.started = True
        try:
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
        if any(spec is not None for spec in self._can_specs.values()):
            self._can = CanBuses(self._can_specs, self.bitrate)
        if self.ethernet is not None:
            self.xcp = EthernetXcpPort(self.ecu, self.lock, self.ethernet)
        else:
            self.xcp = CanXcpPort(self.ecu, self.lock, self._can)
        self.ecu.dto_sink = self.xcp.send_dtos
        if self._can is not None:
            self._can.open(self._on_can_frame)
        self.xcp.start()
        can2 = self._can.transmitter("CAN2" if self._can_specs["CAN2"] is not None else "CAN1") if self._can else None
        if can2 is not None:
            self._send_can2 = can2.send
        if self.can2_driver is not None:
            self.can2_driver.transmit = self._send_can2

    def close(self) -> None:
        """Stop every thread and close the buses and sockets this simulator opened; safe to call twice."""
        if self.closed:
            return
        self.closed = True
        self._stop.set()
        if self._clock_thread is not None:
            self._clock_thread.join(timeout=2)
        if self.xcp is not None:
            self.xcp.close()
        if self._can is not None:
            self._can.close()
        if self._pcm_task is not None:
            self.ecu.scheduler.cancel(self._pcm_task)

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
        return self._can.buses if self._can is not None else {}

    def dropped_frames(self, name: str = "CAN1") -> int:
        """DTO frames the simulator dropped on a bus because its transmit buffer was full (a DAQ overload)."""
        transmitter = self._can.transmitter(name) if self._can is not None else None
        return transmitter.dropped if transmitter is not None else 0

    def bus_clock(self, name: str = "CAN1") -> BusClock | None:
        """The timing model of a bus (``CAN1``/``CAN2``), None without ``bitrate`` or before :meth:`start`."""
        transmitter = self._can.transmitter(name) if self._can is not None else None
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

    def end_session(self) -> None:
        """The ECU ends the XCP session on its own (a watchdog, its application's request): DAQ stops, the master is
        disconnected and told so with EV_SESSION_TERMINATED (ASAM XCP), its commands unanswered until CONNECT."""
        with self.lock:
            self.ecu.slave.disconnect()
        self.xcp.send_event(EV_SESSION_TERMINATED)

    # --- CAN frames ------------------------------------------------------------------------------

    def _on_can_frame(self, role: str, message: can.Message) -> None:
        xcp = self.xcp
        if role == "CAN1" and self.ethernet is None and xcp.accepts(message):
            xcp.on_frame(message)
        elif self.can2_driver is not None and (role == "CAN2" or self._can_specs["CAN2"] is None
                                               or self._can.shares("CAN1", "CAN2")):
            with self.lock:
                self.can2_driver.receive(message)

    def _pcm_cycle(self) -> None:
        for frame in self.pcm.frames():
            if self.can2_driver is not None:
                self.can2_driver.receive(frame)
            self._send_can2(frame)

    # --- what it serves ------------------------------------------------------------------------

    def describe(self) -> dict[str, Any]:
        """The XCP transport, buses, bit rate and EPK this simulator serves (for the CLI and logs)."""
        params = self.ecu.params
        with self.lock:
            epk = self.ecu.read(params.epk_address, params.epk_length)
        return {
            "xcp": self.xcp.describe() if self.xcp is not None else None,
            "buses": self._can.describe() if self._can is not None else {},
            "bitrate": self.bitrate,
            "epk": epk.decode("ascii", "replace").rstrip("\0"),
            "state": self.ecu.state.value,
            "time_scale": self.time_scale,
            "daq": self._describe_daq(),
            "profile": self.profile,
        }

    def _describe_daq(self) -> dict[str, Any]:
        """DAQ_CONFIG_TYPE and the lists: how many can be allocated, or the static ones' shapes."""
        daq = self.ecu.params.daq
        if not daq.static:
            return {"config": "dynamic", "max_daq": daq.max_daq}
        return {"config": "static", "lists": [
            {"odts": shape.odts, "entries": shape.entries, "fixed_event": shape.fixed_event} for shape in daq.static_lists]}
