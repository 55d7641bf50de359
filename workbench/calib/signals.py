"""A MEASUREMENT's bytes and raw values made physical, for one sample or a million.

::

    codec = measurement_codec(model, "zsRailPressure")
    codec.span                              # where to read it (address, size, extension)
    codec.decode(data)                      # one sample's bytes -> physical (scalar or array)
    codec.to_physical(raw_array)            # raw values of many samples (any shape) -> physical
    codec.decode_samples(buffer, count)     # count consecutive samples' bytes -> physical array

The raw value is the element as the data type holds it (what the DAQ decoder unpacks with
``codec.dtype``); :meth:`MeasurementCodec.to_physical` applies the BIT_MASK (and BIT_OPERATION:
see :func:`workbench.calib.rawtypes.extract_bits`), then the COMPU_METHOD, vectorized. Arrays
(MATRIX_DIM, ARRAY_SIZE) come out in their shape, X first, in the memory order their LAYOUT
gives (ROW_DIR, the default: C order; COLUMN_DIR: Fortran order, as in
:mod:`workbench.calib.layout`).
"""

from __future__ import annotations

from math import prod
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.objects import Measurement
from workbench.calib import rawtypes
from workbench.calib.memory import Span
from workbench.errors import ConversionError

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel

__all__ = ["MeasurementCodec", "measurement_codec"]


def measurement_codec(model: "A2lModel", measurement: "str | Measurement") -> "MeasurementCodec":
    """The codec of a MEASUREMENT (by name or object).

    :raises UnknownSymbolError: no such measurement. :raises A2lParseError: its COMPU_METHOD is
        missing or malformed (located).
    """
    if isinstance(measurement, str):
        measurement = model.measurement(measurement)
    return MeasurementCodec(model, measurement)


class MeasurementCodec:
    """How one MEASUREMENT is read: data type, byte order, bit mask, shape, conversion."""

    def __init__(self, model: "A2lModel", measurement: Measurement):
        self.measurement = measurement
        self.name = measurement.name
        self.conversion = model.conversion(measurement)
        self.unit = model.unit_of(measurement)
        self.datatype = measurement.datatype
        self.byte_order = measurement.byte_order
        self.element_size = rawtypes.element_size(self.datatype)
        self.shape: tuple[int, ...] = measurement.shape
        self.count = prod(self.shape) if self.shape else 1
        self.size = self.count * self.element_size  # bytes of one sample
        self.order = "F" if measurement.layout == "COLUMN_DIR" else "C"
        self.dtype: np.dtype | None = rawtypes.numpy_dtype(self.datatype, self.byte_order)  # None: word-swapped
        self.verbal = self.conversion.verbal

    def __repr__(self) -> str:
        return f"<MeasurementCodec {self.name} {self.datatype}{list(self.shape) if self.shape else ''}>"

    @property
    def span(self) -> Span:
        """Where one sample lies. :raises ConversionError: a virtual measurement (no ECU_ADDRESS)."""
        if self.measurement.address is None:
            raise ConversionError(f"MEASUREMENT {self.name} has no ECU_ADDRESS (virtual): nothing to read")
        return Span(self.measurement.address, self.size, self.measurement.address_extension)

    def raw(self, data: bytes, samples: int | None = None) -> np.ndarray:
        """The raw elements in ``data``: one sample (``samples`` None) shaped like the MEASUREMENT, or
        ``samples`` consecutive samples shaped ``(samples, *shape)``. :raises ConversionError: too few bytes."""
        count = 1 if samples is None else samples
        values = rawtypes.decode(bytes(data), self.datatype, self.byte_order, count * self.count)
        if self.order == "C" or len(self.shape) < 2:
            values = values.reshape((count, *self.shape))
        else:  # Fortran order of each sample: C order of the reversed shape, axes turned back
            values = values.reshape((count, *self.shape[::-1])).transpose((0, *range(len(self.shape), 0, -1)))
        return values[0] if samples is None else values

    def to_physical(self, raw: Any) -> Any:
        """Raw values (a number or an array of any shape) -> physical, element by element: BIT_MASK /
        BIT_OPERATION, then the COMPU_METHOD. A scalar gives a Python number (or text)."""
        measurement = self.measurement
        if measurement.bit_mask is not None or measurement.bit_operation is not None:
            scalar = np.ndim(raw) == 0
            raw = rawtypes.extract_bits(np.asarray(raw), measurement.bit_mask if measurement.bit_mask is not None
                                        else (1 << (8 * self.element_size)) - 1, self.datatype,
                                        measurement.bit_operation)
            if scalar:
                raw = raw.reshape(()).item()
        return self.conversion.to_physical(raw)

    def decode(self, data: bytes) -> Any:
        """One sample's bytes -> its physical value (a number or text, or an array of the MEASUREMENT's shape)."""
        raw = self.raw(data)
        return self.to_physical(raw.reshape(()).item() if not self.shape else raw)

    def decode_samples(self, data: bytes, samples: int) -> np.ndarray:
        """``samples`` consecutive samples' bytes -> physical values, shape ``(samples, *shape)``."""
        return np.asarray(self.to_physical(self.raw(data, samples)))
