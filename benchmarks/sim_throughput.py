"""How fast the simulated ECU serves XCP on a ``virtual`` bus, and how close the bus timing model gets to the bus limit.

Measures, for the simulator without and with the bit-rate model (``--bitrate``):

* SHORT_UPLOAD round trips per second, with a raw python-can master and with pyxcp;
* DAQ frames per second the simulator sustains in real time: two DAQ lists of 120 full
  8-byte DTOs each on the 4 ms event offer 60,000 frames/s, more than the host or a bus carries.

With the model, each figure is also given as a fraction of what a real CAN bus of that bit
rate carries (frame bits with stuffing, from :func:`workbench.sim.can_timing.frame_bits`, of
the frames as they cross the bus: both round-trip frames padded to 8 bytes by MAX_DLC_REQUIRED,
the mean of the DTOs received). The model lets senders run up to 10 ms ahead, so a figure may
exceed 100 % by up to that lead divided by the measuring time (0.5 % at 2 s).
Plain script: ``.venv/bin/python benchmarks/sim_throughput.py [--seconds S] [--bitrate N]``.
"""

from __future__ import annotations

import argparse
import itertools
import logging
import struct
import time

import can
from pyxcp.config import create_application_from_config
from pyxcp.master import Master

from workbench.sim.can_timing import frame_bits
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.server import Simulator
from workbench.xcp_protocol import Cmd

MASTER, SLAVE = 0x7F0, 0x7F1
CAL_ADDRESS = 0x40000010
DAQ_LISTS, DAQ_ODTS = 2, 120  # 240 DTOs every 4 ms; an overload drops whole lists, so each fits the buffer
_channels = itertools.count()


def _simulator(bitrate: int | None, time_scale: float | None = None) -> tuple[Simulator, str]:
    demo = build_demo_ecu(unlocked=True)
    channel = f"bench-{next(_channels)}"
    return Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, bitrate=bitrate, time_scale=time_scale), channel


class RawMaster:
    def __init__(self, channel: str):
        self.bus = can.Bus(interface="virtual", channel=channel)

    def request(self, cto: bytes, timeout_s: float = 1.0) -> bytes:
        self.bus.send(can.Message(arbitration_id=MASTER, is_extended_id=False, data=cto.ljust(8, b"\0")))  # MAX_DLC_REQUIRED
        while (message := self.bus.recv(timeout_s)) is not None:
            if message.arbitration_id == SLAVE:
                return bytes(message.data)
        raise TimeoutError(cto.hex(" "))


SHORT_UPLOAD = bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", CAL_ADDRESS)


def round_trips_raw(bitrate: int | None, seconds: float) -> tuple[float, bytes]:
    """Round trips per second, and the response frame's data (padded to 8 bytes, as sent on the bus)."""
    sim, channel = _simulator(bitrate)
    with sim:
        master = RawMaster(channel)
        master.request(bytes([Cmd.CONNECT, 0]))
        count, start, response = 0, time.perf_counter(), b""
        while time.perf_counter() - start < seconds:
            response = master.request(SHORT_UPLOAD)
            count += 1
        elapsed = time.perf_counter() - start
        master.bus.shutdown()
    return count / elapsed, response


def round_trips_pyxcp(bitrate: int | None, seconds: float) -> tuple[float, None]:
    sim, channel = _simulator(bitrate)
    app = create_application_from_config(
        {"Transport": {"CAN": {"interface": "virtual", "channel": channel, "can_id_master": MASTER, "can_id_slave": SLAVE,
                             "max_dlc_required": True}}},
        log_level=logging.CRITICAL,
    )
    with sim, Master("can", config=app) as master:
        master.connect()
        count, start = 0, time.perf_counter()
        while time.perf_counter() - start < seconds:
            master.shortUpload(4, CAL_ADDRESS)
            count += 1
        elapsed = time.perf_counter() - start
        master.disconnect()
    return count / elapsed, None


def daq_frames(bitrate: int | None, seconds: float) -> tuple[float, float]:
    """DTOs per second received in real time from ``DAQ_LISTS`` lists of ``DAQ_ODTS`` full ODTs on the 4 ms event,
    and their mean length in bits (their stuff bits depend on the data)."""
    sim, channel = _simulator(bitrate, time_scale=1.0)
    with sim:
        master = RawMaster(channel)
        master.request(bytes([Cmd.CONNECT, 0]))
        master.request(bytes([Cmd.FREE_DAQ]))
        master.request(bytes([Cmd.ALLOC_DAQ, 0]) + struct.pack("<H", DAQ_LISTS))
        for daq in range(DAQ_LISTS):
            master.request(bytes([Cmd.ALLOC_ODT, 0]) + struct.pack("<H", daq) + bytes([DAQ_ODTS]))
        for daq, odt in itertools.product(range(DAQ_LISTS), range(DAQ_ODTS)):
            master.request(bytes([Cmd.ALLOC_ODT_ENTRY, 0]) + struct.pack("<H", daq) + bytes([odt, 2]))
        for daq, odt in itertools.product(range(DAQ_LISTS), range(DAQ_ODTS)):
            master.request(bytes([Cmd.SET_DAQ_PTR, 0]) + struct.pack("<H", daq) + bytes([odt, 0]))
            for size in (4, 3):
                master.request(bytes([Cmd.WRITE_DAQ, 0xFF, size, 0]) + struct.pack("<I", 0x40020000 + 8 * odt))
        for daq in range(DAQ_LISTS):
            master.request(bytes([Cmd.SET_DAQ_LIST_MODE, 0]) + struct.pack("<HH", daq, 0) + bytes([1, 0]))
            master.request(bytes([Cmd.START_STOP_DAQ_LIST, 1]) + struct.pack("<H", daq))
        count, bits = 0, 0
        start = time.perf_counter()
        while time.perf_counter() - start < seconds:
            message = master.bus.recv(0.1)
            if message is not None and message.arbitration_id == SLAVE:
                count += 1
                bits += frame_bits(message)
        elapsed = time.perf_counter() - start
        master.bus.shutdown()
    return count / elapsed, bits / max(count, 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="measuring time per figure")
    parser.add_argument("--bitrate", type=int, default=1_000_000, help="bit rate of the timing model")
    args = parser.parse_args()
    def bits(identifier: int, data: bytes) -> int:
        return frame_bits(can.Message(arbitration_id=identifier, is_extended_id=False, data=data))

    print(f"simulated ECU on python-can 'virtual', {args.seconds:.1f} s per figure")
    print(f"{'figure':44} {'no timing model':>16} {'model ' + str(args.bitrate):>22} {'bus limit':>10}")
    response = b""
    for label, measure in (("SHORT_UPLOAD round trips/s (raw master)", round_trips_raw),
                           ("SHORT_UPLOAD round trips/s (pyxcp)", round_trips_pyxcp)):
        free, sample = measure(None, args.seconds)
        response = sample or response
        paced, _ = measure(args.bitrate, args.seconds)
        round_trip_bits = bits(MASTER, SHORT_UPLOAD) + bits(SLAVE, response)  # both frames as they cross the bus
        upload_limit = args.bitrate / round_trip_bits
        print(f"{label:44} {free:16.0f} {paced:12.0f} ({paced / upload_limit:5.1%}) {upload_limit:10.0f}")
    free, _ = daq_frames(None, args.seconds)
    paced, dto_bits = daq_frames(args.bitrate, args.seconds)
    daq_limit = args.bitrate / dto_bits
    print(f"{'DAQ frames/s (8-byte DTOs, real time)':44} {free:16.0f} {paced:12.0f} ({paced / daq_limit:5.1%}) {daq_limit:10.0f}")
    print(f"(round trip = {round_trip_bits} bits; a DTO = {dto_bits:.1f} bits on average)")

if __name__ == "__main__":
    main()
