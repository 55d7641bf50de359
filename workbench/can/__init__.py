"""CAN databases (cantools): CAN2 decode/encode, fix-calibration names, code generation."""

from workbench.can.naming import (
    fix_enable_name,
    fix_value_name,
    raw_c_type,
    rx_signal_name,
    tx_enable_name,
)

__all__ = ["fix_enable_name", "fix_value_name", "raw_c_type", "rx_signal_name", "tx_enable_name"]
