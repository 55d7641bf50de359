"""The FLCU application in Python with the simulated fuel system: the thesis's chapter 7 scenarios."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from flcu_harness import Rig, target_frame

from workbench.errors import UnknownSymbolError
from workbench.sim.flcu import (
    ANIN_RAIL,
    DOUT_LED,
    DOUT_OTV1,
    DOUT_OTV2,
    PWMOUT_PRV,
    CanRxStatus,
    DiagStatus,
    FlcuApplication,
    RxPduInfo,
    TankCtrlState,
    Variables,
)
from workbench.sim.plant import PlantParameters


def state(rig: Rig) -> TankCtrlState:
    return TankCtrlState(rig.variables.u8("xsTankCtrlState"))


def test_rail_pressure_reaches_the_target_in_about_a_second():
    """Figure 94: from 0 bar to the 25 bar target in about a second, slight overshoot."""
    rig = Rig(target_bar=25.0)
    samples = []
    for _ in range(60):  # 3 s, sampled every 50 ms
        rig.run(0.05)
        samples.append((rig.ms / 1000, float(rig.variables.f32("zsRailPressure"))))
    reached = next(t for t, p in samples if p >= 24.75)
    assert 0.5 <= reached <= 1.3
    assert max(p for _, p in samples) < 26.5
    assert all(abs(p - 25.0) < 0.5 for t, p in samples if t >= 1.5)
    assert rig.variables.f32("xsDC") == pytest.approx(20.0, abs=3.0)  # the 20 kg/h flow at 700 bar


def test_tank_switch_at_the_threshold():
    """Figure 102: tank 2 active from 700 bar; at about 679 bar (20 bar below tank 1) OTV2 closes, OTV1 opens."""
    rig = Rig(PlantParameters(tank1_start_bar=700.0, tank2_start_bar=700.5, tank_bar_per_kg=580.0))
    rig.run(0.2)
    assert state(rig) is TankCtrlState.TANK2_ON
    assert rig.plant.valve_open(DOUT_OTV2) and not rig.plant.valve_open(DOUT_OTV1)

    seconds = rig.run_until(lambda: state(rig) is TankCtrlState.TANK1_ON, limit_s=15.0)
    tank1 = float(rig.variables.f32("zsTank1Pressure"))
    tank2 = float(rig.variables.f32("zsTank2Pressure"))
    assert tank1 == pytest.approx(700.0, abs=0.5)
    assert 20.0 < tank1 - tank2 < 20.5 and tank2 == pytest.approx(679.5, abs=0.6)
    assert 4.0 < seconds < 10.0  # the thesis saw it after about 6.5 s
    rig.run(0.01)  # ActuatorCommands ran in the same task; the plant follows
    assert rig.plant.valve_open(DOUT_OTV1) and not rig.plant.valve_open(DOUT_OTV2)
    assert rig.variables.u8("xsValve1State") == 1 and rig.variables.u8("xsValve2State") == 0


def test_valves_close_when_both_tanks_are_empty():
    """Figure 103: with both tanks below the 5 bar empty-tank threshold the valves close and the
    LED lights (the thesis lowered the tank pressures by hand: 6 bar cannot feed a 25 bar rail)."""
    rig = Rig(PlantParameters(tank1_start_bar=6.0, tank2_start_bar=4.0))
    rig.run(0.2)
    assert state(rig) is TankCtrlState.TANK1_ON and rig.plant.valve_open(DOUT_OTV1)
    assert rig.variables.u8("xsLEDEn") == 0 and rig.plant.digital_outputs[DOUT_LED] == 0

    rig.plant.set_pressures(tank1_bar=4.0)
    rig.run(0.2)
    assert rig.variables.f32("zsTank1Pressure") < 5.0 and rig.variables.f32("zsTank2Pressure") < 5.0
    assert rig.variables.u8("xsLEDEn") == 1
    assert state(rig) is TankCtrlState.OFF
    assert rig.variables.u8("xsValve1State") == 0 and rig.variables.u8("xsValve2State") == 0
    assert not rig.plant.valve_open(DOUT_OTV1) and not rig.plant.valve_open(DOUT_OTV2)
    assert rig.plant.digital_outputs[DOUT_LED] == 1
    assert rig.can.tx["FLCU_TO_PCM_001"][-1][1] & 0x01 == 1  # FuelLevelLow


def test_rail_pressure_fix_overrides_the_sensor():
    rig = Rig()
    rig.run(1.0)
    rig.variables.set_f32("zfRAILPRESSURE_VALUE", 12.5)
    rig.variables.set_u8("zfRAILPRESSURE_EN", 1)
    rig.run(0.2)
    assert rig.variables.f32("zsRailPressure") == np.float32(12.5)
    assert rig.variables.f32("zsRailPressureTmp") > 20.0  # the sensor still reads the real rail
    assert rig.can.tx["FLCU_TO_PCM_002"][-1][1:3] == (1250).to_bytes(2, "little")

    rig.variables.set_u8("zfRAILPRESSURE_EN", 2)  # only 1 enables a fix
    rig.run(0.01)
    assert rig.variables.f32("zsRailPressure") == rig.variables.f32("zsRailPressureTmp")


def _expected_status(chid: bool, timeout: bool, dlc: bool, new_data: bool, out_of_range: bool) -> CanRxStatus:
    for flag, status in (
        (chid, CanRxStatus.CAN_RX_CHID_ERR),
        (timeout, CanRxStatus.CAN_RX_TIMEOUT_ERR),
        (dlc, CanRxStatus.CAN_RX_DLC_ERR),
        (not new_data, CanRxStatus.CAN_RX_NEWDATA_ERR),
        (out_of_range, CanRxStatus.CAN_RX_SIG_OUT_OF_RANGE),
    ):
        if flag:
            return status
    return CanRxStatus.CAN_RX_OK


@pytest.mark.parametrize("chid,timeout,dlc,new_data,out_of_range", list(itertools.product((False, True), repeat=5)))
def test_rx_status_priority_and_bit_status(chid, timeout, dlc, new_data, out_of_range):
    rig = Rig()
    raw = 6000 if out_of_range else 2500  # 60 bar is above the DBC maximum of 50 bar
    pdu = RxPduInfo(4, raw.to_bytes(2, "little") + bytes(6), dlc, timeout, new_data, chid)
    rig.can.rx["PCM_TO_FLCU_002"] = pdu
    rig.app.task_100ms()
    v = rig.variables
    assert v.u8("csPCM_TO_FLCU_002_Status") == _expected_status(chid, timeout, dlc, new_data, out_of_range)
    bits = dlc | timeout << 1 | (not new_data) << 2 | chid << 3 | out_of_range << 4
    assert v.u8("csPCM_TO_FLCU_002_BitStatus") == bits
    assert v.f32("csPCM_TO_FLCU_002_TargetRailPressure") == np.float32(50.0 if out_of_range else 25.0)
    assert v.raw("CANRX_PCM_TO_FLCU_002_Pdu", 13) == pdu.to_bytes()


def test_timed_out_message_keeps_its_last_value_and_the_fix_wins():
    rig = Rig()
    rig.can.rx["PCM_TO_FLCU_002"] = target_frame(3000)
    rig.app.task_100ms()
    rig.can.rx["PCM_TO_FLCU_002"] = RxPduInfo(4, (3000).to_bytes(2, "little") + bytes(6), timeout=True)
    rig.app.task_100ms()
    v = rig.variables
    assert v.u8("csPCM_TO_FLCU_002_Status") == CanRxStatus.CAN_RX_TIMEOUT_ERR
    assert v.f32("csPCM_TO_FLCU_002_TargetRailPressure") == np.float32(30.0)
    v.set_u16("cfTARGETRAILPRESSURE_VALUE", 1234)
    v.set_u8("cfTARGETRAILPRESSURE_EN", 1)
    rig.app.task_100ms()
    assert v.f32("csPCM_TO_FLCU_002_TargetRailPressure") == np.float32(1234) * np.float32(0.01)


def test_sensor_out_of_range_disables_the_system():
    rig = Rig()
    rig.run(1.0)
    assert rig.variables.u8("xsSystemAbilitation") == 1
    rig.plant.override_voltage(ANIN_RAIL, 4.8)
    rig.run(0.1)
    v = rig.variables
    assert v.u8("xsRailPSDiagStatus") == DiagStatus.OUT_OF_RANGE and v.u8("xsSensorDiag") == 0
    assert v.u8("xsSystemAbilitation") == 0 and state(rig) is TankCtrlState.OFF
    assert v.f32("xsDC") == 0.0 and rig.plant.prv_duty_percent == 0.0
    assert rig.can.tx["FLCU_TO_PCM_003"][-1][4] == DiagStatus.OUT_OF_RANGE  # RailPSDiagnosticStatus


def test_prv_driver_error_zeroes_the_duty_and_is_reported():
    rig = Rig()
    rig.run(1.0)
    rig.plant.set_output_error(PWMOUT_PRV, DiagStatus.OPEN_LOAD)
    rig.run(0.1)
    v = rig.variables
    assert v.u8("xsPRVDiagStatus") == DiagStatus.OPEN_LOAD and v.u8("xsActuatorDiag") == 0
    assert v.f32("xsPRVDutyCmd") == 0.0 and rig.plant.pwm_outputs[PWMOUT_PRV] == (1000, 0.0)


def test_tx_enable_and_signal_fix():
    rig = Rig()
    rig.run(0.35)
    sent = len(rig.can.tx["FLCU_TO_PCM_002"])
    rig.variables.set_u8("csFLCU_TO_PCM_002_En", 0)
    rig.variables.set_u16("cfFUELLEVEL_VALUE", 4242)
    rig.variables.set_u8("cfFUELLEVEL_EN", 1)
    rig.run(0.3)
    assert len(rig.can.tx["FLCU_TO_PCM_002"]) == sent
    assert rig.variables.raw("CANTX_FLCU_TO_PCM_002_Pdu", 1) == bytes([4])  # still encoded
    assert rig.can.tx["FLCU_TO_PCM_001"][-1][2:4] == (4242).to_bytes(2, "little")


def test_fuel_level_and_unknown_symbols():
    rig = Rig()
    rig.run(0.3)
    assert rig.variables.f32("xsFuelLevel") == pytest.approx(100.0, abs=0.2)
    with pytest.raises(UnknownSymbolError, match="zsNOPE"):
        rig.variables.f32("zsNOPE")
    plain = Variables(rig.memory, {name: s.address for name, s in rig.elf.symbols.items()})
    assert plain.f32("zsEWMA_ALPHA") == np.float32(0.2)


def test_the_twin_writes_exactly_the_c_applications_measurements():
    rig = Rig()
    in_ram = {
        s.name
        for s in rig.elf.symbols.values()
        if s.kind == "object" and s.section in (".bss", ".data") and not s.name.startswith(("API_", "CanNetwork_"))
    }
    assert sorted(FlcuApplication.MEASUREMENTS) == sorted(in_ram)
