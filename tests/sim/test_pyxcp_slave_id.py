"""pyxcp, an independent master, detects the simulated demo ECU with XCP on CAN's GET_SLAVE_ID on the A2L's
CAN_ID_BROADCAST and reads its DAQ lists' id with GET_DAQ_ID, over a udp_multicast bus of the test's own."""

from __future__ import annotations

import pytest
from pyxcp import types
from pyxcp_master import connect, pyxcp_master

from workbench.sim import serve_demo


def test_pyxcp_get_slave_id_on_the_broadcast_id_and_get_daq_id(free_udp_port):
    bus = {"interface": "udp_multicast", "port": free_udp_port}
    with serve_demo(bus, time_scale=None):
        # pyxcp sends its commands on CAN_ID_MASTER: the broadcast id here; the slave answers on its CAN_ID_SLAVE
        with pyxcp_master("udp_multicast", "239.74.163.2", can_id_master=0x6F0, can_id_slave=0x7F1,
                          bus_kwargs={"port": free_udp_port}) as master:
            master.slaveProperties.byteOrder = types.ByteOrder.INTEL  # pyxcp 0.29 knows it only after a CONNECT
            echo, inverse = master.getSlaveID(0), master.getSlaveID(1)
        with pyxcp_master("udp_multicast", "239.74.163.2", can_id_master=echo.identifier,
                          bus_kwargs={"port": free_udp_port}) as master:
            connect(master)
            daq_id = master.getDaqId(0)
    assert (bytes(echo.magic), echo.identifier) == (b"XCP", 0x7F0)
    assert (bytes(inverse.magic), inverse.identifier) == (b"\xa7\xbc\xaf", 0x7F0)
    assert (str(daq_id.canIdFixed), daq_id.identifier) == ("FIXED", 0x7F1)


def test_pyxcp_moves_a_variable_daq_list_with_set_daq_id(free_udp_port):
    """The daq-can-ids-variable profile to pyxcp's GET_DAQ_ID/SET_DAQ_ID: list 0 configurable (on 0x7F4 until set),
    moved to 0x7F6; list 2 fixed on 0x7F3, SET_DAQ_ID refused (ERR_OUT_OF_RANGE, in pyxcp's words)."""
    bus = {"interface": "udp_multicast", "port": free_udp_port}
    with serve_demo(bus, profile="daq-can-ids-variable", time_scale=None), \
            pyxcp_master("udp_multicast", "239.74.163.2", bus_kwargs={"port": free_udp_port}) as master:
        connect(master)
        master.cond_unlock()
        before = master.getDaqId(0)
        master.setDaqId(0, 0x7F6)
        after, fixed = master.getDaqId(0), master.getDaqId(2)
        with pytest.raises(BaseException, match="OUT_OF_RANGE"):
            master.setDaqId(2, 0x7F7)
    assert [(str(answer.canIdFixed), answer.identifier) for answer in (before, after, fixed)] == [
        ("CONFIGURABLE", 0x7F4), ("CONFIGURABLE", 0x7F6), ("FIXED", 0x7F3)]
