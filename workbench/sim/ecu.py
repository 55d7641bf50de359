"""The simulated ECU: memory, boot, the application on its OS tasks, and the XCP slave.

The ECU is passive and application-agnostic: whoever owns it feeds XCP commands
(:meth:`SimulatedEcu.handle_cto`, which returns the responses) and moves simulated time
(:meth:`SimulatedEcu.advance` or the shared :class:`Scheduler`); the DTOs a task event
samples go to ``dto_sink``, one call per DAQ list with all of that list's DTOs. It runs any application object with the documented interface
(docs/demo-ecu.md): ``TASKS = ((period_s, method_name, daq_event), ...)``, ``initialize()``
and a constructor ``(memory, symbols, hardware)``. Not thread-safe: callers serialise.
"""

from __future__ import annotations

import random
from collections.abc import Callable, Mapping
from enum import Enum
from typing import Any

from workbench.image import MemoryImage
from workbench.logs import logger
from workbench.sim.faults import FaultPlan
from workbench.sim.layout import ApplicationLayout
from workbench.sim.memory import EcuMemory
from workbench.sim.memory_map import HDS9, MemoryMap
from workbench.sim.paging import CalPageSwitch
from workbench.sim.scheduler import PeriodicTask, Scheduler
from workbench.sim.xcp.info_rom import InfoRom
from workbench.sim.xcp.parameters import XcpParameters
from workbench.sim.xcp.slave import XcpSlave

__all__ = ["ApplicationFactory", "ApplicationMemory", "EcuState", "SimulatedEcu"]

log = logger(__name__)

ApplicationFactory = Callable[[Any, Mapping[str, int], Any], Any]


class EcuState(Enum):
    OFF = "off"
    BOOT = "boot"  # no valid application: XCP answers, programming works, no tasks run
    APPLICATION = "application"
    HALTED = "halted"  # the application was stopped for programming (PROGRAM_START)


class ApplicationMemory:
    """The application's view of memory: calibrations come from the ECU's active page."""

    def __init__(self, ecu: SimulatedEcu):
        self._memory = ecu.memory
        self._pages = ecu.pages

    def read(self, address: int, size: int) -> bytes:
        return self._memory.read(self._pages.translate(address, size, self._pages.ecu_pages), size)

    def write(self, address: int, data: bytes) -> None:
        self._memory.write(address, data)


class SimulatedEcu:
    def __init__(
        self,
        flash: MemoryImage,
        layout: ApplicationLayout,
        application: ApplicationFactory | None,
        hardware: Any = None,
        params: XcpParameters | None = None,
        memory_map: MemoryMap = HDS9,
        scheduler: Scheduler | None = None,
        faults: FaultPlan | None = None,
        dto_sink: Callable[[list[bytes]], None] | None = None,
        rng: random.Random | None = None,
    ):
        """
        :param flash: the factory-programmed flash content (the s19); bytes outside every flash
            region raise :class:`~workbench.sim.memory.MemoryAccessError`.
        :param layout: what the application build puts where (from its ELF).
        :param application: builds the application at every start: ``(memory, symbols, hardware)``.
        :param hardware: the BSW the application calls; its ``reset()`` runs at every power-on,
            its ``safe_state()`` whenever the application stops (power off, programming).
        """
        self.params = params or XcpParameters()
        self.memory_map = memory_map
        self.layout = layout
        self.info = InfoRom.build(self.params, memory_map)
        self.memory = EcuMemory(
            list(memory_map.flash), memory_map.ram_windows, {"XCP_INFO": (self.info.start, self.info.data)}
        )
        self.memory.load_flash(flash)
        self.pages = CalPageSwitch(memory_map, self.params.segments)
        self.scheduler = scheduler or Scheduler()
        self.faults = faults or FaultPlan()
        self.dto_sink = dto_sink or (lambda sample: None)
        self.slave = XcpSlave(self, self.params, self.info, self.faults, rng)
        self._application_factory = application
        self._hardware = hardware
        self.application: Any = None
        self.state = EcuState.OFF
        self._tasks: list[PeriodicTask] = []
        self._power_on_us = 0
        self.on_power_on: list[Callable[[], None]] = []  # what a transport keeps in RAM forgets itself (SET_DAQ_ID's)

    # --- power ------------------------------------------------------------------------------

    def power_on(self) -> EcuState:
        """Boot: check the application-valid key; valid → CAL ROM → CAL RAM, .data/.bss, initialize, tasks."""
        if self.state is not EcuState.OFF:
            return self.state
        self._power_on_us = self.scheduler.now_us
        self.pages.reset()
        self.slave.reset()
        for forget in self.on_power_on:
            forget()
        if self._hardware is not None:
            self._hardware.reset()
        if self.memory.read(self.memory_map.app_key_address, len(self.memory_map.app_key)) != self.memory_map.app_key:
            self.state = EcuState.BOOT
            log.info("power on: no valid application key, staying in boot")
            return self.state
        cal_ram = self.memory_map.cal_ram
        self.memory.write(cal_ram.start, self.memory.read(self.memory_map.cal_rom_start, cal_ram.size))
        for copy in self.layout.init_copies:
            self.memory.write(copy.address, self.memory.read(copy.load_address, copy.size))
        for zero in self.layout.zero_ranges:
            self.memory.write(zero.start, bytes(zero.size))
        self.state = EcuState.APPLICATION
        if self._application_factory is not None:
            self._start_application()
        return self.state

    def _start_application(self) -> None:
        self.application = self._application_factory(ApplicationMemory(self), self.layout.symbols, self._hardware)
        self.application.initialize()
        for order, (period_s, method, event) in enumerate(sorted(self.application.TASKS)):
            self._tasks.append(self.scheduler.add(period_s, self._task_runner(getattr(self.application, method), event), method, order))

    def _task_runner(self, step: Callable[[], None], event: int | None) -> Callable[[], None]:
        def run() -> None:
            step()
            if event is not None:
                for sample in self.slave.daq.on_event(event, self.timestamp_ticks()):
                    self.dto_sink(sample)

        return run

    def power_off(self) -> None:
        """Cut the power: RAM and the XCP session are lost, flash keeps what was written."""
        self._stop_application()
        self.application = None
        self.memory.clear_ram()
        self.slave.reset()
        self.state = EcuState.OFF

    def _stop_application(self) -> None:
        for task in self._tasks:
            self.scheduler.cancel(task)
        self._tasks.clear()
        if self._hardware is not None:
            self._hardware.safe_state()

    # --- what the XCP slave asks of its ECU ----------------------------------------------------

    @property
    def application_running(self) -> bool:
        return self.state is EcuState.APPLICATION

    def timestamp_ticks(self) -> int:
        """The DAQ timestamp counter: ticks since power-on (wraps at 32 bits in the DTO)."""
        tick_ns = round(self.params.daq.timestamp_tick_s * 1e9)
        return (self.scheduler.now_us - self._power_on_us) * 1000 // tick_ns

    def halt_application(self) -> None:
        self._stop_application()
        if self.state is EcuState.APPLICATION:
            self.state = EcuState.HALTED

    def reset(self) -> None:
        self.power_off()
        self.power_on()

    def power_loss(self) -> None:
        log.info("power loss injected")
        self.power_off()

    # --- driving it -----------------------------------------------------------------------------

    def handle_cto(self, cto: bytes) -> list[bytes]:
        """One XCP command in, the packets to answer with out (none while the power is off)."""
        if self.state is EcuState.OFF:
            return []
        return self.slave.handle(cto)

    def advance(self, seconds: float) -> None:
        """Move simulated time forward, running every task (and DAQ event) due meanwhile."""
        self.scheduler.advance(seconds)

    def read(self, address: int, size: int) -> bytes:
        """Physical memory, for tests and tools (no page switching)."""
        return self.memory.read(address, size)
