"""Faults of the simulated FLCU by name (workbench.sim.inject), seen in the application's own variables;
the control channel that serves them to another process (workbench.sim.control)."""

from __future__ import annotations

import os

import pytest

from workbench.elf import ElfSymbols
from workbench.errors import InputError
from workbench.sim import build_demo_ecu
from workbench.sim.control import ControlClient, ControlServer, endpoint_key, endpoint_keys, find_control
from workbench.sim.flcu import DOUT_OTV1, CanRxStatus, DiagStatus
from workbench.sim.inject import FlcuFaults

DIAG = {status.value: status.name for status in DiagStatus}


class Rig:
    """The demo ECU powered, its PCM fed straight into the CAN2 driver every 100 ms, time moved by hand."""

    def __init__(self):
        self.demo = build_demo_ecu(unlocked=True)
        self.pcm = self.demo.pcm_node(target_bar=25.0)
        scheduler = self.demo.ecu.scheduler
        scheduler.add(self.pcm.period_s, lambda: [self.demo.can2.receive(f) for f in self.pcm.frames()], "PCM", -1)
        self.demo.ecu.power_on()
        self.faults = FlcuFaults(self.demo, pcm=self.pcm)
        self._symbols = ElfSymbols(self.demo.files.elf)

    def run(self, seconds: float) -> None:
        self.demo.ecu.advance(seconds)

    def u8(self, name: str) -> int:
        return self.demo.ecu.read(self._symbols.symbol(name).address, 1)[0]

    def f32(self, name: str) -> float:
        import struct

        return struct.unpack("<f", self.demo.ecu.read(self._symbols.symbol(name).address, 4))[0]


@pytest.fixture
def rig() -> Rig:
    rig = Rig()
    rig.run(0.5)
    assert rig.u8("xsSystemAbilitation") == 1 and rig.u8("csPCM_TO_FLCU_001_Status") == CanRxStatus.CAN_RX_OK
    return rig


def test_a_sensor_voltage_out_of_range_saturates_and_is_diagnosed(rig):
    assert rig.faults.sensor_voltage("rail", 4.9) == "rail sensor (ANIN_CH_ID_003) at 4.9 V"
    rig.run(0.3)
    assert rig.f32("zsRailPressure") == pytest.approx(50.0)  # saturated at 4.5 V: the LUT's top
    assert DIAG[rig.u8("xsRailPSDiagStatus")] == "OUT_OF_RANGE" and rig.u8("xsSystemAbilitation") == 0
    rig.faults.sensor_voltage("RAIL", None)
    rig.run(0.2)
    assert DIAG[rig.u8("xsRailPSDiagStatus")] == "NO_ERROR"


def test_a_valve_driver_error_closes_the_valve(rig):
    assert rig.u8("xsOTV1Cmd") == 1 and rig.demo.plant.valve_open(DOUT_OTV1)
    assert rig.faults.actuator_error("otv1", "open_load") == "otv1 driver (DOUT_HS_CH_ID_000) reports OPEN_LOAD"
    rig.run(0.1)
    assert DIAG[rig.u8("xsOTV1DiagStatus")] == "OPEN_LOAD" and rig.u8("xsOTV1Cmd") == 0
    assert not rig.demo.plant.valve_open(DOUT_OTV1)
    rig.faults.actuator_error("PRV", 2)
    rig.run(0.1)
    assert DIAG[rig.u8("xsPRVDiagStatus")] == "SHORT_TO_BAT" and rig.f32("xsPRVDutyCmd") == 0.0
    rig.faults.clear()
    rig.run(0.1)
    assert rig.u8("xsOTV1DiagStatus") == rig.u8("xsPRVDiagStatus") == DiagStatus.NO_ERROR


def test_rx_faults_set_the_message_status_by_priority(rig):
    rig.faults.pcm_message("PCM_TO_FLCU_002", dlc=2)
    rig.run(0.2)
    assert rig.u8("csPCM_TO_FLCU_002_Status") == CanRxStatus.CAN_RX_DLC_ERR
    rig.run(0.3)  # no good frame for 300 ms
    assert rig.u8("csPCM_TO_FLCU_002_Status") == CanRxStatus.CAN_RX_TIMEOUT_ERR
    rig.faults.channel_id_error("PCM_TO_FLCU_002")
    rig.run(0.1)
    assert rig.u8("csPCM_TO_FLCU_002_Status") == CanRxStatus.CAN_RX_CHID_ERR
    assert rig.faults.pcm_message("PCM_TO_FLCU_002", dlc=4) == "PCM PCM_TO_FLCU_002: DLC 4 again"
    rig.faults.channel_id_error("PCM_TO_FLCU_002", active=False)
    rig.run(0.2)
    assert rig.u8("csPCM_TO_FLCU_002_Status") == CanRxStatus.CAN_RX_OK
    rig.faults.pcm_message("PCM_TO_FLCU_001", stopped=True)
    rig.run(0.45)
    assert rig.u8("csPCM_TO_FLCU_001_Status") == CanRxStatus.CAN_RX_TIMEOUT_ERR
    assert rig.u8("csPCM_TO_FLCU_001_EnableFLCU") == 1  # the last good value is kept


def test_faults_as_text(rig):
    assert rig.faults.apply("rail=4.9V") == "rail sensor (ANIN_CH_ID_003) at 4.9 V"
    assert rig.faults.apply("LED=SHORT_TO_GND") == "LED driver (DOUT_LS_CH_ID_000) reports SHORT_TO_GND"
    assert rig.faults.apply("chid:PCM_TO_FLCU_001") == "PCM_TO_FLCU_001: channel id error on"
    assert rig.faults.apply("pcm-stop:PCM_TO_FLCU_002") == "PCM PCM_TO_FLCU_002: stopped"
    assert rig.faults.apply("pcm-dlc:PCM_TO_FLCU_001=3") == "PCM PCM_TO_FLCU_001: sent with DLC 3"
    for spec, says in (("rail=high", "a sensor takes a voltage"), ("fuel=1", "expected SENSOR=VOLTS"),
                       ("OTV1=BROKEN", "no diagnostic status 'BROKEN'"), ("chid:FLCU_TO_PCM_001", "no CAN2 RX message"),
                       ("pcm-dlc:PCM_TO_FLCU_001=9", "DLC of 0..8")):
        with pytest.raises(InputError, match=says):
            rig.faults.apply(spec)
    with pytest.raises(InputError, match="runs no PCM"):
        FlcuFaults(rig.demo).pcm_message("PCM_TO_FLCU_001", stopped=True)


class _Recorded:
    def __init__(self):
        self.calls = []

    def sensor_voltage(self, sensor, volts):
        self.calls.append((sensor, volts))
        if volts is not None and volts < 0:
            raise InputError("negative")
        return f"{sensor} at {volts} V"


def test_the_control_channel_is_found_by_the_bus_it_serves(tmp_path, monkeypatch, free_udp_port, free_tcp_port):
    monkeypatch.setenv("XDG_RUNTIME_DIR", str(tmp_path))
    bus = {"interface": "udp_multicast", "channel": "239.74.163.2", "port": free_udp_port}
    served = {"xcp": {"transport": "CAN"}, "buses": {"CAN1": dict(bus, receive_own_messages=False)}}
    assert endpoint_keys(served) == [endpoint_key(bus)]
    assert find_control(endpoint_key(bus)) is None  # nothing registered: a real ECU
    faults = _Recorded()
    with ControlServer(faults, endpoint_keys(served)):
        client = find_control(endpoint_key(bus))
        assert client is not None and client.hello["pid"] > 0
        assert client.call("sensor_voltage", "rail", 4.9) == "rail at 4.9 V"
        with pytest.raises(InputError, match="the simulator refused sensor_voltage: negative"):
            client.call("sensor_voltage", "rail", -1.0)
        with pytest.raises(InputError, match="has no call 'power_off'"):
            client.call("power_off")
        client.close()
    assert faults.calls == [("rail", 4.9), ("rail", -1.0)]
    assert find_control(endpoint_key(bus)) is None  # unregistered when it closed
    with ControlServer(faults, endpoint_keys(served)):
        entry = next(tmp_path.rglob("*.json"))
        entry.write_text(entry.read_text().replace(f'"pid": {os.getpid()}', '"pid": 999999999'))
        assert find_control(endpoint_key(bus)) is None and not entry.exists()  # left behind by a killed simulator
    with pytest.raises(Exception, match="does not answer"):
        ControlClient("127.0.0.1", free_tcp_port)
