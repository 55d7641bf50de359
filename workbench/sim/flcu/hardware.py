"""The BSW API the FLCU application calls, as the simulated ECU provides it.

The C application calls ``API_ANIN_getADC``, ``API_DOUT_setDigOut`` … (``assets/ecu/api.h``);
the Python twin calls the same services on a :class:`Hardware` object. Channels are the C
enumerator names as strings. The analog/digital/PWM half is the simulated fuel system
(:mod:`workbench.sim.plant`), the CAN half the simulator's CAN2 driver.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Protocol

__all__ = ["ANIN_MANIFOLD", "ANIN_RAIL", "ANIN_TANK1", "ANIN_TANK2", "DOUT_LED", "DOUT_OTV1", "DOUT_OTV2", "PWMOUT_PRV",
           "CanRxStatus", "DiagStatus", "Hardware", "RxPduInfo", "TankCtrlState"]

# Channels of the FLCU (docs/demo-ecu.md, "Hardware channels")
ANIN_TANK1 = "ANIN_CH_ID_000"
ANIN_TANK2 = "ANIN_CH_ID_001"
ANIN_MANIFOLD = "ANIN_CH_ID_002"
ANIN_RAIL = "ANIN_CH_ID_003"
DOUT_OTV1 = "DOUT_HS_CH_ID_000"
DOUT_OTV2 = "DOUT_HS_CH_ID_001"
DOUT_LED = "DOUT_LS_CH_ID_000"
PWMOUT_PRV = "PWMOUT_LS_CH_ID_000"


class DiagStatus(IntEnum):
    """``Std_eDiagStatusT``."""

    NO_ERROR = 0
    SHORT_TO_GND = 1
    SHORT_TO_BAT = 2
    OPEN_LOAD = 3
    OUT_OF_RANGE = 4
    IMPLAUSIBLE = 5


class TankCtrlState(IntEnum):
    """``tTankCtrlState``."""

    OFF = 0
    TANK1_ON = 1
    TANK2_ON = 2


class CanRxStatus(IntEnum):
    """``tCANRxStatus``."""

    CAN_RX_OK = 0
    CAN_RX_DLC_ERR = 1
    CAN_RX_TIMEOUT_ERR = 2
    CAN_RX_NEWDATA_ERR = 3
    CAN_RX_CHID_ERR = 4
    CAN_RX_SIG_OUT_OF_RANGE = 5


@dataclass(frozen=True)
class RxPduInfo:
    """``tRxPduInfo``: a received CAN message as the driver keeps it.

    ``dlc``/``data``: the last frame received with the configured DLC (``data`` is 8 bytes);
    ``dlc_error``: the last frame had another DLC; ``timeout``: no good frame within the RX
    timeout; ``new_data_received``: a good frame arrived since the previous read of this
    message; ``channel_id_error``: the frame came on another channel.
    """

    dlc: int = 0
    data: bytes = bytes(8)
    dlc_error: bool = False
    timeout: bool = False
    new_data_received: bool = False
    channel_id_error: bool = False

    def __post_init__(self) -> None:
        if len(self.data) != 8:
            raise ValueError(f"RxPduInfo.data must be 8 bytes, got {len(self.data)}")

    def to_bytes(self) -> bytes:
        """The C struct's 13 bytes: Dlc, Data[8], DlcError, TimeOut, NewDataReceived, ChannelIdErr."""
        flags = (self.dlc_error, self.timeout, self.new_data_received, self.channel_id_error)
        return bytes([self.dlc & 0xFF]) + bytes(self.data) + bytes(int(bool(f)) for f in flags)


class Hardware(Protocol):
    """The services of ``api.h`` the application uses (units as in the C API)."""

    def anin_get_adc(self, channel: str) -> float:
        """Voltage of an analog input [V]."""

    def dout_set(self, channel: str, value: int) -> None:
        """Drive a digital output (0/1)."""

    def dout_error_info(self, channel: str) -> int:
        """``Std_eDiagStatusT`` of a digital output."""

    def pwmout_set(self, channel: str, period_us: int, duty_percent: float) -> None:
        """Drive a PWM output: period [µs], duty [%] in the driver's 0.01 % steps."""

    def pwmout_error_info(self, channel: str) -> int:
        """``Std_eDiagStatusT`` of a PWM output."""

    def can_get_rx_pdu(self, message_name: str) -> RxPduInfo:
        """The driver's PDU of a received message; reading clears ``new_data_received``."""

    def can_set_tx_pdu(self, message_name: str, dlc: int, data: bytes) -> None:
        """Hand a payload (8 bytes) to the driver for transmission."""
