"""pyxcp against a separate ``workbench sim`` process on ``udp_multicast`` — the two-process workflow."""

from __future__ import annotations

import random
import signal
import struct
import time

import pytest
from pyxcp.daq_stim import DaqList
from pyxcp_master import Samples, connect, pyxcp_master, record_50ms_samples
from sim_process import start_sim_process

from workbench import demo
from workbench.elf import ElfSymbols
from workbench.image import load_image
from workbench.sim.memory_map import HDS9

pytestmark = pytest.mark.slow
CALIB = HDS9.region("CALIB")


@pytest.fixture
def sim_process(free_udp_port):
    """``workbench sim`` on a multicast group and a port of its own, with the PCM; yields the bus settings.

    python-can binds the port for every group: the port, not the group, keeps tests (and users) apart.
    """
    group = f"239.74.{random.randint(164, 250)}.{random.randint(1, 250)}"
    process, banner = start_sim_process("--interface", "udp_multicast", "--channel", group,
                                        "--bus-kwargs", f"port={free_udp_port}", "--pcm", "--duration", "120")
    assert f"{group} (port={free_udp_port})" in banner and "0x7F0" in banner
    process.banner = banner
    yield {"channel": group, "bus_kwargs": {"port": free_udp_port}}, process
    if process.poll() is None:
        process.kill()
        process.wait()


def test_pyxcp_against_a_workbench_sim_process(sim_process):
    bus, process = sim_process
    symbols = ElfSymbols(demo.elf())
    s19 = load_image(demo.s19())
    threshold = symbols.symbol("xsSWITCH_TANK_THR").address
    names = [("zsRailPressure", "F32"), ("xsSWITCH_TANK_THR", "F32"), ("xsFULL_TANK_PRESS", "F32")]
    policy = Samples([DaqList(name="task50", event_num=1, stim=False, enable_timestamps=True,
                              measurements=[(n, symbols.symbol(n).address, 0, k) for n, k in names],
                              priority=0, prescaler=1)])
    with pyxcp_master("udp_multicast", policy=policy, **bus) as master:
        connect(master)
        epk = master.identifier(5)
        assert epk in process.banner
        assert bytes(master.shortUpload(4, threshold)) == s19.read(HDS9.rom_address(threshold), 4)
        master.cond_unlock()  # seed & key for CAL/PAG, DAQ and PGM
        master.push(threshold, 0, struct.pack("<f", 21.5))
        assert struct.unpack("<f", bytes(master.shortUpload(4, threshold)))[0] == 21.5

        policy.setup()
        rows = record_50ms_samples(policy)
        assert {row["xsSWITCH_TANK_THR"] for _, row in rows} == {21.5}
        assert {row["xsFULL_TANK_PRESS"] for _, row in rows} == {700.0}
        # the PCM's target drives the rail up to 25 bar; on a loaded machine DAQ may start when it is there already
        first, last = rows[0][1]["zsRailPressure"], rows[-1][1]["zsRailPressure"]
        assert last > first or abs(last - 25.0) < 1.5, (first, last)

        patched = s19.crop(CALIB.start, CALIB.end)
        patched.add(HDS9.rom_address(threshold), struct.pack("<f", 30.0), overwrite=True)
        master.programStart()
        master.setMta(CALIB.start)
        master.programClear(0, CALIB.size)
        for start, data in patched.segments:
            master.flash_program(start, data)
        master.programReset()

    with pyxcp_master("udp_multicast", **bus) as master:
        _connect_after_reset(master)
        assert struct.unpack("<f", bytes(master.shortUpload(4, threshold)))[0] == 30.0  # new CAL ROM -> CAL RAM
        master.disconnect()

    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=10)
    assert process.returncode == 0, err
    assert "stopped" in out and "Traceback" not in err


def _connect_after_reset(master) -> None:
    deadline = time.monotonic() + 5
    while True:
        try:
            connect(master)
            return
        except Exception:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.1)
