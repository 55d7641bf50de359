"""MDF4 recording (asammdf): DAQ signals, CAN2 frames decoded with a DBC and the raw CAN bus, streamed to disk.

* :mod:`~workbench.record.recorder` — :class:`Recorder` (non-blocking, a context manager) and
  :func:`record` (for a duration); :class:`RecordingStats`;
* :mod:`~workbench.record.mdf_stream` — :class:`MdfStreamWriter`: an MDF4 file readable after every flush;
  :func:`finalize` for a file whose recording was killed, :func:`contents` what a file holds;
* :mod:`~workbench.record.daq_channels` — DAQ events as channel groups (A2L names, units, conversions);
* :mod:`~workbench.record.conversions` — COMPU_METHODs as MDF conversions, checked against asammdf;
* :mod:`~workbench.record.can_channels` — DBC messages as channel groups, and ASAM bus logging;
* :mod:`~workbench.record.timebase` — one time axis for ECU samples and host-stamped frames;
* :mod:`~workbench.record.trigger` — start and stop conditions, the seconds kept from before the start.

The names are imported on first use: ``import workbench.record`` loads neither asammdf nor python-can.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.record.recorder": ("CAN2_BUS_CHANNEL", "Recorder", "RecordingStats", "record"),
    "workbench.record.mdf_stream": ("ChannelSpec", "GroupContents", "GroupSpec", "HeaderSpec", "MdfStreamWriter",
                                    "SourceSpec", "contents", "finalize"),
    "workbench.record.conversions": ("MdfEncoding", "mdf_encoding"),
    "workbench.record.trigger": ("Condition", "Trigger"),
}
__all__, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.record.conversions import MdfEncoding, mdf_encoding
    from workbench.record.mdf_stream import (ChannelSpec, GroupContents, GroupSpec, HeaderSpec, MdfStreamWriter,
                                             SourceSpec, contents, finalize)
    from workbench.record.recorder import CAN2_BUS_CHANNEL, Recorder, RecordingStats, record
    from workbench.record.trigger import Condition, Trigger
