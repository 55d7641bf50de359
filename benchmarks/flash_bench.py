"""How close ``workbench flash`` comes to the CAN bus limit, against the simulated ECU with its bus timing model.

Flashes a full CALIB (128 KiB) and a 1 MiB APPLICATIVE image with :func:`workbench.flash.flash_ecu` into the
demo ECU served on a python-can ``virtual`` bus whose timing model runs at 500 kbit/s and 1 Mbit/s, and
compares the bytes per second with the bus limit: the time the frames the programming needs take on the
bus, counted exactly (:func:`workbench.sim.can_timing.frame_bits`: stuff bits of these very frames, CRC
delimiter, ACK, EOF, intermission). Those frames are the ones the protocol cannot do without at the ECU's
MAX_CTO_PGM and MAX_BS_PGM: per range a SET_MTA and its response, per block of 252 bytes 42 PROGRAM /
PROGRAM_NEXT frames of 6 data bytes (padded to 8, MAX_DLC_REQUIRED) and one response, and per range the
PROGRAM with size 0 that ends the memory segment and its response.

Two figures per case: "programming" (the PROGRAM commands, what the limit describes) and "whole flash"
(connect, seed & key, PROGRAM_START, clearing the key, erasing, programming, checksums of the erased
sectors, the key, PROGRAM_RESET, reconnect, EPK), each as a fraction of the limit. The timing model lets
senders run up to 10 ms ahead of the modelled bus, so a figure may exceed 100 % by up to that lead over
the measured time. Plain script: ``.venv/bin/python benchmarks/flash_bench.py [--bitrate N ...]``.
"""

from __future__ import annotations

import argparse
import itertools
import logging
import random
import statistics
import struct
import time
from dataclasses import dataclass

import can

from workbench import demo
from workbench.flash import FlashLayout, flash_ecu, plan_flash
from workbench.image import MemoryImage, load_image
from workbench.session import Session
from workbench.sim.can_timing import frame_bits
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.memory_map import HDS9
from workbench.sim.server import Simulator
from workbench.xcp_protocol import PID_RES, Cmd

MASTER, SLAVE = 0x7F0, 0x7F1
BLOCK, PER_FRAME = 252, 6  # the demo ECU's MAX_BS_PGM 42 and MAX_CTO_PGM 8: 42 whole frames of 6 bytes
_channels = itertools.count()


def calib_image() -> MemoryImage:
    """All of CALIB: the demo's EPK, then pseudo-random calibrations up to the end of the region."""
    region = HDS9.region("CALIB")
    epk = load_image(demo.s19()).read(region.start, 16)
    return MemoryImage.from_bytes(region.start, epk + random.Random(1).randbytes(region.size - 16))


def applicative_image(size: int = 1 << 20) -> MemoryImage:
    """The demo's application, then pseudo-random code up to ``size`` bytes in all."""
    region = HDS9.region("APPLICATIVE")
    image = load_image(demo.s19()).crop(region.start, region.end)
    end = image.ranges[-1].end
    image.add(end, random.Random(2).randbytes(size - image.size))
    return image


def _bits(identifier: int, packet: bytes) -> int:
    return frame_bits(can.Message(arbitration_id=identifier, is_extended_id=False, data=packet.ljust(8, b"\0")))


def bus_limit_s(image: MemoryImage, bitrate: int) -> float:
    """Seconds the frames programming ``image`` needs take on the bus (see the module)."""
    response = _bits(SLAVE, bytes([PID_RES]))
    bits = 0
    for address, data in image.segments:
        bits += _bits(MASTER, bytes([Cmd.SET_MTA, 0, 0, 0]) + struct.pack("<I", address)) + response
        for start in range(0, len(data), BLOCK):
            block = data[start:start + BLOCK]
            for offset in range(0, len(block), PER_FRAME):
                command = Cmd.PROGRAM if offset == 0 else Cmd.PROGRAM_NEXT
                count = len(block) if offset == 0 else len(block) - offset
                bits += _bits(MASTER, bytes([command, count]) + block[offset:offset + PER_FRAME])
            bits += response
        bits += _bits(MASTER, bytes([Cmd.PROGRAM, 0])) + response  # the end of the memory segment (ASAM)
    return bits / bitrate


@dataclass
class Measured:
    program_s: float  # the PROGRAM commands
    whole_s: float  # the whole flash
    bus_bits: int  # what the simulator's timing model carried meanwhile
    reactions_s: list[float]  # per block: from the master's receiving the response to its sending the next block


def measure(image: MemoryImage, region: str, bitrate: int) -> Measured:
    channel = f"flash-bench-{next(_channels)}"
    demo_ecu = build_demo_ecu()
    simulator = Simulator(demo_ecu.ecu, {"interface": "virtual", "channel": channel}, bitrate=bitrate, time_scale=None)
    with simulator, Session.open(demo.a2l(), interface="virtual", channel=channel) as session:
        plan = plan_flash(image, FlashLayout.from_a2l(session.doc, session.config), [region], source=region)
        reactions = _watch_reactions(session.link)
        clock = simulator.bus_clock()
        bits_before = clock.bits
        began = time.perf_counter()
        result = flash_ecu(session, plan)
        whole = time.perf_counter() - began
        if demo_ecu.ecu.read(plan.sectors[0].range.start, plan.sectors[0].range.size) != \
                plan.sector_content(plan.sectors[0]):
            raise SystemExit("the flash differs from the image")
    return Measured(result.program_seconds, whole, clock.bits - bits_before, reactions)


def _watch_reactions(link) -> list[float]:
    """Times from a block's response (the last frame's exchange returning) to the next block's first frame."""
    reactions: list[float] = []
    answered: list[float] = []
    exchange, send = link.exchange, link.send

    def timed_exchange(packet, timeout_s, *, drop_queued=True):
        response = exchange(packet, timeout_s, drop_queued=drop_queued)
        answered[:] = [time.perf_counter()] if packet[0] == Cmd.PROGRAM_NEXT else []
        return response

    def timed_send(packet):
        if answered and packet[0] == Cmd.PROGRAM:
            reactions.append(time.perf_counter() - answered.pop())
        send(packet)

    link.exchange, link.send = timed_exchange, timed_send
    return reactions


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bitrate", type=int, action="append", help="bit rate(s) of the timing model "
                                                                      "(default: 500000 and 1000000)")
    parser.add_argument("--app-kib", type=int, default=1024, help="size of the APPLICATIVE image in KiB (default 1024)")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    cases = (("CALIB", calib_image()), ("APPLICATIVE", applicative_image(args.app_kib * 1024)))
    print(f"{'case':28} {'bytes':>8} {'bus limit':>11} {'programming':>22} {'whole flash':>22} {'bus busy':>9} "
          f"{'reaction':>9} {'with it':>8}")
    for bitrate in args.bitrate or (500_000, 1_000_000):
        for region, image in cases:
            limit = bus_limit_s(image, bitrate)
            run = measure(image, region, bitrate)
            rate = image.size / 1024
            reaction = statistics.median(run.reactions_s)
            exposed = limit + reaction * (len(run.reactions_s) + 1)  # nothing hides the master's reaction
            print(f"{region + f' at {bitrate // 1000} kbit/s':28} {image.size:8d} {rate / limit:7.1f} KiB/s "
                  f"{rate / run.program_s:7.1f} KiB/s ({limit / run.program_s:6.1%}) {rate / run.whole_s:7.1f} KiB/s "
                  f"({limit / run.whole_s:6.1%}) {run.bus_bits / bitrate / run.whole_s:8.1%} "
                  f"{reaction * 1e6:6.0f} us {limit / exposed:7.1%}")
    print("reaction: median time from a block's response to the next block (the model's 10 ms lead hides it); "
          "with it: the limit's share if every block waited for it on a real bus")


if __name__ == "__main__":
    main()
