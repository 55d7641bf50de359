"""How fast the simulated ECU serves XCP on Ethernet, against XCP on CAN (``virtual``) in the same run.

Per transport (CAN on python-can's ``virtual`` bus, UDP and TCP on loopback), the demo ECU served by
``serve_demo`` with the A2L's packet sizes of that transport:

* SHORT_UPLOAD round trips per second, with a raw master and with pyxcp;
* calibration bytes read per second with UPLOAD in slave block mode (255 bytes per command:
  37 response frames on CAN, 2 packets on Ethernet);
* DTOs per second from one DAQ list as large as one ODT of the transport allows (on CAN one 8-byte
  DTO, on Ethernet 254 four-byte entries: a 1021-byte DTO) on the 4 ms event, against the 250 offered.

Ratios are against XCP on CAN measured in the same run. Plain script:
``.venv/bin/python benchmarks/sim_ethernet.py [--seconds S]``.
"""

from __future__ import annotations

import argparse
import logging
import socket
import struct
import time
from collections.abc import Callable

import can
from pyxcp.config import create_application_from_config
from pyxcp.master import Master

from workbench.sim import EthernetEndpoint, serve_demo
from workbench.xcp_protocol import Cmd

CAL_ADDRESS = 0x40000010
RAM = 0x40020000
HEADER = struct.Struct("<HH")
SHORT_UPLOAD = bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", CAL_ADDRESS)


class CanMaster:
    def __init__(self, channel: str):
        self.bus = can.Bus(interface="virtual", channel=channel)

    def send(self, cto: bytes) -> None:
        self.bus.send(can.Message(arbitration_id=0x7F0, is_extended_id=False, data=cto.ljust(8, b"\0")))

    def receive(self, timeout_s: float = 1.0) -> bytes | None:
        while (message := self.bus.recv(timeout_s)) is not None:
            if message.arbitration_id == 0x7F1:
                return bytes(message.data)
        return None

    def close(self) -> None:
        self.bus.shutdown()


class EthMaster:
    def __init__(self, address: tuple[str, int], protocol: str):
        self.udp = protocol == "UDP"
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM) if self.udp else socket.create_connection(address)
        if self.udp:
            self.sock.connect(address)
        else:
            self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.ctr = 0
        self._pending: list[bytes] = []
        self._stream = b""

    def send(self, cto: bytes) -> None:
        self.sock.send(HEADER.pack(len(cto), self.ctr) + cto)
        self.ctr = (self.ctr + 1) & 0xFFFF

    def receive(self, timeout_s: float = 1.0) -> bytes | None:
        self.sock.settimeout(timeout_s)
        while not self._pending:
            try:
                data = self.sock.recv(0xFFFF)
            except TimeoutError:
                return None
            data = data if self.udp else self._stream + data
            while len(data) >= 4 and len(data) >= 4 + HEADER.unpack_from(data)[0]:
                length = HEADER.unpack_from(data)[0]
                self._pending.append(data[4 : 4 + length])
                data = data[4 + length :]
            self._stream = b"" if self.udp else data
        return self._pending.pop(0)

    def close(self) -> None:
        self.sock.close()


def _serve(transport: str, channel: str):
    if transport == "CAN":
        return serve_demo({"interface": "virtual", "channel": channel}, unlocked=True)
    return serve_demo(ethernet=EthernetEndpoint("127.0.0.1", 0, transport), unlocked=True)


def _master(transport: str, sim, channel: str):
    return CanMaster(channel) if transport == "CAN" else EthMaster(sim.xcp.address, transport)


def _request(master, cto: bytes, answers: int = 1) -> list[bytes]:
    master.send(cto)
    return [master.receive() for _ in range(answers)]


def per_second(step: Callable[[], int], seconds: float) -> float:
    """How many units ``step`` (which returns the units it did) does per second, run for ``seconds``."""
    count, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        count += step()
    return count / (time.perf_counter() - start)


def round_trips(transport: str, seconds: float) -> float:
    channel = f"bench-eth-rt-{transport}"
    with _serve(transport, channel) as sim:
        master = _master(transport, sim, channel)
        _request(master, bytes([Cmd.CONNECT, 0]))
        rate = per_second(lambda: len(_request(master, SHORT_UPLOAD)), seconds)
        master.close()
    return rate


def round_trips_pyxcp(transport: str, seconds: float) -> float:
    channel = f"bench-eth-pyxcp-{transport}"
    with _serve(transport, channel) as sim:
        if transport == "CAN":
            config = {"CAN": {"interface": "virtual", "channel": channel, "can_id_master": 0x7F0, "can_id_slave": 0x7F1,
                              "max_dlc_required": True}}
        else:
            host, port = sim.xcp.address
            config = {"Eth": {"host": host, "port": port, "protocol": transport}}
        app = create_application_from_config({"Transport": config}, log_level=logging.CRITICAL)
        logging.getLogger("pyxcp").setLevel(logging.CRITICAL)
        with Master("can" if transport == "CAN" else "eth", config=app) as master:
            master.connect()
            rate = per_second(lambda: len(master.shortUpload(4, CAL_ADDRESS)) // 4, seconds)
            master.disconnect()
    return rate


def upload_bytes(transport: str, seconds: float) -> float:
    channel = f"bench-eth-up-{transport}"
    with _serve(transport, channel) as sim:
        master = _master(transport, sim, channel)
        max_cto = _request(master, bytes([Cmd.CONNECT, 0]))[0][3]
        packets = -(-255 // (max_cto - 1))

        def upload() -> int:
            _request(master, bytes([Cmd.SET_MTA, 0, 0, 0]) + struct.pack("<I", 0xFC0000))
            return sum(len(packet) - 1 for packet in _request(master, bytes([Cmd.UPLOAD, 255]), packets))

        rate = per_second(upload, seconds)
        master.close()
    return rate


def daq_rate(transport: str, seconds: float) -> tuple[float, int]:
    """DTOs per second received, and their size, from one list of the largest ODT on the 4 ms event."""
    channel = f"bench-eth-daq-{transport}"
    with _serve(transport, channel) as sim:
        master = _master(transport, sim, channel)
        max_dto = struct.unpack_from("<H", _request(master, bytes([Cmd.CONNECT, 0]))[0], 4)[0]
        entries = min((max_dto - 1) // 4, 254)
        setup = [
            bytes([Cmd.FREE_DAQ]),
            bytes([Cmd.ALLOC_DAQ, 0]) + struct.pack("<H", 1),
            bytes([Cmd.ALLOC_ODT, 0]) + struct.pack("<H", 0) + bytes([1]),
            bytes([Cmd.ALLOC_ODT_ENTRY, 0]) + struct.pack("<H", 0) + bytes([0, max(entries, 1)]),
            bytes([Cmd.SET_DAQ_PTR, 0]) + struct.pack("<H", 0) + bytes([0, 0]),
            *(bytes([Cmd.WRITE_DAQ, 0xFF, 4, 0]) + struct.pack("<I", RAM + 4 * n) for n in range(max(entries, 1))),
            bytes([Cmd.SET_DAQ_LIST_MODE, 0]) + struct.pack("<HH", 0, 0) + bytes([1, 0]),
            bytes([Cmd.START_STOP_DAQ_LIST, 1]) + struct.pack("<H", 0),
        ]
        for cto in setup:
            _request(master, cto)
        count, size, start = 0, 0, time.perf_counter()
        while time.perf_counter() - start < seconds:
            dto = master.receive(0.1)
            if dto is not None and dto[0] == 0:
                count, size = count + 1, len(dto)
        elapsed = time.perf_counter() - start
        master.close()
    return count / elapsed, size


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="measuring time per figure")
    args = parser.parse_args()
    transports = ("CAN", "UDP", "TCP")
    print(f"simulated ECU, XCP on CAN (virtual) and on Ethernet (loopback), {args.seconds:.1f} s per figure")
    print(f"{'figure':40}" + "".join(f"{name:>20}" for name in transports))
    for label, measure in (("SHORT_UPLOAD round trips/s (raw)", round_trips),
                           ("SHORT_UPLOAD round trips/s (pyxcp)", round_trips_pyxcp),
                           ("UPLOAD bytes/s (255 per command)", upload_bytes)):
        figures = [measure(transport, args.seconds) for transport in transports]
        print(f"{label:40}" + "".join(f"{value:12.0f} ({value / figures[0]:4.1f}x)" for value in figures))
    rates = [daq_rate(transport, args.seconds) for transport in transports]
    print(f"{'DTOs/s of the largest ODT (250 offered)':40}" + "".join(f"{rate:11.0f} ({size:4d} B)" for rate, size in rates))


if __name__ == "__main__":
    main()
