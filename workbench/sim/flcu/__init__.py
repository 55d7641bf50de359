"""The FLCU demo application in Python: the simulated ECU's twin of the C code in ``assets/ecu``."""

from workbench.sim.flcu.application import FlcuApplication
from workbench.sim.flcu.hardware import (
    ANIN_MANIFOLD,
    ANIN_RAIL,
    ANIN_TANK1,
    ANIN_TANK2,
    DOUT_LED,
    DOUT_OTV1,
    DOUT_OTV2,
    PWMOUT_PRV,
    CanRxStatus,
    DiagStatus,
    Hardware,
    RxPduInfo,
    TankCtrlState,
)
from workbench.sim.flcu.variables import Variables

__all__ = [
    "ANIN_MANIFOLD",
    "ANIN_RAIL",
    "ANIN_TANK1",
    "ANIN_TANK2",
    "DOUT_LED",
    "DOUT_OTV1",
    "DOUT_OTV2",
    "PWMOUT_PRV",
    "CanRxStatus",
    "DiagStatus",
    "FlcuApplication",
    "Hardware",
    "RxPduInfo",
    "TankCtrlState",
    "Variables",
]
