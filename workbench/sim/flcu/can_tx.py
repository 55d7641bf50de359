"""CANTX (100 ms, ``CANTX.c``): encode FLCU_TO_PCM_001/002/003, fix switches, TX enables.

raw = round(phys / factor) in float32, saturated to the raw type; ``cf<SIGNAL>_VALUE``
replaces the raw value while ``cf<SIGNAL>_EN`` == 1; a message goes to the driver only while
``cs<Message>_En`` == 1. Every payload is kept in ``CANTX_<Message>_Pdu`` (``tTxPduInfo``).
"""

from __future__ import annotations

import numpy as np

from workbench.can.naming import fix_enable_name, fix_value_name, tx_enable_name
from workbench.sim.flcu.hardware import Hardware
from workbench.sim.flcu.rt import HALF, ZERO
from workbench.sim.flcu.variables import Variables

__all__ = ["MEASUREMENTS", "CanTx", "raw_u16"]

_U16_MAX = np.float32(65535.0)
_FACTOR_0_01 = np.float32(0.01)
MESSAGES = (("FLCU_TO_PCM_001", 4), ("FLCU_TO_PCM_002", 4), ("FLCU_TO_PCM_003", 8))
MEASUREMENTS = tuple(f"CANTX_{name}_Pdu" for name, _ in MESSAGES)
# FLCU_TO_PCM_003: one 8-bit status per byte, in payload order: (DBC signal, source)
_DIAG_SIGNALS = (
    ("Tank1PSDiagStatus", "xsTank1PSDiagStatus"),
    ("Tank2PSDiagStatus", "xsTank2PSDiagStatus"),
    ("ManifoldPSDiagStatus", "xsManifoldPSDiagStatus"),
    ("RailPSDiagnosticStatus", "xsRailPSDiagStatus"),
    ("OTV1DiagStatus", "xsOTV1DiagStatus"),
    ("OTV2DiagStatus", "xsOTV2DiagStatus"),
    ("PRVDiagStatus", "xsPRVDiagStatus"),
    ("LedDiagStatus", "xsLEDDiagStatus"),
)
# DBC signal -> (cf<SIGNAL>_EN, cf<SIGNAL>_VALUE)
_FIXES = {signal: (fix_enable_name(signal), fix_value_name(signal))
          for signal in ("FuelLevelLow", "FuelLevel", "RailPressure", *(s for s, _ in _DIAG_SIGNALS))}


def raw_u16(phys: np.float32, factor: np.float32) -> int:
    """``CANTX_rawU16``: round(phys / factor) saturated to [0, 65535]; NaN gives 0."""
    raw = phys / factor
    if not raw > ZERO:
        return 0
    if raw >= _U16_MAX:
        return 65535
    return int(raw + HALF)


class CanTx:
    def __init__(self, variables: Variables, hardware: Hardware):
        self._v = variables
        self._hw = hardware

    def initialize(self) -> None:
        for name, dlc in MESSAGES:
            self._v.set_raw(f"CANTX_{name}_Pdu", bytes([dlc]) + bytes(8))

    def _fix_u8(self, signal: str, raw: int) -> int:
        enable, value = _FIXES[signal]
        return self._v.u8(value) if self._v.u8(enable) == 1 else raw

    def _fix_u16(self, signal: str, raw: int) -> int:
        enable, value = _FIXES[signal]
        return self._v.u16(value) if self._v.u8(enable) == 1 else raw

    def _send(self, message: str, dlc: int, payload: bytes) -> None:
        """Store Dlc and the ``dlc`` payload bytes the C code writes; hand all 8 to the driver."""
        pdu = f"CANTX_{message}_Pdu"
        self._v.set_raw(pdu, bytes([dlc]) + payload[:dlc])
        if self._v.u8(tx_enable_name(message)) == 1:
            self._hw.can_set_tx_pdu(message, dlc, self._v.raw(pdu, 8, 1))

    def step(self) -> None:
        v = self._v
        low = self._fix_u8("FuelLevelLow", v.u8("xsLEDEn"))
        level = self._fix_u16("FuelLevel", raw_u16(v.f32("xsFuelLevel"), _FACTOR_0_01))
        self._send("FLCU_TO_PCM_001", 4, bytes([low & 0x01, level & 0xFF, level >> 8, 0]))

        rail = self._fix_u16("RailPressure", raw_u16(v.f32("zsRailPressure"), _FACTOR_0_01))
        self._send("FLCU_TO_PCM_002", 4, bytes([rail & 0xFF, rail >> 8, 0, 0]))

        self._send("FLCU_TO_PCM_003", 8, bytes(self._fix_u8(signal, v.u8(source)) for signal, source in _DIAG_SIGNALS))
