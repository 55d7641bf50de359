"""Planning DAQ lists: signals into ODT entries into ODTs, within the limits the slave reports.

The plan is made from what the slave says (GET_DAQ_PROCESSOR_INFO, GET_DAQ_RESOLUTION_INFO and
CONNECT's MAX_DTO), never from what the A2L claims or what the demo ECU happens to allow:

* an ODT carries MAX_DTO minus the identification field (1-4 bytes), and the first ODT of a
  timestamped list also minus the timestamp;
* an ODT entry holds at most MAX_ODT_ENTRY_SIZE_DAQ bytes (an entry's size, not an ODT's
  capacity) and a multiple of GRANULARITY_ODT_ENTRY_SIZE_DAQ (entries are widened and aligned
  to it; the extra bytes are read and ignored);
* an ODT has at most as many entries as its capacity counts granules (and at most 255).

Signals at neighbouring addresses share entries. A scalar is never split across ODTs when it
fits one (slaves guarantee consistency per ODT at least); arrays split at element boundaries.
Entries are packed first-fit decreasing, which keeps the ODT count near the minimum.

Each signal's bytes end up at known offsets of the *sample*: the concatenated data of a list's
ODTs in ODT order, which is what :mod:`workbench.xcp.daq.assemble` rebuilds from the DTOs.

A slave with static DAQ lists (DAQ_CONFIG_TYPE static) fixes the lists, their ODTs (MAX_ODT) and
the entries of each ODT (MAX_ODT_ENTRIES), and may tie a list to one event: each event's signals
are packed within the limits of a list that takes them (:mod:`workbench.xcp.daq.assign` chooses
which). A static ODT is never left empty: its empty first entry would end the list's transmission.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from workbench.errors import InputError
from workbench.logs import logger
from workbench.xcp.daq.assign import assign_static_lists
from workbench.xcp.info import DaqListInfo, DaqProcessorInfo, DaqResolutionInfo

log = logger(__name__)

__all__ = ["DaqListPlan", "DaqPlan", "DaqSignal", "Odt", "OdtEntry", "plan_daq"]

MAX_ENTRIES_PER_ODT = 255
MAX_ABSOLUTE_ODTS = 0xFC  # absolute PIDs 0x00..0xFB


@dataclass(frozen=True)
class DaqSignal:
    """Bytes to sample: ``size`` at ``address``; ``element_size`` < ``size`` for an array (it may split there)."""

    key: Hashable
    address: int
    size: int
    extension: int = 0
    element_size: int | None = None

    @property
    def unit(self) -> int:
        return self.element_size or self.size


@dataclass(frozen=True)
class OdtEntry:
    address: int
    size: int
    extension: int = 0
    filler: bool = False  # sampled only so that an ODT is not empty; its bytes belong to no signal


@dataclass(frozen=True)
class Odt:
    entries: tuple[OdtEntry, ...]

    @property
    def size(self) -> int:
        return sum(entry.size for entry in self.entries)


@dataclass(frozen=True)
class DaqListPlan:
    """One DAQ list: its event, ODTs, and where each signal's bytes lie in a sample."""

    number: int
    event: int
    odts: tuple[Odt, ...]
    timestamps: bool
    positions: dict[Hashable, np.ndarray] = field(compare=False)  # key -> sample byte offsets, in the signal's byte order
    prescaler: int = 1
    priority: int = 0

    @property
    def sample_size(self) -> int:
        return sum(odt.size for odt in self.odts)

    @property
    def keys(self) -> list[Hashable]:
        return list(self.positions)


@dataclass(frozen=True)
class DaqPlan:
    lists: tuple[DaqListPlan, ...]
    pid_size: int
    identification_field: str
    timestamp_size: int
    max_dto: int
    static: bool = False  # the lists are the slave's static ones (CLEAR_DAQ_LIST, no ALLOC_*)

    @property
    def odt_count(self) -> int:
        return sum(len(daq.odts) for daq in self.lists)


@dataclass
class _Piece:
    """Contiguous bytes that must stay in one ODT (entries of ``sizes`` from ``address``)."""

    address: int
    extension: int
    sizes: list[int]

    @property
    def size(self) -> int:
        return sum(self.sizes)

    def at_most(self, max_entries: int) -> list[_Piece]:
        """This piece in consecutive parts of at most ``max_entries`` entries (what an ODT of a static list holds)."""
        if len(self.sizes) <= max_entries:
            return [self]
        return [_Piece(self.address + sum(self.sizes[:i]), self.extension, self.sizes[i:i + max_entries])
                for i in range(0, len(self.sizes), max_entries)]

    def entries(self) -> list[tuple[int, int]]:
        """(address, size) of each entry."""
        starts = self.address + np.concatenate(([0], np.cumsum(self.sizes[:-1]))).astype(int)
        return list(zip(starts.tolist(), self.sizes))


def plan_daq(groups: dict[int, Sequence[DaqSignal]], processor: DaqProcessorInfo, resolution: DaqResolutionInfo,
             max_dto: int, *, timestamps: bool = True, first_list: int = 0,
             consistency: Mapping[int, str] | None = None, prescaler: int = 1,
             static_lists: Sequence[DaqListInfo] | None = None,
             event_name: Callable[[int], str] | None = None, address_granularity: int = 1) -> DaqPlan:
    """One DAQ list per event of ``groups`` (event number -> signals), numbered from ``first_list``.

    ``prescaler``: every list sends one sample in ``prescaler`` events (the slave must offer it).

    ``timestamps``: ask for the slave's timestamps (when it supports them; TIMESTAMP_FIXED forces them), unless
    they leave the first ODT no room for data (a 4-byte timestamp after a 4-byte identification field on CAN).
    ``consistency``: per event, what GET_DAQ_EVENT_INFO says the slave keeps consistent: "ODT" (the
    default) keeps every scalar within one ODT; "DAQ" or "EVENT" lets a value continue in the next ODT,
    so every ODT is filled to the last byte.
    ``static_lists``: GET_DAQ_LIST_INFO of each of the slave's lists, required when its DAQ configuration is
    static (``processor.dynamic`` false); each event then gets one of these lists (``first_list`` does not
    apply) that takes its event and holds its ODTs within that list's MAX_ODT and MAX_ODT_ENTRIES.
    ``event_name(number)``: an event's name, for the messages.
    ``address_granularity``: CONNECT's, in bytes: WRITE_DAQ counts an entry's size in these elements from an
    aligned address, so entries are whole elements of it too.

    :raises InputError: a signal cannot be sampled with these limits, or the lists need more
        ODTs or lists than the slave has (for static lists: which event fits no list, and why).
    :raises ValueError: a static slave's lists were not given.
    """
    if prescaler != 1 and not (1 <= prescaler <= 0xFF and processor.prescaler_supported):
        raise InputError(f"prescaler {prescaler}: the slave offers " + (
            "1..255" if processor.prescaler_supported else "no prescaler (choose a slower event instead)"))
    if not processor.dynamic and static_lists is None:
        raise ValueError("the slave's DAQ lists are static: plan with their GET_DAQ_LIST_INFO (static_lists)")
    if address_granularity > resolution.granularity:
        resolution = replace(resolution, granularity=address_granularity)
    pid_size = processor.pid_size
    stamped = resolution.timestamp_size > 0 and (resolution.timestamp_fixed or (timestamps and processor.timestamp_supported))
    timestamp_size = resolution.timestamp_size if stamped else 0
    capacity = max_dto - pid_size
    if stamped and capacity - timestamp_size < resolution.granularity <= capacity and not resolution.timestamp_fixed:
        log.info("DAQ without timestamps: after the %d-byte identification field a %d-byte timestamp leaves the "
                 "%d-byte DTO no room for data; samples are timed by their arrival", pid_size, timestamp_size, max_dto)
        timestamp_size = 0
    if capacity - timestamp_size < resolution.granularity or resolution.max_entry_size < resolution.granularity:
        raise InputError(f"the slave's DTO ({max_dto} bytes) leaves no room for data after its "
                         f"{pid_size}-byte identification field and {timestamp_size}-byte timestamp")
    active = {event: signals for event, signals in sorted(groups.items()) if signals}
    pieces = {event: _pieces(signals, resolution, capacity) for event, signals in active.items()}
    packings: dict[tuple[int, int], list[Odt]] = {}

    def pack(event: int, max_entries: int = MAX_ENTRIES_PER_ODT) -> list[Odt]:
        """``event``'s ODTs with at most ``max_entries`` entries each (cached: static lists share limits)."""
        if (event, max_entries) not in packings:
            rooms = _Rooms(capacity, timestamp_size, resolution.granularity, max_entries)
            split = (consistency or {}).get(event, "ODT") != "ODT"
            packings[event, max_entries] = (_pack_split if split else _pack_whole)(pieces[event], rooms)
        return packings[event, max_entries]

    if static_lists is None:
        numbers = {event: first_list + offset for offset, event in enumerate(active)}
        odts = {event: pack(event) for event in active}
    else:
        chosen = assign_static_lists(list(active), static_lists, lambda event, info: len(pack(event, info.max_odt_entries)),
                                     event_name)
        numbers = {event: info.number for event, info in chosen.items()}
        odts = {event: _never_empty(pack(event, chosen[event].max_odt_entries), resolution.granularity)
                for event in active}
    lists = [DaqListPlan(numbers[event], event, tuple(odts[event]), bool(timestamp_size),
                         _positions(signals, odts[event]), prescaler)
             for event, signals in sorted(active.items(), key=lambda item: numbers[item[0]])]
    plan = DaqPlan(tuple(lists), pid_size, processor.identification_field, timestamp_size, max_dto,
                   static=static_lists is not None)
    if not plan.static:
        _check_totals(plan)
    return plan


def _never_empty(odts: list[Odt], granule: int) -> list[Odt]:
    """A static list's ODTs with something in the first one: under ODT consistency nothing may fit beside the
    timestamp, and an empty first entry ends the list's transmission. The filler re-reads the first granule of
    the next entry; :func:`_positions` takes every byte from its first real place, never from a filler."""
    if odts[0].entries:
        return odts
    first = odts[1].entries[0]
    return [Odt((OdtEntry(first.address, granule, first.extension, filler=True),)), *odts[1:]]


@dataclass(frozen=True)
class _Rooms:
    capacity: int
    timestamp_size: int
    granule: int
    max_entries: int = MAX_ENTRIES_PER_ODT  # a static list's MAX_ODT_ENTRIES

    def bytes(self, odt: int) -> int:
        return self.capacity - (self.timestamp_size if odt == 0 else 0)

    def entries(self, odt: int) -> int:
        return min(self.max_entries, self.bytes(odt) // self.granule)


def _pieces(signals: Sequence[DaqSignal], resolution: DaqResolutionInfo, capacity: int) -> list[_Piece]:
    """The signals' bytes merged where they touch, cut into entries, grouped into what must share an ODT."""
    granule = resolution.granularity
    max_entry = min(resolution.max_entry_size, capacity)  # an entry larger than a DTO could never be sent
    max_entry -= max_entry % granule
    units = sorted({(s.extension, s.address + i, min(s.unit, s.size - i)) for s in signals for i in range(0, s.size, s.unit)})
    pieces: list[_Piece] = []
    for extension, address, size in units:
        start = address - address % granule
        end = -(-(address + size) // granule) * granule
        last = pieces[-1] if pieces else None
        if last is not None and last.extension == extension and start <= last.address + last.size:
            covered = last.address + last.size
            if end <= covered:
                continue
            if len(last.sizes) == 1 and last.size + end - covered <= max_entry:  # grow the entry
                last.sizes[0] += end - covered
                continue
            start = covered
        piece = _Piece(start, extension, _entry_sizes(end - start, max_entry))
        if piece.size <= capacity:
            pieces.append(piece)
        else:  # more than an ODT holds (a double on CAN, an array): its entries go separately
            pieces += [_Piece(start + sum(piece.sizes[:i]), extension, [entry]) for i, entry in enumerate(piece.sizes)]
    return pieces


def _entry_sizes(size: int, max_entry: int) -> list[int]:
    return [max_entry] * (size // max_entry) + ([size % max_entry] if size % max_entry else [])


def _pack_whole(pieces: list[_Piece], rooms: _Rooms) -> list[Odt]:
    """First-fit decreasing; a piece stays in one ODT (the first ODT, short of the timestamp, may stay empty)."""
    bins: list[list[_Piece]] = []
    room: list[int] = []
    slots: list[int] = []
    pieces = [part for piece in pieces for part in piece.at_most(rooms.max_entries)]
    for piece in sorted(pieces, key=lambda p: (-p.size, p.extension, p.address)):
        i = next((i for i in range(len(bins)) if piece.size <= room[i] and len(piece.sizes) <= slots[i]), None)
        while i is None:
            bins.append([])
            room.append(rooms.bytes(len(bins) - 1))
            slots.append(rooms.entries(len(bins) - 1))
            if piece.size <= room[-1] and len(piece.sizes) <= slots[-1]:
                i = len(bins) - 1
        bins[i].append(piece)
        room[i] -= piece.size
        slots[i] -= len(piece.sizes)
    return [Odt(tuple(OdtEntry(address, size, piece.extension)
                      for piece in sorted(content, key=lambda p: (p.extension, p.address))
                      for address, size in piece.entries())) for content in bins]


def _pack_split(pieces: list[_Piece], rooms: _Rooms) -> list[Odt]:
    """In address order, every ODT filled to its last granule; an entry that does not fit is cut in two."""
    odts: list[list[OdtEntry]] = [[]]
    room, slots = rooms.bytes(0), rooms.entries(0)
    pending = [OdtEntry(address, size, piece.extension) for piece in sorted(pieces, key=lambda p: (p.extension, p.address))
               for address, size in piece.entries()]
    pending.reverse()
    while pending:
        entry = pending.pop()
        if slots == 0 or room < rooms.granule:
            odts.append([])
            room, slots = rooms.bytes(len(odts) - 1), rooms.entries(len(odts) - 1)
        if entry.size > room:
            cut = room - room % rooms.granule
            pending.append(OdtEntry(entry.address + cut, entry.size - cut, entry.extension))
            entry = OdtEntry(entry.address, cut, entry.extension)
        odts[-1].append(entry)
        room -= entry.size
        slots -= 1
    return [Odt(tuple(entries)) for entries in odts]


def _positions(signals: Sequence[DaqSignal], odts: list[Odt]) -> dict[Hashable, np.ndarray]:
    """Where each signal byte lies in the sample (the ODTs' data concatenated)."""
    located: dict[tuple[int, int], int] = {}
    offset = 0
    for odt in odts:
        for entry in odt.entries:
            for i in range(entry.size if not entry.filler else 0):
                located.setdefault((entry.extension, entry.address + i), offset + i)
            offset += entry.size
    return {s.key: np.array([located[(s.extension, s.address + i)] for i in range(s.size)], dtype=np.intp)
            for s in signals}


def _check_totals(plan: DaqPlan) -> None:
    """The limits of the identification field. Not MAX_DAQ: in a dynamic configuration it counts the lists
    allocated so far (ASAM: MIN_DAQ + DAQ_COUNT, so MIN_DAQ before ALLOC_DAQ) or, in some slaves, the limit;
    ALLOC_DAQ says (ERR_MEMORY_OVERFLOW) when the lists do not fit."""
    lists = len(plan.lists)
    if plan.identification_field == "ABSOLUTE" and plan.odt_count > MAX_ABSOLUTE_ODTS:
        raise InputError(f"the measurement needs {plan.odt_count} ODTs in {lists} DAQ lists; absolute ODT numbers "
                         f"allow {MAX_ABSOLUTE_ODTS}: measure fewer signals at once")
    for daq in plan.lists:
        if len(daq.odts) > MAX_ABSOLUTE_ODTS:  # a relative ODT number is a PID too (0x00..0xFB)
            raise InputError(f"DAQ list {daq.number} needs {len(daq.odts)} ODTs; a list holds "
                             f"{MAX_ABSOLUTE_ODTS} at most: measure fewer signals on event {daq.event}")
        if plan.identification_field == "RELATIVE_BYTE" and daq.number > 0xFF:
            raise InputError(f"DAQ list {daq.number}: a RELATIVE_BYTE identification field numbers 256 lists at most")
