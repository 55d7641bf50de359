"""Polling by name and a DAQ stream through the session's own transport, each against a reference in the same run.

1. XCP on Ethernet (UDP and TCP): a ``workbench sim --host`` process; in this process, alternating rounds of
   ``Session.read("xsSWITCH_TANK_THR")`` (by name, physical: model lookup, codec, SHORT_UPLOAD, conversion)
   and a raw socket master sending the same SHORT_UPLOAD (LEN/CTR framed by hand, a blocking receive) to the
   same slave. Figure: microseconds per read and the ratio (goal: at most 2x the raw socket).
2. In-process on a ``virtual`` bus without a bus model: the simulator in this process; alternating rounds of
   ``Session.read`` and a raw python-can master (``bus.send``, then ``bus.recv`` until the slave's id) doing
   the same SHORT_UPLOAD. Figure: reads/s and the ratio (goal: at least 0.8x the raw master).
3. In-process at 1 Mbit/s (the simulator's bus timing model): the session's reads/s as a fraction of the round
   trips the bus carries (the request and the response as they are sent, both padded to 8 bytes by
   MAX_DLC_REQUIRED, exact bit counts with stuffing from :func:`workbench.sim.can_timing.frame_bits`).
   Goal: at least 95 %.
4. Between processes on udp_multicast: ``Session.read`` against pyxcp's ``shortUpload``, the independent
   master, on a ``workbench sim`` process.
5. DAQ on XCP on UDP and TCP: a ``workbench sim --host`` process; one DAQ list of ``--daq-kib`` KiB (each
   size given) on the 4 ms event (ODTs of MAX_DTO 1024 bytes), through the session's link for
   ``--daq-seconds``: DTOs/s received, the slave's clock against real time (below 100 %: the simulator
   cannot compute the samples faster, it runs at its full rate), samples lost (timestamp gaps, broken ODT
   sequences), overloads and gaps in the slave's packet counter (packets the host lost).

Rounds alternate the two sides and each ratio is taken from a pair of neighbouring rounds (the median is
printed with the range), so a machine that drifts moves both. Plain script:
``.venv/bin/python benchmarks/session_bench.py [--seconds 1] [--rounds 5] [--only ethernet,virtual,bus,pyxcp,daq]``.
"""

from __future__ import annotations

import argparse
import logging
import socket
import statistics
import struct
import subprocess
import sys
import time
from collections.abc import Callable

import can

from workbench import Session
from workbench.sim import serve_demo
from workbench.sim.can_timing import frame_bits
from workbench.sim.seedkey import compute_key
from workbench.xcp.daq import DaqSignal, DaqStream, plan_daq
from workbench.xcp_protocol import Cmd

NAME = "xsSWITCH_TANK_THR"
HEADER = struct.Struct("<HH")
CAL_RAM = 0x40000010  # any mapped memory can be sampled; the .cal_ram image is a large readable block
TASK_4MS = 0
SECTIONS = ("ethernet", "virtual", "bus", "pyxcp", "daq")


def free_port(kind: socket.SocketKind) -> int:
    with socket.socket(socket.AF_INET, kind) as probe:
        probe.bind(("", 0))
        return probe.getsockname()[1]


def start_simulator(*options: str) -> subprocess.Popen:
    process = subprocess.Popen([sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", "sim",
                                *options], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in process.stdout:
        if line.startswith("serving"):
            return process
    raise RuntimeError(process.stderr.read())


def stop(process: subprocess.Popen) -> None:
    process.terminate()
    process.wait(10)


def rate(call: Callable[[], object], seconds: float) -> float:
    count, started = 0, time.perf_counter()
    while time.perf_counter() - started < seconds:
        call()
        count += 1
    return count / (time.perf_counter() - started)


def alternate(ours: Callable[[], object], reference: Callable[[], object], seconds: float, rounds: int
              ) -> tuple[list[float], list[float]]:
    """Rates of ``ours`` and ``reference`` in alternating rounds (warmed up first)."""
    rate(ours, 0.1), rate(reference, 0.1)
    ours_rates, reference_rates = [], []
    for _ in range(rounds):
        ours_rates.append(rate(ours, seconds))
        reference_rates.append(rate(reference, seconds))
    return ours_rates, reference_rates


def ratios(ours: list[float], reference: list[float]) -> str:
    """The reference's time per call over ours, round by round: median (min-max)."""
    values = [a / b for a, b in zip(ours, reference)]
    return f"{statistics.median(values):.2f}x ({min(values):.2f}-{max(values):.2f})"


def short_upload(address: int) -> bytes:
    return bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", address)


# --- 1. XCP on Ethernet: Session.read vs a raw socket ---------------------------------------------

class RawSocketMaster:
    """SHORT_UPLOAD by hand: one framed packet out, one datagram (or segment) back."""

    def __init__(self, port: int, protocol: str):
        kind = socket.SOCK_DGRAM if protocol == "udp" else socket.SOCK_STREAM
        self.sock = socket.socket(socket.AF_INET, kind)
        if protocol == "tcp":
            self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.sock.connect(("127.0.0.1", port))
        self.sock.settimeout(1.0)
        self.ctr = 0

    def request(self, packet: bytes) -> bytes:
        self.sock.send(HEADER.pack(len(packet), self.ctr) + packet)
        self.ctr = (self.ctr + 1) & 0xFFFF
        return self.sock.recv(0xFFFF)[HEADER.size:]

    def close(self) -> None:
        self.request(bytes([Cmd.DISCONNECT]))
        self.sock.close()


def ethernet(protocol: str, seconds: float, rounds: int) -> str:
    port = free_port(socket.SOCK_DGRAM if protocol == "udp" else socket.SOCK_STREAM)
    simulator = start_simulator("--host", "127.0.0.1", "--port", str(port), "--protocol", protocol)
    try:
        ours, reference = [], []
        for _ in range(rounds):  # one master connected at a time: the slave has one
            with Session.open(host="127.0.0.1", port=port, protocol=protocol) as ecu:
                address = ecu.model.characteristic(NAME).address
                rate(lambda: ecu.read(NAME), 0.1)
                ours.append(rate(lambda: ecu.read(NAME), seconds))
            raw = RawSocketMaster(port, protocol)
            raw.request(bytes([Cmd.CONNECT, 0]))
            packet = short_upload(address)
            rate(lambda: raw.request(packet), 0.1)
            reference.append(rate(lambda: raw.request(packet), seconds))
            raw.close()
    finally:
        stop(simulator)
    return (f"polling, XCP on {protocol.upper()} between processes: Session.read by name "
            f"{1e6 / max(ours):.1f} us, raw socket SHORT_UPLOAD {1e6 / max(reference):.1f} us (best rounds): "
            f"Session.read takes {ratios(reference, ours)} the raw socket's time (goal <= 2x)")


# --- 2. in-process virtual bus: Session.read vs a raw python-can master -----------------------------

class RawCanMaster:
    def __init__(self, channel: str):
        self.bus = can.Bus(interface="virtual", channel=channel)

    def request(self, packet: bytes) -> bytes:
        self.bus.send(can.Message(arbitration_id=0x7F0, is_extended_id=False, data=packet.ljust(8, b"\0")))
        while (message := self.bus.recv(1.0)) is not None:
            if message.arbitration_id == 0x7F1:
                return bytes(message.data)
        raise TimeoutError("no response")

    def close(self) -> None:
        self.request(bytes([Cmd.DISCONNECT]))
        self.bus.shutdown()


def in_process(seconds: float, rounds: int) -> str:
    channel = f"session-bench-{time.monotonic_ns()}"
    with serve_demo({"interface": "virtual", "channel": channel}):
        ours, reference = [], []
        for _ in range(rounds):
            with Session.open(interface="virtual", channel=channel) as ecu:
                address = ecu.model.characteristic(NAME).address
                rate(lambda: ecu.read(NAME), 0.1)
                ours.append(rate(lambda: ecu.read(NAME), seconds))
            raw = RawCanMaster(channel)
            raw.request(bytes([Cmd.CONNECT, 0]))
            packet = short_upload(address)
            rate(lambda: raw.request(packet), 0.1)
            reference.append(rate(lambda: raw.request(packet), seconds))
            raw.close()
    return (f"polling, in-process virtual bus, no bus model: Session.read by name {max(ours):,.0f}/s, raw python-can "
            f"SHORT_UPLOAD {max(reference):,.0f}/s (best rounds): {ratios(ours, reference)} of the raw master's "
            f"reads/s (goal >= 0.8x)")


# --- 3. in-process at 1 Mbit/s ---------------------------------------------------------------------

def round_trip_bits(address: int) -> int:
    """The bits of a polled read on the wire: the SHORT_UPLOAD and its answer (20.0 as a float), both padded to 8
    bytes (MAX_DLC_REQUIRED), with their stuff bits."""
    request = can.Message(arbitration_id=0x7F0, is_extended_id=False, data=short_upload(address).ljust(8, b"\0"))
    answer = can.Message(arbitration_id=0x7F1, is_extended_id=False,
                         data=(bytes([0xFF]) + struct.pack("<f", 20.0)).ljust(8, b"\0"))
    return frame_bits(request) + frame_bits(answer)


def at_the_bus_limit(seconds: float, rounds: int, bitrate: int = 1_000_000) -> str:
    channel = f"session-bench-bus-{time.monotonic_ns()}"
    with serve_demo({"interface": "virtual", "channel": channel, "bitrate": bitrate}):
        with Session.open(interface="virtual", channel=channel) as ecu:
            address = ecu.model.characteristic(NAME).address
            rate(lambda: ecu.read(NAME), 0.1)
            achieved = [rate(lambda: ecu.read(NAME), seconds) for _ in range(rounds)]
    limit = bitrate / round_trip_bits(address)
    return (f"polling at 1 Mbit/s (the simulator's bus model, in-process): {statistics.median(achieved):,.0f} reads/s "
            f"(median of {rounds}) of the {limit:,.0f} round trips/s the bus carries: "
            f"{statistics.median(achieved) / limit:.1%} (goal >= 95 %)")


# --- 4. between processes on udp_multicast: Session.read vs pyxcp ------------------------------------

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


def against_pyxcp(seconds: float, rounds: int) -> str:
    port = free_port(socket.SOCK_DGRAM)
    simulator = start_simulator("--bus-kwargs", f"port={port}")
    try:
        ours, reference = [], []
        for _ in range(rounds):
            with Session.open(bus_kwargs={"port": port}) as ecu:
                address = ecu.model.characteristic(NAME).address
                ours.append(rate(lambda: ecu.read(NAME), seconds))
            with pyxcp_master(port) as master:
                master.connect()
                reference.append(rate(lambda: master.shortUpload(4, address), seconds))
                master.disconnect()
    finally:
        stop(simulator)
    return (f"polling, udp_multicast between processes: Session.read by name {max(ours):,.0f}/s, raw pyxcp shortUpload "
            f"{max(reference):,.0f}/s (best rounds): {ratios(ours, reference)}")


# --- 5. DAQ on Ethernet ----------------------------------------------------------------------------

def daq_on_ethernet(protocol: str, kib: int, seconds: float) -> str:
    port = free_port(socket.SOCK_DGRAM if protocol == "udp" else socket.SOCK_STREAM)
    simulator = start_simulator("--host", "127.0.0.1", "--port", str(port), "--protocol", protocol)
    try:
        with Session.open(host="127.0.0.1", port=port, protocol=protocol) as ecu:
            master = ecu.master
            processor, resolution = master.get_daq_processor_info(), master.get_daq_resolution_info()
            signals = {TASK_4MS: [DaqSignal("block", CAL_RAM, kib * 1024, element_size=1)]}
            plan = plan_daq(signals, processor, resolution, master.max_dto, consistency={TASK_4MS: "DAQ"})
            odts, max_dto = len(plan.lists[0].odts), master.max_dto
            with DaqStream(master, plan, processor, resolution, {TASK_4MS: 0.004}) as stream:
                while not (batches := stream.read(1.0)):  # start-up: the first whole samples
                    pass
                ecu_start = max(float(batch.time[-1]) for batch in batches)
                first, gaps, started = stream.stats, ecu.link.counter_gaps, time.perf_counter()
                ecu_end = ecu_start
                while time.perf_counter() - started < seconds:
                    ecu_end = max([ecu_end, *(float(batch.time[-1]) for batch in stream.read(0.1))])
                elapsed = time.perf_counter() - started
                stats = stream.stats
            gaps = ecu.link.counter_gaps - gaps
    finally:
        stop(simulator)
    received = (stats.dtos - first.dtos) / elapsed
    pace = (ecu_end - ecu_start) / elapsed  # the simulated ECU's 4 ms task against real time: its own limit
    return (f"DAQ on XCP on {protocol.upper()} between processes, {kib} KiB every 4 ms ({odts} DTOs of up to "
            f"{max_dto} bytes) for {elapsed:.0f} s: {received:,.0f} DTOs/s ({received * kib / odts / 1024:.1f} "
            f"MiB/s), the slave's clock at {pace:.0%} of real time; {stats.samples - first.samples} samples, "
            f"{stats.lost - first.lost} lost, {stats.overloads - first.overloads} overloads, CTR gaps {gaps}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=1.0, help="length of each round")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--daq-kib", type=int, nargs="+", default=[4, 64], help="KiB sampled every 4 ms by DAQ on "
                                                                                "Ethernet, a run each")
    parser.add_argument("--daq-seconds", type=float, default=10.0)
    parser.add_argument("--only", default=",".join(SECTIONS), help=f"comma-separated, of {', '.join(SECTIONS)}")
    args = parser.parse_args()
    only = set(args.only.split(","))
    if "ethernet" in only:
        for protocol in ("udp", "tcp"):
            print(ethernet(protocol, args.seconds, args.rounds), flush=True)
    if "virtual" in only:
        print(in_process(args.seconds, args.rounds), flush=True)
    if "bus" in only:
        print(at_the_bus_limit(args.seconds, args.rounds), flush=True)
    if "pyxcp" in only:
        print(against_pyxcp(args.seconds, args.rounds), flush=True)
    if "daq" in only:
        for protocol in ("udp", "tcp"):
            for kib in args.daq_kib:
                print(daq_on_ethernet(protocol, kib, args.daq_seconds), flush=True)


if __name__ == "__main__":
    main()
