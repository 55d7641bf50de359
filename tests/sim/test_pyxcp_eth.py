"""pyxcp, an independent master, against the demo ECU over XCP on UDP and TCP: in this process
(``serve_demo``) and as a ``workbench sim --host`` process of its own."""

from __future__ import annotations

import re
import signal
import struct

import pytest
from pyxcp.daq_stim import DaqList
from pyxcp_master import Samples, connect, pyxcp_eth_master, record_50ms_samples
from sim_process import start_sim_process

from workbench import demo
from workbench.elf import ElfSymbols
from workbench.image import load_image
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.sim.memory_map import HDS9

pytestmark = pytest.mark.slow
PROTOCOLS = ["UDP", "TCP"]
# sixteen float measurements: 64 bytes, one ODT on Ethernet (MAX_DTO 1024), ten on CAN (7 bytes each)
MEASUREMENTS = [
    "zsRailPressure", "zsTank1Pressure", "zsTank2Pressure", "zsManifoldPressure", "zsRailPressureTmp",
    "zsTank1VoltFilt", "zsTank2VoltFilt", "zsManifoldVoltFilt", "zsRailVoltFilt", "xsDC", "xsFuelLevel",
    "xsPidP", "xsPidI", "xsPidD", "xsPidFF", "xsSWITCH_TANK_THR",
]


@pytest.fixture(scope="module")
def symbols():
    return ElfSymbols(demo.elf())


def measure_and_calibrate(host: str, port: int, protocol: str, symbols: ElfSymbols, epk: str) -> None:
    """What a calibration engineer does first, through pyxcp on XCP on ``protocol``."""
    s19 = load_image(demo.s19())
    threshold = symbols.symbol("xsSWITCH_TANK_THR").address
    policy = Samples([DaqList(name="task50", event_num=1, stim=False, enable_timestamps=True,
                              measurements=[(n, symbols.symbol(n).address, 0, "F32") for n in MEASUREMENTS],
                              priority=0, prescaler=1)])
    with pyxcp_eth_master(host, port, protocol, policy=policy) as master:
        connect(master)
        assert (master.slaveProperties.maxCto, master.slaveProperties.maxDto) == (255, 1024)
        assert master.identifier(5) == epk
        master.setMta(HDS9.cal_rom_start)
        assert bytes(master.upload(200)) == s19.read(HDS9.cal_rom_start, 200)  # one UPLOAD on Ethernet
        with pytest.raises(BaseException, match="UNLOCK_SLAVE"):  # ERR_ACCESS_LOCKED, in pyxcp's words and class
            master.push(threshold, 0, struct.pack("<f", 21.5))
        master.cond_unlock()  # seed & key for CAL/PAG, DAQ and PGM
        master.push(threshold, 0, struct.pack("<f", 21.5))
        assert struct.unpack("<f", bytes(master.shortUpload(4, threshold)))[0] == 21.5

        policy.setup()
        assert len(policy.daq_lists[0].measurements_opt) == 1  # pyxcp planned one ODT from MAX_DTO
        rows = record_50ms_samples(policy)
        assert {row["xsSWITCH_TANK_THR"] for _, row in rows} == {21.5}
        assert rows[-1][1]["zsRailPressure"] > rows[0][1]["zsRailPressure"]  # the PCM's target drives the rail up
        master.disconnect()


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_pyxcp_in_process(protocol, symbols):
    with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", 0, protocol), pcm_target_bar=25.0) as sim:
        host, port = sim.xcp.address
        measure_and_calibrate(host, port, protocol, symbols, sim.describe()["epk"])


@pytest.mark.parametrize("protocol", PROTOCOLS)
def test_pyxcp_against_a_workbench_sim_process(protocol, symbols):
    process, banner = start_sim_process("--host", "127.0.0.1", "--port", "0", "--protocol", protocol.lower(), "--pcm",
                                        "--duration", "120")
    try:
        where = re.search(rf"XCP +on {protocol} at 127\.0\.0\.1:(\d+) \(MAX_CTO 255, MAX_DTO 1024\)", banner)
        assert where, banner
        epk = re.search(r"EPK +(\d+)", banner).group(1)
        measure_and_calibrate("127.0.0.1", int(where.group(1)), protocol, symbols, epk)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=10)
        assert process.returncode == 0, err
        assert "stopped" in out and "Traceback" not in err
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
