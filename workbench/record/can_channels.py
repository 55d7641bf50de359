"""CAN frames as MDF channels: decoded with a DBC (one group per message) and raw (ASAM MDF bus logging).

Decoded: each DBC message is a channel group named after it; each signal a channel holding the
raw value from the frame with the DBC's scaling as a linear conversion and its ``VAL_`` table as
a value-to-text conversion (the scaling as the default for values the table does not name), the
unit and the comment. Multiplexed messages are left to the bus log (their signals come and go
with the multiplexer); :attr:`CanMessageGroups.multiplexed` names them.

Raw: one channel group with the composed channel ``CAN_DataFrame`` (``.BusChannel``, ``.ID``,
``.IDE``, ``.DLC``, ``.DataLength``, ``.DataBytes``, ``.Dir``, ``.EDL``, ``.BRS``, ``.ESI``) and the
bus-event flags, as the ASAM MDF bus logging standard names them and python-can's MF4Writer
(``can.io.mf4``) writes them: asammdf's ``MDF.extract_bus_logging`` and CANape decode it with any
DBC, python-can's MF4Reader plays it back. Error and remote frames are counted, not logged.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from workbench.can.model import step_decimals
from workbench.record.mdf_stream import ChannelSpec, GroupSpec, SourceSpec

__all__ = ["CanMessageGroups", "RawCanGroup", "can_frame_dtype"]


def can_frame_dtype(data_bytes: int = 8) -> np.dtype:
    """One CAN_DataFrame record: ``data_bytes`` 8 for classic CAN, 64 for CAN FD."""
    return np.dtype([("CAN_DataFrame.BusChannel", "<u1"), ("CAN_DataFrame.ID", "<u4"), ("CAN_DataFrame.IDE", "<u1"),
                     ("CAN_DataFrame.DLC", "<u1"), ("CAN_DataFrame.DataLength", "<u1"),
                     ("CAN_DataFrame.DataBytes", f"({data_bytes},)u1"), ("CAN_DataFrame.Dir", "<u1"),
                     ("CAN_DataFrame.EDL", "<u1"), ("CAN_DataFrame.BRS", "<u1"), ("CAN_DataFrame.ESI", "<u1")])


class RawCanGroup:
    """The bus log of one CAN bus, ``bus_channel`` its number in the log (CAN2: 2)."""

    def __init__(self, bus_channel: int, describe: str, *, fd: bool = False):
        self.bus_channel = bus_channel
        self.width = 64 if fd else 8
        self.dtype = can_frame_dtype(self.width)
        self._rows = np.dtype([(name, f"S{self.width}" if name.endswith("DataBytes") else self.dtype.fields[name][0])
                               for name in self.dtype.names])  # the same bytes, the data as one zero-padded string
        self.spec = GroupSpec(f"CAN{bus_channel}", (ChannelSpec("CAN_DataFrame", self.dtype),),
                              f"CAN bus logging of CAN{bus_channel} ({describe}): every data frame, raw",
                              SourceSpec(f"CAN{bus_channel}", f"CAN{bus_channel}", describe, kind="BUS", bus="CAN"))

    def records(self, frames: Sequence) -> np.ndarray:
        """python-can messages (data frames) -> CAN_DataFrame records (one pass in Python, a bus may be saturated)."""
        from can.util import len2dlc

        channel, width = self.bus_channel, self.width
        rows = [(channel, frame.arbitration_id, frame.is_extended_id, len2dlc(frame.dlc) if frame.is_fd else frame.dlc,
                 min(len(frame.data), width), bytes(frame.data), 0 if frame.is_rx else 1, frame.is_fd,
                 frame.bitrate_switch, frame.error_state_indicator) for frame in frames]
        return np.array(rows, dtype=self._rows).view(self.dtype)


class CanMessageGroups:
    """The decoded channel groups of a DBC's messages (``database``: a cantools Database)."""

    def __init__(self, database, dbc_path: str | Path, bus_name: str = "CAN2"):
        self.messages = [message for message in database.messages if not message.is_multiplexed()]
        self.multiplexed = [message.name for message in database.messages if message.is_multiplexed()]
        # the path <bus>.<message>: asammdf names a channel '<path>.<name>', as its extract_bus_logging names the
        # signal decoded from the raw log ('CAN2.PCM_TO_FLCU_002.TargetRailPressure')
        self.specs = [GroupSpec(message.name, tuple(_channel(signal) for signal in message.signals),
                                f"{bus_name} 0x{message.frame_id:X} {message.name}"
                                + (f": {message.comment}" if message.comment else ""),
                                SourceSpec(bus_name, f"{bus_name}.{message.name}", f"decoded with {dbc_path}",
                                           kind="BUS", bus="CAN"))
                      for message in self.messages]
        self.by_frame = {(message.frame_id, bool(message.is_extended_frame)): index
                         for index, message in enumerate(self.messages)}

    def index_of(self, frame) -> int | None:
        """The group of a python-can message, None when the DBC has no (plain) message for it."""
        return self.by_frame.get((frame.arbitration_id, bool(frame.is_extended_id)))

    def columns(self, index: int, frames: Sequence) -> tuple[list[int], list[np.ndarray]]:
        """(the positions in ``frames`` that decoded, one raw-value column per signal) of group ``index``."""
        from cantools.database import DecodeError

        message = self.messages[index]
        decoded, rows = [], []
        for position, frame in enumerate(frames):
            try:
                rows.append(message.decode(bytes(frame.data), decode_choices=False, scaling=False))
            except (DecodeError, ValueError, KeyError):  # a frame shorter than the message: in the bus log only
                continue
            decoded.append(position)
        return decoded, [np.array([row[signal.name] for row in rows], dtype=_dtype(signal)) for signal in message.signals]


def _dtype(signal) -> np.dtype:
    if signal.is_float:
        return np.dtype(f"<f{signal.length // 8}")
    size = next(size for size in (1, 2, 4, 8) if signal.length <= 8 * size)
    return np.dtype(f"<{'i' if signal.is_signed else 'u'}{size}")


def _channel(signal) -> ChannelSpec:
    scaling = None if (signal.scale, signal.offset) == (1, 0) else {"a": float(signal.scale), "b": float(signal.offset)}
    conversion = scaling
    if signal.choices:
        conversion = {"default_addr": scaling or {"a": 1.0, "b": 0.0}}
        for i, (raw, text) in enumerate(signal.choices.items()):
            conversion[f"val_{i}"], conversion[f"text_{i}"] = float(raw), str(text)
    decimals = None if signal.choices or signal.is_float else step_decimals(signal.scale, signal.offset)
    return ChannelSpec(signal.name, _dtype(signal), signal.unit or "", signal.comment or "", conversion, decimals)
