"""CANRX (100 ms, ``CANRX.c``): decode PCM_TO_FLCU_001/002, fix switches, message status.

Status priority: ChannelIdErr > TimeOut > DLC > NewData missing > SignalOutOfRange; the
``_BitStatus`` word has bit0 DLC, bit1 TimeOut, bit2 NewData missing, bit3 ChannelIdErr,
bit4 SignalOutOfRange. The driver keeps the last good payload, so a timed-out message keeps
its last value.
"""

from __future__ import annotations

import numpy as np

from workbench.can.naming import fix_enable_name, fix_value_name, rx_bit_status_name, rx_status_name
from workbench.sim.flcu.hardware import CanRxStatus, Hardware, RxPduInfo
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "CanRx", "message_status"]

BIT_DLC, BIT_TIMEOUT, BIT_NEWDATA, BIT_CHID, BIT_SIG_OUT_OF_RANGE = 0x01, 0x02, 0x04, 0x08, 0x10
_TARGET_FACTOR = np.float32(0.01)
_TARGET_MAX = np.float32(50.0)
PDU_SIZE = 13
_ENABLE_FIX = (fix_enable_name("EnableFLCU"), fix_value_name("EnableFLCU"))
_TARGET_FIX = (fix_enable_name("TargetRailPressure"), fix_value_name("TargetRailPressure"))
_U8_OUTPUTS = (
    "csPCM_TO_FLCU_001_EnableFLCU",
    "csPCM_TO_FLCU_001_Status",
    "csPCM_TO_FLCU_001_BitStatus",
    "csPCM_TO_FLCU_002_Status",
    "csPCM_TO_FLCU_002_BitStatus",
)
MEASUREMENTS = (
    "CANRX_PCM_TO_FLCU_001_Pdu",
    "CANRX_PCM_TO_FLCU_002_Pdu",
    "csPCM_TO_FLCU_002_TargetRailPressure",
    *_U8_OUTPUTS,
)


def message_status(pdu: RxPduInfo, signal_out_of_range: bool) -> tuple[CanRxStatus, int]:
    """``(_Status, _BitStatus)`` of one message (figures 61 and 62)."""
    no_new_data = not pdu.new_data_received
    if pdu.channel_id_error:
        status = CanRxStatus.CAN_RX_CHID_ERR
    elif pdu.timeout:
        status = CanRxStatus.CAN_RX_TIMEOUT_ERR
    elif pdu.dlc_error:
        status = CanRxStatus.CAN_RX_DLC_ERR
    elif no_new_data:
        status = CanRxStatus.CAN_RX_NEWDATA_ERR
    elif signal_out_of_range:
        status = CanRxStatus.CAN_RX_SIG_OUT_OF_RANGE
    else:
        status = CanRxStatus.CAN_RX_OK
    bits = (
        (BIT_DLC if pdu.dlc_error else 0)
        | (BIT_TIMEOUT if pdu.timeout else 0)
        | (BIT_NEWDATA if no_new_data else 0)
        | (BIT_CHID if pdu.channel_id_error else 0)
        | (BIT_SIG_OUT_OF_RANGE if signal_out_of_range else 0)
    )
    return status, bits


class CanRx:
    def __init__(self, variables: Variables, hardware: Hardware):
        self._v = variables
        self._hw = hardware

    def initialize(self) -> None:
        v = self._v
        v.set_raw("CANRX_PCM_TO_FLCU_001_Pdu", bytes(PDU_SIZE))
        v.set_raw("CANRX_PCM_TO_FLCU_002_Pdu", bytes(PDU_SIZE))
        v.set_f32("csPCM_TO_FLCU_002_TargetRailPressure", 0.0)
        for name in _U8_OUTPUTS:
            v.set_u8(name, 0)

    def _read_pdu(self, message: str) -> RxPduInfo:
        """The driver's PDU, stored as the C struct; the flags read back as C reads them (!= 0)."""
        raw = self._hw.can_get_rx_pdu(message).to_bytes()
        self._v.set_raw(f"CANRX_{message}_Pdu", raw)
        return RxPduInfo(raw[0], raw[1:9], *(flag != 0 for flag in raw[9:13]))

    def _publish_status(self, message: str, pdu: RxPduInfo, signal_out_of_range: bool) -> None:
        status, bits = message_status(pdu, signal_out_of_range)
        self._v.set_u8(rx_status_name(message), status)
        self._v.set_u8(rx_bit_status_name(message), bits)

    def step(self) -> None:
        v = self._v
        # PCM_TO_FLCU_001: EnableFLCU 0|1@1+ (1,0) [0|1]; a 1-bit signal cannot leave its range
        pdu = self._read_pdu("PCM_TO_FLCU_001")
        enable = pdu.data[0] & 0x01
        if v.u8(_ENABLE_FIX[0]) == 1:
            enable = v.u8(_ENABLE_FIX[1])
        v.set_u8("csPCM_TO_FLCU_001_EnableFLCU", enable)
        self._publish_status("PCM_TO_FLCU_001", pdu, False)

        # PCM_TO_FLCU_002: TargetRailPressure 0|16@1+ (0.01,0) [0|50] "bar"
        pdu = self._read_pdu("PCM_TO_FLCU_002")
        target = np.float32(pdu.data[0] | (pdu.data[1] << 8)) * _TARGET_FACTOR
        out_of_range = bool(target > _TARGET_MAX)
        if out_of_range:
            target = _TARGET_MAX
        if v.u8(_TARGET_FIX[0]) == 1:
            target = np.float32(v.u16(_TARGET_FIX[1])) * _TARGET_FACTOR
        v.set_f32("csPCM_TO_FLCU_002_TargetRailPressure", target)
        self._publish_status("PCM_TO_FLCU_002", pdu, out_of_range)
