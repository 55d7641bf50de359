"""pyxcp, an independent master, detects the simulated demo ECU with XCP on CAN's GET_SLAVE_ID on the A2L's
CAN_ID_BROADCAST and reads its DAQ lists' id with GET_DAQ_ID, over a udp_multicast bus of the test's own."""

from __future__ import annotations

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
