"""Calibration by name: values in physical units, their memory layout, limits, fix overrides, datasets.

Public names are imported on first use (``import workbench.calib`` loads no numpy).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.calib.values": ("Axis", "CalValue"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.calib.values import Axis, CalValue
