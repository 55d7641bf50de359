"""The bench's CAN2 port on udp_multicast, the bus of ``workbench sim`` in another process: python-can hands a
udp_multicast bus its own frames back, which the port counted as another node sending the PCM's messages (every
failure of the two-process workflow named a second PCM that was not there; user trial 7)."""

from __future__ import annotations

import time

import can

from workbench import demo
from workbench.can import load_dbc
from workbench.testbench.can2 import Can2Port
from workbench.testbench.timeline import Timeline


def _until(check, timeout: float = 5.0) -> bool:
    deadline = time.monotonic() + timeout
    while not check() and time.monotonic() < deadline:
        time.sleep(0.01)
    return check()


def test_its_own_frames_are_not_another_node_and_silence_is_told(free_udp_port):
    bus = {"interface": "udp_multicast", "channel": "239.74.163.2", "port": free_udp_port}
    port = Can2Port(dict(bus, receive_own_messages=False), load_dbc(demo.dbc_can2()), Timeline())
    other = can.Bus(**bus)
    try:
        port.send("PCM_TO_FLCU_001", {"EnableFLCU": 1}, period_s=0.02)
        assert _until(lambda: len(port.frame_times("PCM_TO_FLCU_001")) > 0, timeout=0.3) is False  # its echoes
        assert port.competing() == {} and port.silent()  # it sent, nobody else spoke
        other.send(can.Message(arbitration_id=0x110, is_extended_id=False, data=b"\x00"))  # a second PCM
        other.send(can.Message(arbitration_id=0x123, is_extended_id=False, data=b"\x10\x09\x00\x00"))  # the ECU
        assert _until(lambda: len(port.frame_times("FLCU_TO_PCM_002")) == 1)  # sent after the PCM's: both came
        assert port.competing() == {"PCM_TO_FLCU_001": 1} and not port.silent()
    finally:
        port.close()
        other.shutdown()
