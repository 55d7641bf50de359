"""DAQ samples as MDF channels: one channel group per DAQ event, one channel per signal (and array element).

A group's master ``time`` is the ECU's DAQ timestamp (s, see :mod:`workbench.record.timebase`), or the
master's receive time when the ECU sends no timestamps (the group's comment says which);
``HostTime_<event>`` keeps the host clock of each sample (s since the epoch: the ECU time mapped
onto the host's), so the recording can be aligned with anything else the host recorded.

Each signal is stored as the ECU sent it, bit field taken out (BIT_MASK, BIT_OPERATION), with
its COMPU_METHOD as an MDF conversion where one maps (:mod:`workbench.record.conversions`),
named as in the A2L, with its unit, its long identifier as comment and its display format's decimals as the
channel's precision (asammdf, CANape and the window's offline view show as many). Arrays (MATRIX_DIM) are
one channel per element, ``name[i]`` (``name[x][y]`` ...): every MDF reader plots and exports
scalar channels, CANape lists A2L arrays element by element the same way, and asammdf reads a
conversion on every element; asammdf's array channels (CA blocks) carry one conversion for all
elements poorly and most tools show them only as a whole.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass

import numpy as np

from workbench.a2l.display_format import format_parts
from workbench.calib import rawtypes
from workbench.calib.signals import MeasurementCodec
from workbench.record.conversions import MdfEncoding, mdf_encoding
from workbench.record.mdf_stream import ChannelSpec, GroupSpec, SourceSpec
from workbench.xcp.daq import DaqBatch

__all__ = ["DaqGroup"]

_FLOAT64 = np.dtype("<f8")


@dataclass(frozen=True)
class _Stored:
    """One signal as the group stores it."""

    codec: MeasurementCodec
    encoding: MdfEncoding
    dtype: np.dtype  # of each element channel
    element_names: tuple[str, ...]


class DaqGroup:
    """The channel group of one DAQ event: its :attr:`spec` and the columns of a :class:`DaqBatch`."""

    def __init__(self, event: int, event_name: str, period_s: float | None, codecs: Sequence[MeasurementCodec],
                 source: SourceSpec | None = None, encodings: dict | None = None, *, ecu_timestamps: bool = True):
        self.event, self.event_name, self.period_s = event, event_name, period_s
        self.signals = [_stored(codec, encodings if encodings is not None else {}) for codec in codecs]
        self.host_time_name = f"HostTime_{event_name}"
        host_time = ("the ECU's timestamp mapped onto the host's clock" if ecu_timestamps
                     else "its receive time (the ECU sends no DAQ timestamps)")
        channels = [ChannelSpec(self.host_time_name, _FLOAT64, "s",
                                f"host clock of each sample, s since 1970-01-01 UTC: {host_time}")]
        for signal in self.signals:
            channels += [ChannelSpec(name, signal.dtype, _unit(signal), _comment(signal), signal.encoding.conversion,
                                     _decimals(signal)) for name in signal.element_names]
        cycle = f", every {period_s * 1e3:g} ms" if period_s else ""
        clock = "the ECU's DAQ timestamps" if ecu_timestamps else "the master's receive time (no DAQ timestamps)"
        self.spec = GroupSpec(event_name, tuple(channels),
                              f"XCP DAQ event {event} {event_name}{cycle}: {len(self.signals)} signals, timed by {clock}",
                              source)

    @property
    def names(self) -> list[str]:
        return [signal.codec.name for signal in self.signals]

    def columns(self, batch: DaqBatch) -> list[np.ndarray]:
        """The channels' values of ``batch``'s samples, in :attr:`spec` order (host time first)."""
        count = len(batch)
        columns = [np.asarray(batch.host_time, dtype=np.float64)]
        for signal in self.signals:
            raw = conversion_input(signal.codec, signal.codec.raw(batch.column(signal.codec.name).tobytes(), count))
            values = signal.codec.conversion.to_physical(raw) if signal.encoding.physical else raw
            flat = np.asarray(values).reshape(count, -1).astype(signal.dtype, copy=False)
            columns += [flat[:, element] for element in range(flat.shape[1])]
        return columns

    def physical(self, batch: DaqBatch, names: Collection[str] | None = None) -> dict[str, np.ndarray]:
        """name -> physical values, shape (samples,) or (samples, *shape), as a DAQ measurement gives them (of
        ``names`` only, when given)."""
        return {signal.codec.name: np.asarray(signal.codec.decode_samples(batch.column(signal.codec.name).tobytes(),
                                                                          len(batch)))
                for signal in self.signals if names is None or signal.codec.name in names}


def conversion_input(codec: MeasurementCodec, raw: np.ndarray) -> np.ndarray:
    """The value the COMPU_METHOD takes: the raw elements, bit field extracted (BIT_MASK, BIT_OPERATION)."""
    measurement = codec.measurement
    if measurement.bit_mask is None and measurement.bit_operation is None:
        return raw
    mask = measurement.bit_mask if measurement.bit_mask is not None else (1 << (8 * codec.element_size)) - 1
    return rawtypes.extract_bits(raw, mask, codec.datatype, measurement.bit_operation)


def _stored(codec: MeasurementCodec, encodings: dict) -> _Stored:
    """How ``codec``'s signal is stored; ``encodings`` caches the conversion checks by (method, raw dtype)."""
    measurement = codec.measurement
    raw_dtype = rawtypes.numpy_dtype(codec.datatype, "MSB_LAST")  # stored little-endian, whatever the ECU's order
    if measurement.bit_operation is not None:  # shifted as it says, maybe beyond the element's type: int64
        raw_dtype = conversion_input(codec, np.zeros(1, raw_dtype)).dtype
    # a BIT_MASK alone: the field moved down to bit 0 fits the element's own type (a flag of a UBYTE stays 1 byte)
    key = (codec.conversion.name, raw_dtype.str)
    if key not in encodings:
        encodings[key] = mdf_encoding(codec.conversion, raw_dtype)
    encoding = encodings[key]
    dtype = _FLOAT64 if encoding.physical else raw_dtype
    if codec.shape:
        names = tuple(codec.name + "".join(f"[{i}]" for i in index) for index in np.ndindex(*codec.shape))
    else:
        names = (codec.name,)
    return _Stored(codec, encoding, dtype, names)


def _physical(signal: _Stored) -> bool:
    """False for raw values of a conversion that could not be carried (readers see no physical values)."""
    encoding = signal.encoding
    return encoding.conversion is not None or encoding.physical or signal.codec.conversion.conversion_type == "IDENTICAL"


def _unit(signal: _Stored) -> str:
    return signal.codec.unit if _physical(signal) else ""


def _decimals(signal: _Stored) -> int | None:
    """The A2L's display format (the MEASUREMENT's FORMAT, else its COMPU_METHOD's), as the window shows it
    live; none for a verbal value (its texts) or for raw values of a conversion that could not be carried."""
    if signal.codec.verbal or not _physical(signal):
        return None
    measurement = signal.codec.measurement
    return format_parts(measurement.format)[1] if measurement.format else signal.codec.conversion.decimals


def _comment(signal: _Stored) -> str:
    text = signal.codec.measurement.long_identifier
    return f"{text} ({signal.encoding.note})" if signal.encoding.note else text
