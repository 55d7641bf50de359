"""pyxcp, an independent master, against the simulated FLCU ECU on an in-process ``virtual`` bus."""

from __future__ import annotations

import itertools
import struct
import time

import pytest
from pyxcp.daq_stim import DaqList
from pyxcp_master import Samples, connect, pyxcp_master

from workbench.elf import ElfSymbols
from workbench.image import load_image
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.ecu import EcuState
from workbench.sim.memory_map import HDS9
from workbench.sim.server import Simulator

_channels = itertools.count()
CALIB = HDS9.region("CALIB")


@pytest.fixture
def channel() -> str:
    return f"sim-pyxcp-{next(_channels)}"


@pytest.fixture
def demo():
    return build_demo_ecu()


@pytest.fixture
def symbols(demo):
    return ElfSymbols(demo.files.elf)


def calibration_in_s19(demo, symbols, name: str, size: int) -> bytes:
    address = symbols.symbol(name).address
    return load_image(demo.files.s19).read(HDS9.rom_address(address), size)


def test_connect_epk_upload_download(demo, symbols, channel):
    with Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, time_scale=1.0):
        with pyxcp_master("virtual", channel) as master:
            connect(master)
            assert master.identifier(5) == demo.a2l.epk()
            threshold = symbols.symbol("xsSWITCH_TANK_THR").address
            uploaded = bytes(master.shortUpload(4, threshold))
            assert uploaded == calibration_in_s19(demo, symbols, "xsSWITCH_TANK_THR", 4)
            assert struct.unpack("<f", uploaded)[0] == 20.0
            master.cond_unlock("CALPAG")
            master.push(threshold, 0, struct.pack("<f", 35.5))
            assert struct.unpack("<f", bytes(master.shortUpload(4, threshold)))[0] == 35.5
            master.setMta(threshold)
            # the slave pads to DLC 8 (MAX_DLC_REQUIRED); pyxcp's upload() hands the padding back
            assert struct.unpack("<f", bytes(master.upload(4))[:4])[0] == 35.5
            lut = symbols.symbol("zvRailPConv")
            master.setMta(lut.address)
            table = bytes(master.fetch(lut.size))  # slave block mode: up to 255 bytes per UPLOAD
            assert table == calibration_in_s19(demo, symbols, "zvRailPConv", lut.size)
            master.disconnect()


def test_seed_and_key_unlocks_every_resource(demo, channel):
    with Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, time_scale=1.0):
        with pyxcp_master("virtual", channel) as master:
            connect(master)
            assert master.getCurrentProtectionStatus() == {
                "dbg": False, "pgm": True, "stim": False, "daq": True, "calpag": True}
            master.cond_unlock()
            assert not any(master.getCurrentProtectionStatus().values())
            master.disconnect()


def test_daq_on_the_50ms_event_decodes_the_ecu_values(demo, symbols, channel):
    # written by the 4 ms and 50 ms tasks, which run before the event at each 50 ms instant
    names = [("zsRailPressure", "F32"), ("xsDC", "F32"), ("xsTankCtrlState", "U8"),
             ("xsSWITCH_TANK_THR", "F32"), ("xsFuelLevel", "F32")]
    target = ("csPCM_TO_FLCU_002_TargetRailPressure", symbols.symbol("csPCM_TO_FLCU_002_TargetRailPressure").address, 0, "F32")
    measurements = [(name, symbols.symbol(name).address, 0, kind) for name, kind in names] + [target]
    policy = Samples([DaqList(name="task50", event_num=1, stim=False, enable_timestamps=True,
                              measurements=measurements, priority=0, prescaler=1)])
    sim = Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, can2_driver=demo.can2,
                    pcm=demo.pcm_node(target_bar=25.0), time_scale=None)
    expected = []
    with sim, pyxcp_master("virtual", channel, policy=policy) as master:
        connect(master)
        master.cond_unlock("DAQ")
        policy.setup()
        policy.start()
        for _ in range(30):  # 1.5 s of simulated time, one 50 ms event per step
            sim.advance(0.05)
            expected.append([_value(demo.ecu, symbols, name, kind) for name, kind in names])
        _wait_for(lambda: len(policy.rows) >= 30)
        policy.stop()
        master.disconnect()
    values = [[row[name] for name, _ in names] for _, row in policy.rows[:30]]
    assert values == expected  # float32 bytes decoded by pyxcp and read from the ECU: identical
    ticks = [timestamp for timestamp, _ in policy.rows[:30]]
    assert {b - a for a, b in zip(ticks, ticks[1:])} == {50_000_000}  # ECU timestamps, ns: exactly 50 ms apart
    assert policy.rows[29][1][target[0]] == 25.0 and values[-1][0] > 20.0  # the PCM's target arrived; the rail rose
    assert all(row[3] == 20.0 for row in values) and values[-1][2] == 1  # TANK1_ON


def test_full_block_mode_program_of_calib(demo, symbols, channel):
    image = load_image(demo.files.s19).crop(CALIB.start, CALIB.end)
    threshold = symbols.symbol("xsSWITCH_TANK_THR").address
    rom_threshold = HDS9.rom_address(threshold)
    patched = load_image(demo.files.s19).crop(CALIB.start, CALIB.end)
    patched.add(rom_threshold, struct.pack("<f", 42.0), overwrite=True)
    with Simulator(demo.ecu, {"interface": "virtual", "channel": channel}, time_scale=1.0):
        with pyxcp_master("virtual", channel) as master:
            connect(master)
            master.cond_unlock("PGM")
            response = master.programStart()
            assert response.commModePgm.masterBlockMode and response.maxBsPgm == 42
            master.setMta(CALIB.start)
            master.programClear(0, CALIB.size)
            for start, data in patched.segments:  # only the ranges the file fills
                master.flash_program(start, data)
            master.programReset()
        assert demo.ecu.state is EcuState.APPLICATION
        assert demo.ecu.read(rom_threshold, 4) == struct.pack("<f", 42.0)
        assert demo.ecu.read(threshold, 4) == struct.pack("<f", 42.0)  # copied to CAL RAM at the restart
        for start, data in image.segments:
            if not start <= rom_threshold < start + len(data):
                assert demo.ecu.read(start, len(data)) == data
        assert demo.ecu.read(CALIB.start + 0x1000, 16) == b"\xff" * 16  # gaps stay erased


def _value(ecu, symbols, name, kind):
    raw = ecu.read(symbols.symbol(name).address, 4 if kind == "F32" else 1)
    return struct.unpack("<f", raw)[0] if kind == "F32" else raw[0]


def _wait_for(condition, timeout_s: float = 5.0) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.01)
