"""DAQ, dynamic or static: allocation, ODT entries, list modes, start/stop and sampling at the task events.

Limits the slave enforces (they are what GET_DAQ_PROCESSOR_INFO / GET_DAQ_RESOLUTION_INFO
and the A2L publish, see :class:`DaqParameters`):

* allocation order FREE_DAQ → ALLOC_DAQ → ALLOC_ODT (every list) → ALLOC_ODT_ENTRY
  (every ODT); anything else, or allocating the same list/ODT twice, is ERR_SEQUENCE;
* predefined lists (:attr:`DaqParameters.predefined`, MIN_DAQ of them) come first, numbered from 0, and
  survive FREE_DAQ; the allocated lists are numbered from MIN_DAQ; a predefined list's entries cannot be
  written (ERR_WRITE_PROTECTED) but it can be started;
* MAX_DAQ in GET_DAQ_PROCESSOR_INFO is the lists a configuration can hold, or (with
  :attr:`DaqParameters.max_daq_counts_allocated`, as the spec defines it) MIN_DAQ + the lists allocated
  so far, MIN_DAQ before ALLOC_DAQ; ALLOC_DAQ beyond the limit is ERR_MEMORY_OVERFLOW either way;
* the identification field (:attr:`DaqParameters.identification_field`): ABSOLUTE ODT numbers (one PID per
  ODT of all lists, 0x00..0xFB, so at most 252 ODTs), or RELATIVE_BYTE/_WORD/_WORD_ALIGNED: the ODT's number
  within its list, then the list's number as a byte, a word, or a word after a fill byte;
* an ODT entry holds 1..MAX_ODT_ENTRY_SIZE_DAQ bytes, a multiple of GRANULARITY_ODT_ENTRY_SIZE_DAQ
  (ERR_OUT_OF_RANGE otherwise); WRITE_DAQ counts its size in elements of the address granularity;
* an ODT's entries must fit the DTO: MAX_DTO minus the identification field, and in the first ODT of a
  list whose mode asks for timestamps also minus the timestamp (1, 2 or 4 bytes): more entries than the
  DTO holds is ERR_OUT_OF_RANGE at ALLOC_ODT_ENTRY, more bytes ERR_DAQ_CONFIG at WRITE_DAQ, and a
  SET_DAQ_LIST_MODE that turns timestamps on over a full first ODT is ERR_DAQ_CONFIG too;
* timestamps are selectable per list, or with TIMESTAMP_FIXED always there; a slave without timestamps
  refuses the mode bit (ERR_MODE_NOT_VALID); no prescaler (it must be 1);
* no STIM, no PID_OFF, no ALTERNATING/DTO_CTR modes, no bit-wise entries (bit offset 0xFF only).

With :attr:`DaqParameters.static_lists` the configuration is static (DAQ_CONFIG_TYPE 0) instead:

* the lists, their ODTs and the ODTs' entries exist from the start (MAX_DAQ = their number, MIN_DAQ 0:
  none is predefined); GET_DAQ_LIST_INFO tells each one's MAX_ODT, MAX_ODT_ENTRIES and FIXED_EVENT;
* FREE_DAQ and ALLOC_* are not implemented (ERR_CMD_UNKNOWN, as the optional dynamic commands of a static
  slave); CLEAR_DAQ_LIST empties a list's entries (size 0) and mode (ERR_DAQ_ACTIVE while it runs);
* an EVENT_FIXED list samples only its event (SET_DAQ_LIST_MODE with another: ERR_OUT_OF_RANGE);
* an entry of size 0 ends its ODT, and an ODT whose first entry has size 0 ends the list: that ODT and
  the ones after it are not transmitted; a list with nothing to transmit does not start (ERR_DAQ_CONFIG).

DTO layout: ``identification field [timestamp, first ODT only] data…``; an absolute PID is FIRST_PID of
the list + ODT number (FIRST_PID = the ODTs of the lists before it). Timestamps and relative list numbers
are in the slave's byte order.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from itertools import takewhile
from typing import TYPE_CHECKING

from workbench.sim.memory import MemoryAccessError
from workbench.sim.xcp.parameters import IDENTIFICATION_FIELDS
from workbench.sim.xcp.responses import XcpNegative, need
from workbench.xcp_protocol import MAX_DAQ_PID, Cmd, Err

if TYPE_CHECKING:
    from workbench.sim.xcp.slave import XcpSlave

__all__ = ["DaqList", "DaqProcessor", "OdtEntry"]

MODE_TIMESTAMP = 0x10  # the only SET_DAQ_LIST_MODE bit supported
LIST_MODE_SELECTED, LIST_MODE_RUNNING = 0x01, 0x40  # GET_DAQ_LIST_MODE's CURRENT_MODE, beside MODE_TIMESTAMP
NO_BIT_OFFSET = 0xFF
PROPERTY_DYNAMIC = 0x01
PROPERTY_TIMESTAMP = 0x10
LIST_PROPERTY_PREDEFINED = 0x01  # GET_DAQ_LIST_INFO's DAQ_LIST_PROPERTIES
LIST_PROPERTY_EVENT_FIXED = 0x02
LIST_PROPERTY_DAQ = 0x04  # DAQ_LIST_TYPE: DAQ only (no STIM)
EVENT_PROPERTY_DAQ = 0x04
EVENT_CONSISTENCY_DAQ = 0x40
TIMESTAMP_FIXED = 0x08
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
    fixed_event: int | None = None  # a static or predefined list's FIXED_EVENT
    predefined: bool = False
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
        """No DAQ list runs or holds anything: dynamic lists are freed, static ones emptied, predefined ones kept."""
        self.lists: list[DaqList] = []
        self._stage = _Stage.FREED
        self._odt_count = 0
        self._ptr: tuple[int, int, int] | None = None
        for shape in self.params.static_lists:
            self.lists.append(DaqList([[OdtEntry() for _ in range(shape.entries)] for _ in range(shape.odts)],
                                      self._first_pid(), shape.fixed_event, shape.fixed_event))
            self._odt_count += shape.odts
        for predefined in self.params.predefined:
            entries = [OdtEntry(address, size) for address, size in predefined.entries]
            self.lists.append(DaqList([entries], self._first_pid(), predefined.event, predefined.event,
                                      predefined=True))
            self._odt_count += 1

    def _first_pid(self) -> int:
        """The PID of a new list's first ODT: absolute ODT numbers count on, relative ones start at 0."""
        return self._odt_count if self.params.identification_field == "ABSOLUTE" else 0

    @property
    def running(self) -> bool:
        return any(daq.running for daq in self.lists)

    def handlers(self):
        configuration = {
            Cmd.GET_DAQ_LIST_INFO: self._get_daq_list_info,
            Cmd.CLEAR_DAQ_LIST: self._clear_daq_list,
        } if self.params.static else {
            **({Cmd.GET_DAQ_LIST_INFO: self._get_daq_list_info} if self.params.predefined else {}),
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
            Cmd.GET_DAQ_LIST_MODE: self._get_daq_list_mode,
            Cmd.START_STOP_DAQ_LIST: self._start_stop_daq_list,
            Cmd.START_STOP_SYNCH: self._start_stop_synch,
        }

    def odt_capacity(self, odt: int, timestamps: bool) -> int:
        """Data bytes an ODT can carry: the DTO minus the identification field, minus the timestamp in a
        timestamped ODT 0."""
        payload = self.slave.params.max_dto - self.params.pid_size
        return payload - self.params.timestamp_size if odt == 0 and timestamps else payload

    # --- information ---------------------------------------------------------------------------

    def _get_processor_info(self, req: bytes) -> bytes:
        params = self.params
        properties = (0 if params.static else PROPERTY_DYNAMIC) | (PROPERTY_TIMESTAMP if params.timestamp_size else 0)
        if params.static:
            max_daq = len(params.static_lists)
        elif params.max_daq_counts_allocated:
            max_daq = len(self.lists)  # MIN_DAQ + the lists allocated so far (ASAM: MAX_DAQ = MIN_DAQ + DAQ_COUNT)
        else:
            max_daq = params.max_daq
        key_byte = IDENTIFICATION_FIELDS.index(params.identification_field) << 6  # address extension free
        return self.slave.pack("BHHBB", properties, max_daq, len(self.events), params.min_daq, key_byte)

    def _get_resolution_info(self, req: bytes) -> bytes:
        params = self.params
        timestamp_mode = ((params.timestamp_unit << 4 | params.timestamp_size
                           | (TIMESTAMP_FIXED if params.timestamp_fixed else 0)) if params.timestamp_size else 0)
        ticks = params.timestamp_ticks if params.timestamp_size else 0
        return self.slave.pack("BBBBBH", params.granularity, params.max_odt_entry_size, 1, 0, timestamp_mode, ticks)

    def _get_event_info(self, req: bytes) -> bytes:
        need(req, 4)
        number = self.slave.unpack_from("H", req, 2)[0]
        event = self.events.get(number)
        if event is None:
            raise XcpNegative(Err.OUT_OF_RANGE)
        address, length = self.slave.info.index[f"event:{number}"]
        self.slave.mta = address
        cycle, unit = event.cycle if self.slave.params.events_cyclic else (0, 0)
        return bytes([EVENT_CONSISTENCY_DAQ | EVENT_PROPERTY_DAQ, UNLIMITED_LISTS, length, cycle, unit, event.priority])

    def _get_daq_clock(self, req: bytes) -> bytes:
        return self.slave.pack("BBBI", 0, 0, 0, self.slave.target.timestamp_ticks() & 0xFFFFFFFF)

    def _get_daq_list_info(self, req: bytes) -> bytes:
        need(req, 4)
        _, daq = self._list(req)
        properties = (LIST_PROPERTY_DAQ | (LIST_PROPERTY_EVENT_FIXED if daq.fixed_event is not None else 0)
                      | (LIST_PROPERTY_PREDEFINED if daq.predefined else 0))
        odts = daq.odts or []
        entries = max((len(entries) for entries in odts if entries is not None), default=0)
        return self.slave.pack("BBBH", properties, len(odts), entries, daq.fixed_event or 0)

    # --- allocation ------------------------------------------------------------------------------

    def _list(self, req: bytes, offset: int = 2) -> tuple[int, DaqList]:
        number = self.slave.unpack_from("H", req, offset)[0]
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
        if self._stage != _Stage.FREED or len(self.lists) > self.params.min_daq:
            raise XcpNegative(Err.SEQUENCE)
        count = self.slave.unpack_from("H", req, 2)[0]
        if self.params.min_daq + count > self.params.max_daq:
            raise XcpNegative(Err.MEMORY_OVERFLOW)
        self.lists += [DaqList() for _ in range(count)]
        self._stage = _Stage.DAQ
        return b""

    def _alloc_odt(self, req: bytes) -> bytes:
        need(req, 5)
        if self._stage not in (_Stage.DAQ, _Stage.ODT):
            raise XcpNegative(Err.SEQUENCE)
        _, daq = self._list(req)
        if daq.predefined:
            raise XcpNegative(Err.OUT_OF_RANGE)
        if daq.odts is not None:
            raise XcpNegative(Err.SEQUENCE)
        count = req[4]
        absolute = self.params.identification_field == "ABSOLUTE"
        if (self._odt_count + count if absolute else count) > min(self.params.max_odt_total, MAX_DAQ_PID + 1):
            raise XcpNegative(Err.MEMORY_OVERFLOW)
        daq.first_pid = self._first_pid()
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
        if daq.predefined:
            raise XcpNegative(Err.WRITE_PROTECTED)
        bit_offset, size, extension = req[1], self.slave.elements(req[2]), req[3]
        address = self.slave.unpack_from("I", req, 4)[0]
        if bit_offset != NO_BIT_OFFSET or extension != 0:
            raise XcpNegative(Err.OUT_OF_RANGE)
        if not 0 < size <= self.params.max_odt_entry_size or size % self.params.granularity:
            raise XcpNegative(Err.OUT_OF_RANGE)
        self.slave.require_aligned(address)
        try:
            self.slave.target.memory.area_at(address, size)
        except MemoryAccessError:
            raise XcpNegative(Err.OUT_OF_RANGE) from None
        used = sum(e.size for i, e in enumerate(entries) if i != index)
        if used + size > self.odt_capacity(odt, self._stamped(daq)):
            raise XcpNegative(Err.DAQ_CONFIG)
        entries[index] = OdtEntry(address, size)
        self._ptr = (number, odt, index + 1)
        return b""

    def _set_daq_list_mode(self, req: bytes) -> bytes:
        need(req, 8)
        mode = req[1]
        _, daq = self._list(req)
        event, prescaler, priority = self.slave.unpack_from("H", req, 4)[0], req[6], req[7]
        if daq.running:
            raise XcpNegative(Err.DAQ_ACTIVE)
        if mode & ~MODE_TIMESTAMP or (mode & MODE_TIMESTAMP and not self.params.timestamp_size):
            raise XcpNegative(Err.MODE_NOT_VALID)  # STIM, PID_OFF, ALTERNATING, DTO_CTR unsupported
        if event not in self.events or prescaler != 1 or daq.fixed_event not in (None, event):
            raise XcpNegative(Err.OUT_OF_RANGE)
        timestamps = bool(mode & MODE_TIMESTAMP) or self.params.timestamp_fixed
        if timestamps and daq.odts and daq.odts[0] and sum(e.size for e in daq.odts[0]) > self.odt_capacity(0, True):
            raise XcpNegative(Err.DAQ_CONFIG)  # the first ODT leaves no room for the timestamp
        daq.event, daq.timestamps, daq.priority = event, timestamps, priority
        return b""

    def _get_daq_list_mode(self, req: bytes) -> bytes:
        """The list's CURRENT_MODE (SELECTED, TIMESTAMP, RUNNING), its event (0 before SET_DAQ_LIST_MODE), prescaler
        and priority."""
        need(req, 4)
        _, daq = self._list(req)
        mode = ((LIST_MODE_SELECTED if daq.selected else 0) | (MODE_TIMESTAMP if daq.timestamps else 0)
                | (LIST_MODE_RUNNING if daq.running else 0))
        return self.slave.pack("BxxHBB", mode, daq.event or 0, 1, daq.priority)

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

    def _stamped(self, daq: DaqList) -> bool:
        return daq.timestamps or self.params.timestamp_fixed

    def _identification(self, number: int, daq: DaqList, odt: int) -> bytes:
        """A DTO's identification field: the absolute PID, or the relative ODT number and the list's number."""
        field = self.params.identification_field
        if field == "ABSOLUTE":
            return bytes([daq.first_pid + odt])
        if field == "RELATIVE_BYTE":
            return bytes([odt, number])
        return bytes([odt]) + (b"\0" if field == "RELATIVE_WORD_ALIGNED" else b"") + self.slave.pack("H", number)

    def list_of(self, dto: bytes) -> int | None:
        """The number of the DAQ list a DTO of this processor belongs to, read from its identification field."""
        field = self.params.identification_field
        if field == "ABSOLUTE":
            return next((number for number, daq in enumerate(self.lists)
                         if daq.odts and daq.first_pid <= dto[0] < daq.first_pid + len(daq.odts)), None)
        if field == "RELATIVE_BYTE":
            return dto[1]
        return self.slave.unpack_from("H", dto, 2 if field == "RELATIVE_WORD_ALIGNED" else 1)[0]

    def on_event(self, channel: int, timestamp_ticks: int) -> list[list[bytes]]:
        """The DTOs of every running list on ``channel``, sampled now: one list of DTOs per DAQ list."""
        samples = []
        memory_read = self.slave.read
        byteorder = "little" if self.slave.order == "<" else "big"
        size = self.params.timestamp_size
        stamp = (timestamp_ticks % (1 << 8 * size)).to_bytes(size, byteorder)
        for number, daq in enumerate(self.lists):
            if not daq.running or daq.event != channel:
                continue
            frames = []
            for odt, entries in enumerate(daq.odts):
                if self.params.static:
                    if not entries[0].size:
                        break  # an ODT whose first entry is empty ends the list
                    entries = takewhile(lambda entry: entry.size, entries)  # an empty entry ends the ODT
                frame = bytearray(self._identification(number, daq, odt))
                if odt == 0 and self._stamped(daq):
                    frame += stamp
                for entry in entries:
                    if entry.size:
                        frame += memory_read(entry.address, entry.size)
                frames.append(bytes(frame))
            samples.append(frames)
        return samples
