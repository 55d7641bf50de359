"""DAQ, dynamic or static: allocation, ODT entries, list modes, start/stop and sampling at the task events.

Limits the slave enforces (they are what GET_DAQ_PROCESSOR_INFO / GET_DAQ_RESOLUTION_INFO
and the A2L publish, see :class:`DaqParameters`):

* allocation order FREE_DAQ → ALLOC_DAQ → ALLOC_ODT (every list) → ALLOC_ODT_ENTRY
  (every ODT); anything else, or allocating the same list/ODT twice, is ERR_SEQUENCE;
* absolute ODT numbers: one PID per ODT of all lists (0x00..0xFB), so at most 252 ODTs;
* an ODT entry holds 1..MAX_ODT_ENTRY_SIZE_DAQ bytes (ERR_OUT_OF_RANGE otherwise);
* an ODT's entries must fit the DTO: MAX_DTO − 1 (PID) bytes, and in the first ODT of a list
  whose mode asks for timestamps also minus the 4-byte timestamp: more entries than the DTO
  holds is ERR_OUT_OF_RANGE at ALLOC_ODT_ENTRY, more bytes ERR_DAQ_CONFIG at WRITE_DAQ, and a
  SET_DAQ_LIST_MODE that turns timestamps on over a full first ODT is ERR_DAQ_CONFIG too;
* timestamps are selectable per list (not TIMESTAMP_FIXED); no prescaler (it must be 1);
* no STIM, no PID_OFF, no ALTERNATING/DTO_CTR modes, no bit-wise entries (bit offset 0xFF only).

With :attr:`DaqParameters.static_lists` the configuration is static (DAQ_CONFIG_TYPE 0) instead:

* the lists, their ODTs and the ODTs' entries exist from the start (MAX_DAQ = their number, MIN_DAQ 0:
  none is predefined); GET_DAQ_LIST_INFO tells each one's MAX_ODT, MAX_ODT_ENTRIES and FIXED_EVENT;
* FREE_DAQ and ALLOC_* are not implemented (ERR_CMD_UNKNOWN, as the optional dynamic commands of a static
  slave); CLEAR_DAQ_LIST empties a list's entries (size 0) and mode (ERR_DAQ_ACTIVE while it runs);
* an EVENT_FIXED list samples only its event (SET_DAQ_LIST_MODE with another: ERR_OUT_OF_RANGE);
* an entry of size 0 ends its ODT, and an ODT whose first entry has size 0 ends the list: that ODT and
  the ones after it are not transmitted; a list with nothing to transmit does not start (ERR_DAQ_CONFIG).

DTO layout: ``PID [timestamp, first ODT only] data…`` with PID = FIRST_PID of the list + ODT number
(static lists: FIRST_PID = the ODTs of the lists before it).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import IntEnum
from itertools import takewhile
from typing import TYPE_CHECKING

from workbench.sim.memory import MemoryAccessError
from workbench.sim.xcp.responses import XcpNegative, need
from workbench.xcp_protocol import Cmd, Err

if TYPE_CHECKING:
    from workbench.sim.xcp.slave import XcpSlave

MODE_TIMESTAMP = 0x10  # the only SET_DAQ_LIST_MODE bit supported
NO_BIT_OFFSET = 0xFF
PROPERTY_DYNAMIC = 0x01
PROPERTY_TIMESTAMP = 0x10
LIST_PROPERTY_EVENT_FIXED = 0x02  # GET_DAQ_LIST_INFO's DAQ_LIST_PROPERTIES (PREDEFINED 0x01 is never set)
LIST_PROPERTY_DAQ = 0x04  # DAQ_LIST_TYPE: DAQ only (no STIM)
EVENT_PROPERTY_DAQ = 0x04
EVENT_CONSISTENCY_DAQ = 0x40
KEY_BYTE = 0x00  # identification field absolute, address extension free (only extension 0 exists), default optimisation
UNLIMITED_LISTS = 0xFF


class _Stage(IntEnum):
    FREED = 0
    DAQ = 1
    ODT = 2
    ENTRY = 3


@dataclass
class OdtEntry:
    address: int = 0
    size: int = 0  # 0: not written yet (contributes nothing)


@dataclass
class DaqList:
    odts: list[list[OdtEntry]] | None = None  # None until ALLOC_ODT
    first_pid: int = 0
    event: int | None = None
    fixed_event: int | None = None  # a static list's FIXED_EVENT
    timestamps: bool = False
    priority: int = 0
    selected: bool = False
    running: bool = False


class DaqProcessor:
    def __init__(self, slave: XcpSlave):
        self.slave = slave
        self.params = slave.params.daq
        self.events = {e.number: e for e in slave.params.events}
        self.free()

    def free(self) -> None:
        """No DAQ list runs or holds anything: dynamic lists are freed, static ones emptied."""
        self.lists: list[DaqList] = []
        self._stage = _Stage.FREED
        self._odt_count = 0
        self._ptr: tuple[int, int, int] | None = None
        for shape in self.params.static_lists:
            self.lists.append(DaqList([[OdtEntry() for _ in range(shape.entries)] for _ in range(shape.odts)],
                                      self._odt_count, shape.fixed_event, shape.fixed_event))
            self._odt_count += shape.odts

    @property
    def running(self) -> bool:
        return any(daq.running for daq in self.lists)

    def handlers(self):
        configuration = {
            Cmd.GET_DAQ_LIST_INFO: self._get_daq_list_info,
            Cmd.CLEAR_DAQ_LIST: self._clear_daq_list,
        } if self.params.static else {
            Cmd.FREE_DAQ: self._free_daq,
            Cmd.ALLOC_DAQ: self._alloc_daq,
            Cmd.ALLOC_ODT: self._alloc_odt,
            Cmd.ALLOC_ODT_ENTRY: self._alloc_odt_entry,
        }
        return {
            Cmd.GET_DAQ_PROCESSOR_INFO: self._get_processor_info,
            Cmd.GET_DAQ_RESOLUTION_INFO: self._get_resolution_info,
            Cmd.GET_DAQ_EVENT_INFO: self._get_event_info,
            Cmd.GET_DAQ_CLOCK: self._get_daq_clock,
            **configuration,
            Cmd.SET_DAQ_PTR: self._set_daq_ptr,
            Cmd.WRITE_DAQ: self._write_daq,
            Cmd.SET_DAQ_LIST_MODE: self._set_daq_list_mode,
            Cmd.START_STOP_DAQ_LIST: self._start_stop_daq_list,
            Cmd.START_STOP_SYNCH: self._start_stop_synch,
        }

    def odt_capacity(self, odt: int, timestamps: bool) -> int:
        """Data bytes an ODT can carry: the DTO minus the PID, minus the timestamp in a timestamped ODT 0."""
        payload = self.slave.params.max_dto - 1
        return payload - self.params.timestamp_size if odt == 0 and timestamps else payload

    # --- information ---------------------------------------------------------------------------

    def _get_processor_info(self, req: bytes) -> bytes:
        params = self.params
        properties = (0 if params.static else PROPERTY_DYNAMIC) | PROPERTY_TIMESTAMP
        max_daq = len(params.static_lists) if params.static else params.max_daq
        return struct.pack("<BHHBB", properties, max_daq, len(self.events), 0, KEY_BYTE)

    def _get_resolution_info(self, req: bytes) -> bytes:
        size_code = {1: 1, 2: 2, 4: 4}[self.params.timestamp_size]
        timestamp_mode = self.params.timestamp_unit << 4 | size_code  # TIMESTAMP_FIXED (0x08) not set
        return struct.pack(
            "<BBBBBH", self.params.granularity, self.params.max_odt_entry_size, 1, 0, timestamp_mode,
            self.params.timestamp_ticks,
        )

    def _get_event_info(self, req: bytes) -> bytes:
        need(req, 4)
        number = struct.unpack_from("<H", req, 2)[0]
        event = self.events.get(number)
        if event is None:
            raise XcpNegative(Err.OUT_OF_RANGE)
        address, length = self.slave.info.index[f"event:{number}"]
        self.slave.mta = address
        cycle, unit = event.cycle
        return bytes([EVENT_CONSISTENCY_DAQ | EVENT_PROPERTY_DAQ, UNLIMITED_LISTS, length, cycle, unit, event.priority])

    def _get_daq_clock(self, req: bytes) -> bytes:
        return struct.pack("<BBBI", 0, 0, 0, self.slave.target.timestamp_ticks() & 0xFFFFFFFF)

    def _get_daq_list_info(self, req: bytes) -> bytes:
        need(req, 4)
        _, daq = self._list(req)
        properties = LIST_PROPERTY_DAQ | (LIST_PROPERTY_EVENT_FIXED if daq.fixed_event is not None else 0)
        return struct.pack("<BBBH", properties, len(daq.odts), len(daq.odts[0]), daq.fixed_event or 0)

    # --- allocation ------------------------------------------------------------------------------

    def _list(self, req: bytes, offset: int = 2) -> tuple[int, DaqList]:
        number = struct.unpack_from("<H", req, offset)[0]
        if number >= len(self.lists):
            raise XcpNegative(Err.OUT_OF_RANGE)
        return number, self.lists[number]

    def _free_daq(self, req: bytes) -> bytes:
        self.free()
        return b""

    def _clear_daq_list(self, req: bytes) -> bytes:
        need(req, 4)
        _, daq = self._list(req)
        if daq.running:
            raise XcpNegative(Err.DAQ_ACTIVE)
        for entries in daq.odts:
            entries[:] = [OdtEntry() for _ in entries]
        daq.event, daq.timestamps, daq.priority, daq.selected = daq.fixed_event, False, 0, False
        return b""

    def _alloc_daq(self, req: bytes) -> bytes:
        need(req, 4)
        if self._stage != _Stage.FREED or self.lists:
            raise XcpNegative(Err.SEQUENCE)
        count = struct.unpack_from("<H", req, 2)[0]
        if count > self.params.max_daq:
            raise XcpNegative(Err.MEMORY_OVERFLOW)
        self.lists = [DaqList() for _ in range(count)]
        self._stage = _Stage.DAQ
        return b""

    def _alloc_odt(self, req: bytes) -> bytes:
        need(req, 5)
        if self._stage not in (_Stage.DAQ, _Stage.ODT):
            raise XcpNegative(Err.SEQUENCE)
        _, daq = self._list(req)
        if daq.odts is not None:
            raise XcpNegative(Err.SEQUENCE)
        count = req[4]
        if self._odt_count + count > self.params.max_odt_total:
            raise XcpNegative(Err.MEMORY_OVERFLOW)
        daq.first_pid = self._odt_count
        daq.odts = [None] * count  # type: ignore[list-item]  # entries come with ALLOC_ODT_ENTRY
        self._odt_count += count
        self._stage = _Stage.ODT
        return b""

    def _alloc_odt_entry(self, req: bytes) -> bytes:
        need(req, 6)
        if self._stage not in (_Stage.ODT, _Stage.ENTRY):
            raise XcpNegative(Err.SEQUENCE)
        _, daq = self._list(req)
        odt, count = req[4], req[5]
        if daq.odts is None or odt >= len(daq.odts):
            raise XcpNegative(Err.OUT_OF_RANGE)
        if daq.odts[odt] is not None:
            raise XcpNegative(Err.SEQUENCE)
        if count > self.odt_capacity(odt, timestamps=False) // self.params.granularity:
            raise XcpNegative(Err.OUT_OF_RANGE)
        daq.odts[odt] = [OdtEntry() for _ in range(count)]
        self._stage = _Stage.ENTRY
        return b""

    # --- configuration -----------------------------------------------------------------------------

    def _set_daq_ptr(self, req: bytes) -> bytes:
        need(req, 6)
        number, daq = self._list(req)
        odt, entry = req[4], req[5]
        if daq.odts is None or odt >= len(daq.odts) or daq.odts[odt] is None or entry >= len(daq.odts[odt]):
            raise XcpNegative(Err.OUT_OF_RANGE)
        if daq.running:
            raise XcpNegative(Err.DAQ_ACTIVE)
        self._ptr = (number, odt, entry)
        return b""

    def _write_daq(self, req: bytes) -> bytes:
        need(req, 8)
        if self._ptr is None:
            raise XcpNegative(Err.SEQUENCE)
        number, odt, index = self._ptr
        daq = self.lists[number]
        entries = daq.odts[odt]
        if index >= len(entries):
            raise XcpNegative(Err.OUT_OF_RANGE)  # the pointer ran past the ODT's last entry
        if daq.running:
            raise XcpNegative(Err.DAQ_ACTIVE)
        bit_offset, size, extension = req[1], req[2], req[3]
        address = struct.unpack_from("<I", req, 4)[0]
        if bit_offset != NO_BIT_OFFSET or extension != 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        if not 0 < size <= self.params.max_odt_entry_size or size % self.params.granularity:
            raise XcpNegative(Err.OUT_OF_RANGE)
        try:
            self.slave.target.memory.area_at(address, size)
        except MemoryAccessError:
            raise XcpNegative(Err.OUT_OF_RANGE) from None
        used = sum(e.size for i, e in enumerate(entries) if i != index)
        if used + size > self.odt_capacity(odt, daq.timestamps):
            raise XcpNegative(Err.DAQ_CONFIG)
        entries[index] = OdtEntry(address, size)
        self._ptr = (number, odt, index + 1)
        return b""

    def _set_daq_list_mode(self, req: bytes) -> bytes:
        need(req, 8)
        mode = req[1]
        _, daq = self._list(req)
        event, prescaler, priority = struct.unpack_from("<H", req, 4)[0], req[6], req[7]
        if daq.running:
            raise XcpNegative(Err.DAQ_ACTIVE)
        if mode & ~MODE_TIMESTAMP:
            raise XcpNegative(Err.MODE_NOT_VALID)  # STIM, PID_OFF, ALTERNATING, DTO_CTR unsupported
        if event not in self.events or prescaler != 1 or daq.fixed_event not in (None, event):
            raise XcpNegative(Err.OUT_OF_RANGE)
        timestamps = bool(mode & MODE_TIMESTAMP)
        if timestamps and daq.odts and daq.odts[0] and sum(e.size for e in daq.odts[0]) > self.odt_capacity(0, True):
            raise XcpNegative(Err.DAQ_CONFIG)  # the first ODT leaves no room for the timestamp
        daq.event, daq.timestamps, daq.priority = event, timestamps, priority
        return b""

    def _start_stop_daq_list(self, req: bytes) -> bytes:
        need(req, 4)
        mode = req[1]
        _, daq = self._list(req)
        if mode > 2:
            raise XcpNegative(Err.MODE_NOT_VALID)
        if mode and (daq.event is None or daq.odts is None or None in daq.odts):
            raise XcpNegative(Err.DAQ_CONFIG)
        if mode and self.params.static and not daq.odts[0][0].size:
            raise XcpNegative(Err.DAQ_CONFIG)  # nothing to transmit
        if mode == 0:
            daq.running = daq.selected = False
        elif mode == 1:
            daq.running = True
        else:
            daq.selected = True
        return bytes([daq.first_pid])

    def _start_stop_synch(self, req: bytes) -> bytes:
        need(req, 2)
        mode = req[1]
        if mode > 2:
            raise XcpNegative(Err.MODE_NOT_VALID)
        for daq in self.lists:
            if mode == 0:
                daq.running = False
            elif daq.selected:
                daq.running = mode == 1
            daq.selected = False
        return b""

    # --- sampling ---------------------------------------------------------------------------------

    def on_event(self, channel: int, timestamp_ticks: int) -> list[list[bytes]]:
        """The DTOs of every running list on ``channel``, sampled now: one list of DTOs per DAQ list."""
        samples = []
        memory_read = self.slave.read
        for daq in self.lists:
            if not daq.running or daq.event != channel:
                continue
            frames = []
            for odt, entries in enumerate(daq.odts):
                if self.params.static:
                    if not entries[0].size:
                        break  # an ODT whose first entry is empty ends the list
                    entries = takewhile(lambda entry: entry.size, entries)  # an empty entry ends the ODT
                frame = bytearray([daq.first_pid + odt])
                if odt == 0 and daq.timestamps:
                    frame += (timestamp_ticks & 0xFFFFFFFF).to_bytes(self.params.timestamp_size, "little")
                for entry in entries:
                    if entry.size:
                        frame += memory_read(entry.address, entry.size)
                frames.append(bytes(frame))
            samples.append(frames)
        return samples
