"""The master against every slave profile, on CAN and on Ethernet: connect, poll, DAQ, pages, write, read-back,
fix override, cache sync and flash, each reading only what the slave and its A2L say.

The tests of one (profile, transport) share its simulator and its session (in a test worker of their own,
in any order); each leaves the ECU and the session as it found them.
"""

from __future__ import annotations

import struct
import time

import numpy as np

from workbench import demo
from workbench.elf import ElfSymbols
from workbench.flash import FlashLayout, flash_ecu, plan_flash
from workbench.image import load_image
from workbench.sim.memory_map import HDS9
from workbench.sync import sync_compare

THRESHOLD = "xsSWITCH_TANK_THR"  # real32, 20.0 in the s19
ODD_BYTE = "cfENABLEFLCU_VALUE"  # uint8 at an odd address (0x400001A3)
WORD = "cfTARGETRAILPRESSURE_VALUE"  # uint16 at an address that is no multiple of 4
CURVE = "zvRailPConv"
# on CAN a timestamp leaves the first DTO no room for data: a 4-byte list number, or a 4-byte element
NO_ROOM_FOR_TIME = {"odt-relative-word-aligned", "granularity-dword"}


def wait_until(condition, timeout_s: float = 3.0) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.01)
    return condition()


def address_of(ecu, name: str) -> int:
    return ecu.model.object(name).address


def test_connects_checks_the_epk_and_reads_what_the_slave_says(ecu, served):
    assert ecu.epk.matches is True
    info = ecu.info()
    params = served.simulator.ecu.params
    assert (info.max_cto, info.max_dto) == (params.max_cto, params.max_dto)
    assert info.address_granularity == params.address_granularity
    assert info.byte_order.startswith("MSB_FIRST" if params.byte_order == ">" else "MSB_LAST")
    assert info.daq is not None and info.daq.min_daq == params.daq.min_daq
    assert len(info.pages) == len(served.simulator.ecu.pages.segments)


def test_polling_reads_what_the_ecu_holds(ecu, served):
    assert ecu.read(THRESHOLD) == 20.0
    for name in (ODD_BYTE, WORD, CURVE):
        address, size = address_of(ecu, name), 3
        assert ecu.read_memory(address, size) == served.memory(address, size)  # odd spans, any granularity
    assert ecu.read_value(CURVE).value[-1] == 50.0
    values = ecu.read_many(["zsSensVolt", "xsTankCtrlState", "zsRailPressure", ODD_BYTE])
    assert values["zsSensVolt"].shape == (4,) and np.all((values["zsSensVolt"] >= 0) & (values["zsSensVolt"] <= 5))
    assert values["xsTankCtrlState"] in ("OFF", "TANK1_ON", "TANK2_ON")


def test_daq_samples_two_events_on_the_ecu_clock(ecu, served):
    names = ["zsRailPressure", "zsSensVolt", "xsTankCtrlState", "xsFuelLevel"]
    batches = []
    with ecu.measure(names) as live:
        deadline = time.monotonic() + 5.0
        while time.monotonic() < deadline and (sum(len(b) for b in batches if b.event == 0) < 25
                                               or not any(b.event == 1 for b in batches)):
            batches += live.read(0.1)
        stats, stamped = live.stats, live.stream.plan.timestamp_size > 0
    fast = [b for b in batches if b.event == 0]
    times = np.concatenate([b.time for b in fast])
    assert len(times) >= 25 and any(b.event == 1 for b in batches)
    if stamped:  # the ECU's clock: one 4 ms step from sample to sample
        assert np.allclose(np.diff(times), 0.004, atol=1e-4)
    else:  # arrival: DTOs that came in one datagram or read share their time
        assert np.all(np.diff(times) >= 0)
    no_room = served.transport == "CAN" and served.profile in NO_ROOM_FOR_TIME
    assert stamped == (served.simulator.ecu.params.daq.timestamp_size > 0 and not no_room)
    volts = np.concatenate([b.values["zsSensVolt"] for b in fast])
    assert volts.shape[1] == 4 and np.all((volts >= 0) & (volts <= 5))
    assert stats.lost == 0 and stats.unknown == 0


def test_pages_switch_every_segment_and_read_by_page(ecu, served):
    segments = range(len(served.simulator.ecu.pages.segments))
    ecu.write(THRESHOLD, 21.5)
    try:
        assert ecu.read(THRESHOLD, page="reference") == 20.0  # CAL ROM, through the segment that holds it
        assert ecu.read(THRESHOLD) == 21.5
        ecu.set_page("reference")
        assert [ecu.page(n).ecu_page for n in segments] == [1] * len(segments)
        assert ecu.read(THRESHOLD) == 20.0
        assert served.simulator.ecu.pages.ecu_pages == [1] * len(segments)  # the application runs on it too
        ecu.set_page("working")
        assert [ecu.page(n).xcp_page for n in segments] == [0] * len(segments)
        assert ecu.read(THRESHOLD) == 21.5
    finally:
        ecu.set_page("working")
        ecu.write(THRESHOLD, 20.0)


def test_writes_land_in_the_ecu_and_are_read_back(ecu, served):
    before = {name: ecu.read(name) for name in (ODD_BYTE, WORD)}
    curve = ecu.read_value(CURVE)
    try:
        assert ecu.write(ODD_BYTE, "Enabled").value == "Enabled"
        ecu.write(WORD, 31.5)
        table = curve.value.copy()
        table[4] += 1.0
        assert ecu.write(CURVE, table).value[4] == table[4]
        assert ecu.read(WORD) == 31.5
        address = address_of(ecu, ODD_BYTE)
        assert served.memory(address, 1) == ecu.read_memory(address, 1)
    finally:
        for name, value in before.items():
            ecu.write(name, value)
        ecu.write(CURVE, curve.value)
    assert ecu.read_value(CURVE).value.tolist() == curve.value.tolist()


def test_a_fix_override_replaces_the_signal_until_released(ecu):
    kept = ecu.read("zfRAILPRESSURE_VALUE")
    ecu.override("zfRAILPRESSURE", 33.25)
    try:
        assert wait_until(lambda: ecu.read("zsRailPressure") == 33.25)
    finally:
        state = ecu.release("zfRAILPRESSURE")
        ecu.write("zfRAILPRESSURE_VALUE", kept)
    assert not state.active
    assert wait_until(lambda: ecu.read("zsRailPressure") != 33.25)


def test_cache_sync_finds_the_one_changed_calibration(ecu):
    assert sync_compare(ecu, demo.s19()).equal
    ecu.write(THRESHOLD, 22.0)
    try:
        report = sync_compare(ecu, demo.s19())
        assert report.changed == [THRESHOLD]
    finally:
        ecu.write(THRESHOLD, 20.0)


def test_flash_calib_in_packets_the_slave_allows(ecu, served):
    """CALIB with one value changed, then the demo's CALIB again (tests of this profile may follow on this ECU)."""
    calib = HDS9.region("CALIB")
    original = load_image(demo.s19()).crop(calib.start, calib.end)
    changed = load_image(demo.s19()).crop(calib.start, calib.end)
    rom = HDS9.rom_address(ElfSymbols(demo.elf()).symbol(THRESHOLD).address)
    changed.add(rom, struct.pack("<f", 27.5), overwrite=True)
    layout = FlashLayout.from_a2l(ecu.doc, ecu.config)
    try:
        result = flash_ecu(ecu, plan_flash(changed, layout, ["CALIB"], source="cal.s19"))
        assert result.application_running and result.verified
        own = {s.range for s in served.simulator.ecu.memory_map.sectors}  # erased in the slave's sectors only
        assert result.plan.sectors and {s.range for s in result.plan.sectors} <= own
        assert served.memory(rom, 4) == struct.pack("<f", 27.5)
        assert ecu.read(THRESHOLD) == 27.5 and ecu.epk.matches is True
    finally:
        flash_ecu(ecu, plan_flash(original, layout, ["CALIB"], source="FLCU.s19"))
    assert ecu.read(THRESHOLD) == 20.0
