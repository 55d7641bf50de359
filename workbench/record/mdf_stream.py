"""An MDF4 file written as a stream: readable after every flush, also when the writer is killed.

asammdf's own writer keeps the data in a temporary file until ``save()`` builds the MDF, so a
killed recording leaves nothing. Here asammdf writes the file's *skeleton* — identification,
header, file history, one data group per channel group with its channels, conversions, texts and
sources, no data — and :class:`MdfStreamWriter` appends the samples to it:

* each :meth:`~MdfStreamWriter.flush` writes, per group with new records, one data block (DZ,
  transposed deflate, or DT) and a one-entry DL (variable length: the block's offset in the
  group's data) at the end of the file, and links them in: DG → HL → DL → DL → … (the HL, which
  MDF 4.1 asks for in front of DZ blocks, only when compressing; DG → DL → … otherwise);
* the new blocks are written and synced (``fsync``) *before* the link that makes them reachable
  and the channel group's cycle counter are patched in place (8 bytes each), so a block is never
  linked before it is complete, and blocks of a flush that was cut short are unreachable bytes at
  the end, which readers skip;
* while it is written the file says so, as MDF 4.1 provides for loggers: identification
  ``UnFinMF`` with the flag "cycle counters to be updated", because a kill between the link and
  the counter of a group leaves one counter behind its data. asammdf (and so python-can's MF4
  reader) reads such a file and counts the records from the data; :meth:`~MdfStreamWriter.close`
  marks the file finalized (``MDF``), and :func:`finalize` does the same in place for a file whose
  writer was killed, for tools that read finalized files only. A kill loses at most what came
  after the last flush.

Records are laid out as asammdf put the channels in the skeleton (read back from it, never
assumed): the master channel ``time`` (float64 s) first, then each channel at its byte offset.
"""

from __future__ import annotations

import copy
import os
import re
import struct
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from workbench.errors import InputError, WorkbenchError
from workbench.fileio import unreadable
from workbench.logs import logger

log = logger(__name__)

__all__ = ["ChannelSpec", "GroupContents", "GroupSpec", "HeaderSpec", "MdfStreamWriter", "SourceSpec", "contents",
           "finalize"]

MDF_VERSION = "4.11"
COMPRESSION_LEVEL = 1  # zlib: level 1 already shrinks DAQ records 4-10x (transposed), higher costs far more time
_HD_ADDRESS = 0x40
_U64 = struct.Struct("<Q")
_FINALIZED, _UNFINALIZED = b"MDF     ", b"UnFinMF "
_UNFINALIZED_FLAGS_AT = 60  # the identification block's id_unfin_flags (u16)
_UPDATE_CYCLE_COUNTERS = 0x01


@dataclass(frozen=True)
class ChannelSpec:
    """One channel: ``dtype`` of the stored values (a structured dtype makes a composed channel, as
    ASAM bus logging's ``CAN_DataFrame``), ``conversion`` an asammdf conversion dictionary, ``decimals``
    the physical value's display precision (the channel's cn_precision; None: not given)."""

    name: str
    dtype: np.dtype
    unit: str = ""
    comment: str = ""
    conversion: dict | None = None
    decimals: int | None = None


@dataclass(frozen=True)
class SourceSpec:
    """A channel group's acquisition source (MDF SI block): ``kind`` "ECU", "BUS" or "TOOL";
    ``bus`` "CAN", "ETHERNET" or "NONE"."""

    name: str
    path: str
    comment: str = ""
    kind: str = "ECU"
    bus: str = "NONE"


@dataclass(frozen=True)
class GroupSpec:
    """One channel group: its acquisition name (the DAQ event, the CAN message), channels after the master."""

    acq_name: str
    channels: tuple[ChannelSpec, ...]
    comment: str = ""
    source: SourceSpec | None = None


# characters XML 1.0 cannot hold (an ECU's EPK of NUL bytes, say): ElementTree writes them, every reader refuses them
_XML_FORBIDDEN = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _escaped(match: re.Match) -> str:
    return f"\\x{ord(match.group()):02x}"


@dataclass(frozen=True)
class HeaderSpec:
    """The file header: ``description`` its text, ``properties`` the common properties (name -> text);
    ``history`` what the file history's entry says was done (its tool: the workbench)."""

    description: str = ""
    author: str = ""
    project: str = ""
    subject: str = ""
    properties: dict[str, str] = field(default_factory=dict)
    history: str = "created"

    def xml(self) -> str:
        """The header comment as MDF4 has it: ``<HDcomment>`` with ``<TX>`` and ``<common_properties>``."""
        root = ElementTree.Element("HDcomment")
        ElementTree.SubElement(root, "TX").text = self.description
        common = ElementTree.SubElement(root, "common_properties")
        named = {"author": self.author, "project": self.project, "subject": self.subject, **self.properties}
        for name, value in named.items():
            if value:
                ElementTree.SubElement(common, "e", name=name).text = _XML_FORBIDDEN.sub(_escaped, value)
        return ElementTree.tostring(root, encoding="unicode")

    def history_xml(self) -> str:
        """The file history entry (FH block comment): what was done, by which tool and user. A viewer's file
        info (CANape, asammdf, MATLAB's mdfInfo) names the workbench as the tool that wrote the file."""
        from workbench import __version__

        root = ElementTree.Element("FHcomment")
        for tag, text in (("TX", self.history), ("tool_id", "workbench"), ("tool_vendor", "workbench"),
                          ("tool_version", __version__), ("user_name", self.author)):
            if text:
                ElementTree.SubElement(root, tag).text = text
        return ElementTree.tostring(root, encoding="unicode")


@dataclass
class _GroupState:
    dtype: np.dtype  # one record
    data_link_at: int  # where the DG's data link lies
    cycles_at: int  # where the CG's cycle counter lies
    pending: list[bytes] = field(default_factory=list)
    pending_records: int = 0
    records: int = 0  # written and linked
    data_bytes: int = 0  # uncompressed bytes written and linked
    last_link_at: int | None = None  # the link the next DL goes into (None: the DG's data link)


class MdfStreamWriter:
    """Append records to the groups of a new MDF4 file at ``path`` (see the module docstring).

    ``compress``: DZ blocks (transposed deflate) instead of DT. ``start_time``: the header's start
    time (s since the epoch; default now), which the groups' ``time`` channels count from.

    :raises OSError: ``path`` cannot be created. :raises WorkbenchError: asammdf laid out a channel
        otherwise than the writer can fill.
    """

    def __init__(self, path: str | Path, groups: Sequence[GroupSpec], header: HeaderSpec | None = None, *,
                 compress: bool = True, start_time: float | None = None):
        self.path = Path(path)
        self.compress = compress
        self.specs = tuple(groups)
        self._write_skeleton(header or HeaderSpec(), start_time)
        self._states = self._layout()
        self._file = open(self.path, "r+b")
        self._hd_time_at = _HD_ADDRESS + 24 + 8 * self._read_u64(_HD_ADDRESS + 16)
        self.file_bytes = self._file.seek(0, os.SEEK_END)  # as of the last flush
        self.closed = False

    # --- the skeleton -------------------------------------------------------------------------

    def _write_skeleton(self, header: HeaderSpec, start_time: float | None) -> None:
        """asammdf writes every block but the data, to a temporary name first: the file at ``path``
        is complete from its first moment."""
        from asammdf import MDF, Signal, Source
        from asammdf.blocks.v4_blocks import FileHistory

        mdf = MDF(version=MDF_VERSION)
        mdf.header.start_time = _local_time(start_time)
        mdf.header.comment = header.xml()
        history = FileHistory()
        history.comment = header.history_xml()
        mdf.file_history.append(history)  # instead of asammdf's own "created" entry, which names asammdf
        for spec in self.specs:
            source = spec.source
            acq_source = None if source is None else Source(source.name, source.path, source.comment,
                                                            getattr(Source, f"SOURCE_{source.kind}"),
                                                            getattr(Source, f"BUS_TYPE_{source.bus}"))
            signals = [Signal(np.zeros(0, channel.dtype), np.zeros(0, np.float64), name=channel.name,
                              unit=channel.unit, comment=channel.comment, source=acq_source,
                              conversion=copy.deepcopy(channel.conversion))  # asammdf edits the dictionary
                       for channel in spec.channels]
            mdf.append(signals, acq_name=spec.acq_name, acq_source=acq_source, comment=spec.comment,
                       common_timebase=True)
            _set_precisions(mdf.groups[-1].channels, spec.channels)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, temporary = tempfile.mkstemp(prefix=f".{self.path.name}.", suffix=".tmp.mf4", dir=self.path.parent)
        os.close(fd)  # asammdf's save() opens it again (and would add ".mf4" to another suffix)
        try:
            mdf.save(temporary, overwrite=True, add_history_block=False)
            mdf.close()
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temporary, 0o666 & ~umask)  # a new file's usual mode, not a temporary file's 0o600
            with open(temporary, "r+b") as handle:  # unfinalized from its first moment at path: a reader that
                _mark(handle, finalized=False)  # took it for finalized would map it whole, and it grows
            os.replace(temporary, self.path)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise

    def _layout(self) -> list[_GroupState]:
        """Each group's record dtype and patch places, as asammdf wrote them."""
        from asammdf import MDF

        mdf = MDF(self.path)
        try:
            states = []
            for spec, group in zip(self.specs, mdf.groups, strict=True):
                channel_group = group.channel_group
                if group.data_group.record_id_len or channel_group.invalidation_bytes_nr:
                    raise WorkbenchError(f"{self.path}: asammdf wrote group {spec.acq_name} with record ids or "
                                         "invalidation bytes; the stream writer cannot fill it")
                names, formats, offsets = ["time"], [np.dtype("<f8")], [0]
                channels = group.channels  # the master, then the channels in order, a structure's members after it
                if channels[0].name != "time" or channels[0].byte_offset != 0:
                    raise WorkbenchError(f"{self.path}: group {spec.acq_name} has no float64 master at offset 0")
                position = 1
                for index, wanted in enumerate(spec.channels):
                    members = wanted.dtype.names or ()
                    placed = channels[position:position + 1 + len(members)]
                    start = placed[0].byte_offset if placed else -1
                    layout = [(wanted.name, start), *((m, start + wanted.dtype.fields[m][1]) for m in members)]
                    if [(channel.name, channel.byte_offset) for channel in placed] != layout:
                        raise WorkbenchError(f"{self.path}: asammdf laid out {wanted.name} of group {spec.acq_name} "
                                             "otherwise than the stream writer fills it")
                    names.append(f"c{index}")
                    formats.append(wanted.dtype)
                    offsets.append(start)
                    position += len(placed)
                dtype = np.dtype({"names": names, "formats": formats, "offsets": offsets,
                                  "itemsize": channel_group.samples_byte_nr})
                states.append(_GroupState(dtype, group.data_group.address + 24 + 16,  # after next DG, first CG
                                          channel_group.address + 24 + 8 * channel_group.links_nr + 8))
            return states
        finally:
            mdf.close()

    def _read_u64(self, address: int) -> int:
        self._file.seek(address)
        return _U64.unpack(self._file.read(8))[0]

    # --- appending ----------------------------------------------------------------------------

    def append(self, group: int, time: np.ndarray, columns: Sequence[np.ndarray]) -> None:
        """Records of ``group``: ``time`` (s from the start time) and one array per channel (its
        ``dtype``; element channels of a structure: a structured array). Kept until :meth:`flush`."""
        count = len(time)
        if not count:
            return
        state = self._states[group]
        records = np.zeros(count, state.dtype)
        records["time"] = time
        for index, column in enumerate(columns):
            records[f"c{index}"] = column
        state.pending.append(records.tobytes())
        state.pending_records += count

    @property
    def pending_bytes(self) -> int:
        return sum(len(chunk) for state in self._states for chunk in state.pending)

    def records(self, group: int) -> int:
        """Records of ``group`` on disk (flushed)."""
        return self._states[group].records

    def flush(self) -> None:
        """Write what was appended since the last flush; the file is complete when this returns.

        :raises WorkbenchError: the disk refused (full, gone); what was flushed before stays readable.
        """
        ready = [state for state in self._states if state.pending]
        if not ready:
            return
        handle = self._file
        try:
            handle.seek(0, os.SEEK_END)
            links = [(state, *self._write_blocks(state)) for state in ready]
            handle.flush()
            os.fsync(handle.fileno())  # the blocks are on disk before anything points at them
            for state, first, next_link_at, size, count in links:
                handle.seek(state.last_link_at if state.last_link_at is not None else state.data_link_at)
                handle.write(_U64.pack(first))
                state.last_link_at = next_link_at
                state.data_bytes += size
                state.records += count
                handle.seek(state.cycles_at)
                handle.write(_U64.pack(state.records))
            handle.flush()
            self.file_bytes = handle.seek(0, os.SEEK_END)
        except OSError as exc:
            raise WorkbenchError(f"{self.path}: cannot write the recording ({exc.strerror or exc})") from None

    def _write_blocks(self, state: _GroupState) -> tuple[int, int, int, int]:
        """Append the pending data as a block, a DL (and the HL of a first DZ); returns (the address to link
        in, where the next DL is linked, the data's size, the records)."""
        from asammdf.blocks import v4_constants as v4c
        from asammdf.blocks.v4_blocks import DataBlock, DataList, DataZippedBlock, HeaderList

        data = b"".join(state.pending)
        count = state.pending_records
        state.pending, state.pending_records = [], 0
        if self.compress:
            block = DataZippedBlock(data=data, zip_type=v4c.FLAG_DZ_TRANSPOSED_DEFLATE, param=state.dtype.itemsize,
                                    original_type=b"DT", compression_level=COMPRESSION_LEVEL)
        else:
            block = DataBlock(data=data, type="DT")
        block_at = self._append_block(bytes(block))
        data_list = DataList(links_nr=2, flags=0, data_block_nr=1, data_block_addr0=block_at, offset_0=state.data_bytes)
        list_at = self._append_block(bytes(data_list))
        first = list_at
        if self.compress and state.last_link_at is None:
            first = self._append_block(bytes(HeaderList(first_dl_addr=list_at, flags=0,
                                                        zip_type=v4c.FLAG_DZ_TRANSPOSED_DEFLATE)))
        return first, list_at + 24, len(data), count  # a DL's first link is its next DL

    def _append_block(self, block: bytes) -> int:
        """Write ``block`` at the end of the file, 8-byte aligned (MDF4 blocks are); returns its address."""
        handle = self._file
        address = handle.tell()
        handle.write(block)
        handle.write(b"\0" * (-len(block) % 8))
        return address

    def set_start_time(self, epoch_s: float) -> None:
        """The header's start time (s since the epoch), which every ``time`` channel counts from."""
        self._file.seek(self._hd_time_at)
        self._file.write(_U64.pack(round(epoch_s * 1e9)))
        self._file.flush()

    def close(self) -> None:
        """Flush and close; safe to call twice. The file stays at :attr:`path` (the caller may move it)."""
        if self.closed:
            return
        try:
            self.flush()
            os.fsync(self._file.fileno())
            _mark(self._file, finalized=True)
            os.fsync(self._file.fileno())
        finally:
            self._file.close()
            self.closed = True


def finalize(path: str | Path) -> bool:
    """Mark a recording whose writer was killed as finalized, in place: each channel group's cycle counter
    set to the records its data holds (as asammdf counts them). Returns False when it was finalized already.

    :raises InputError: ``path`` is no MDF4 file asammdf can read. :raises WorkbenchError: it cannot be written.
    """
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            head = handle.read(64)
    except OSError as exc:
        raise unreadable(path, exc, "an MDF4 file") from None
    if head[:8] == _FINALIZED and not struct.unpack_from("<H", head, _UNFINALIZED_FLAGS_AT)[0]:
        return False
    mdf = _open_mdf(path)  # reads an unfinalized file from a copy, counting the records from the data
    try:
        counters = [(group.channel_group.address + 24 + 8 * group.channel_group.links_nr + 8,
                     group.channel_group.cycles_nr) for group in mdf.groups]
    finally:
        mdf.close()
    try:
        with open(path, "r+b") as handle:
            for address, cycles in counters:
                handle.seek(address)
                handle.write(_U64.pack(cycles))
            handle.flush()
            os.fsync(handle.fileno())
            _mark(handle, finalized=True)
            os.fsync(handle.fileno())
    except OSError as exc:
        raise WorkbenchError(f"{path}: cannot finalize it ({exc.strerror or exc})") from None
    return True


@dataclass(frozen=True)
class GroupContents:
    """What one channel group of a recording holds: ``records`` samples from ``first_s`` to ``last_s`` (s on the
    file's time axis; None when it holds none)."""

    name: str
    records: int
    first_s: float | None
    last_s: float | None


def contents(path: str | Path) -> list[GroupContents]:
    """What each channel group of an MDF4 file holds, by its acquisition name (a killed recording: up to its last
    flush). :raises InputError: ``path`` is no MDF4 file asammdf can read."""
    mdf = _open_mdf(path)
    try:
        found = []
        for index, group in enumerate(mdf.groups):
            times = mdf.get_master(index)
            found.append(GroupContents(group.channel_group.acq_name or f"group {index}", len(times),
                                       float(times[0]) if len(times) else None,
                                       float(times[-1]) if len(times) else None))
        return found
    finally:
        mdf.close()


def _open_mdf(path: str | Path):
    """asammdf's MDF of ``path``. :raises InputError: it cannot read the file."""
    from asammdf import MDF

    try:
        return MDF(path)
    except OSError as exc:
        raise unreadable(path, exc, "an MDF4 file") from None
    except Exception as exc:  # asammdf's errors have no common base; every one means "not readable"
        raise InputError(f"{path}: not an MDF4 file asammdf can read ({exc})") from None


def _mark(handle, *, finalized: bool) -> None:
    """The identification block: finalized, or unfinalized with cycle counters to be updated."""
    handle.seek(0)
    handle.write(_FINALIZED if finalized else _UNFINALIZED)
    handle.seek(_UNFINALIZED_FLAGS_AT)
    handle.write(struct.pack("<H", 0 if finalized else _UPDATE_CYCLE_COUNTERS))
    handle.flush()


def _set_precisions(channels, specs: Sequence[ChannelSpec]) -> None:
    """The display precision of the channels that have one (asammdf's ``Signal`` takes none): cn_precision
    and its "precision valid" flag, as CANape writes the A2L's FORMAT."""
    from asammdf.blocks import v4_constants as v4c

    decimals = {spec.name: spec.decimals for spec in specs if spec.decimals is not None}
    for channel in channels:
        if channel.name in decimals:
            channel.precision = min(decimals[channel.name], 0xFE)  # 0xFF would mean "unlimited"
            channel.flags |= v4c.FLAG_CN_PRECISION


def _local_time(epoch_s: float | None) -> datetime:
    when = datetime.now(timezone.utc) if epoch_s is None else datetime.fromtimestamp(epoch_s, timezone.utc)
    return when.astimezone()
