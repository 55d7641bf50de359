"""Calibration by name: values in physical units, their memory layout, limits, fix overrides, datasets.

Public names are imported on first use (``import workbench.calib`` loads no numpy).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.calib.cells": ("cell_edits", "cell_span", "cell_values"),
    "workbench.calib.codec": ("read_value", "value_edits"),
    "workbench.calib.layout": ("Field", "ObjectLayout", "ResolvedLayout", "object_layout"),
    "workbench.calib.limits": ("LimitViolation", "check_cells", "check_limits"),
    "workbench.calib.memory": ("ByteEdit", "MemoryBytes", "Span", "read_spans"),
    "workbench.calib.signals": ("MeasurementCodec", "measurement_codec"),
    "workbench.calib.values": ("Axis", "CalValue"),
    "workbench.calib.writable": ("check_inside", "checked_cells", "checked_value", "writable_spans"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.calib.cells import cell_edits, cell_span, cell_values
    from workbench.calib.codec import read_value, value_edits
    from workbench.calib.layout import Field, ObjectLayout, ResolvedLayout, object_layout
    from workbench.calib.limits import LimitViolation, check_cells, check_limits
    from workbench.calib.memory import ByteEdit, MemoryBytes, Span, read_spans
    from workbench.calib.signals import MeasurementCodec, measurement_codec
    from workbench.calib.values import Axis, CalValue
    from workbench.calib.writable import check_inside, checked_cells, checked_value, writable_spans
