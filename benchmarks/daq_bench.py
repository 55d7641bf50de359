"""DAQ through the workbench's master: host decode throughput, and a long run at the CAN bus limit.

1. Decode: DTOs of every MEASUREMENT of the demo A2L in one list (classic CAN limits, absolute
   PIDs, 4-byte timestamps) are fed to the assembler the link's receive thread feeds, then read
   as batches and converted to physical values with each signal's codec, as a measurement does.
   Figure: DTOs per second on this host, against what a saturated 1 Mbit/s bus carries (the
   goal: over 5x that, at least 50,000 DTO/s).
2. At the bus limit: the simulator with its bus timing model at 1 Mbit/s on a ``virtual`` bus
   (``--between-processes`` also: a ``workbench sim`` process on udp_multicast); one DAQ list on
   the 4 ms event sized to fill about 90 % of the bus (frame bits with stuffing from
   :func:`workbench.sim.can_timing.frame_bits`); the master collects for ``--seconds`` and reports
   DTOs/s as a fraction of the bus limit, samples, lost samples (timestamp gaps and broken ODT
   sequences) and whether the ECU's timestamps rise.

Plain script: ``.venv/bin/python benchmarks/daq_bench.py [--seconds 60] [--skip-bus]``.
"""

from __future__ import annotations

import argparse
import socket
import struct
import subprocess
import sys
import time

import can
import numpy as np

from session_bench import free_port

from workbench.bus_defaults import BusSpec
from workbench.sim.can_timing import frame_bits
from workbench.sim.seedkey import compute_key
from workbench.xcp.daq import DaqSignal, DaqStream, DtoAssembler, plan_daq
from workbench.xcp.info import DaqProcessorInfo, DaqResolutionInfo
from workbench.xcp.link import Link, LinkSettings
from workbench.xcp.master import XcpMaster
from workbench.xcp_protocol import CanId

BITRATE = 1_000_000
CAL_RAM = 0x40000010  # any mapped memory can be sampled; the .cal_ram image is a large readable block
DTO_FRAME = can.Message(arbitration_id=0x7F1, is_extended_id=False, data=bytes(range(0x11, 0x19)))  # typical data


def bus_limit_frames_per_s(bitrate: int = BITRATE) -> float:
    return bitrate / frame_bits(DTO_FRAME)


def decode_throughput(samples: int = 5_000) -> tuple[float, int, int]:
    """DTOs/s from the bytes the link receives to physical values, for every MEASUREMENT of the demo A2L
    in one list (the planning of a real measurement, each signal's conversion: enums to texts included)."""
    from workbench import demo
    from workbench.a2l import load_a2l
    from workbench.calib.signals import measurement_codec

    model = load_a2l(demo.a2l()).model()
    codecs = {name: measurement_codec(model, name) for name in model.names("MEASUREMENT")}
    processor = DaqProcessorInfo(True, False, False, True, False, "none", 16, 3, 0, 0, "free", "ABSOLUTE")
    resolution = DaqResolutionInfo(1, 4, 4, False, 1e-5, 1)
    signals = {0: [DaqSignal(name, c.span.address, c.size, element_size=c.element_size) for name, c in codecs.items()]}
    plan = plan_daq(signals, processor, resolution, 8, consistency={0: "DAQ"})
    daq = plan.lists[0]
    payload = [bytes(range(odt.size)) for odt in daq.odts]
    frames = [(bytes((number,)) + (struct.pack("<I", sample * 400) if number == 0 else b"") + payload[number]).ljust(8, b"\0")
              for sample in range(samples) for number in range(len(daq.odts))]

    class _Master:  # what DaqStream reads of the master when it only decodes
        order = "<"

    stream = DaqStream(_Master(), plan, processor, resolution, {0: 0.004})
    stream.assembler = DtoAssembler(plan, {daq.number: 0})
    feed, decoded = stream.assembler.feed, 0

    def decode_batches() -> int:
        return sum(len(codecs[name].decode_samples(batch.column(name).tobytes(), len(batch)))
                   for batch in stream.read(0) for name in daq.positions)

    started = time.perf_counter()
    for index, frame in enumerate(frames):
        feed(frame, index)
        if index % 5000 == 4999:
            decoded += decode_batches()
    decoded += decode_batches()
    elapsed = time.perf_counter() - started
    assert decoded == samples * len(codecs), decoded
    return len(frames) / elapsed, len(daq.odts), len(codecs)


def run_at_bus_limit(seconds: float, load: float = 0.9, *, between_processes: bool = False) -> dict:
    """One DAQ list on the 4 ms event sized to ``load`` of the bus, collected for ``seconds``.

    In-process (default): the simulator on a ``virtual`` bus with its timing model at 1 Mbit/s, the
    master beside it. Between processes: a ``workbench sim`` process on udp_multicast, where each
    datagram costs the sender about 120 µs (this host): the software bus, not the master, is then the limit.
    """
    from workbench.sim import serve_demo

    if between_processes:
        port = free_port(socket.SOCK_DGRAM)
        sim = subprocess.Popen([sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", "sim",
                                "--bitrate", str(BITRATE), "--bus-kwargs", f"port={port}", "--pcm"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for line in sim.stdout:
            if line.startswith("serving"):
                break
        bus = {"interface": "udp_multicast", "channel": "239.74.163.2", "port": port, "receive_own_messages": False}
        served = None
    else:
        sim = None
        bus = {"interface": "virtual", "channel": f"daq-bench-{time.monotonic_ns()}"}
        served = serve_demo({**bus, "bitrate": BITRATE}, pcm_target_bar=25.0)
    try:
        with Link(LinkSettings("CAN", BusSpec.from_kwargs(bus), CanId(0x7F0), CanId(0x7F1),
                               max_dlc_required=True)) as link:
            master = XcpMaster(link, key_function=compute_key)
            master.connect()
            processor, resolution = master.get_daq_processor_info(), master.get_daq_resolution_info()
            frames_per_sample = int(load * bus_limit_frames_per_s() * 0.004)
            size = (8 - 1 - 4) + (frames_per_sample - 1) * (8 - 1)
            signals = {0: [DaqSignal("block", CAL_RAM, size, element_size=1)]}
            plan = plan_daq(signals, processor, resolution, master.max_dto, consistency={0: "DAQ"})
            times = []
            with DaqStream(master, plan, processor, resolution, {0: 0.004}) as stream:
                stream.read(1.0)  # the first samples: start-up
                start_dtos, started = stream.stats.dtos, time.perf_counter()
                while time.perf_counter() - started < seconds:
                    times += [batch.time for batch in stream.read(0.1)]
                elapsed = time.perf_counter() - started
                stats = stream.stats
            master.disconnect()
        dropped = served.dropped_frames() if served is not None else None
    finally:
        if served is not None:
            served.close()
        if sim is not None:
            sim.terminate()
            sim.wait(10)
    dtos_per_s = (stats.dtos - start_dtos) / elapsed
    series = np.concatenate(times) if times else np.zeros(0)
    return {"odts": len(plan.lists[0].odts), "dtos_per_s": dtos_per_s, "bus_limit": bus_limit_frames_per_s(),
            "samples": stats.samples, "lost": stats.lost, "overloads": stats.overloads,
            "monotonic": bool(np.all(np.diff(series) > 0)), "seconds": elapsed, "dropped_by_ecu": dropped}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=60.0, help="length of the run at the bus limit")
    parser.add_argument("--skip-bus", action="store_true", help="only the decode throughput")
    parser.add_argument("--between-processes", action="store_true",
                        help="also run against a workbench sim process on udp_multicast")
    args = parser.parse_args()
    limit = bus_limit_frames_per_s()
    rate, odts, signals = decode_throughput()
    print(f"decode to physical values: {rate:,.0f} DTO/s on this host ({signals} signals of the demo A2L, {odts} ODTs "
          f"a sample); a saturated 1 Mbit/s bus carries {limit:,.0f} frames/s: {rate / limit:.1f}x")
    if args.skip_bus:
        return
    for between in (False, True) if args.between_processes else (False,):
        result = run_at_bus_limit(args.seconds, between_processes=between)
        where = "udp_multicast between processes" if between else "in-process virtual bus, timing model"
        print(f"at the bus limit, {where} ({result['seconds']:.0f} s, {result['odts']} ODTs on the 4 ms event): "
              f"{result['dtos_per_s']:,.0f} DTO/s = {result['dtos_per_s'] / result['bus_limit']:.1%} of the "
              f"{result['bus_limit']:,.0f} frames/s a 1 Mbit/s bus carries; samples {result['samples']}, "
              f"lost {result['lost']}, overloads {result['overloads']}, ECU timestamps rising: {result['monotonic']}"
              + (f"; frames the ECU dropped (transmit buffer full): {result['dropped_by_ecu']}"
                 if result["dropped_by_ecu"] is not None else ""))


if __name__ == "__main__":
    main()
