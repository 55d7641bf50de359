"""The ECU's memory model: flash semantics, RAM loss, boot copies."""

import struct

import pytest
from mini_ecu import CAL_GAIN, COUNTER, DATA_INIT, MINI_LAYOUT, XcpProbe, mini_image

from workbench.image import AddressRange, MemoryImage, Region
from workbench.sim.ecu import EcuState, SimulatedEcu
from workbench.sim.memory import AccessFault, EcuMemory, MemoryAccessError
from workbench.xcp_protocol import Cmd, Resource


def memory() -> EcuMemory:
    return EcuMemory([Region("F", 0x1000, 0x400, 0x100)], {"RAM": AddressRange(0x8000, 0x8100)}, {"ROM": (0x9000, b"hi")})


def test_erased_flash_programs_once():
    mem = memory()
    assert mem.read(0x1000, 4) == b"\xff" * 4
    mem.program(0x1000, b"ab")
    with pytest.raises(MemoryAccessError) as info:
        mem.program(0x1001, b"x")
    assert info.value.fault is AccessFault.NOT_ERASED
    assert mem.erase(0x1000, 0x100) == [AddressRange(0x1000, 0x1100)]
    mem.program(0x1001, b"x")


@pytest.mark.parametrize(
    ("call", "fault"),
    [
        (lambda m: m.erase(0x1000, 0x80), AccessFault.NOT_SECTOR_ALIGNED),
        (lambda m: m.erase(0x8000, 0x100), AccessFault.UNMAPPED),
        (lambda m: m.write(0x1000, b"x"), AccessFault.READ_ONLY),
        (lambda m: m.write(0x9000, b"x"), AccessFault.READ_ONLY),
        (lambda m: m.read(0x13FF, 2), AccessFault.CROSSES_AREA),
        (lambda m: m.read(0x0, 1), AccessFault.UNMAPPED),
        (lambda m: m.program(0x8000, b"x"), AccessFault.UNMAPPED),
    ],
)
def test_refused_accesses(call, fault):
    with pytest.raises(MemoryAccessError) as info:
        call(memory())
    assert info.value.fault is fault


def test_power_loss_clears_ram_and_keeps_flash_and_rom():
    mem = memory()
    mem.program(0x1100, b"keep")
    mem.write(0x8000, b"lost")
    mem.clear_ram()
    assert (mem.read(0x1100, 4), mem.read(0x8000, 4), mem.read(0x9000, 2)) == (b"keep", bytes(4), b"hi")
    assert mem.flash_image() == MemoryImage.from_bytes(0x1100, b"keep")


def test_image_outside_flash_is_refused():
    with pytest.raises(MemoryAccessError):
        memory().load_flash(MemoryImage.from_bytes(0x8000, b"x"))


def test_power_on_copies_cal_rom_and_data_and_a_power_cycle_loses_ram(ecu):
    assert ecu.state is EcuState.APPLICATION and ecu.application.initialized
    assert ecu.read(CAL_GAIN, 4) == struct.pack("<f", 2.0)
    assert ecu.read(DATA_INIT, 4) == struct.pack("<I", 0xC0FFEE00)
    probe = XcpProbe(ecu)
    probe.connect()
    probe.unlock(Resource.CAL_PAG)
    probe.set_mta(CAL_GAIN)
    probe.ok(Cmd.DOWNLOAD, 4, struct.pack("<f", 8.0))
    ecu.advance(0.2)
    assert struct.unpack("<I", ecu.read(COUNTER, 4))[0] == 50
    ecu.power_off()
    ecu.power_on()
    assert ecu.read(CAL_GAIN, 4) == struct.pack("<f", 2.0)  # the working page change was RAM only
    assert ecu.read(COUNTER, 4) == bytes(4)


def test_tasks_run_fastest_first_at_the_same_instant():
    order = []
    ecu = SimulatedEcu(mini_image(), MINI_LAYOUT, lambda memory, symbols, hardware: _Recording(order))
    ecu.power_on()
    ecu.advance(0.1)
    assert order[-3:] == ["task_4ms", "task_50ms", "task_100ms"]
    assert order.count("task_4ms") == 25 and order.count("task_50ms") == 2


class _Recording:
    TASKS = ((0.100, "task_100ms", 2), (0.004, "task_4ms", 0), (0.050, "task_50ms", 1))

    def __init__(self, order):
        self.order = order

    def initialize(self):
        pass

    def task_4ms(self):
        self.order.append("task_4ms")

    def task_50ms(self):
        self.order.append("task_50ms")

    def task_100ms(self):
        self.order.append("task_100ms")
