"""Measuring by name with DAQ: signals grouped by event, sampled by the ECU, delivered in physical units.

::

    with ecu.measure(["zsRailPressure", "xsDC"]) as live:      # each on its A2L DAQ event
        for batch in live:                                      # SampleBatch per event, as they come
            print(batch.time[-1], batch.values["zsRailPressure"][-1])

A measurement plans its DAQ lists from what the slave reports (see :mod:`workbench.xcp.daq.plan`),
decodes samples in batches with numpy, stamps them with the ECU's clock, and counts what was lost.
One DAQ measurement runs per session at a time (the slave's DAQ lists are shared); closing the
session stops it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.objects import Characteristic, Measurement
from workbench.a2l.xcp import XcpConfig, read_daq_events
from workbench.calib.signals import MeasurementCodec, measurement_codec
from workbench.errors import InputError, WorkbenchError, XcpCommandError
from workbench.logs import logger
from workbench.xcp.daq import DaqSignal, DaqStats, DaqStream, plan_daq
from workbench.xcp.info import DaqEventInfo, DaqListInfo, DaqProcessorInfo, DaqResolutionInfo
from workbench.xcp_protocol import Err

if TYPE_CHECKING:
    from workbench.a2l.model import A2lModel
    from workbench.session.session import Session

log = logger(__name__)

__all__ = ["DaqMeasurement", "SampleBatch", "event_number"]

CAN_FRAME_BITS = 125  # an 8-byte classic frame: 111 bits and its stuff bits (at most 135)
BUSY_SHARE = 0.8  # DTOs above this share of the frames a bus carries leave no room for others' frames and jitter


@dataclass(frozen=True)
class SampleBatch:
    """Consecutive samples of the signals on one event."""

    event: int
    event_name: str
    time: np.ndarray  # s since the measurement's first sample, by the ECU's clock
    host_time: np.ndarray  # s since the epoch (the ECU's clock mapped to the host's)
    values: dict[str, np.ndarray]  # name -> physical values, shape (samples,) or (samples, *its shape)

    def __len__(self) -> int:
        return len(self.time)


class DaqMeasurement:
    """A DAQ measurement of ``names`` (MEASUREMENTs, or globs of them: ``zsRail*``), each on ``event`` or the event
    the A2L names for it."""

    def __init__(self, session: Session, names: Sequence[str], event: str | int | None = None, prescaler: int = 1):
        if not names:
            raise InputError("name at least one signal to measure")
        self.session = session
        model = session.model
        self.names = list(dict.fromkeys(model.expand(names, "MEASUREMENT", what="measurement")))  # globs as the CLI
        self.codecs: dict[str, MeasurementCodec] = {}
        for name in self.names:
            obj = model.object(name)
            signal = obj if isinstance(obj, Measurement) else sampled_characteristic(model, obj)
            if signal is None:
                kind = type(obj).__name__.upper() + (f" ({obj.type})" if isinstance(obj, Characteristic) else "")
                raise InputError(f"{name} is a {kind}: DAQ samples MEASUREMENTs and VALUE or VAL_BLK calibrations; "
                                 "read it by polling (measure without --daq, or Session.read)")
            self.codecs[name] = measurement_codec(model, signal)
        self.events = self._events(event)
        self.prescaler = prescaler
        self.stream: DaqStream | None = None
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()

    # --- which event --------------------------------------------------------------------------

    def _events(self, event: str | int | None) -> dict[str, int]:
        """name -> event number: the one asked for, else the A2L's DAQ_EVENT of the signal, else the fastest."""
        chosen = self.session.event_number(event) if event is not None else None
        events: dict[str, int] = {}
        for name in self.names:
            preference = read_daq_events(self.session.model.block(name))
            if chosen is not None:
                if preference.fixed and chosen not in preference.fixed:
                    raise InputError(f"{name} can only be measured on event(s) "
                                     f"{', '.join(map(str, preference.fixed))} (its FIXED_EVENT_LIST), not {chosen}")
                events[name] = chosen
            else:
                preferred = preference.preferred
                events[name] = preferred if preferred is not None else self.session.fastest_event()
        return events

    # --- life cycle ---------------------------------------------------------------------------

    def start(self) -> DaqMeasurement:
        """Configure and start the DAQ lists. :raises XcpCommandError: the slave refused the configuration."""
        session = self.session
        with session.lock:
            session.claim_daq(self)
            try:
                master = session.master
                processor, resolution = session.daq_processor_info(), session.daq_resolution_info()
                groups: dict[int, list[DaqSignal]] = {}
                for name, codec in self.codecs.items():
                    span = codec.span
                    groups.setdefault(self.events[name], []).append(
                        DaqSignal(name, span.address, span.size, span.extension, codec.element_size))
                info = {number: session.event_info(number) for number in groups}
                static = None if processor.dynamic else [session.daq_list_info(n) for n in range(processor.max_daq)]
                plan = plan_daq(groups, processor, resolution, master.max_dto, first_list=processor.min_daq,
                                consistency={n: i.consistency for n, i in info.items() if i is not None},
                                prescaler=self.prescaler, static_lists=static, event_name=session.event_name,
                                address_granularity=master.granularity)
                self.stream = DaqStream(master, plan, processor, resolution,
                                        {n: i.period_s * self.prescaler for n, i in info.items()
                                         if i is not None and i.period_s}, lock=session.lock)
                self.stream.start()
            except BaseException:
                session.release_daq(self)
                raise
        return self

    def stop(self) -> None:
        """Stop sampling (the samples already received can still be read); safe to call twice."""
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2)
        stream, session = self.stream, self.session
        if stream is None or not stream.running:
            return
        with session.lock:
            try:
                stream.close()
            finally:
                session.release_daq(self)

    close = stop

    def __enter__(self) -> DaqMeasurement:
        return self.start() if self.stream is None else self

    def __exit__(self, *exc_info) -> None:
        self.stop()

    # --- data ---------------------------------------------------------------------------------

    def read(self, timeout_s: float | None = 0.0) -> list[SampleBatch]:
        """The samples since the last read, one batch per event (waits up to ``timeout_s`` for the first)."""
        if self.stream is None:
            raise WorkbenchError("the measurement has not been started")
        batches = []
        for batch in self.stream.read(timeout_s):
            keys = batch.daq_list.keys
            values = {name: self.codecs[name].decode_samples(batch.column(name).tobytes(), len(batch)) for name in keys}
            event = batch.daq_list.event
            batches.append(SampleBatch(event, self.session.event_name(event), batch.time, batch.host_time, values))
        return batches

    def __iter__(self) -> Iterator[SampleBatch]:
        """Batches as they arrive, until :meth:`stop`."""
        while not self._stop.is_set():
            yield from self.read(0.1)

    def on_samples(self, callback: Callable[[SampleBatch], Any]) -> None:
        """Call ``callback(batch)`` from a thread of the measurement's own for every batch, until :meth:`stop`.
        An exception in the callback stops the delivery (it is logged)."""
        if self._thread is not None:
            raise WorkbenchError("samples already go to a callback")

        def deliver() -> None:
            try:
                for batch in self:
                    callback(batch)
            except Exception:  # the user's callback: log it with its traceback, stop delivering
                log.exception("the sample callback failed; delivery stopped")

        self._thread = threading.Thread(target=deliver, name="daq-callback", daemon=True)
        self._thread.start()

    @property
    def stats(self) -> DaqStats:
        return self.stream.stats if self.stream is not None else DaqStats(0, 0, 0, 0, 0)

    @property
    def running(self) -> bool:
        return self.stream is not None and self.stream.running

    @property
    def time_source(self) -> str:
        """Which clock the samples' ``time`` comes from, for people: the ECU's DAQ timestamps (their size and
        tick), or the master's receive time when the ECU sends none or the plan left them no room (classic CAN);
        "" before :meth:`start`."""
        stream = self.stream
        if stream is None:
            return ""
        if stream.plan.timestamp_size:
            tick = stream.resolution.timestamp_resolution_s
            return f"the ECU's DAQ timestamps ({stream.plan.timestamp_size}-byte counter of {tick * 1e6:g} us ticks)"
        return "the master's receive time (the ECU sends no DAQ timestamps with these lists)"

    @property
    def ecu_timestamps(self) -> bool:
        """Whether the samples are timed by the ECU's DAQ timestamps (False before :meth:`start`)."""
        return self.stream is not None and bool(self.stream.plan.timestamp_size)

    def stray_dtos(self) -> str:
        """The DTOs that came on the ECU's DAQ ids but belong to no list of this measurement, and what they probably
        are; "" for none."""
        unknown = self.stats.unknown
        if not unknown:
            return ""
        return (f"{unknown} DTO(s) of no DAQ list of this measurement: another master's DAQ on this ECU (CANape, a "
                "second workbench), or lists an earlier session left running")

    def loss_cause(self) -> str:
        """Why samples were lost when the CAN bus is the likely cause: the DTOs per second the lists send beside
        what a classic CAN bus of the session's bit rate carries; "" when nothing was lost, the bit rate is not
        known (a software bus given none) or the plan fits the bus."""
        link, bus = self.session.link, self.session.bus_spec
        rate = self.stream.dtos_per_second if self.stream is not None else None
        if (not self.stats.lost or rate is None or not link.is_can or link.settings.fd or bus is None
                or not bus.bitrate):
            return ""
        carried = bus.bitrate / CAN_FRAME_BITS
        if rate < BUSY_SHARE * carried:
            return ""
        return (f"the DAQ lists send {rate:,.0f} DTOs/s, {rate / carried:.0%} of the about {carried:,.0f} frames/s "
                f"CAN carries at {bus.bitrate / 1000:g} kbit/s: measure fewer signals on the fast events, or on a "
                "slower event")


class EventAccess:
    """Mixed into :class:`Session`: DAQ events by name and the one running measurement."""

    lock: Any

    def measure(self: Session, names: Sequence[str], *, event: str | int | None = None,
                prescaler: int = 1) -> DaqMeasurement:
        """A DAQ measurement of ``names``; start it with ``with`` (or :meth:`DaqMeasurement.start`).

        :param event: one event (name or number) for every signal (default: each signal's A2L DAQ_EVENT).
        :param prescaler: a sample every ``prescaler`` events, when the slave offers PRESCALER_SUPPORTED.
        :raises WorkbenchError: the ECU is in its boot loader (nothing to measure there).
        """
        self.require_application()
        return DaqMeasurement(self, names, event, prescaler)

    def event_number(self: Session, event: str | int) -> int:
        """An event by number, or by the name or short name the A2L gives it (:func:`event_number`)."""
        return event_number(self.config, event)

    def event_name(self: Session, number: int) -> str:
        daq = self.config.daq
        for known in daq.events if daq else ():
            if known.number == number:
                return known.name
        info = self.event_info(number)
        return info.name if info is not None and info.name else f"event {number}"

    def fastest_event(self: Session) -> int:
        """The A2L's cyclic DAQ event with the shortest period (0 when the A2L lists none)."""
        daq = self.config.daq
        cyclic = [event for event in (daq.events if daq else ()) if event.period_s]
        return min(cyclic, key=lambda event: event.period_s).number if cyclic else 0

    def event_info(self: Session, number: int) -> DaqEventInfo | None:
        """GET_DAQ_EVENT_INFO of an event (cached); where the slave does not offer it (or refuses the event), what the
        A2L's EVENT says; None when neither knows the event."""
        cache = self._event_info
        if number not in cache:
            try:
                cache[number] = self.master.get_daq_event_info(number)
            except XcpCommandError as error:
                log.debug("GET_DAQ_EVENT_INFO %d: %s; the A2L's EVENT instead", number, error)
                cache[number] = _a2l_event_info(self.config, number)
        return cache[number]

    def daq_processor_info(self: Session) -> DaqProcessorInfo:
        """GET_DAQ_PROCESSOR_INFO; from a slave that does not implement it, what the A2L's DAQ block states (see
        :meth:`daq_resolution_info`)."""
        daq = self._a2l_daq_for(self.master.get_daq_processor_info)
        if isinstance(daq, DaqProcessorInfo):
            return daq
        return DaqProcessorInfo(
            dynamic=daq.config_type == "DYNAMIC", prescaler_supported=daq.prescaler_supported,
            resume_supported=daq.resume_supported, timestamp_supported=bool(daq.timestamp and daq.timestamp.size),
            pid_off_supported=False, overload_indication=_A2L_OVERLOAD.get(daq.overload_indication, "none"),
            max_daq=daq.max_daq, max_event_channels=daq.max_event_channels, min_daq=daq.min_daq, optimisation_type=0,
            address_extension=_A2L_EXTENSION.get(daq.address_extension, "free"),
            identification_field=daq.identification_field)

    def daq_resolution_info(self: Session) -> DaqResolutionInfo:
        """GET_DAQ_RESOLUTION_INFO; from a slave that does not implement it (ERR_CMD_UNKNOWN: it is optional), what the
        A2L's DAQ block states (GRANULARITY_ODT_ENTRY_SIZE_DAQ, MAX_ODT_ENTRY_SIZE_DAQ, TIMESTAMP_SUPPORTED), as ASAM's
        error matrix says ("use the A2L").

        :raises XcpCommandError: another refusal, or the A2L has no DAQ block to take it from.
        """
        daq = self._a2l_daq_for(self.master.get_daq_resolution_info)
        if isinstance(daq, DaqResolutionInfo):
            return daq
        stamp = daq.timestamp
        if stamp is None or not stamp.size:
            return DaqResolutionInfo(daq.granularity, daq.max_odt_entry_size, 0, False, 1e-6, 1)
        return DaqResolutionInfo(daq.granularity, daq.max_odt_entry_size, stamp.size, stamp.fixed, stamp.unit_s,
                                 max(stamp.ticks, 1))

    def daq_list_info(self: Session, number: int) -> DaqListInfo:
        """GET_DAQ_LIST_INFO of a static or predefined list; from a slave that does not implement it, the A2L's DAQ_LIST
        of that number (see :meth:`daq_resolution_info`).

        :raises XcpCommandError: another refusal, or the A2L states no such DAQ_LIST.
        """
        try:
            return self.master.get_daq_list_info(number)
        except XcpCommandError as error:
            stated = {daq_list.number: daq_list for daq_list in (self.config.daq.lists if self.config.daq else ())}
            if error.code != Err.CMD_UNKNOWN:
                raise
            if number not in stated:
                raise error.about(f"DAQ list {number} (the A2L's DAQ has no DAQ_LIST {number} to tell its ODTs)") \
                    from None
            log.info("GET_DAQ_LIST_INFO: ERR_CMD_UNKNOWN; the A2L's DAQ_LIST %d instead", number)
            known = stated[number]
            return DaqListInfo(number, known.predefined, known.fixed_event, known.direction, known.max_odt,
                               known.max_odt_entries)

    def _a2l_daq_for(self: Session, ask: Callable[[], Any]) -> Any:
        """What ``ask`` (a GET_DAQ_..._INFO) answers, or the A2L's DAQ block where the slave does not implement it.

        :raises XcpCommandError: another refusal, or the A2L has no DAQ block.
        """
        try:
            return ask()
        except XcpCommandError as error:
            daq = self.config.daq
            if error.code != Err.CMD_UNKNOWN or daq is None:
                raise
            log.info("%s: ERR_CMD_UNKNOWN; the A2L's DAQ block instead", error.command)
            return daq

    def claim_daq(self: Session, measurement: DaqMeasurement) -> None:
        running = self._daq
        if running is not None and running is not measurement and running.running:
            raise InputError("a DAQ measurement is running in this session: stop it first, or measure all the "
                             "signals in one measure() call")
        self._daq = measurement

    def release_daq(self: Session, measurement: DaqMeasurement) -> None:
        if self._daq is measurement:
            self._daq = None


_A2L_OVERLOAD = {"OVERLOAD_INDICATION_PID": "PID", "OVERLOAD_INDICATION_EVENT": "event"}
_A2L_EXTENSION = {"ADDRESS_EXTENSION_ODT": "per ODT", "ADDRESS_EXTENSION_DAQ": "per DAQ list"}


def _a2l_event_info(config: XcpConfig, number: int) -> DaqEventInfo | None:
    """The A2L's EVENT ``number`` as GET_DAQ_EVENT_INFO would say it (consistency unknown: ODT, the least)."""
    for event in config.daq.events if config.daq else ():
        if event.number == number:
            return DaqEventInfo(number, event.name, event.direction, event.max_daq_lists, event.period_s,
                                event.priority, "ODT")
    return None


def sampled_characteristic(model: A2lModel, obj: Any) -> Measurement | None:
    """A VALUE or VAL_BLK CHARACTERISTIC whose RECORD_LAYOUT is its values alone (FNC_VALUES, DIRECT) as the
    MEASUREMENT DAQ samples, as CANape measures a calibration (XCPlite gives the parameters on its stacks a
    DAQ_EVENT and writes its measured arrays as VAL_BLKs); None for anything else (curves and maps carry axes)."""
    if not isinstance(obj, Characteristic) or obj.type not in ("VALUE", "VAL_BLK"):
        return None
    layout = model.record_layout_of(obj)
    values = layout.fnc_values
    if values is None or values.addressing not in (None, "DIRECT") or len(layout.entries) != 1:
        return None
    return Measurement(obj.name, obj.long_identifier, obj.address, obj.address_extension, datatype=values.datatype,
                       conversion=obj.conversion, lower_limit=obj.lower_limit, upper_limit=obj.upper_limit,
                       byte_order=obj.byte_order, bit_mask=obj.bit_mask, matrix_dim=obj.matrix_dim,
                       array_size=obj.number if obj.type == "VAL_BLK" else None, layout=values.mode,
                       discrete=obj.discrete, format=obj.format, phys_unit=obj.phys_unit)


def event_number(config: XcpConfig, event: str | int) -> int:
    """A DAQ event by number, or by the name or short name the A2L's IF_DATA XCP gives it (checked before
    connecting: a name the A2L lacks needs no ECU to be refused).

    :raises InputError: a name or number the A2L has no event of (its events are listed; a number passes when
        the A2L lists none).
    """
    daq = config.daq
    events = list(daq.events) if daq else []
    if isinstance(event, int) or (isinstance(event, str) and event.isdigit()):
        if not events or int(event) in {known.number for known in events}:
            return int(event)
    for known in events:
        if event in (known.name, known.short_name):
            return known.number
    names = [f"{known.number} {known.name}" if isinstance(event, int) or event.isdigit() else known.name
             for known in events]
    raise InputError(f"no DAQ event {event!r} (the A2L has {', '.join(names) or 'none'})")
