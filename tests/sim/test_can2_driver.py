"""The CAN2 driver's RX status and TX, and the FLCU messages on the bus with the residual-bus PCM."""

from __future__ import annotations

import itertools

import can
import pytest

from workbench import demo as demo_files
from workbench.can.dbc_file import load_dbc
from workbench.elf import ElfSymbols
from workbench.sim.can2 import Can2Driver
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.server import Simulator

_channels = itertools.count()


@pytest.fixture
def driver():
    clock = {"now": 0.0}
    can2 = Can2Driver(load_dbc(demo_files.dbc_can2()), "FLCU", lambda: clock["now"])
    can2.clock = clock
    return can2


def frame(identifier: int, data: bytes) -> can.Message:
    return can.Message(arbitration_id=identifier, is_extended_id=False, data=data)


def test_messages_by_role(driver):
    assert [m.name for m in driver.rx_messages] == ["PCM_TO_FLCU_001", "PCM_TO_FLCU_002"]
    assert [m.name for m in driver.tx_messages] == ["FLCU_TO_PCM_001", "FLCU_TO_PCM_002", "FLCU_TO_PCM_003"]


def test_new_data_is_cleared_by_the_read(driver):
    assert driver.receive(frame(0x220, bytes([0xC4, 0x09, 0, 0])))
    info = driver.can_get_rx_pdu("PCM_TO_FLCU_002")
    assert (info.dlc, info.data[:2], info.new_data_received, info.timeout) == (4, b"\xc4\x09", True, False)
    assert not driver.can_get_rx_pdu("PCM_TO_FLCU_002").new_data_received


def test_timeout_after_300_ms_without_a_good_frame(driver):
    driver.clock["now"] = 0.3
    assert not driver.can_get_rx_pdu("PCM_TO_FLCU_001").timeout
    driver.clock["now"] = 0.31
    assert driver.can_get_rx_pdu("PCM_TO_FLCU_001").timeout
    driver.receive(frame(0x110, b"\x01"))
    info = driver.can_get_rx_pdu("PCM_TO_FLCU_001")
    assert not info.timeout and info.data[0] == 1


def test_wrong_dlc_keeps_the_last_good_data(driver):
    driver.receive(frame(0x220, bytes([1, 2, 3, 4])))
    driver.can_get_rx_pdu("PCM_TO_FLCU_002")
    driver.receive(frame(0x220, bytes([9, 9])))
    info = driver.can_get_rx_pdu("PCM_TO_FLCU_002")
    assert info.dlc_error and not info.new_data_received and info.data[:4] == bytes([1, 2, 3, 4])
    driver.receive(frame(0x220, bytes([5, 6, 7, 8])))
    assert not driver.can_get_rx_pdu("PCM_TO_FLCU_002").dlc_error


def test_channel_id_error_only_when_injected(driver):
    assert not driver.can_get_rx_pdu("PCM_TO_FLCU_001").channel_id_error
    driver.inject_channel_id_error("PCM_TO_FLCU_001")
    assert driver.can_get_rx_pdu("PCM_TO_FLCU_001").channel_id_error
    assert not driver.receive(frame(0x123, bytes(4)))  # a TX id is not received


def test_flcu_messages_on_their_own_can2_bus_with_the_pcm():
    demo = build_demo_ecu()
    symbols = ElfSymbols(demo.files.elf)
    can1, can2 = f"sim-can1-{next(_channels)}", f"sim-can2-{next(_channels)}"
    sim = Simulator(demo.ecu, {"interface": "virtual", "channel": can1}, {"interface": "virtual", "channel": can2},
                    can2_driver=demo.can2, pcm=demo.pcm_node(target_bar=25.0), time_scale=None)
    with can.Bus(interface="virtual", channel=can1) as observer1, can.Bus(interface="virtual", channel=can2) as observer2, sim:
        sim.advance(1.0)
        seen = _drain(observer2)
        assert seen[0x110] == seen[0x220] == 10  # the PCM, every 100 ms
        assert seen[0x167] == seen[0x123] == seen[0x145] == 10  # FLCU_TO_PCM_001..003
        assert _drain(observer1) == {}  # nothing of CAN2 on CAN1
        status = demo.ecu.read(symbols.symbol("csPCM_TO_FLCU_002_Status").address, 1)[0]
        assert status == 0  # CAN_RX_OK
        with sim.lock:
            demo.ecu.memory.write(symbols.symbol("csFLCU_TO_PCM_002_En").address, b"\x00")
        sim.advance(0.5)
        seen = _drain(observer2)
        assert 0x123 not in seen and seen[0x167] == 5


def test_rail_pressure_on_can2_follows_the_ecu():
    demo = build_demo_ecu()
    channel = f"sim-can-{next(_channels)}"
    with can.Bus(interface="virtual", channel=channel) as observer, Simulator(
            demo.ecu, {"interface": "virtual", "channel": channel}, can2_driver=demo.can2,
            pcm=demo.pcm_node(target_bar=25.0), time_scale=None) as sim:
        sim.advance(2.0)
        frames = [m for m in _messages(observer) if m.arbitration_id == 0x123]
        rail = demo.dbc.database.decode_message(0x123, frames[-1].data)["RailPressure"]
        assert 24.0 < rail < 26.5


def _messages(bus):
    out = []
    while (message := bus.recv(0.05)) is not None:
        out.append(message)
    return out


def _drain(bus) -> dict[int, int]:
    counts: dict[int, int] = {}
    for message in _messages(bus):
        counts[message.arbitration_id] = counts.get(message.arbitration_id, 0) + 1
    return counts
