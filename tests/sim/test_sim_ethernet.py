"""XCP on Ethernet as a raw socket sees it: framing and CTR, the Ethernet packet sizes, one master at a time,
malformed input ignored, faults, and the errors of a port that cannot be served."""

from __future__ import annotations

import socket
import struct
from dataclasses import replace

import pytest
from eth_master import RawEthMaster
from mini_ecu import CAL_GAIN, COUNTER, XcpProbe, make_ecu

from workbench.errors import WorkbenchError
from workbench.sim import EthernetEndpoint, Simulator, XcpParameters
from workbench.xcp_protocol import Cmd, Err, Resource

ETHERNET = XcpParameters(max_cto=255, max_dto=1024, protected=Resource(0))
CONNECT = bytes([Cmd.CONNECT, 0])
GET_STATUS = bytes([Cmd.GET_STATUS])


def short_upload(address: int, size: int) -> bytes:
    return bytes([Cmd.SHORT_UPLOAD, size, 0, 0]) + struct.pack("<I", address)


def serve(protocol: str, params: XcpParameters = ETHERNET) -> Simulator:
    """The mini ECU on XCP on ``protocol`` at a free loopback port, simulated time moved by the test."""
    return Simulator(make_ecu(params=params), ethernet=EthernetEndpoint("127.0.0.1", 0, protocol), time_scale=None)


@pytest.fixture(params=["UDP", "TCP"])
def rig(request):
    with serve(request.param) as sim, RawEthMaster(sim.xcp.address, request.param) as master:
        yield sim, master


def test_connect_answers_the_ethernet_sizes_and_ctr_counts_every_slave_packet(rig):
    sim, master = rig
    (ctr, response), = master.request(CONNECT)
    assert ctr == 0 and response[0] == 0xFF
    assert struct.unpack_from("<BH", response, 3) == (255, 1024)  # MAX_CTO, MAX_DTO
    assert [ctr for ctr, _ in master.request(GET_STATUS)] == [1]
    _start_daq(master, entries=[(COUNTER, 4)], timestamps=False)
    with sim.lock:
        sim.advance(0.2)  # four 50 ms events: four DTOs
    after_daq = master.packets(4) + master.request(GET_STATUS)
    assert [packet[0] for _, packet in after_daq[-5:]] == [0, 0, 0, 0, 0xFF]  # DTOs (PID 0), then the response
    ctrs = [ctr for ctr, _ in after_daq]
    assert ctrs == list(range(ctrs[0], ctrs[0] + len(ctrs)))  # responses and DTOs share one counter, no gap


def test_several_packets_in_one_datagram_are_answered_in_order(rig):
    _, master = rig
    master.request(CONNECT)
    answers = master.request(GET_STATUS, short_upload(CAL_GAIN, 4), GET_STATUS)
    assert [packet for _, packet in answers][1] == b"\xff" + struct.pack("<f", 2.0)
    assert [len(packet) for _, packet in answers] == [6, 5, 6]


def test_the_packet_sizes_are_ethernet_sizes(rig):
    _, master = rig
    master.request(CONNECT)
    master.request(bytes([Cmd.SET_MTA, 0, 0, 0]) + struct.pack("<I", 0xFC0000))
    upload = [packet for _, packet in master.request(bytes([Cmd.UPLOAD, 255]), expect=2)]
    assert [len(packet) for packet in upload] == [255, 2]  # slave block mode: 254 + 1 data bytes
    assert len(master.request(short_upload(0xFC0000, 254))[0][1]) == 255
    assert master.request(short_upload(0xFC0000, 255))[0][1] == bytes([0xFE, Err.OUT_OF_RANGE])
    # a DOWNLOAD of 20 bytes fits one packet (on CAN it needs DOWNLOAD_NEXT frames)
    master.request(bytes([Cmd.SET_MTA, 0, 0, 0]) + struct.pack("<I", CAL_GAIN))
    assert master.request(bytes([Cmd.DOWNLOAD, 8]) + struct.pack("<ff", 3.0, 4.0))[0][1] == b"\xff"
    assert master.request(short_upload(CAL_GAIN, 8))[0][1] == b"\xff" + struct.pack("<ff", 3.0, 4.0)


def test_an_odt_carries_what_max_dto_allows_and_not_one_byte_more(rig):
    sim, master = rig
    master.request(CONNECT)
    entries = [(0x40020100 + 4 * n, 4) for n in range(254)]  # 1016 bytes + PID + timestamp = 1021 <= MAX_DTO
    _start_daq(master, entries, timestamps=True, extra_entries=1)
    with sim.lock:
        sim.advance(0.05)
    (_, dto), = master.packets(1)
    assert len(dto) == 1 + 4 + 1016
    # the ODT's last entry: 4 more bytes would make the DTO 1025 > MAX_DTO
    master.request(bytes([Cmd.START_STOP_SYNCH, 0]))
    master.request(bytes([Cmd.SET_DAQ_PTR, 0]) + struct.pack("<H", 0) + bytes([0, 254]))
    refused = master.request(bytes([Cmd.WRITE_DAQ, 0xFF, 4, 0]) + struct.pack("<I", 0x40020000))
    assert refused[0][1] == bytes([0xFE, Err.DAQ_CONFIG])


def test_the_same_odt_does_not_fit_can_sizes():
    """A master planning with Ethernet sizes against the CAN slave (or the other way round) hears it at once."""
    ecu = make_ecu(params=replace(ETHERNET, max_cto=8, max_dto=8))
    ecu.power_on()
    probe = XcpProbe(ecu)
    probe.connect()
    probe.ok(Cmd.ALLOC_DAQ, 0, struct.pack("<H", 1))
    probe.ok(Cmd.ALLOC_ODT, 0, struct.pack("<H", 0), 1)
    assert probe.err(Cmd.ALLOC_ODT_ENTRY, 0, struct.pack("<H", 0), 0, 8) == Err.OUT_OF_RANGE  # 7 bytes after the PID


@pytest.mark.parametrize("datagram", [
    b"", b"\x01", b"\x00\x00\x00\x00",  # empty, no header, LEN 0
    b"\x05\x00\x00\x00\xfd",  # LEN beyond the datagram
    b"\x00\x01\x00\x00" + bytes(256),  # LEN 256 > MAX_CTO
    b"\x01\x00\x00\x00\xfd\x01\x00",  # a good GET_STATUS and a torn header: the whole datagram is ignored
], ids=["empty", "short", "len0", "truncated", "too-long", "torn-tail"])
def test_a_malformed_datagram_is_ignored_and_the_slave_serves_on(datagram):
    with serve("UDP") as sim, RawEthMaster(sim.xcp.address, "UDP") as master:
        master.request(CONNECT)
        master.send_raw(datagram)
        assert master.packets() == []
        assert sim.xcp.ignored == 1
        assert [ctr for ctr, _ in master.request(GET_STATUS)] == [1]  # nothing was sent in between


def test_a_malformed_tcp_stream_ends_the_connection_and_the_session():
    with serve("TCP") as sim:
        with RawEthMaster(sim.xcp.address, "TCP") as master:
            master.request(CONNECT)
            master.send_raw(b"\x00\x00\x00\x00")  # LEN 0: the stream cannot be framed any more
            assert master.closed_by_slave()
        with RawEthMaster(sim.xcp.address, "TCP") as master:
            assert master.request(GET_STATUS, expect=0) == []  # the session ended with the connection
            assert master.request(CONNECT)[0][0] == 0  # a new master, CTR from 0


def test_a_tcp_stream_may_arrive_in_pieces():
    with serve("TCP") as sim, RawEthMaster(sim.xcp.address, "TCP") as master:
        framed = struct.pack("<HH", 2, 0) + CONNECT
        for byte in framed:
            master.send_raw(bytes([byte]))
        (_, response), = master.packets(1)
        assert response[0] == 0xFF


def test_closing_the_tcp_connection_stops_daq():
    with serve("TCP") as sim:
        with RawEthMaster(sim.xcp.address, "TCP") as master:
            master.request(CONNECT)
            _start_daq(master, [(COUNTER, 4)], timestamps=False)
            assert sim.ecu.slave.daq.running
        _wait_for(lambda: not sim.ecu.slave.connected)
        assert not sim.ecu.slave.daq.running


def test_a_new_tcp_connection_replaces_the_old_one():
    with serve("TCP") as sim, RawEthMaster(sim.xcp.address, "TCP") as first:
        first.request(CONNECT)
        with RawEthMaster(sim.xcp.address, "TCP") as second:
            assert second.request(CONNECT)[0][0] == 0
            assert first.closed_by_slave()
            assert second.request(GET_STATUS)[0][1][0] == 0xFF


def test_udp_serves_one_master_until_another_connects():
    with serve("UDP") as sim, RawEthMaster(sim.xcp.address, "UDP") as first, \
            RawEthMaster(sim.xcp.address, "UDP") as second:
        first.request(CONNECT)
        first.request(bytes([Cmd.ALLOC_DAQ, 0, 1, 0]))
        assert second.request(GET_STATUS, expect=0) == []  # not the session's master
        assert second.request(CONNECT)[0][0] == 0  # takes the session over, CTR from 0
        assert sim.ecu.slave.daq.lists == []  # the old session ended first
        assert first.request(GET_STATUS, expect=0) == []


def test_faults_act_on_packets(rig):
    sim, master = rig
    master.request(CONNECT)
    sim.ecu.faults.drop_frame(1)
    assert master.request(GET_STATUS, expect=0) == []
    assert [ctr for ctr, _ in master.request(GET_STATUS)] == [1]  # a packet never sent takes no CTR
    sim.ecu.faults.duplicate_frame(1, direction="rx")
    assert [ctr for ctr, _ in master.request(GET_STATUS, expect=2)] == [2, 3]
    sim.ecu.faults.delay_frame(1, 0.2)
    master.send(GET_STATUS)
    master.send(short_upload(CAL_GAIN, 4))
    late = master.packets(2)
    assert [len(packet) for _, packet in late] == [5, 6]  # the delayed GET_STATUS answer comes second
    assert sim.ecu.faults.fired == ["drop tx frame 2", "duplicate rx frame 4", "delay tx frame 6"]


def test_power_off_silences_the_port(rig):
    sim, master = rig
    master.request(CONNECT)
    sim.power_off()
    assert master.request(CONNECT, expect=0) == []
    sim.power_on()
    assert master.request(CONNECT)[0][1][0] == 0xFF


@pytest.mark.parametrize("protocol, kind", [("UDP", socket.SOCK_DGRAM), ("TCP", socket.SOCK_STREAM)])
def test_a_port_in_use_is_a_one_line_error_and_leaves_nothing_open(protocol, kind):
    with socket.socket(socket.AF_INET, kind) as taken:
        taken.bind(("127.0.0.1", 0))
        if kind == socket.SOCK_STREAM:
            taken.listen(1)
        port = taken.getsockname()[1]
        sim = Simulator(make_ecu(params=ETHERNET), ethernet=EthernetEndpoint("127.0.0.1", port, protocol))
        with pytest.raises(WorkbenchError, match=rf"^cannot serve XCP on {protocol} at 127.0.0.1:{port}: Address already in use$"):
            sim.start()
    assert sim.closed


def test_the_endpoint_and_the_transport_are_checked():
    with pytest.raises(ValueError, match="UDP or TCP"):
        EthernetEndpoint("127.0.0.1", 5555, "sctp")
    with pytest.raises(ValueError, match="0..65535"):
        EthernetEndpoint("127.0.0.1", 70000)
    with pytest.raises(ValueError, match="exactly one transport"):
        Simulator(make_ecu())
    with pytest.raises(ValueError, match="exactly one transport"):
        Simulator(make_ecu(), {"interface": "virtual"}, ethernet=EthernetEndpoint())


def _start_daq(master: RawEthMaster, entries, timestamps: bool, extra_entries: int = 0) -> None:
    """One DAQ list on the 50 ms event with one ODT of ``entries`` (address, size), started."""
    ctos = [
        bytes([Cmd.FREE_DAQ]),
        bytes([Cmd.ALLOC_DAQ, 0]) + struct.pack("<H", 1),
        bytes([Cmd.ALLOC_ODT, 0]) + struct.pack("<H", 0) + bytes([1]),
        bytes([Cmd.ALLOC_ODT_ENTRY, 0]) + struct.pack("<H", 0) + bytes([0, len(entries) + extra_entries]),
        bytes([Cmd.SET_DAQ_PTR, 0]) + struct.pack("<H", 0) + bytes([0, 0]),
        *(bytes([Cmd.WRITE_DAQ, 0xFF, size, 0]) + struct.pack("<I", address) for address, size in entries),
        bytes([Cmd.SET_DAQ_LIST_MODE, 0x10 if timestamps else 0]) + struct.pack("<H", 0) + struct.pack("<H", 1) + bytes([1, 0]),
        bytes([Cmd.START_STOP_DAQ_LIST, 2]) + struct.pack("<H", 0),
        bytes([Cmd.START_STOP_SYNCH, 1]),
    ]
    for start in range(0, len(ctos), 50):  # several packets per datagram (UDP) or write (TCP); each answer its own
        batch = ctos[start : start + 50]  # datagram: 50 keep within the master's receive buffer
        responses = master.request(*batch)
        assert [packet[0] for _, packet in responses] == [0xFF] * len(batch), [p.hex(" ") for _, p in responses]


def _wait_for(condition, timeout_s: float = 2.0) -> None:
    import time

    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.01)
