"""serve_demo: the one call that serves the demo ECU (what ``workbench sim`` runs), its defaults and its errors."""

from __future__ import annotations

import re
import subprocess
import sys
import time
from pathlib import Path

import can
import pytest
from eth_master import RawEthMaster
from raw_master import MASTER_ID, SLAVE_ID

from workbench.errors import InputError
from workbench.bus_defaults import complete_bus_settings
from workbench.sim import DemoFiles, EthernetEndpoint, serve_demo
from workbench.xcp_protocol import Cmd

CONNECT = bytes([Cmd.CONNECT, 0]).ljust(8, b"\0")
FLCU_TO_PCM_002 = 0x123


def test_bus_settings_get_the_workbench_defaults():
    assert complete_bus_settings() == {"interface": "udp_multicast", "channel": "239.74.163.2", "receive_own_messages": False}
    assert complete_bus_settings({"interface": "virtual"}) == {"interface": "virtual", "channel": "workbench"}
    assert complete_bus_settings({"interface": "udp_multicast", "port": 43300})["port"] == 43300
    assert complete_bus_settings({"interface": "vector", "channel": 1, "app_name": "Bench"}) == {
        "interface": "vector", "channel": 1, "app_name": "Bench"}


def _answers_to_connect(bus: can.BusABC) -> int:
    bus.send(can.Message(arbitration_id=MASTER_ID, is_extended_id=False, data=CONNECT))
    answers, deadline = 0, time.monotonic() + 1.0
    while (message := bus.recv(max(deadline - time.monotonic(), 0.01))) is not None and time.monotonic() < deadline:
        answers += message.arbitration_id == SLAVE_ID
    return answers


def test_udp_multicast_simulators_on_one_host_are_kept_apart_by_their_ports(free_udp_port, another_free_udp_port):
    """python-can binds the port for every group: the group alone isolates nothing, the port does."""
    group = "239.74.163.77"
    settings = {"interface": "udp_multicast", "channel": group, "receive_own_messages": False}
    with serve_demo({**settings, "port": free_udp_port}, time_scale=None), \
            can.Bus(**settings, port=free_udp_port) as master:
        with serve_demo({**settings, "port": free_udp_port}, time_scale=None):
            assert _answers_to_connect(master) == 2  # one group, one port: both ECUs hear the master
        with serve_demo({**settings, "port": another_free_udp_port}, time_scale=None):
            assert _answers_to_connect(master) == 1  # a port of its own: the other ECU hears nothing


def test_xcp_on_ethernet_with_the_flcu_messages_on_a_can_bus():
    with can.Bus(interface="virtual", channel="serve-demo-can2") as observer, serve_demo(
            {"interface": "virtual", "channel": "serve-demo-can2"}, ethernet=EthernetEndpoint("127.0.0.1", 0, "tcp"),
            pcm_target_bar=25.0, time_scale=5.0) as sim:
        info = sim.describe()
        assert info["xcp"]["transport"] == "TCP" and info["buses"] == {
            "CAN2": {"interface": "virtual", "channel": "serve-demo-can2"}}
        ids = set()
        deadline = time.monotonic() + 5
        while {FLCU_TO_PCM_002, 0x110} - ids and time.monotonic() < deadline:
            message = observer.recv(0.5)
            if message is not None:
                ids.add(message.arbitration_id)
        assert {FLCU_TO_PCM_002, 0x110} <= ids  # the ECU's RailPressure and the PCM's EnableFLCU
        with RawEthMaster(sim.xcp.address, "TCP") as master:
            assert master.request(bytes([Cmd.CONNECT, 0]))[0][1][0] == 0xFF
        with sim.lock:
            assert sim.can2_driver.can_get_rx_pdu("PCM_TO_FLCU_001").dlc > 0  # the PCM's frames reach the ECU


def test_a_software_bus_bitrate_is_the_timing_model():
    with serve_demo({"interface": "virtual", "channel": "serve-demo-timing", "bitrate": 500_000}, time_scale=None) as sim:
        assert sim.bitrate == 500_000 and "bitrate" not in sim.describe()["buses"]["CAN1"]
        assert sim.bus_clock("CAN1").bitrate == 500_000


def _edited_demo(tmp_path: Path, edit) -> DemoFiles:
    files = DemoFiles.defaults()
    path = tmp_path / "edited.a2l"
    path.write_text(edit(Path(files.a2l).read_text(encoding="utf-8")), encoding="utf-8")
    return DemoFiles(path, files.elf, files.s19, files.dbc)


def test_without_a_port_the_a2ls_port_is_served(tmp_path, free_tcp_port):
    files = _edited_demo(tmp_path, lambda text: text.replace("5555            /* PORT */", f"{free_tcp_port} /* PORT */"))
    with serve_demo(ethernet=EthernetEndpoint(protocol="TCP"), files=files, time_scale=None) as sim:
        assert sim.xcp.address == ("127.0.0.1", free_tcp_port)


def test_an_a2l_without_the_transports_block_is_bad_input(tmp_path):
    files = _edited_demo(tmp_path, lambda text: re.sub(r"/begin XCP_ON_TCP_IP.*?/end XCP_ON_TCP_IP", "", text, flags=re.S))
    with pytest.raises(InputError, match=r"edited.a2l: IF_DATA XCP has no XCP_ON_TCP_IP block; the simulated ECU serves "
                                         r"XCP on TCP as the A2L describes it"):
        serve_demo(ethernet=EthernetEndpoint(port=0, protocol="TCP"), files=files)


def test_ethernet_sizes_the_transport_cannot_carry_are_bad_input(tmp_path):
    files = _edited_demo(tmp_path, lambda text: text.replace("255       /* MAX_CTO: one", "300       /* MAX_CTO: one"))
    with pytest.raises(InputError, match=r"XCP on UDP needs MAX_CTO 8..255 and MAX_DTO 8..65503, the A2L says 300/1024"):
        serve_demo(ethernet=EthernetEndpoint(port=0), files=files)


def test_the_can2_bus_is_given_once():
    with pytest.raises(InputError, match="give bus or can2, not both"):
        serve_demo({"interface": "virtual"}, can2={"interface": "virtual"}, ethernet=EthernetEndpoint(port=0))


def test_importing_the_package_loads_no_bus_no_dbc_no_application():
    code = ("import sys, workbench.sim\n"
            "print(sorted(m for m in ('can', 'cantools', 'asammdf', 'workbench.sim.server', 'workbench.sim.flcu') "
            "if m in sys.modules))")
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip() == "[]"
