"""A measurement file for analysis without an ECU: every plottable channel of an MDF file (ours, or any
other that asammdf reads) as the plots take them - time, value, unit, the texts of a verbal
channel (kept as their numbers, so they plot as steps) and the decimals to show: the channel's own
precision where it has one (our recordings carry the A2L's FORMAT, as CANape's do), else as many as its
range needs (never the floats' full repr). Plain asammdf, no Qt: run in a worker.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from workbench.errors import InputError
from workbench.gui.formatting import range_decimals

__all__ = ["FileChannel", "read_measurement_file"]


@dataclass(frozen=True)
class FileChannel:
    name: str  # unique in the file: the channel's name, its group's added where two groups have one
    unit: str
    comment: str
    times: np.ndarray  # seconds, the file's time axis
    values: np.ndarray  # float64
    states: tuple[tuple[float, str], ...] = ()  # raw number -> text of a verbal channel
    decimals: int | None = None  # shown: the channel's precision (our recorder's: the A2L's FORMAT), else by range


def read_measurement_file(path: str | Path) -> list[FileChannel]:
    """The channels of ``path`` that hold one number (or one text) per sample; arrays and bus-logging
    structures are left out.

    :raises InputError: the file is missing or is no measurement file asammdf can read.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    from asammdf import MDF

    try:
        mdf = MDF(path)
    except Exception as exc:  # noqa: BLE001 - asammdf raises anything on a file that is not MDF
        raise InputError(f"{path}: not a measurement file asammdf reads: {exc}") from None
    with mdf:
        found = []
        for group_index, group in enumerate(mdf.groups):
            acquisition = getattr(group.channel_group, "acq_name", "") or f"group {group_index}"
            master = mdf.masters_db.get(group_index)
            for channel_index, channel in enumerate(group.channels):
                if channel_index == master:
                    continue
                signal = mdf.get(group=group_index, index=channel_index, raw=True)
                channel_found = _channel(mdf, signal, group_index, channel_index)
                if channel_found is not None:
                    found.append((acquisition, channel_found))
    counts: dict[str, int] = {}
    for _, channel in found:
        counts[channel.name] = counts.get(channel.name, 0) + 1
    return [channel if counts[channel.name] == 1 else _renamed(channel, f"{acquisition}.{channel.name}")
            for acquisition, channel in found]


def _channel(mdf, raw, group: int, index: int) -> FileChannel | None:
    samples = raw.samples
    if samples.ndim != 1 or samples.dtype.names or samples.dtype.kind not in "iufb":
        return None
    values = samples.astype(np.float64)
    states: tuple[tuple[float, str], ...] = ()
    physical = mdf.get(group=group, index=index).samples
    if physical.dtype.kind in "SUO":  # a verbal conversion: remember which number is which text
        pairs = {}
        for number, text in zip(values.tolist(), physical.tolist()):
            pairs.setdefault(number, text.decode("latin-1") if isinstance(text, bytes) else str(text))
        states = tuple(sorted(pairs.items()))
    elif physical.dtype.kind in "iufb" and physical.ndim == 1:
        values = physical.astype(np.float64)
    comment = raw.comment if isinstance(raw.comment, str) else ""
    decimals = _precision(mdf.groups[group].channels[index])
    if decimals is None and not states:
        decimals = range_decimals(values)
    return FileChannel(raw.name, raw.unit or "", comment, np.asarray(raw.timestamps, dtype=np.float64), values,
                       states, decimals)


def _precision(channel) -> int | None:
    """The display precision an MDF 4 channel carries (cn_precision, when its flag says it is valid)."""
    from asammdf.blocks import v4_constants as v4c

    flags, precision = getattr(channel, "flags", 0), getattr(channel, "precision", 0xFF)
    if isinstance(flags, int) and flags & v4c.FLAG_CN_PRECISION and precision != 0xFF:
        return int(precision)
    return None


def _renamed(channel: FileChannel, name: str) -> FileChannel:
    return dataclasses.replace(channel, name=name)
