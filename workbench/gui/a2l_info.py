"""What the views need to know about an A2L object, read from the typed A2L model."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from workbench.a2l.datatypes import DATATYPES
from workbench.a2l.display_format import format_parts
from workbench.a2l.model import axis_decimals, value_decimals
from workbench.calib.rawtypes import extract_bits
from workbench.errors import InputError, WorkbenchError
from workbench.gui.formatting import format_value
from workbench.gui.signal_hub import SignalInfo

__all__ = ["CalibrationInfo", "axis_decimals", "axis_inputs", "calibration_info", "measurement_info", "two_states",
           "value_decimals", "verbal_states"]



def verbal_states(model, obj) -> tuple[tuple[float, str], ...]:
    """(raw, text) of a TAB_VERB conversion, () for any other."""
    conversion = model.conversion(obj)
    if not getattr(conversion, "verbal", False):
        return ()
    return tuple((raw, text) for text, raw in conversion.raw_of.items())


def two_states(model, measurement) -> tuple[tuple[float, str], ...]:
    """The two values of a two-state MEASUREMENT without texts, labelled as the numbers they are: an integer one
    whose limits are 0 .. 1 under an identical conversion (a flag), or one whose BIT_MASK is a single bit (its two
    values as the session decodes them: BIT_OPERATION, then the conversion, IDENTICAL or LINEAR). () for any
    other: a verbal one has its texts (:func:`verbal_states`), an array or a float is no flag."""
    conversion = model.conversion(measurement)
    if measurement.shape or conversion.conversion_type not in ("IDENTICAL", "LINEAR"):
        return ()
    mask = measurement.bit_mask
    if mask is not None and mask > 0 and mask & (mask - 1) == 0:
        raw = extract_bits(np.array([0, mask]), mask, measurement.datatype, measurement.bit_operation)
    elif (mask is None and measurement.bit_operation is None and DATATYPES.get(measurement.datatype, ("", ""))[1]
          in ("signed", "unsigned") and (measurement.lower_limit, measurement.upper_limit) == (0, 1)):
        raw = np.array([0, 1])
    else:
        return ()
    values = np.asarray(conversion.to_physical(raw.astype(np.float64)), dtype=np.float64)
    if (mask is None and not np.array_equal(values, [0.0, 1.0])) or values[0] == values[1]:
        return ()  # limits 0 .. 1 of a scaled value: more than two values; a bit scaled by 0: one
    return tuple((float(v), format_value(float(v))) for v in sorted(values))  # "0" and "1", not "0.000"


def measurement_info(model, name: str) -> SignalInfo | None:
    """The :class:`SignalInfo` of MEASUREMENT ``name``, None when the A2L has no such measurement."""
    try:
        measurement = model.measurement(name)
        conversion = model.conversion(measurement)
        unit = model.unit_of(measurement)
    except (WorkbenchError, KeyError):
        return None
    decimals = format_parts(measurement.format)[1] if measurement.format else conversion.decimals
    states = verbal_states(model, measurement)
    return SignalInfo(name, "XCP", unit, measurement.long_identifier, measurement.lower_limit,
                      measurement.upper_limit, states, decimals,
                      two_states=() if states else two_states(model, measurement))


@dataclass(frozen=True)
class CalibrationInfo:
    """A CHARACTERISTIC (or AXIS_PTS) as an editor shows it."""

    name: str
    type: str  # VALUE, CURVE, MAP, VAL_BLK, ASCII, AXIS_PTS
    description: str
    unit: str
    limits: tuple[float, float]
    decimals: int | None
    states: tuple[str, ...]  # the texts of a verbal value
    writable: bool
    axis_labels: tuple[str, ...]  # "target [bar]" per axis, X first
    functions: tuple[str, ...]
    extended_limits: tuple[float, float] | None = None  # the A2L's EXTENDED_LIMITS
    axis_decimals: tuple[int | None, ...] = ()  # the decimals of each axis' points, X first
    axis_quantities: tuple[tuple[str, str], ...] = ()  # (input quantity, unit) of each axis, X first
    axis_inputs: tuple[str | None, ...] = ()  # the MEASUREMENT each axis' input is (its operating point), X first
    # the AXIS_PTS and CURVE_AXIS curves whose bytes the value shows (COM_AXIS, RES_AXIS, CURVE_AXIS): a write of one
    # changes what the other's editor shows
    shares: tuple[str, ...] = ()


def axis_inputs(model, obj) -> tuple[str | None, ...]:
    """The MEASUREMENT that is each axis' input, X first: the AXIS_DESCR's INPUT_QUANTITY, else (a COM_AXIS) its
    AXIS_PTS'; None where there is none or it names no MEASUREMENT of the A2L."""
    inputs = []
    for axis in getattr(obj, "axes", ()):
        name = axis.input_quantity
        try:
            if name is None and axis.axis_pts_ref:
                name = model.axis_pts(axis.axis_pts_ref).input_quantity
            inputs.append(name if name is not None and model.kind_of(name) == "MEASUREMENT" else None)
        except (WorkbenchError, KeyError):
            inputs.append(None)
    return tuple(inputs)


_BEYOND_MAPS = ("CUBOID", "CUBE_4", "CUBE_5")  # the editors show one or two dimensions


def calibration_info(model, name: str) -> CalibrationInfo:
    """:raises UnknownSymbolError: no such CHARACTERISTIC/AXIS_PTS; :raises A2lParseError: a broken reference;
    :raises InputError: an object of more than two dimensions (a CUBOID, a VAL_BLK of MATRIX_DIM 2 3 4), which the
    editors cannot show (the message says how to read and write it)."""
    kind = model.kind_of(name)
    obj = model.characteristic(name) if kind == "CHARACTERISTIC" else model.axis_pts(name)
    kind_text = getattr(obj, "type", "AXIS_PTS")
    if kind_text in _BEYOND_MAPS or sum(size > 1 for size in getattr(obj, "matrix_dim", ()) or ()) > 2:
        shape = f" of MATRIX_DIM {' '.join(map(str, obj.matrix_dim))}" if kind_text == "VAL_BLK" else ""
        raise InputError(f"{name} is a {kind_text}{shape}: the window's editors show values, curves, maps and "
                         f"blocks of up to two dimensions; read it with `workbench cal get {name}` and write it with "
                         f"`workbench cal set {name} --from FILE.json`")
    conversion = model.conversion(obj)
    decimals = format_parts(obj.format)[1] if obj.format else conversion.decimals
    quantities = tuple((axis.input_quantity or axis.axis_pts_ref or axis.axis, model.unit_of(axis))
                       for axis in getattr(obj, "axes", ()))
    labels = [f"{quantity} [{unit}]" if unit else quantity for quantity, unit in quantities]
    states = tuple(conversion.allowed) if getattr(conversion, "verbal", False) else ()
    return CalibrationInfo(name, getattr(obj, "type", "AXIS_PTS"), obj.long_identifier, model.unit_of(obj),
                           (obj.lower_limit, obj.upper_limit), decimals, states,
                           obj.writable, tuple(labels), obj.functions, getattr(obj, "extended_limits", None),
                           tuple(axis_decimals(model, axis) for axis in getattr(obj, "axes", ())), quantities,
                           axis_inputs(model, obj),
                           tuple(ref for axis in getattr(obj, "axes", ()) for ref in (axis.axis_pts_ref, axis.curve_axis_ref)
                                 if ref))
