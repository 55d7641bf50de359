"""Writes through the session against raw pyxcp doing the same three commands, and against the CAN bus limit.

A checked write by name is SET_MTA, DOWNLOAD and a SHORT_UPLOAD of what was written (the limits,
shape and page are known before anything is sent). The yardstick is pyxcp sending exactly those
three commands with no conversion and no check.

1. Against raw pyxcp: a ``workbench sim`` process on a udp_multicast port of its own; in this
   process, alternating rounds of ``Session.write("xsSWITCH_TANK_THR", v)`` (a VALUE),
   ``Session.write_cells("xvPRV_DC_FF", {(2, 3): v})`` (a map cell) and pyxcp's ``setMta``,
   ``download`` and ``shortUpload`` of the same 4 bytes. Figure: writes/s of each, the ratio.
2. At 1 Mbit/s: the simulator with its bus timing model (``--bitrate``); the session's writes/s as a
   fraction of what the bus carries for three round trips (request and response padded to 8 bytes).

Plain script: ``.venv/bin/python benchmarks/write_bench.py [--seconds 2] [--rounds 3]``.
"""

from __future__ import annotations

import argparse
import itertools
import socket
import struct

import can
from session_bench import free_port, pyxcp_master, rate, start_simulator

from workbench import Session
from workbench.sim.can_timing import frame_bits

VALUE, MAP, CELL = "xsSWITCH_TANK_THR", "xvPRV_DC_FF", (2, 3)


def _values():
    return itertools.cycle((20.0, 21.0))


def against_pyxcp(seconds: float, rounds: int) -> tuple[float, float, float]:
    """Best of ``rounds`` for a VALUE, a map cell and raw pyxcp, alternating, one master connected at a time."""
    port = free_port(socket.SOCK_DGRAM)
    simulator = start_simulator("--bus-kwargs", f"port={port}")
    try:
        values, cells, raws = [], [], []
        for _ in range(rounds):
            with Session.open(bus_kwargs={"port": port}) as ecu:
                address = ecu.model.characteristic(VALUE).address
                numbers = _values()
                ecu.write(VALUE, 20.0)  # unlocked, the page known: what every further write costs
                values.append(rate(lambda: ecu.write(VALUE, next(numbers)), seconds))
                cells.append(rate(lambda: ecu.write_cells(MAP, {CELL: next(numbers)}), seconds))
                ecu.write(VALUE, 20.0)
            with pyxcp_master(port) as master:
                master.connect()
                master.cond_unlock("CALPAG")
                payloads = itertools.cycle((struct.pack("<f", 20.0), struct.pack("<f", 21.0)))

                def raw_write() -> None:
                    master.setMta(address)
                    master.download(next(payloads))
                    master.shortUpload(4, address)

                raws.append(rate(raw_write, seconds))
                master.setMta(address)
                master.download(struct.pack("<f", 20.0))
                master.disconnect()
        return max(values), max(cells), max(raws)
    finally:
        simulator.terminate()
        simulator.wait(10)


def at_the_bus_limit(seconds: float, bitrate: int = 1_000_000) -> tuple[float, float, float]:
    """(writes/s, reads/s by name in the same run, round trips/s the bus carries)."""
    port = free_port(socket.SOCK_DGRAM)
    simulator = start_simulator("--bus-kwargs", f"port={port}", "--bitrate", str(bitrate))
    try:
        with Session.open(bus_kwargs={"port": port}) as ecu:
            numbers = _values()
            ecu.write(VALUE, 20.0)
            writes = rate(lambda: ecu.write(VALUE, next(numbers)), seconds)
            reads = rate(lambda: ecu.read(VALUE), seconds)
            ecu.write(VALUE, 20.0)
        frame = can.Message(arbitration_id=0x7F0, is_extended_id=False, data=bytes(8))
        return writes, reads, bitrate / (2 * frame_bits(frame))
    finally:
        simulator.terminate()
        simulator.wait(10)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    value, cell, raw = against_pyxcp(args.seconds, args.rounds)
    print(f"writes, udp_multicast between processes: Session.write of a VALUE {value:,.0f}/s, write_cells of a map "
          f"cell {cell:,.0f}/s, raw pyxcp SET_MTA+DOWNLOAD+SHORT_UPLOAD {raw:,.0f}/s: {value / raw:.2f}x and "
          f"{cell / raw:.2f}x")
    writes, reads, trips = at_the_bus_limit(args.seconds)
    print(f"at 1 Mbit/s (bus timing model): {writes:,.0f} writes/s of the {trips / 3:,.0f} the bus carries (three "
          f"round trips each): {3 * writes / trips:.0%}; reads by name in the same run {reads / trips:.0%} of theirs")


if __name__ == "__main__":
    main()
