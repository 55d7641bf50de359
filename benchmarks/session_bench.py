"""Polling reads through the session against raw pyxcp, and against the CAN bus limit.

1. Against raw pyxcp: a ``workbench sim`` process on a udp_multicast port of its own; in this
   process, alternating rounds of ``Session.read("xsSWITCH_TANK_THR")`` (by name, in physical
   units: model lookup, codec, SHORT_UPLOAD, conversion) and pyxcp's ``Master.shortUpload`` of the
   same 4 bytes (no conversion). Figure: reads/s of each and the ratio (goal: at least 0.9x).
2. At 1 Mbit/s: the simulator with its bus timing model (``--bitrate``); the session's reads/s as
   a fraction of the round trips the bus carries (a request and a response frame, both padded to
   8 bytes by MAX_DLC_REQUIRED, exact bit counts from :func:`workbench.sim.can_timing.frame_bits`).

Plain script: ``.venv/bin/python benchmarks/session_bench.py [--seconds 2] [--rounds 3]``.
"""

from __future__ import annotations

import argparse
import logging
import socket
import subprocess
import sys
import time

import can

from workbench import Session
from workbench.sim.can_timing import frame_bits
from workbench.sim.seedkey import compute_key

NAME = "xsSWITCH_TANK_THR"


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("", 0))
        return probe.getsockname()[1]


def start_simulator(port: int, *extra: str) -> subprocess.Popen:
    process = subprocess.Popen([sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", "sim",
                                "--bus-kwargs", f"port={port}", *extra],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in process.stdout:
        if line.startswith("serving"):
            return process
    raise RuntimeError(process.stderr.read())


def rate(call, seconds: float) -> float:
    count, started = 0, time.perf_counter()
    while time.perf_counter() - started < seconds:
        call()
        count += 1
    return count / (time.perf_counter() - started)


def pyxcp_master(port: int):
    from pyxcp.config import create_application_from_config
    from pyxcp.master import Master

    app = create_application_from_config({"Transport": {"CAN": {
        "interface": "udp_multicast", "channel": "239.74.163.2", "can_id_master": 0x7F0, "can_id_slave": 0x7F1,
        "max_dlc_required": True}}}, log_level=logging.CRITICAL)
    app.transport.can.udp_multicast.port = port
    logging.getLogger("pyxcp").setLevel(logging.CRITICAL)
    master = Master("can", config=app)
    master.seed_n_key_function = lambda resource, seed: compute_key(bytes(seed), resource)
    return master


def against_pyxcp(seconds: float, rounds: int) -> tuple[float, float]:
    """Best of ``rounds`` for each master, the two alternating, one connected at a time."""
    port = free_udp_port()
    simulator = start_simulator(port)
    try:
        session_rates, pyxcp_rates = [], []
        for _ in range(rounds):
            with Session.open(bus_kwargs={"port": port}) as ecu:
                address = ecu.model.characteristic(NAME).address
                session_rates.append(rate(lambda: ecu.read(NAME), seconds))
            with pyxcp_master(port) as master:
                master.connect()
                pyxcp_rates.append(rate(lambda: master.shortUpload(4, address), seconds))
                master.disconnect()
        return max(session_rates), max(pyxcp_rates)
    finally:
        simulator.terminate()
        simulator.wait(10)


def at_the_bus_limit(seconds: float, bitrate: int = 1_000_000) -> tuple[float, float]:
    port = free_udp_port()
    simulator = start_simulator(port, "--bitrate", str(bitrate))
    try:
        with Session.open(bus_kwargs={"port": port}) as ecu:
            achieved = rate(lambda: ecu.read(NAME), seconds)
        frame = can.Message(arbitration_id=0x7F0, is_extended_id=False, data=bytes(8))
        limit = bitrate / (2 * frame_bits(frame))
        return achieved, limit
    finally:
        simulator.terminate()
        simulator.wait(10)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    session, raw = against_pyxcp(args.seconds, args.rounds)
    print(f"polling, udp_multicast between processes: session.read by name {session:,.0f}/s, raw pyxcp shortUpload "
          f"{raw:,.0f}/s: {session / raw:.2f}x")
    achieved, limit = at_the_bus_limit(args.seconds)
    print(f"polling at 1 Mbit/s (bus timing model): {achieved:,.0f} reads/s of the {limit:,.0f} round trips/s the bus "
          f"carries: {achieved / limit:.0%}")


if __name__ == "__main__":
    main()
