"""Helpers of the flash tests: the bench (the demo ECU on a private ``virtual`` bus, or on a lockstep wire where
timeouts cost no time, simulated time standing still so only XCP runs, and a session on it with short
timeouts) and images to flash."""

from __future__ import annotations

import itertools
import random
import struct
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, replace

from lockstep_bus import LockstepWire

from workbench import demo
from workbench.elf import ElfSymbols
from workbench.flash import FlashLayout
from workbench.image import MemoryImage, load_image
from workbench.session import Session
from workbench.sim.demo_ecu import DemoEcu, build_demo_ecu
from workbench.sim.memory_map import HDS9
from workbench.sim.server import Simulator
from workbench.xcp.master import Timeouts

FAST = Timeouts(t1=0.1, t2=0.3, t3=0.3, t4=1.0, t5=0.1, t6=0.2, t7=0.02)
# Off the lockstep wire, for tests that expect every answer: what an answer of the simulator (sharing the CPU with
# every test worker) may take on a loaded machine; FAST's T1 of 100 ms saw CONNECT go unanswered three times in CI
PATIENT = replace(FAST, t1=2.0, t5=2.0)
APPLICATIVE = HDS9.region("APPLICATIVE")
CALIB = HDS9.region("CALIB")
_channels = itertools.count()


@dataclass
class Bench:
    demo: DemoEcu
    simulator: Simulator
    session: Session
    channel: str | None  # the private virtual bus (None on a lockstep wire)

    @property
    def ecu(self):
        return self.demo.ecu

    @property
    def layout(self) -> FlashLayout:
        return FlashLayout.from_a2l(self.session.doc, self.session.config)

    def flash_content(self, region) -> bytes:
        return self.ecu.read(region.start, region.size)

    def whole_flash(self) -> bytes:
        return b"".join(self.flash_content(region) for region in HDS9.flash)

    def power_cycle(self) -> None:
        self.simulator.power_off()
        self.simulator.power_on()
        self.session.connect()


@contextmanager
def open_bench(*, lockstep: bool = False):
    """A :class:`Bench`; the simulator and the session are closed on leaving. ``lockstep``: on a
    :class:`LockstepWire` instead of a virtual bus (no ``workbench`` command reaches it)."""
    demo_ecu = build_demo_ecu()
    with ExitStack() as stack:
        if lockstep:
            wire = stack.enter_context(LockstepWire())
            channel, ecu_bus, master_bus = None, wire.ecu, {"bus": wire.master}
        else:
            channel = f"flash-test-{next(_channels)}"
            ecu_bus = {"interface": "virtual", "channel": channel}
            master_bus = ecu_bus
        simulator = stack.enter_context(Simulator(demo_ecu.ecu, ecu_bus, time_scale=None))
        session = stack.enter_context(Session.open(demo.a2l(), **master_bus, timeouts=FAST))
        yield Bench(demo_ecu, simulator, session, channel)


def calibration_rom_address(name: str) -> int:
    """Where a calibration's value lies in CAL ROM (its CAL RAM address mirrored)."""
    return HDS9.rom_address(ElfSymbols(demo.elf()).symbol(name).address)


def calib_image_with(name: str, value: float) -> MemoryImage:
    """The demo s19's CALIB part with the real32 calibration ``name`` set to ``value``."""
    image = load_image(demo.s19()).crop(CALIB.start, CALIB.end)
    image.add(calibration_rom_address(name), struct.pack("<f", value), overwrite=True)
    return image


def application_image(size: int, seed: int = 1) -> MemoryImage:
    """The demo s19's APPLICATIVE part followed by ``size`` bytes in all of pseudo-random code."""
    image = load_image(demo.s19()).crop(APPLICATIVE.start, APPLICATIVE.end)
    end = image.ranges[-1].end
    image.add(end + 0x10, random.Random(seed).randbytes(size))
    return image
