"""A running DAQ measurement: configure the slave from a plan, start, collect batches, stop.

:class:`DaqStream` writes the plan into the slave in the order real slaves demand (FREE_DAQ,
ALLOC_DAQ, ALLOC_ODT for every list, ALLOC_ODT_ENTRY for every ODT, then SET_DAQ_PTR/WRITE_DAQ,
SET_DAQ_LIST_MODE, on CAN SET_DAQ_ID for a list the link gives an id of its own, START_STOP_DAQ_LIST select,
START_STOP_SYNCH start; a static configuration has no
ALLOC_*: every DAQ list is stopped and the plan's lists are emptied with CLEAR_DAQ_LIST instead, so the
entries the plan does not fill stay empty and end each ODT and list), feeds the DTOs the link
receives to a :class:`~workbench.xcp.daq.assemble.DtoAssembler`, and hands out
:class:`DaqBatch`\\ es: a list's samples as one byte matrix with their times, so the decoding
into values is a few numpy operations per signal, not a Python loop per sample.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Hashable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import NoReturn

import numpy as np

from workbench.errors import (ConnectionLostError, EcuSilentError, InputError, WorkbenchError, XcpCommandError,
                              XcpTimeoutError, placeholder_hint)
from workbench.logs import logger
from workbench.xcp.daq.assemble import DtoAssembler
from workbench.xcp.daq.clock import DaqClock
from workbench.xcp.daq.plan import DaqListPlan, DaqPlan
from workbench.xcp.info import DaqProcessorInfo, DaqResolutionInfo
from workbench.xcp.master import XcpMaster
from workbench.xcp_protocol import CanId, Err

log = logger(__name__)

__all__ = ["DaqBatch", "DaqStats", "DaqStream"]

_START_SELECTED, _STOP_ALL = 1, 0
_SELECT = 2
_LOST_CHECK_S = 0.1  # a waiting read() looks this often whether the ECU is lost
PROBE_AFTER_S = 1.0  # no cyclic event tells when DTOs are due: after this long without any, the ECU is asked
_START_CHECKS = 3  # silences after the start before an answering ECU that sends no DTO is refused (late events)
_LIST_RUNNING = 0x40  # GET_DAQ_LIST_MODE's CURRENT_MODE bit RUNNING


@dataclass(frozen=True)
class DaqBatch:
    """Consecutive samples of one DAQ list."""

    daq_list: DaqListPlan
    time: np.ndarray  # s since the measurement's first sample, slave clock (host clock without timestamps)
    host_time: np.ndarray  # s since the epoch
    data: np.ndarray  # uint8 (samples, sample size)

    def __len__(self) -> int:
        return len(self.time)

    def column(self, key: Hashable) -> np.ndarray:
        """The bytes of signal ``key``: uint8 (samples, its size), in memory order."""
        return np.ascontiguousarray(self.data[:, self.daq_list.positions[key]])  # C order, so .view(dtype) works


@dataclass(frozen=True)
class DaqStats:
    dtos: int
    samples: int
    lost: int  # samples missing (a broken ODT sequence, or a gap in the slave's timestamps)
    overloads: int  # overload indications from the slave
    unknown: int  # DTOs of no list of this measurement


def _ms(seconds: float) -> str:
    return f"{seconds * 1000:.0f} ms"


@contextmanager
def _room_for(what: str, advice: str) -> Iterator[None]:
    """An ERR_MEMORY_OVERFLOW of the allocation inside as a sentence: the slave has no room for ``what``."""
    try:
        yield
    except XcpCommandError as error:
        if error.code != Err.MEMORY_OVERFLOW:
            raise
        raise WorkbenchError(f"the ECU has no room for {what} ({error.command}: {error.name}); {advice}") from error


class DaqStream:
    """``event_periods``: event number -> cycle in seconds (for gap detection; None: not cyclic). ``lock``: held
    by whoever sends commands on the master from other threads (a session's): a probe of the ECU (:meth:`read`)
    is sent only while no other command is under way."""

    def __init__(self, master: XcpMaster, plan: DaqPlan, processor: DaqProcessorInfo, resolution: DaqResolutionInfo,
                 event_periods: dict[int, float | None] | None = None, lock: threading.RLock | None = None):
        self.master = master
        self.lock = lock or threading.RLock()
        self.plan = plan
        self.processor = processor
        self.resolution = resolution
        self.event_periods = event_periods or {}
        self.clock = DaqClock(plan.timestamp_size, resolution.timestamp_resolution_s)
        self.assembler: DtoAssembler | None = None
        self._arrived = threading.Event()
        self._gaps: dict[int, int] = {}  # list -> samples missing from its timestamps
        self._last_time: dict[int, float] = {}
        self._probe_after: float | None = None  # seconds of silence after which the ECU is asked (no cycle to expect)
        self._silence: float | None = None
        self._first_dto_due: float | None = None  # time.monotonic() by which a DTO is due, until one came
        self._lists_due: float | None = None  # XCP on CAN: ... by which every list's is, until they were looked at
        self._no_dtos: str | None = None  # why DAQ sent nothing this master hears, the ECU answering
        self._start_checks = 0  # the silences since the start on which the ECU answered that its lists send here
        self._overload_events = 0
        self._due_lock = threading.Lock()  # the first DTO and a verdict on the silence before it take turns
        self.running = False

    # --- life cycle ---------------------------------------------------------------------------

    def start(self) -> DaqStream:
        """Write the plan into the slave and start every list at once.

        :raises InputError: the plan is for static lists and the slave's are dynamic, or the other way round.
        :raises XcpCommandError: the slave refuses the configuration (the message names the command).
        """
        master, plan = self.master, self.plan
        if plan.static == self.processor.dynamic:
            raise InputError(f"the DAQ plan is for {'static' if plan.static else 'dynamic'} lists but the slave's are "
                             f"{'dynamic' if self.processor.dynamic else 'static'}: plan again from what it reports")
        for attempt in range(2):
            try:
                self._configure()
                break
            except XcpTimeoutError as error:  # a slow slave: the master's SYNCH resynchronised, start over
                if attempt or isinstance(error, ConnectionLostError):  # ... unless SYNCH went unanswered too
                    raise
                log.info("DAQ configuration: a command timed out; configuring again")
        if not plan.lists:
            return self
        first_pids = {daq.number: master.start_stop_daq_list(daq.number, _SELECT) for daq in plan.lists}
        self._overload_events = master.link.overload_events  # EV_DAQ_OVERLOADs count from here
        self.assembler = DtoAssembler(plan, first_pids, master.order,
                                      overload_in_pid=self.processor.overload_indication == "PID")
        silence = self._silence = self.silence_limit()
        # a start without any DTO may be lists sending where this master does not listen (CAN: GET_DAQ_ID says), lists
        # the ECU does not run or events that do not run (Ethernet: GET_STATUS, GET_DAQ_LIST_MODE say), with the ECU
        # answering: the stream judges that silence itself (:meth:`_silent_from_start`), the link from the first DTO on
        judged_here = silence is not None
        self._no_dtos, self._start_checks = None, 0
        self._first_dto_due = time.monotonic() + master.timeouts.t1 + silence if judged_here else None  # START: <= T1
        self._lists_due = self._first_dto_due
        master.link.dto_handler = self._on_dto
        master.start_stop_synch(_START_SELECTED)
        if not judged_here:
            master.link.watch_dtos(silence)
        self._probe_after = None if silence is not None else max(self.master.timeouts.t1, PROBE_AFTER_S)
        self.running = True
        return self

    def silence_limit(self) -> float | None:
        """How long the ECU may stay silent before it counts as lost: 3 periods of the slowest cyclic event
        measured, at least T1; None when no list samples a cyclic event (XCPlite's events state no cycle: a
        silence then says nothing, and :meth:`read` asks the ECU after :data:`PROBE_AFTER_S` of it)."""
        periods = [period for daq in self.plan.lists if (period := self.event_periods.get(daq.event))]
        return max(self.master.timeouts.t1, 3 * max(periods)) if periods else None

    def _configure(self) -> None:
        """Lists, ODTs and entries as planned, then each list's mode: everything before the start (repeatable)."""
        master, plan = self.master, self.plan
        if plan.static:
            self._clear_static_lists()
        else:
            self._allocate()
        for daq in plan.lists:
            for number, odt in enumerate(daq.odts):
                if odt.entries:
                    master.set_daq_ptr(daq.number, number, 0)
                for entry in odt.entries:
                    try:
                        master.write_daq(entry.size, entry.address, entry.extension)
                    except XcpCommandError as exc:
                        raise exc.about(f"sampling {entry.size} bytes at 0x{entry.address:X}"
                                        + placeholder_hint(entry.address)) from None
            master.set_daq_list_mode(daq.number, daq.event, timestamp=daq.timestamps, prescaler=daq.prescaler,
                                     priority=daq.priority)
        self._assign_can_ids()

    def _assign_can_ids(self) -> None:
        """XCP on CAN: SET_DAQ_ID for the plan's lists the link assigns an id of their own (DAQ_LIST_CAN_ID VARIABLE),
        before they start; the link listens there already.

        :raises XcpCommandError: the slave refuses an id (the message names the list and the id).
        """
        assigned = dict(self.master.link.settings.assigned_daq_can_ids)
        for daq in self.plan.lists:
            can_id = assigned.get(daq.number)
            if can_id is None:
                continue
            try:
                self.master.set_daq_id(daq.number, can_id)
            except XcpCommandError as exc:
                raise exc.about(f"moving DAQ list {daq.number}'s DTOs to CAN id {can_id}") from None

    def _allocate(self) -> None:
        """Dynamic lists for the plan: FREE_DAQ, ALLOC_DAQ, every ALLOC_ODT, every ALLOC_ODT_ENTRY.

        :raises WorkbenchError: the slave has no room for them (ERR_MEMORY_OVERFLOW): the message says what to
            measure less of. Its MAX_DAQ cannot tell beforehand: a dynamic configuration may count in it only
            the lists allocated so far.
        """
        master, plan = self.master, self.plan
        master.free_daq()
        if not plan.lists:
            return
        events = len(plan.lists)
        with _room_for(f"the DAQ lists of {events} event(s)", "measure fewer events at once"):
            master.alloc_daq(events)  # dynamic lists are numbered from MIN_DAQ: the plan starts there
        with _room_for(f"{plan.odt_count} ODTs", "measure fewer signals at once"):
            for daq in plan.lists:
                master.alloc_odt(daq.number, len(daq.odts))
        with _room_for(f"{sum(len(odt.entries) for daq in plan.lists for odt in daq.odts)} ODT entries",
                       "measure fewer signals at once"):
            for daq in plan.lists:
                for number, odt in enumerate(daq.odts):
                    master.alloc_odt_entry(daq.number, number, len(odt.entries))

    def _clear_static_lists(self) -> None:
        """Static lists for the plan: stop every list (a running one cannot be cleared), empty the plan's."""
        self.master.start_stop_synch(_STOP_ALL)
        for daq in self.plan.lists:
            self.master.clear_daq_list(daq.number)

    def _on_dto(self, dto: bytes, host_ns: int) -> None:
        self.assembler.feed(dto, host_ns)
        self._arrived.set()
        if self._first_dto_due is not None:  # the first DTO: a silence from now on is the link's to judge
            with self._due_lock:
                self._first_dto_due = None
            self.master.link.watch_dtos(self._silence)

    def stop(self) -> None:
        """Stop every list (START_STOP_SYNCH stop all), stop taking DTOs; safe to call twice.

        The link keeps the DTOs that came before the stop: :meth:`read` still returns them.
        """
        if not self.running:
            return
        self.running = False
        try:
            self.master.start_stop_synch(_STOP_ALL)
        finally:
            self.master.link.dto_handler = None

    # --- data ---------------------------------------------------------------------------------

    def read(self, timeout_s: float | None = 0.0) -> list[DaqBatch]:
        """The samples that arrived since the last read, one batch per list; waits up to ``timeout_s``
        for the first one (None: until one arrives).

        :raises ConnectionLostError: none came and the ECU is lost (:meth:`silence_limit`, a broken link): at
            once when it is lost already, within :data:`_LOST_CHECK_S` when that happens during the wait.
        :raises WorkbenchError: no DTO came since the start though the ECU answers (the message says what it
            answered: on CAN where GET_DAQ_ID puts the lists, on Ethernet whether they run), or on CAN none of a list
            while others' came, and GET_DAQ_ID puts it where this master does not listen (the message names where
            the lists send, and where this master listens).
        """
        if self.assembler is None:
            return []
        if self._lists_due is not None and self.running and self._first_dto_due is None and self.master.link.is_can \
                and time.monotonic() >= self._lists_due:
            self._silent_lists()
        samples = self.assembler.take()
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        while not samples:  # what came before a loss is returned first; then the loss is said at once
            self._check_link()
            left = _LOST_CHECK_S if deadline is None else min(_LOST_CHECK_S, deadline - time.monotonic())
            if left <= 0:
                break
            self._arrived.wait(left)
            self._arrived.clear()
            samples = self.assembler.take()
        by_list: dict[int, list] = {}
        for sample in samples:
            by_list.setdefault(sample.daq_list, []).append(sample)
        lists = {daq.number: daq for daq in self.plan.lists}
        return [self._batch(lists[number], found) for number, found in by_list.items()]

    def _check_link(self) -> None:
        if not self.running:
            return
        link = self.master.link
        link.check()
        if self._first_dto_due is not None and time.monotonic() >= self._first_dto_due:
            self._silent_from_start()
        if self._no_dtos is not None:
            raise WorkbenchError(self._no_dtos)
        if self._probe_after is not None and link.quiet_s >= self._probe_after:
            self._probe()

    def _silent_from_start(self) -> None:
        """No DTO since the start for the silence limit: ask the ECU why (:meth:`_why_silent`). Unanswered with its
        SYNCH, the ECU is lost; answered, its lists send where this master does not listen or do not run (said at
        once), or their events do not run (said after :data:`_START_CHECKS` silences: events may start late) —
        :attr:`_no_dtos` says which. Skipped while another thread has a command under way (asked at the next
        check). A DTO that comes while the answer is judged wins: the receiver's first DTO and this verdict
        take turns (:attr:`_due_lock`).

        :raises ConnectionLostError: the ECU is gone.
        """
        if not self.lock.acquire(blocking=False):
            return
        silence = self._silence
        try:
            where, certain = self._why_silent()
            checks = _START_CHECKS if certain else self._start_checks + 1
            waited = silence if certain else silence * _START_CHECKS
            refusal = f"DAQ: no DTO within {_ms(waited)} of the start, though the ECU answers: {where}"
            with self._due_lock:
                if self._first_dto_due is None:  # a DTO came meanwhile: the receiver was only late
                    return
                self._start_checks = checks
                if checks < _START_CHECKS:  # an ECU still starting its events, a host too loaded to hear them
                    self._first_dto_due = self._lists_due = time.monotonic() + silence  # the other lists wait alike
                else:
                    self._first_dto_due = self._lists_due = None
                    self._no_dtos = refusal
            if checks < _START_CHECKS:
                log.info("DAQ: no DTO yet, %s after the start: %s", _ms(silence * checks), where)
        finally:
            self.lock.release()

    def _why_silent(self) -> tuple[str, bool]:
        """Why no DTO came since the start, as the ECU tells it, and whether that is certain (nothing this master
        hears will come): on CAN where GET_DAQ_ID puts the lists, on Ethernet whether GET_STATUS and
        GET_DAQ_LIST_MODE say they run.

        :raises ConnectionLostError: the ECU answers neither the question nor SYNCH, or the link broke under it.
        """
        if not self.master.link.is_can:
            return self._running_lists()
        try:
            sends = self._daq_can_ids([daq.number for daq in self.plan.lists])
        except EcuSilentError:
            self._give_up("GET_DAQ_ID")
        except ConnectionLostError:  # the link broke under the command: no answer to judge
            raise
        except XcpCommandError as error:  # GET_DAQ_ID is optional
            return (f"it does not say where its DAQ lists send ({error.command}: {error.name}); this master listens on "
                    f"{self._listens()}: the A2L's XCP_ON_CAN may miss the ECU's DAQ_LIST_CAN_ID, or its events do not "
                    "run"), False
        except WorkbenchError as error:  # unanswered (SYNCH answered), or an answer naming no id
            return f"{error}; this master listens on {self._listens()}", False
        elsewhere = self._elsewhere(sends)
        if elsewhere is not None:
            return elsewhere, True
        return (f"GET_DAQ_ID says its lists send on {', '.join(dict.fromkeys(str(i) for i, _ in sends.values()))}, "
                "where this master listens: the ECU's events do not run (is its application started?)"), False

    def _running_lists(self) -> tuple[str, bool]:
        """XCP on Ethernet (no GET_DAQ_ID: the ECU answers this master's address): whether GET_STATUS says DAQ runs
        and GET_DAQ_LIST_MODE (optional) which of the lists do. See :meth:`_why_silent`."""
        numbers = [daq.number for daq in self.plan.lists]
        try:
            if not self.master.get_status().daq_running:
                return "GET_STATUS says no DAQ list runs: the ECU stopped them (another master, or its application?)", \
                    True
            try:
                modes = {number: self.master.get_daq_list_mode(number)[0] for number in numbers}
            except XcpCommandError as error:
                return (f"GET_STATUS says its DAQ runs ({error.command}: {error.name} tells no more): the ECU's events "
                        "do not run (is its application started?)"), False
        except EcuSilentError:
            self._give_up("GET_STATUS")
        except ConnectionLostError:
            raise
        except WorkbenchError as error:  # unanswered (SYNCH answered), or a refusal of GET_STATUS
            return f"{error}", False
        stopped = [number for number, mode in modes.items() if not mode & _LIST_RUNNING]
        if stopped:
            return (f"GET_DAQ_LIST_MODE says DAQ list{'s' if len(stopped) > 1 else ''} "
                    f"{', '.join(map(str, stopped))} do{'' if len(stopped) > 1 else 'es'} not run: the ECU stopped "
                    f"{'them' if len(stopped) > 1 else 'it'} (another master?)"), True
        return (f"GET_STATUS and GET_DAQ_LIST_MODE say DAQ lists {', '.join(map(str, numbers))} run: the ECU's events "
                "do not run (is its application started?)"), False

    def _silent_lists(self) -> None:
        """XCP on CAN, DTOs came but none of some list for the silence limit: where GET_DAQ_ID puts that list, if
        this master does not listen there, is :attr:`_no_dtos`; a list on an id it hears is left to its event
        (which may not run yet). Asked once; skipped while another thread has a command under way.

        :raises WorkbenchError: a list sends where this master does not listen (ConnectionLostError: the ECU is gone).
        """
        if not self.lock.acquire(blocking=False):
            return
        try:
            self._lists_due = None
            silent = self.assembler.silent_lists
            if not silent:
                return
            try:
                elsewhere = self._elsewhere(self._daq_can_ids(silent))
            except EcuSilentError:
                self._give_up("GET_DAQ_ID")
            except ConnectionLostError:
                raise
            except WorkbenchError as error:  # no GET_DAQ_ID, or no answer: nothing to tell
                log.info("DAQ lists %s silent; GET_DAQ_ID: %s", silent, error)
                return
            if elsewhere:
                self._no_dtos = (f"DAQ: no DTO of list {', '.join(map(str, silent))} within {_ms(self._silence)} of "
                                 f"the start, though the others' came: {elsewhere}")
        finally:
            self.lock.release()
        if self._no_dtos is not None:
            raise WorkbenchError(self._no_dtos)

    def _give_up(self, asked: str) -> NoReturn:
        """The ECU answers neither ``asked`` (the command that asked it why DAQ is silent) nor SYNCH: the link is lost
        from now on (every command says so at once), as when the link finds DAQ silent.

        :raises ConnectionLostError: always.
        """
        link = self.master.link
        link.give_up(f"nothing from the ECU for {_ms(link.quiet_s)} while DAQ runs (a DTO was due within "
                     f"{_ms(self._silence)}), nor an answer to {asked} or SYNCH")
        link.check()

    def _daq_can_ids(self, numbers: list[int]) -> dict[int, tuple[CanId, bool]]:
        """GET_DAQ_ID of the lists ``numbers``: each one's CAN id, and whether it is fixed.

        :raises EcuSilentError: the ECU answers neither GET_DAQ_ID nor SYNCH. :raises XcpCommandError: it refuses
            GET_DAQ_ID. :raises WorkbenchError: no answer (SYNCH answered), or one that names no id.
        """
        return {number: self.master.get_daq_id(number) for number in numbers}

    def _heard_ids(self) -> tuple[CanId, ...]:
        settings = self.master.link.settings
        return tuple(dict.fromkeys((settings.can_id_slave, *settings.dto_can_ids)))

    def _listens(self) -> str:
        return ", ".join(map(str, self._heard_ids()))

    def _elsewhere(self, sends: dict[int, tuple[CanId, bool]]) -> str | None:
        """The lists of ``sends`` on ids this master does not listen on and what the A2L should state, in a
        sentence; None: every one sends where it listens."""
        heard = self._heard_ids()
        elsewhere = {number: found for number, found in sends.items() if found[0] not in heard}
        if not elsewhere:
            return None
        lists = ", ".join(f"list {number} on {can_id} ({'fixed' if fixed else 'configurable'})"
                          for number, (can_id, fixed) in elsewhere.items())
        statements = ", ".join(f"DAQ_LIST_CAN_ID {number} FIXED 0x{can_id.a2l:X}" if fixed else
                               f"DAQ_LIST_CAN_ID {number} VARIABLE" for number, (can_id, fixed) in elsewhere.items())
        return (f"GET_DAQ_ID puts DAQ {lists}, where this master does not listen (it listens on {self._listens()}); "
                f"the A2L's XCP_ON_CAN should say so: {statements}")

    def _probe(self) -> None:
        """Ask a silent ECU whether it is there (GET_STATUS): on UDP a host where nothing listens any more says so
        with the datagram (the link breaks), a dead ECU leaves the command and its SYNCH unanswered
        (EcuSilentError). Skipped while another thread has a command under way: that one asks as well.

        :raises ConnectionLostError: the ECU is gone.
        """
        if not self.lock.acquire(blocking=False):
            return
        quiet = self.master.link.quiet_s
        try:
            self.master.get_status()
        except EcuSilentError:
            self.master.link.give_up(
                f"nothing from the ECU for {quiet:.1f} s while DAQ ran, and it answers neither GET_STATUS nor SYNCH: "
                "it stopped, or another master connected to it (a second workbench, CANape: XCP serves one master "
                "at a time)")
            self.master.link.check()
        except ConnectionLostError:
            raise
        except XcpTimeoutError:  # SYNCH was answered: the ECU is there
            log.info("DAQ: GET_STATUS unanswered, SYNCH answered: the ECU is there, its events are silent")
        except XcpCommandError as error:  # an answer all the same
            log.info("DAQ: the ECU answered GET_STATUS with %s", error.name)
        finally:
            self.lock.release()

    def _batch(self, daq: DaqListPlan, samples: list) -> DaqBatch:
        host_ns = np.fromiter((s.host_ns for s in samples), dtype=np.int64, count=len(samples))
        counts = (np.fromiter((s.timestamp for s in samples), dtype=np.int64, count=len(samples))
                  if daq.timestamps else None)
        time, host_time = self.clock.times(daq.number, counts, host_ns, self.event_periods.get(daq.event))
        data = np.frombuffer(b"".join(s.data for s in samples), dtype=np.uint8).reshape(len(samples), daq.sample_size)
        self._count_gaps(daq, time)
        return DaqBatch(daq, time, host_time, data)

    def _count_gaps(self, daq: DaqListPlan, time: np.ndarray) -> None:
        """Samples the slave did not send (NO_OVERLOAD_INDICATION slaves drop them silently): gaps in its timestamps."""
        period = self.event_periods.get(daq.event)
        if not period or not daq.timestamps or not len(time):
            return
        previous = self._last_time.get(daq.number)
        times = np.concatenate(([previous], time)) if previous is not None else time
        steps = np.rint(np.diff(times) / period).astype(np.int64)
        self._gaps[daq.number] = self._gaps.get(daq.number, 0) + int(np.sum(np.maximum(steps - 1, 0)))
        self._last_time[daq.number] = float(time[-1])

    @property
    def stats(self) -> DaqStats:
        assembler = self.assembler
        if assembler is None:
            return DaqStats(0, 0, 0, 0, 0)
        # a timestamp gap counts every missing sample, broken ones included; without timestamps only broken ones show
        lost = sum(self._gaps.get(number, broken) for number, broken in assembler.lost_by_list.items())
        overloads = assembler.overloads + self.master.link.overload_events - self._overload_events  # PID bits, EVs
        return DaqStats(assembler.dtos, assembler.samples, lost, overloads, assembler.unknown)

    @property
    def dtos_per_second(self) -> float | None:
        """The DTOs the plan's lists send per second (each list's ODTs once per its event's period, prescaler
        included); None when an event's period is not known."""
        total = 0.0
        for daq in self.plan.lists:
            period = self.event_periods.get(daq.event)
            if not period:
                return None
            total += len(daq.odts) / period
        return total

    def close(self) -> None:
        """Stop (if running) and free the slave's DAQ lists (static ones: clear the plan's); errors are logged, not
        raised (this runs on the way out)."""
        try:
            self.stop()
            if self.plan.static:
                for daq in self.plan.lists:
                    self.master.clear_daq_list(daq.number)
            else:
                self.master.free_daq()
        except ConnectionLostError as exc:  # said where it was found; nothing to stop on a lost ECU
            log.debug("stopping DAQ: %s", exc)
        except WorkbenchError as exc:
            log.warning("stopping DAQ: %s", exc)

    def __enter__(self) -> DaqStream:
        return self.start()

    def __exit__(self, *exc_info) -> None:
        self.close()
