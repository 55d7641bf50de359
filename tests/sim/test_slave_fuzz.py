"""Random CTOs of random lengths, random frames and datagrams: every command is answered (or meets a
documented silence), malformed input is ignored, nothing breaks."""

from __future__ import annotations

import logging
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from eth_master import RawEthMaster
from mini_ecu import XcpProbe, make_ecu
from raw_master import RawMaster

from workbench.sim.eth_port import EthernetEndpoint
from workbench.sim.server import Simulator
from workbench.sim.xcp.parameters import XcpParameters
from workbench.xcp_protocol import PID_ERR, PID_RES, Cmd, Err, Resource

BLOCK_COMMANDS = {Cmd.DOWNLOAD, Cmd.DOWNLOAD_NEXT, Cmd.PROGRAM, Cmd.PROGRAM_NEXT}
command_byte = st.one_of(st.sampled_from([int(c) for c in Cmd]), st.integers(0, 0xFF))
cto = st.one_of(
    st.just(b""),
    st.tuples(command_byte, st.binary(max_size=7)).map(lambda parts: bytes([parts[0]]) + parts[1]),
)


class _Errors(logging.Handler):
    def __init__(self):
        super().__init__(logging.ERROR)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


def _run(ctos: list[bytes], protected: Resource) -> None:
    ecu = make_ecu(params=XcpParameters(protected=protected))
    ecu.power_on()
    probe = XcpProbe(ecu)
    connected = False
    errors = _Errors()
    logger = logging.getLogger("workbench.sim")
    logger.addHandler(errors)
    try:
        for frame in [bytes([Cmd.CONNECT, 0])] + ctos:
            packets = ecu.handle_cto(frame)
            command = frame[0] if frame else None
            if not packets:
                allowed = frame == b"" or (not connected and command != Cmd.CONNECT) or (
                    connected and command in BLOCK_COMMANDS)
                assert allowed, f"no answer to {frame.hex(' ')} (connected={connected})"
                continue
            assert connected or command == Cmd.CONNECT, f"{frame.hex(' ')} answered while disconnected"
            for packet in packets:
                assert packet[0] in (PID_RES, PID_ERR) and len(packet) <= 8, packet.hex(" ")
            if packets[0][0] == PID_ERR:
                assert len(packets) == 1 and packets[0][1] in set(Err), packets[0].hex(" ")
                if command == Cmd.UNLOCK and packets[0][1] == Err.ACCESS_LOCKED:
                    connected = False  # a wrong key ends the session
            elif command == Cmd.CONNECT:
                connected = True
            elif command in (Cmd.DISCONNECT, Cmd.PROGRAM_RESET):
                connected = False
        # the slave keeps serving
        probe.connect()
        assert probe.ok(Cmd.GET_STATUS)
        assert probe.short_upload(0xFC0000, 4) == ecu.read(0xFC0000, 4)
    finally:
        logger.removeHandler(errors)
    assert not errors.messages  # the slave's catch-all for its own bugs never fired


@pytest.mark.parametrize("protected", [Resource.CAL_PAG | Resource.DAQ | Resource.PGM, Resource(0)], ids=["locked", "open"])
@settings(max_examples=150, deadline=None)
@given(ctos=st.lists(cto, max_size=40))
def test_random_ctos(protected, ctos):
    _run(ctos, protected)


frame_data = st.one_of(
    cto.map(lambda data: data.ljust(8, b"\0")),  # padded as MAX_DLC_REQUIRED asks
    st.binary(max_size=8),  # any DLC: shorter frames must be ignored
)


def test_random_frames_over_the_bus(caplog):
    """The same through a Simulator on a virtual bus: the receiver survives anything, the slave answers after it."""
    caplog.set_level(logging.ERROR, logger="workbench.sim")
    epk_upload = bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", 0xFC0000)
    with Simulator(make_ecu(), {"interface": "virtual", "channel": "sim-fuzz-bus"}, time_scale=None) as sim, \
            RawMaster("sim-fuzz-bus") as master:

        @settings(max_examples=40, deadline=None)
        @given(frames=st.lists(frame_data, max_size=20))
        def run(frames: list[bytes]) -> None:
            for data in frames:
                master.send(data, pad=False)
            master.send(bytes([Cmd.CONNECT, 0]))
            master.send(epk_upload)
            expected = b"\xff" + sim.ecu.read(0xFC0000, 4) + bytes(3)
            responses = []
            while (message := master.bus.recv(2.0)) is not None and bytes(message.data) != expected:
                responses.append(bytes(message.data))
            assert message is not None, "the slave stopped answering"
            assert all(len(r) == 8 and r[0] in (PID_RES, PID_ERR) for r in responses), [r.hex(" ") for r in responses]

        run()
    assert not caplog.records, [r.getMessage() for r in caplog.records]


framed_packet = st.tuples(st.integers(0, 0xFFFF), st.integers(0, 0xFFFF), cto).map(
    lambda parts: struct.pack("<HH", parts[0] if parts[0] % 3 else len(parts[2]), parts[1]) + parts[2])
datagram = st.one_of(
    st.binary(max_size=40),  # anything at all
    st.lists(framed_packet, min_size=1, max_size=4).map(b"".join),  # headers, mostly with a true LEN
)


@pytest.mark.parametrize("protocol", ["UDP", "TCP"])
def test_random_datagrams_over_ethernet(caplog, protocol):
    """XCP on UDP/TCP: any bytes (malformed ones ignored or, on TCP, ending the connection); the slave serves on."""
    caplog.set_level(logging.ERROR, logger="workbench.sim")
    epk_upload = bytes([Cmd.SHORT_UPLOAD, 4, 0, 0]) + struct.pack("<I", 0xFC0000)
    params = XcpParameters(max_cto=255, max_dto=1024)
    with Simulator(make_ecu(params=params), ethernet=EthernetEndpoint("127.0.0.1", 0, protocol), time_scale=None) as sim:

        @settings(max_examples=30, deadline=None)
        @given(datagrams=st.lists(datagram, max_size=10))
        def run(datagrams: list[bytes]) -> None:
            with RawEthMaster(sim.xcp.address, protocol) as master:
                for data in datagrams:
                    try:
                        master.send_raw(data)
                    except (BrokenPipeError, ConnectionResetError):  # TCP: the slave ended a stream it cannot frame
                        break
            with RawEthMaster(sim.xcp.address, protocol) as master:  # after whatever the first one did
                connected = master.request(bytes([Cmd.CONNECT, 0]), epk_upload)
                assert [packet for _, packet in connected][-1:] == [b"\xff" + sim.ecu.read(0xFC0000, 4)], connected

        run()
    assert not caplog.records, [r.getMessage() for r in caplog.records]
