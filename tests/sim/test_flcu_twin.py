"""The Python twin against the C application, compiled for the host, step by step.

Both run the same scenario from the same inputs (the simulated fuel system's voltages and
driver statuses, the same CAN PDUs, the same calibration writes), and after every task every
measurement and state of the C application is compared with the twin's bytes in memory, by
name, together with every output (digital, PWM, transmitted PDUs).

The comparison is exact: both do the same IEEE-754 single-precision operations in the same
order (the C code is built with SSE math and ``-ffp-contract=off``, the twin rounds every
operation to float32 through numpy), so any difference is a bug, not rounding.
"""

from __future__ import annotations

import ctypes
import struct
from collections import defaultdict

import pytest
from flcu_harness import ECU_SOURCES, HostApplication, Rig, build_host_library, c_enumerators, enable_frame, target_frame

from workbench.sim.flcu import (
    ANIN_MANIFOLD,
    ANIN_RAIL,
    ANIN_TANK1,
    ANIN_TANK2,
    DOUT_LED,
    DOUT_OTV1,
    DOUT_OTV2,
    PWMOUT_PRV,
    DiagStatus,
    FlcuApplication,
    RxPduInfo,
)
from workbench.sim.plant import PlantParameters

pytestmark = pytest.mark.gcc

TX_MESSAGES = ("FLCU_TO_PCM_001", "FLCU_TO_PCM_002", "FLCU_TO_PCM_003")  # CAN2_MSG_TX_000..002
RX_MESSAGES = ("PCM_TO_FLCU_001", "PCM_TO_FLCU_002")  # CAN2_MSG_RX_000..001


@pytest.fixture(scope="module")
def host_library(tmp_path_factory):
    library = build_host_library(tmp_path_factory.mktemp("flcu_host"))
    if library is None:
        pytest.skip("no gcc/make on this machine: the C application cannot be compiled for the host")
    return library


class Twin:
    """The Python application (on the fuel system) and the C application, fed the same inputs."""

    def __init__(self, library, tmp_path):
        self.rig = Rig(PlantParameters(tank1_start_bar=700.0, tank2_start_bar=690.0))
        self.rig.pcm_sending = False
        self.c = HostApplication(library, tmp_path / "libflcu_twin.so")
        self.enum = c_enumerators(ECU_SOURCES / "api.h")
        self.c.lib.API_OS_Init()  # the rig initialised the twin
        self.measurements = [
            s
            for s in self.rig.elf.symbols.values()
            if s.kind == "object" and s.section in (".bss", ".data") and not s.name.startswith(("API_", "CanNetwork_"))
        ]
        self.seen: dict[str, set[int]] = defaultdict(set)

    def set_calibration(self, name: str, data: bytes) -> None:
        self.rig.memory.write(self.rig.variables.address(name), data)
        self.c.set_variable(name, data)

    def set_rx(self, message: str, pdu: RxPduInfo) -> None:
        self.rig.can.rx[message] = pdu
        self.c.lib.Harness_setRxPdu(RX_MESSAGES.index(message), pdu.to_bytes())

    def _inputs_to_c(self) -> None:
        plant, lib = self.rig.plant, self.c.lib
        for channel in (ANIN_TANK1, ANIN_TANK2, ANIN_MANIFOLD, ANIN_RAIL):
            lib.Harness_setAdc(self.enum[channel], ctypes.c_float(plant.anin_get_adc(channel)))
        for channel in (DOUT_OTV1, DOUT_OTV2, DOUT_LED):
            lib.Harness_setDoutError(self.enum[channel], plant.dout_error_info(channel))
        lib.Harness_setPwmOutError(self.enum[PWMOUT_PRV], plant.pwmout_error_info(PWMOUT_PRV))

    def _compare(self, when: str) -> None:
        memory = self.rig.memory
        for symbol in self.measurements:
            c_bytes = self.c.variable(symbol.name, symbol.size)
            py_bytes = memory.read(symbol.address, symbol.size)
            assert py_bytes == c_bytes, f"{when}: {symbol.name} C {c_bytes.hex()} Python {py_bytes.hex()}"
        plant, lib = self.rig.plant, self.c.lib
        for channel in (DOUT_OTV1, DOUT_OTV2, DOUT_LED):
            assert lib.Harness_getDout(self.enum[channel]) == plant.digital_outputs.get(channel, 0), f"{when}: {channel}"
        period, duty = plant.pwm_outputs.get(PWMOUT_PRV, (0, 0.0))
        prv = self.enum[PWMOUT_PRV]
        assert (lib.Harness_getPwmPeriod(prv), lib.Harness_getPwmDuty(prv)) == (period, round(duty * 100)), when
        for mailbox, message in enumerate(TX_MESSAGES):
            sent = self.rig.can.tx.get(message, [])
            assert lib.Harness_getTxCount(mailbox) == len(sent), f"{when}: {message} count"
            if sent:
                assert self.c.tx_pdu(mailbox) == sent[-1], f"{when}: {message} payload"

    def tick(self, ms: int) -> None:
        self._inputs_to_c()
        for period_s, method, _event in FlcuApplication.TASKS:
            if ms % round(period_s * 1000) == 0:
                getattr(self.rig.app, method)()
                getattr(self.c.lib, "API_OS_" + method.replace("task_", "Task"))()
                self._compare(f"t={ms} ms after {method}")
        v = self.rig.variables
        for name in ("xsTankCtrlState", "csPCM_TO_FLCU_002_Status", "xsSystemAbilitation", "xsLEDEn",
                     "xsManifoldPSDiagStatus", "xsRailPSDiagStatus", "xsPRVDiagStatus", "xsOTV1DiagStatus"):
            self.seen[name].add(v.u8(name))
        self.seen["dc>0"].add(int(v.f32("xsDC") > 0))
        self.rig.plant.step(0.001)


def scenario(twin: Twin, ms: int) -> None:
    """What happens at ``ms``: PCM frames, fuel-system events, calibration writes."""
    plant = twin.rig.plant
    target = 2500
    if 2200 <= ms < 2500:
        target = 6000  # 60 bar: out of the DBC range
    if ms % 100 == 0:
        twin.set_rx("PCM_TO_FLCU_001", enable_frame(0 if ms >= 3600 else 1))
        if not 1500 <= ms < 2100:
            twin.set_rx("PCM_TO_FLCU_002", target_frame(target))
    events = {
        600: lambda: plant.set_pressures(tank1_bar=668.0),  # tank 2 fuller by 22 bar: switch
        900: lambda: (twin.set_calibration("zfMANIFOLDPRESSURE_VALUE", struct.pack("<f", 300.0)),
                      twin.set_calibration("zfMANIFOLDPRESSURE_EN", b"\x01")),  # implausible manifold
        1100: lambda: twin.set_calibration("zfMANIFOLDPRESSURE_EN", b"\x00"),
        1200: lambda: (twin.set_calibration("cfTARGETRAILPRESSURE_VALUE", (3000).to_bytes(2, "little")),
                       twin.set_calibration("cfTARGETRAILPRESSURE_EN", b"\x01")),
        1500: lambda: twin.set_calibration("cfTARGETRAILPRESSURE_EN", b"\x00"),
        # the PCM stops sending PCM_TO_FLCU_002: no new data, then the driver's 300 ms timeout
        1800: lambda: twin.set_rx("PCM_TO_FLCU_002", RxPduInfo(4, target_frame(2500).data, timeout=True)),
        2000: lambda: twin.set_rx("PCM_TO_FLCU_002", RxPduInfo(4, target_frame(2500).data, dlc_error=True)),
        2500: lambda: plant.override_voltage(ANIN_RAIL, 4.8),
        2700: lambda: plant.override_voltage(ANIN_RAIL, None),
        2800: lambda: plant.set_output_error(PWMOUT_PRV, DiagStatus.OPEN_LOAD),
        2950: lambda: (plant.set_output_error(PWMOUT_PRV, DiagStatus.NO_ERROR),
                       plant.set_output_error(DOUT_OTV1, DiagStatus.SHORT_TO_GND)),
        3100: lambda: plant.set_output_error(DOUT_OTV1, DiagStatus.NO_ERROR),
        3200: lambda: plant.set_pressures(tank1_bar=4.0, tank2_bar=3.5),  # both tanks empty
        3400: lambda: (twin.set_calibration("csFLCU_TO_PCM_002_En", b"\x00"),
                       twin.set_calibration("cfFUELLEVEL_VALUE", (1234).to_bytes(2, "little")),
                       twin.set_calibration("cfFUELLEVEL_EN", b"\x01"),
                       twin.set_calibration("cfLEDDIAGSTATUS_VALUE", b"\x03"),
                       twin.set_calibration("cfLEDDIAGSTATUS_EN", b"\x01")),
    }
    if ms in events:
        events[ms]()


def test_python_twin_matches_the_c_application(host_library, tmp_path):
    twin = Twin(host_library, tmp_path)
    twin._compare("after API_OS_Init")
    for ms in range(4000):
        scenario(twin, ms)
        twin.tick(ms)
    # the scenario went where it was meant to go (else the comparison proves little)
    assert twin.seen["xsTankCtrlState"] == {0, 1, 2}
    assert {1, 2, 3, 5} <= twin.seen["csPCM_TO_FLCU_002_Status"]  # DLC, timeout, new data, out of range
    assert twin.seen["xsManifoldPSDiagStatus"] >= {DiagStatus.IMPLAUSIBLE}
    assert DiagStatus.OUT_OF_RANGE in twin.seen["xsRailPSDiagStatus"]
    assert DiagStatus.OPEN_LOAD in twin.seen["xsPRVDiagStatus"]
    assert DiagStatus.SHORT_TO_GND in twin.seen["xsOTV1DiagStatus"]
    assert twin.seen["xsSystemAbilitation"] == {0, 1} and twin.seen["xsLEDEn"] == {0, 1}
    assert twin.seen["dc>0"] == {0, 1}
