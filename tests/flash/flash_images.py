"""Helpers of the flash tests: the bench (the demo ECU on a private ``virtual`` bus, simulated time standing
still so only XCP runs, and a session on it with short timeouts) and images to flash."""

from __future__ import annotations

import itertools
import random
import struct
from contextlib import contextmanager
from dataclasses import dataclass

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
APPLICATIVE = HDS9.region("APPLICATIVE")
CALIB = HDS9.region("CALIB")
_channels = itertools.count()


@dataclass
class Bench:
    demo: DemoEcu
    simulator: Simulator
    session: Session
    channel: str  # the private virtual bus

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
def open_bench():
    """A :class:`Bench`; the simulator and the session are closed on leaving."""
    channel = f"flash-test-{next(_channels)}"
    demo_ecu = build_demo_ecu()
    with Simulator(demo_ecu.ecu, {"interface": "virtual", "channel": channel}, time_scale=None) as simulator, \
            Session.open(demo.a2l(), interface="virtual", channel=channel, timeouts=FAST) as session:
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
