"""The HIL scenario (hil_scenario.py), unchanged, over every transport the workbench offers:
XCP on CAN in-process (virtual), against a separate `workbench sim` process (udp_multicast on a
port of the test's own), and XCP on Ethernet (UDP and TCP) with CAN2 on a virtual bus."""

from __future__ import annotations

import itertools

import can
import pytest
from hil_scenario import run_scenario

from workbench import Session
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.xcp.master import Timeouts

_channels = itertools.count()
# The scenario tests what the FLCU does, not how fast it answers: a loaded machine may take more than the
# other tests' 300 ms for a response, and waiting longer costs nothing when the answer comes.
PATIENT = Timeouts(t1=3.0, t2=6.0, t3=6.0, t4=10.0, t5=3.0, t6=3.0, t7=0.02)


def test_over_xcp_on_can_in_process():
    channel = f"hil-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}):
        with can.Bus(interface="virtual", channel=channel) as can2:
            with Session.open(interface="virtual", channel=channel, timeouts=PATIENT) as ecu:
                run_scenario(ecu, can2)


@pytest.mark.slow
def test_over_xcp_on_can_against_a_simulator_process(free_udp_port):
    from sim_process import start_sim_process

    process, _ = start_sim_process("--bus-kwargs", f"port={free_udp_port}")
    try:
        bus = {"interface": "udp_multicast", "channel": "239.74.163.2", "port": free_udp_port}
        with can.Bus(**bus, receive_own_messages=False) as can2:
            with Session.open(interface="udp_multicast", bus_kwargs={"port": free_udp_port}) as ecu:
                run_scenario(ecu, can2)
    finally:
        process.terminate()
        process.wait(10)


@pytest.mark.parametrize("protocol", ["UDP", "TCP"])
def test_over_xcp_on_ethernet(protocol, free_udp_port, free_tcp_port):
    port = free_udp_port if protocol == "UDP" else free_tcp_port
    channel = f"hil-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}, ethernet=EthernetEndpoint("127.0.0.1", port, protocol)):
        with can.Bus(interface="virtual", channel=channel) as can2:
            with Session.open(host="127.0.0.1", port=port, protocol=protocol.lower(), timeouts=PATIENT) as ecu:
                run_scenario(ecu, can2)
