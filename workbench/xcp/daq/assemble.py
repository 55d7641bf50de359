"""DTOs back into samples: identify each DTO's list and ODT, collect a list's ODTs, take its timestamp.

A :class:`DtoAssembler` is fed every DTO from the link's receive thread (:meth:`feed` is kept
short: it only copies bytes) and hands out complete samples with :meth:`take`:
``(list number, slave timestamp or None, host receive time ns, sample bytes)``. A sample whose
ODTs do not arrive in order (a lost frame, an overloaded slave dropping some) is discarded
and counted in :attr:`lost` (per list: :attr:`lost_by_list`); the identification field's overload bit (OVERLOAD_INDICATION_PID)
and EV_DAQ_OVERLOAD events count in :attr:`overloads`.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

from workbench.xcp.daq.plan import DaqPlan

__all__ = ["DtoAssembler", "RawSample"]

OVERLOAD_BIT = 0x80
_DISCARDING = -1  # next_odt while the rest of a broken sample goes by


@dataclass(frozen=True)
class RawSample:
    daq_list: int
    timestamp: int | None  # the slave's counter, as sent (wraps)
    host_ns: int  # when ODT 0 arrived at the host
    data: bytes  # the ODTs' data, concatenated


class _ListState:
    __slots__ = ("number", "sizes", "odt_count", "timestamp_size", "next_odt", "buffer", "timestamp", "host_ns")

    def __init__(self, number: int, sizes: list[int], timestamp_size: int):
        self.number = number
        self.sizes = sizes
        self.odt_count = len(sizes)
        self.timestamp_size = timestamp_size
        self.next_odt = 0
        self.buffer = bytearray()
        self.timestamp: int | None = None
        self.host_ns = 0


class DtoAssembler:
    """Samples from the DTOs of ``plan``; ``first_pids`` are START_STOP_DAQ_LIST's answers (absolute PIDs)."""

    def __init__(self, plan: DaqPlan, first_pids: dict[int, int], byte_order: str = "<",
                 overload_in_pid: bool = False):
        self.plan = plan
        self.byte_order = "little" if byte_order == "<" else "big"
        self.overload_in_pid = overload_in_pid
        self._lists = {daq.number: _ListState(daq.number, [odt.size for odt in daq.odts], plan.timestamp_size if daq.timestamps else 0)
                       for daq in plan.lists}
        self._by_pid: dict[int, tuple[_ListState, int]] = {}
        if plan.identification_field == "ABSOLUTE":
            for number, state in self._lists.items():
                for odt in range(state.odt_count):
                    self._by_pid[first_pids[number] + odt] = (state, odt)
        self._ready: list[RawSample] = []
        self._lock = threading.Lock()
        self.dtos = 0
        self.samples = 0
        self.lost_by_list: dict[int, int] = dict.fromkeys(self._lists, 0)
        self.overloads = 0
        self.unknown = 0

    def _identify(self, dto: bytes) -> tuple[_ListState | None, int, int]:
        """(list state, ODT number, offset of what follows the identification field)."""
        field = self.plan.identification_field
        pid = dto[0]
        if self.overload_in_pid and pid & OVERLOAD_BIT:
            self.overloads += 1
            pid &= ~OVERLOAD_BIT
        if field == "ABSOLUTE":
            state, odt = self._by_pid.get(pid, (None, 0))
            return state, odt, 1
        if field == "RELATIVE_BYTE":
            return self._lists.get(dto[1]), pid, 2
        if field == "RELATIVE_WORD":
            return self._lists.get(int.from_bytes(dto[1:3], self.byte_order)), pid, 3
        return self._lists.get(int.from_bytes(dto[2:4], self.byte_order)), pid, 4

    def feed(self, dto: bytes, host_ns: int) -> None:
        """One DTO as the link received it (CAN padding allowed: only the planned bytes are taken)."""
        self.dtos += 1
        state, odt, offset = self._identify(dto)
        if state is None or odt >= state.odt_count:
            self.unknown += 1
            return
        if odt == 0:
            if state.next_odt > 0:
                self.lost_by_list[state.number] += 1  # the previous sample never completed
            state.buffer = bytearray()
            if state.timestamp_size:
                state.timestamp = int.from_bytes(dto[offset:offset + state.timestamp_size], self.byte_order)
                offset += state.timestamp_size
            state.host_ns = host_ns
        elif odt != state.next_odt:
            if state.next_odt != _DISCARDING:
                self.lost_by_list[state.number] += 1  # an ODT went missing: drop the rest of this sample
            state.next_odt = _DISCARDING
            return
        size = state.sizes[odt]
        if len(dto) < offset + size:
            self.lost_by_list[state.number] += 1
            state.next_odt = _DISCARDING
            return
        state.buffer += dto[offset:offset + size]
        if odt + 1 == state.odt_count:
            state.next_odt = 0
            with self._lock:
                self._ready.append(RawSample(state.number, state.timestamp, state.host_ns, bytes(state.buffer)))
                self.samples += 1
        else:
            state.next_odt = odt + 1

    @property
    def silent_lists(self) -> list[int]:
        """The lists whose first sample has not begun yet (no DTO of their ODT 0 came)."""
        return [number for number, state in self._lists.items() if not state.host_ns]

    @property
    def lost(self) -> int:
        """Samples dropped because an ODT was missing or short."""
        return sum(self.lost_by_list.values())

    def take(self) -> list[RawSample]:
        """The samples completed since the last call, in arrival order."""
        with self._lock:
            ready, self._ready = self._ready, []
        return ready

    def overload_event(self) -> None:
        """An EV_DAQ_OVERLOAD event packet (OVERLOAD_INDICATION_EVENT) came."""
        self.overloads += 1
