"""Test support for the FLCU twin: a flat memory loaded like the boot would load it, a CAN
driver stand-in, and the C application compiled for the host (``make -C assets/ecu host``).
"""

from __future__ import annotations

import ctypes
import re
import shutil
import subprocess
from pathlib import Path

import bincopy

from workbench import demo
from workbench.elf import ElfSymbols
from workbench.sim.flcu import FlcuApplication, RxPduInfo
from workbench.sim.plant import FuelSystemPlant, PlantParameters

CAL_ROM, CAL_RAM, CAL_SIZE = 0xFC0000, 0x40000000, 0x20000
RAM, RAM_SIZE = 0x40020000, 0x60000
ECU_SOURCES = demo.path("assets", "ecu")


class FlatMemory:
    """CAL RAM and RAM as plain bytes, filled as the boot code fills them after power-on:
    CAL ROM (from the s19) copied to CAL RAM, ``.data`` copied from its load address."""

    def __init__(self, elf: ElfSymbols, s19_path: Path):
        self._windows = [(CAL_RAM, bytearray(CAL_SIZE)), (RAM, bytearray(RAM_SIZE))]
        image = bincopy.BinFile(str(s19_path))
        for segment in image.segments:
            start, data = segment.minimum_address, bytes(segment.data)
            if CAL_ROM <= start < CAL_ROM + CAL_SIZE:
                self.write(start - CAL_ROM + CAL_RAM, data)
        data_section = elf.sections[".data"]
        self.write(data_section.address, image[data_section.load_address : data_section.load_address + data_section.size])

    def _window(self, address: int, size: int) -> tuple[bytearray, int]:
        for start, data in self._windows:
            if start <= address and address + size <= start + len(data):
                return data, address - start
        raise IndexError(f"0x{address:X}+{size} is outside CAL RAM and RAM")

    def read(self, address: int, size: int) -> bytes:
        data, offset = self._window(address, size)
        return bytes(data[offset : offset + size])

    def write(self, address: int, data: bytes) -> None:
        window, offset = self._window(address, len(data))
        window[offset : offset + len(data)] = data


def demo_elf() -> ElfSymbols:
    return ElfSymbols(demo.elf())


class CanDriver:
    """The CAN half of the hardware: the RX PDUs a test sets, the TX PDUs the application sends.

    Reading an RX PDU clears ``new_data_received``, as the simulator's driver does.
    """

    def __init__(self):
        self.rx: dict[str, RxPduInfo] = {}
        self.tx: dict[str, list[bytes]] = {}

    def can_get_rx_pdu(self, message_name: str) -> RxPduInfo:
        pdu = self.rx.get(message_name, RxPduInfo())
        self.rx[message_name] = RxPduInfo(pdu.dlc, pdu.data, pdu.dlc_error, pdu.timeout, False, pdu.channel_id_error)
        return pdu

    def can_set_tx_pdu(self, message_name: str, dlc: int, data: bytes) -> None:
        self.tx.setdefault(message_name, []).append(bytes([dlc]) + bytes(data))


def build_host_library(directory: Path) -> Path | None:
    """Compile the C application with the host harness; None when there is no gcc/make."""
    if shutil.which("gcc") is None or shutil.which("make") is None:
        return None
    library = directory / "libflcu_host.so"
    subprocess.run(
        ["make", "-s", "-C", str(ECU_SOURCES), "host", f"HOSTLIB={library}", f"OBJ={directory / 'obj'}"],
        check=True,
        capture_output=True,
    )
    return library


def c_enumerators(header: Path) -> dict[str, int]:
    """Every enumerator of the ``typedef enum { ... } Name;`` blocks of a C header."""
    values: dict[str, int] = {}
    for body in re.findall(r"typedef enum\s*\{(.*?)\}", header.read_text(), re.S):
        body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
        value = -1
        for item in filter(None, (part.strip() for part in body.split(","))):
            name, _, explicit = (x.strip() for x in item.partition("="))
            value = int(explicit, 0) if explicit else value + 1
            values[name] = value
    return values


class HostApplication:
    """The C application in a host shared library, driven through ``host/bsw_harness.h``.

    Each instance loads its own copy of the library, so its globals start from the C
    source's initial values.
    """

    def __init__(self, library: Path, copy_to: Path):
        shutil.copyfile(library, copy_to)
        self.lib = ctypes.CDLL(str(copy_to))
        self.lib.Harness_setAdc.argtypes = (ctypes.c_uint32, ctypes.c_float)
        self.lib.Harness_setDoutError.argtypes = (ctypes.c_uint32, ctypes.c_uint8)
        self.lib.Harness_setPwmOutError.argtypes = (ctypes.c_uint32, ctypes.c_uint8)
        self.lib.Harness_setRxPdu.argtypes = (ctypes.c_uint32, ctypes.c_char_p)
        self.lib.Harness_getDout.restype = ctypes.c_uint8
        self.lib.Harness_getPwmPeriod.restype = ctypes.c_uint16
        self.lib.Harness_getPwmDuty.restype = ctypes.c_uint16
        self.lib.Harness_getTxCount.restype = ctypes.c_uint32
        self.lib.Harness_reset()

    def variable(self, name: str, size: int) -> bytes:
        """The bytes of a global of the C application."""
        return bytes((ctypes.c_ubyte * size).in_dll(self.lib, name))

    def set_variable(self, name: str, data: bytes) -> None:
        target = (ctypes.c_ubyte * len(data)).in_dll(self.lib, name)
        ctypes.memmove(target, data, len(data))

    def tx_pdu(self, mailbox: int) -> bytes:
        buffer = ctypes.create_string_buffer(9)
        self.lib.Harness_getTxPdu(mailbox, buffer)
        return buffer.raw


class PlantHardware:
    """The whole BSW API: the fuel system for I/O, :class:`CanDriver` for CAN2."""

    def __init__(self, plant: FuelSystemPlant, can: CanDriver):
        self.plant = plant
        self.can = can
        self.anin_get_adc = plant.anin_get_adc
        self.dout_set = plant.dout_set
        self.dout_error_info = plant.dout_error_info
        self.pwmout_set = plant.pwmout_set
        self.pwmout_error_info = plant.pwmout_error_info
        self.can_get_rx_pdu = can.can_get_rx_pdu
        self.can_set_tx_pdu = can.can_set_tx_pdu


def enable_frame(enable: int) -> RxPduInfo:
    """PCM_TO_FLCU_001 as freshly received."""
    return RxPduInfo(1, bytes([enable]) + bytes(7), new_data_received=True)


def target_frame(raw: int) -> RxPduInfo:
    """PCM_TO_FLCU_002 as freshly received, TargetRailPressure raw (0.01 bar)."""
    return RxPduInfo(4, raw.to_bytes(2, "little") + bytes(6), new_data_received=True)


class Rig:
    """The Python application on a flat memory, the fuel system and a PCM that sends
    EnableFLCU and TargetRailPressure every 100 ms; simulated time in 1 ms ticks.

    Tasks due at the same millisecond run fastest first, each after the PCM frames of that
    millisecond are in the driver and before the plant advances.
    """

    def __init__(self, parameters: PlantParameters | None = None, enable: int = 1, target_bar: float = 25.0):
        self.elf = demo_elf()
        self.memory = FlatMemory(self.elf, demo.s19())
        self.plant = FuelSystemPlant(parameters)
        self.can = CanDriver()
        self.app = FlcuApplication(self.memory, self.elf.symbols, PlantHardware(self.plant, self.can))
        self.variables = self.app.variables
        self.pcm_sending = True
        self.enable = enable
        self.target_bar = target_bar
        self.ms = 0
        self.app.initialize()

    def _pcm_sends(self) -> None:
        if self.pcm_sending:
            self.can.rx["PCM_TO_FLCU_001"] = enable_frame(self.enable)
            self.can.rx["PCM_TO_FLCU_002"] = target_frame(round(self.target_bar * 100))

    def tick(self) -> None:
        """One millisecond."""
        if self.ms % 100 == 0:
            self._pcm_sends()
        for period_s, method, _event in FlcuApplication.TASKS:
            if self.ms % round(period_s * 1000) == 0:
                getattr(self.app, method)()
        self.plant.step(0.001)
        self.ms += 1

    def run(self, seconds: float) -> None:
        for _ in range(round(seconds * 1000)):
            self.tick()

    def run_until(self, condition, limit_s: float) -> float:
        """Run until ``condition()`` holds; returns the simulated time [s]; fails past ``limit_s``."""
        end = self.ms + round(limit_s * 1000)
        while not condition():
            if self.ms >= end:
                raise AssertionError(f"condition not reached within {limit_s} s")
            self.tick()
        return self.ms / 1000
