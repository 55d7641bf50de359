"""A small ECU for the slave's tests: the HDS9 memory map with a tiny application, no ELF needed."""

from __future__ import annotations

import struct

from workbench.image import AddressRange, MemoryImage
from workbench.sim.ecu import SimulatedEcu
from workbench.sim.layout import ApplicationLayout, InitCopy
from workbench.sim.memory_map import HDS9
from workbench.sim.seedkey import compute_key
from workbench.xcp_protocol import PID_ERR, PID_RES, Cmd, Err, Resource

EPK = b"08493820231002"
CAL_GAIN = 0x40000010  # float 2.0 in .cal_ram
CAL_OFFSET = 0x40000014  # float 5.0
CAL_END = 0x40000020
COUNTER = 0x40020000  # uint32 incremented every 4 ms
OUTPUT = 0x40020004  # float gain * counter + offset, every 50 ms
DATA_INIT = 0x40020010  # .data: uint32 0xC0FFEE00 loaded from flash
DATA_LOAD = 0x840100


def mini_image(key: bool = True) -> MemoryImage:
    image = MemoryImage()
    image.add(0xFC0000, EPK)
    image.add(0xFC0010, struct.pack("<ff", 2.0, 5.0) + bytes(8))
    image.add(DATA_LOAD, struct.pack("<I", 0xC0FFEE00))
    if key:
        image.add(HDS9.app_key_address, HDS9.app_key)
    return image


MINI_LAYOUT = ApplicationLayout(
    cal_ram=(AddressRange(CAL_GAIN, CAL_END),),
    init_copies=(InitCopy(DATA_INIT, DATA_LOAD, 4),),
    zero_ranges=(AddressRange(COUNTER, COUNTER + 8),),
    symbols={"counter": COUNTER, "output": OUTPUT},
)


class CounterApp:
    """Counts 4 ms ticks; every 50 ms computes gain * count + offset from its calibrations."""

    TASKS = ((0.004, "task_4ms", 0), (0.050, "task_50ms", 1), (0.100, "task_100ms", 2))

    def __init__(self, memory, symbols, hardware):
        self.memory = memory
        self.symbols = symbols
        self.initialized = False

    def initialize(self) -> None:
        self.initialized = True

    def task_4ms(self) -> None:
        count = struct.unpack("<I", self.memory.read(self.symbols["counter"], 4))[0]
        self.memory.write(self.symbols["counter"], struct.pack("<I", count + 1))

    def task_50ms(self) -> None:
        count = struct.unpack("<I", self.memory.read(COUNTER, 4))[0]
        gain, offset = struct.unpack("<ff", self.memory.read(CAL_GAIN, 8))
        self.memory.write(OUTPUT, struct.pack("<f", gain * count + offset))

    def task_100ms(self) -> None:
        pass


def make_ecu(key: bool = True, **kwargs) -> SimulatedEcu:
    return SimulatedEcu(mini_image(key), MINI_LAYOUT, CounterApp, **kwargs)


class XcpProbe:
    """Send CTOs straight to an ECU and check what comes back."""

    def __init__(self, ecu: SimulatedEcu):
        self.ecu = ecu

    def send(self, *cto: int | bytes) -> list[bytes]:
        return self.ecu.handle_cto(_bytes(cto))

    def ok(self, *cto: int | bytes) -> bytes:
        """The positive response's payload (after 0xFF); fails on anything else."""
        packets = self.send(*cto)
        assert len(packets) == 1, f"{_bytes(cto).hex(' ')} -> {[p.hex(' ') for p in packets]}"
        assert packets[0][0] == PID_RES, f"{_bytes(cto).hex(' ')} -> {packets[0].hex(' ')}"
        return packets[0][1:]

    def err(self, *cto: int | bytes) -> Err:
        packets = self.send(*cto)
        assert len(packets) == 1 and packets[0][0] == PID_ERR, f"{_bytes(cto).hex(' ')} -> {[p.hex(' ') for p in packets]}"
        return Err(packets[0][1])

    def upload(self, size: int) -> bytes:
        """UPLOAD in slave block mode: the data of every response packet, joined."""
        packets = self.send(Cmd.UPLOAD, size)
        assert packets and all(p[0] == PID_RES for p in packets), [p.hex(" ") for p in packets]
        return b"".join(p[1:] for p in packets)

    def silent(self, *cto: int | bytes) -> None:
        packets = self.send(*cto)
        assert packets == [], f"{_bytes(cto).hex(' ')} -> {[p.hex(' ') for p in packets]}"

    def connect(self) -> bytes:
        return self.ok(Cmd.CONNECT, 0)

    def unlock(self, resource: Resource) -> int:
        seed = self.ok(Cmd.GET_SEED, 0, resource)
        key = compute_key(seed[1 : 1 + seed[0]], resource) if seed[0] else b""
        if not seed[0]:
            return -1
        return self.ok(Cmd.UNLOCK, len(key), key)[0]

    def unlock_all(self) -> None:
        for resource in (Resource.CAL_PAG, Resource.DAQ, Resource.PGM):
            self.unlock(resource)

    def set_mta(self, address: int) -> None:
        self.ok(Cmd.SET_MTA, 0, 0, 0, struct.pack("<I", address))

    def short_upload(self, address: int, size: int) -> bytes:
        return self.ok(Cmd.SHORT_UPLOAD, size, 0, 0, struct.pack("<I", address))


def _bytes(parts) -> bytes:
    out = bytearray()
    for part in parts:
        out += part if isinstance(part, (bytes, bytearray)) else bytes([int(part)])
    return bytes(out)
