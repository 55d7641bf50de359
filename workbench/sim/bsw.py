"""The basic software of the simulated ECU: the BSW API of docs/demo-ecu.md in one object.

Analog inputs and digital/PWM outputs go to the simulated fuel system (the plant), the
CAN services to the CAN2 driver. The ECU calls :meth:`Bsw.reset` at power-on and
:meth:`Bsw.safe_state` when the application stops (power off, programming): the outputs
are no longer driven, so the valves close and the PRV stops.
"""

from __future__ import annotations

from workbench.sim.can2 import Can2Driver
from workbench.sim.flcu.hardware import RxPduInfo
from workbench.sim.plant import FuelSystemPlant

__all__ = ["Bsw"]


class Bsw:
    def __init__(self, plant: FuelSystemPlant, can2: Can2Driver):
        self.plant = plant
        self.can2 = can2

    def reset(self) -> None:
        self.can2.reset()

    def safe_state(self) -> None:
        for channel in list(self.plant.digital_outputs):
            self.plant.dout_set(channel, 0)
        for channel, (period_us, _) in list(self.plant.pwm_outputs.items()):
            self.plant.pwmout_set(channel, period_us, 0.0)

    def anin_get_adc(self, channel: str) -> float:
        return self.plant.anin_get_adc(channel)

    def dout_set(self, channel: str, value: int) -> None:
        self.plant.dout_set(channel, value)

    def dout_error_info(self, channel: str) -> int:
        return self.plant.dout_error_info(channel)

    def pwmout_set(self, channel: str, period_us: int, duty_percent: float) -> None:
        self.plant.pwmout_set(channel, period_us, duty_percent)

    def pwmout_error_info(self, channel: str) -> int:
        return self.plant.pwmout_error_info(channel)

    def can_get_rx_pdu(self, message_name: str) -> RxPduInfo:
        return self.can2.can_get_rx_pdu(message_name)

    def can_set_tx_pdu(self, message_name: str, dlc: int, data: bytes) -> None:
        self.can2.can_set_tx_pdu(message_name, dlc, data)
