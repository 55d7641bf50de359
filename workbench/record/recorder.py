"""Recording a session to MDF4: DAQ signals, CAN2 frames decoded with a DBC, and the raw CAN bus.

::

    from workbench import Session
    from workbench.record import Recorder, record

    with Session.open(interface="udp_multicast", channel="239.74.163.2") as ecu:
        stats = record(ecu, "run.mf4", ["zsRailPressure", "xsTankCtrlState", "zsSensVolt"],
                       can2="dbc/FLCU_CAN2.dbc", raw_can=True, duration=60)
        print(stats.samples, stats.lost, stats.file_bytes)

        with Recorder(ecu, "run2.mf4", ["xsDC"]) as recording:   # non-blocking: a GUI keeps working
            ...                                                 # recording.stats while it runs
        # leaving the block (or closing the session) stops and finalizes the file

One thread takes the DAQ samples (the measurement's raw bytes, no decoding to physical values
unless ``on_samples`` wants them) and the CAN frames a python-can Notifier queued, turns them into
MDF records (:mod:`~workbench.record.daq_channels`, :mod:`~workbench.record.can_channels`) on
one time axis (:mod:`~workbench.record.timebase`) and appends them to the file, which is flushed
every ``flush_s`` (:mod:`~workbench.record.mdf_stream`): memory holds at most one period of samples,
and a recording that is killed leaves a file asammdf reads up to its last flush (marked unfinalized,
as MDF provides for loggers; :func:`~workbench.record.mdf_stream.finalize` marks it finalized for
tools that need that). Stopping finalizes the file.

The file is written where it was asked for from the first moment, so a killed recording is found
there. An existing file is replaced only with ``overwrite=True``, and only when the recording
ends: until then the recording goes to ``<name>.<random>.recording.mf4`` beside it (a kill leaves
both, the old file untouched).
"""

from __future__ import annotations

import getpass
import logging
import os
import tempfile
import threading
import time
import weakref
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench import __version__
from workbench.bus_defaults import BusSpec
from workbench.can import DbcFile, load_dbc
from workbench.errors import ConnectionLostError, InputError, WorkbenchError
from workbench.fileio import refuse_read_only
from workbench.logs import logger
from workbench.progress import Progress
from workbench.record.can_channels import CanMessageGroups, RawCanGroup
from workbench.record.daq_channels import DaqGroup
from workbench.record.mdf_stream import HeaderSpec, MdfStreamWriter, SourceSpec
from workbench.record.timebase import RecordingClock
from workbench.record.trigger import Trigger, TriggerGate, checked_trigger
from workbench.session.measure import SampleBatch

if TYPE_CHECKING:
    import can

    from workbench.session import Session
    from workbench.session.can_listeners import Listening

log = logger(__name__)

__all__ = ["CAN2_BUS_CHANNEL", "Recorder", "RecordingStats", "record", "size_text"]

CAN2_BUS_CHANNEL = 2  # the CAN2 bus's number in the bus log (CAN_DataFrame.BusChannel)
POLL_S = 0.05  # how often the recording thread takes what arrived
ORIGIN_WAIT_S = 1.0  # CAN frames wait this long for the first DAQ sample to fix the time axis
MDF_SUFFIXES = (".mf4", ".mdf")  # what a recording may be named: MDF4 under another suffix misleads
MAX_PENDING_BYTES = 16 << 20  # flush early when this much is waiting (a burst, a long flush period)
TIME_AXIS = "time channels: s since the start time."  # the header's time_axis starts so; the clocks follow


def size_text(file_bytes: int) -> str:
    """A file's size for people: MiB from 1 MiB on, KiB below (a short recording is not "0.0 MiB")."""
    return f"{file_bytes / 2**20:.1f} MiB" if file_bytes >= 2**20 else f"{file_bytes / 1024:.0f} KiB"


@dataclass(frozen=True)
class RecordingStats:
    """What a recording holds (so far, while it runs; counted when flushed to the file for ``samples``)."""

    path: Path
    seconds: float  # the last time written (s on the recording's axis)
    samples: int  # DAQ samples (records of the DAQ groups)
    values: int  # signal values in them (a sample of n signals holds n; an array counts once)
    lost: int  # DAQ samples the ECU or the bus lost (the measurement's count)
    overloads: int  # overload indications from the ECU
    can_frames: int  # CAN2 frames decoded into message groups
    raw_frames: int  # frames in the bus log
    undecoded: int  # frames of a DBC message that did not decode (wrong length): in the bus log only
    file_bytes: int
    started_s: float | None = None  # when a start trigger was met (s on the axis); None: not met (nothing recorded)
    trigger: str = ""  # the trigger's conditions, as said; "" without one
    multiplexed: tuple[str, ...] = ()  # the DBC's multiplexed messages: not decoded, in the bus log only

    def describe(self) -> str:
        """One line for people."""
        parts = [f"{self.samples:,} samples ({self.values:,} values, {self.lost} lost)"]
        if self.can_frames or self.undecoded:
            parts.append(f"{self.can_frames:,} CAN2 frames decoded" + (f", {self.undecoded} not" if self.undecoded else ""))
        if self.raw_frames:
            parts.append(f"{self.raw_frames:,} raw CAN frames")
        if self.multiplexed:
            parts.append(f"multiplexed messages not decoded ({', '.join(self.multiplexed)}"
                         + ("; in the raw CAN frames)" if self.raw_frames else "; log the raw CAN frames for them)"))
        size = size_text(self.file_bytes)
        if self.trigger:
            parts.append(f"{self.trigger}: " + ("never started" if self.started_s is None
                                                else f"started at {self.started_s:.3f} s"))
        return f"{self.path}: {self.seconds:.1f} s, " + ", ".join(parts) + f", {size}"


class Recorder:
    """Record ``signals`` (MEASUREMENTs or globs of them, by DAQ on each one's A2L event or on ``event``) of
    ``session``, and the CAN frames of the CAN2 bus, to the MDF4 file ``path``. A context manager (``start`` /
    ``stop``); stops by itself when the session closes.

    :param event, prescaler: as :meth:`~workbench.session.Session.measure` takes them.
    :param can2: a DBC (path or :class:`~workbench.can.DbcFile`): record the CAN2 bus's frames of
        its messages, decoded into one channel group per message.
    :param can_bus: the CAN2 bus, as a :class:`~workbench.bus_defaults.BusSpec`, python-can ``Bus``
        settings or an open bus (it stays the caller's); default: the session's XCP on CAN bus (the demo
        ECU sends its CAN2 messages there), listened to through the link's own receiver. Needed when the
        session runs XCP on Ethernet. Whoever else listens to the same bus through the session (the
        window's CAN monitor) shares its one bus object (:meth:`~workbench.session.Session.listen_can`).
    :param raw_can: also log every frame of that bus raw, as ASAM MDF bus logging (the XCP frames
        too, when XCP shares the bus).
    :param overwrite: replace an existing file when the recording ends (else an existing file is refused).
    :param flush_s: write to disk every ``flush_s`` seconds: what a kill can lose.
    :param compress: DZ blocks (transposed deflate; files about 5x smaller) or plain DT blocks.
    :param trigger: start and stop conditions on recorded signals and the seconds kept from before the start
        (:class:`~workbench.record.trigger.Trigger`); the recording ends by itself at the stop condition.
    :param on_samples: called with every DAQ batch in physical units (a
        :class:`~workbench.session.measure.SampleBatch`, ECU time) from the recording thread, e.g.
        for a live plot; it must return quickly. An exception in it is logged and it is not called again.
    :raises InputError: nothing to record, an unknown or non-MEASUREMENT signal, an unreadable DBC, or
        ``path`` exists (without ``overwrite``) or is a folder.
    """

    def __init__(self, session: Session, path: str | Path, signals: Sequence[str] = (), *,
                 event: str | int | None = None, prescaler: int = 1, can2: DbcFile | str | Path | None = None,
                 can_bus: BusSpec | Mapping[str, Any] | can.BusABC | None = None, raw_can: bool = False,
                 overwrite: bool = False,
                 flush_s: float = 1.0, compress: bool = True, trigger: Trigger | None = None,
                 on_samples: Callable[[SampleBatch], Any] | None = None):
        if not signals and can2 is None and not raw_can:
            raise InputError("nothing to record: name signals, a CAN2 DBC or raw CAN logging")
        self.session = session
        self.path = Path(path)
        if self.path.is_dir():
            raise InputError(f"{self.path}: is a folder; name the .mf4 file to record to")
        if self.path.suffix.lower() not in MDF_SUFFIXES:
            raise InputError(f"{self.path}: a recording is an MDF4 file; name it .mf4")
        if self.path.exists() and not overwrite:
            raise InputError(f"{self.path}: exists; record to another name or overwrite it "
                             "(overwrite=True, --overwrite: replaced when the recording ends)")
        refuse_read_only(self.path)  # --overwrite replaces a file, not one the user protected
        if trigger is not None:
            trigger = checked_trigger(trigger, session.model)
        self.measurement = session.measure(signals, event=event, prescaler=prescaler) if signals else None
        self.trigger = trigger
        missing = sorted((trigger.names if trigger else set()) - set(self.measurement.names if signals else ()))
        if missing:
            raise InputError(f"trigger on {', '.join(missing)}: a condition's signal must be recorded (name it too)")
        self._gate = TriggerGate(trigger)
        self._trigger_names = trigger.names if trigger else set()
        self.dbc = load_dbc(can2) if isinstance(can2, (str, Path)) else can2
        self.raw_can = raw_can
        self._can_bus = BusSpec.from_kwargs(can_bus) if isinstance(can_bus, Mapping) else can_bus
        self.flush_s = flush_s
        self.compress = compress
        self.on_samples = on_samples
        self._writer: MdfStreamWriter | None = None
        self._writing_path = self.path
        self._daq_index: dict[int, tuple[int, DaqGroup]] = {}  # event -> (its group in the file, the group)
        self._messages: CanMessageGroups | None = None
        self._message_base = 0  # the file's group of the DBC's first message
        self._raw: RawCanGroup | None = None
        self._raw_index = 0
        self._clock = RecordingClock()
        self._frames: deque = deque()
        self._listening: Listening | None = None
        self._thread: threading.Thread | None = None
        self._stopping = threading.Event()
        # The thread's end as the main thread waits for it: Python 3.11's Thread.join, interrupted by Ctrl-C,
        # marks a live thread as stopped (bpo-45274's fix), and stop() then closed the file under it.
        self._finished = threading.Event()
        self._lock = threading.Lock()
        self._error: BaseException | None = None
        self._stopped = False
        self._started_at = 0.0  # time.time() when the file was created: how long CAN frames wait for DAQ
        self._axis_start = 0.0  # the time axis's start when no DAQ sample fixes it: before the first CAN frame
        self._measuring_since = 0.0  # time.monotonic() when DAQ ran: what a duration counts from
        self._counts = {"samples": 0, "values": 0, "can_frames": 0, "raw_frames": 0, "undecoded": 0}
        self._last_time = 0.0
        self._last_frame_time: dict[int, float] = {}

    # --- starting -----------------------------------------------------------------------------

    def start(self) -> Recorder:
        """Open the CAN bus, start DAQ, create the file and start the recording thread.

        DAQ starts before the file is created: its plan tells whether the ECU stamps the samples, and the file
        says which clock its times come from (the samples that come meanwhile wait in the measurement).

        :raises InputError: the CAN2 bus is not known (see ``can_bus``), or the file cannot be created (DAQ is
            stopped again).
        :raises XcpCommandError: the ECU refused the DAQ configuration (no file is created).
        """
        if self._thread is not None:
            return self
        session = self.session
        self._messages = CanMessageGroups(self.dbc.database, self.dbc.path) if self.dbc is not None else None
        self._axis_start = time.time()  # the bus is heard from now: no frame comes before the axis starts
        if self.dbc is not None or self.raw_can:
            self._listen()
        try:
            if self.measurement is not None:
                self.measurement.start()
            groups = self._daq_groups()
            self._writer = self._create_file(groups)
        except BaseException:
            self._close_bus()
            if self.measurement is not None:
                self.measurement.stop()
            raise
        self._daq_index = {group.event: (index, group) for index, group in enumerate(groups)}
        if self.measurement is None:
            self._clock.fix(self._axis_start)
        self._measuring_since = time.monotonic()  # connecting and configuring DAQ are no part of a duration
        stop = weakref.WeakMethod(self.stop)  # a session that records many times keeps no finished recorder alive

        def stop_with_the_session() -> None:
            method = stop()
            if method is not None:
                method()

        session.on_close(stop_with_the_session)
        self._thread = threading.Thread(target=self._run, name="mdf-recorder", daemon=True)
        self._thread.start()
        return self

    def _create_file(self, groups: list[DaqGroup]) -> MdfStreamWriter:
        """The file's skeleton: the DAQ groups, a group per DBC message, the bus log.

        :raises InputError: the file cannot be created.
        """
        listening = self._listening
        self._raw = RawCanGroup(CAN2_BUS_CHANNEL, listening.describe(), fd=listening.fd) if self.raw_can else None
        specs = [group.spec for group in groups]
        self._message_base = len(specs)
        specs += self._messages.specs if self._messages is not None else []
        self._raw_index = len(specs)
        specs += [self._raw.spec] if self._raw is not None else []
        try:
            if self.path.exists():
                fd, name = tempfile.mkstemp(prefix=f"{self.path.stem}.", suffix=".recording.mf4", dir=self.path.parent)
                os.close(fd)
                self._writing_path = Path(name)
            self._started_at = time.time()
            return MdfStreamWriter(self._writing_path, specs, self._header(), compress=self.compress,
                                   start_time=self._axis_start)
        except OSError as exc:
            raise InputError(f"{self._writing_path}: cannot create ({exc.strerror or exc})") from None

    def _daq_groups(self) -> list[DaqGroup]:
        measurement = self.measurement
        if measurement is None:
            return []
        session = self.session
        ecu = session.doc.module(session.module).name or "ECU"  # the path too: asammdf names channels 'path.name'
        source = SourceSpec(ecu, ecu, f"{session.link.describe()}; A2L {session.doc.name}", kind="ECU",
                            bus="CAN" if session.link.settings.transport == "CAN" else "ETHERNET")
        encodings: dict = {}
        groups = []
        for event in sorted(set(measurement.events.values())):
            codecs = [measurement.codecs[name] for name in measurement.names if measurement.events[name] == event]
            groups.append(DaqGroup(event, session.event_name(event), self._period(event), codecs, source, encodings,
                                   ecu_timestamps=measurement.ecu_timestamps))
        return groups

    def _period(self, event: int) -> float | None:
        daq = self.session.config.daq
        for known in daq.events if daq else ():
            if known.number == event:
                return known.period_s
        info = self.session.event_info(event)
        return info.period_s if info is not None else None

    def _listen(self) -> None:
        """Queue the CAN2 bus's frames (the session's XCP bus unless ``can_bus`` names another).

        :raises InputError: no CAN2 bus is known (XCP on Ethernet). :raises WorkbenchError: it cannot be opened.
        """
        import can

        frames = self._frames

        class _Queue(can.Listener):
            def on_message_received(self, msg: can.Message) -> None:
                frames.append(msg)

        self._listening = self.session.listen_can(_Queue(), self._can_bus)

    def _header(self) -> HeaderSpec:
        session = self.session
        parts = []
        if self.measurement is not None:
            parts.append(f"{len(self.measurement.names)} signals by XCP DAQ ({session.link.describe()})")
        if self.dbc is not None:
            parts.append(f"CAN2 decoded with {self.dbc.path.name}")
        if self.raw_can:
            parts.append("the CAN2 bus logged raw")
        properties = {"a2l": str(session.doc.path or session.doc.name), "epk_a2l": session.epk.a2l or "",
                      "epk_ecu": session.epk.ecu or "", "time_axis": self._time_axis(),
                      "daq_time_source": self.measurement.time_source if self.measurement is not None else "",
                      "recorded_with": f"workbench {__version__}"}
        if self.dbc is not None:
            properties["can2_dbc"] = str(self.dbc.path)
        if self.trigger is not None:
            properties["trigger"] = self.trigger.describe()
        try:
            author = getpass.getuser()
        except (KeyError, OSError):  # no user name in this environment (a container without passwd entry)
            author = ""
        return HeaderSpec("workbench recording: " + "; ".join(parts), author=author,
                          project=session.doc.project.name or "", subject=session.doc.module(session.module).name or "",
                          properties={key: value for key, value in properties.items() if value})

    def _time_axis(self) -> str:
        """The header's word on the time channels: which clock each kind of group's times come from."""
        measurement = self.measurement
        if measurement is None:
            return f"{TIME_AXIS} CAN groups: the host's receive time, 0 = the start of the recording"
        if not measurement.ecu_timestamps:
            return (f"{TIME_AXIS} DAQ groups: the master's receive time of each sample (the ECU sends no DAQ "
                    "timestamps), 0 = the first DAQ sample; CAN groups: the host's receive time on the same axis")
        return (f"{TIME_AXIS} DAQ groups: the ECU's DAQ clock (its timestamps), 0 = the first DAQ sample; CAN groups: "
                "the host's receive time mapped onto the ECU's clock with the DAQ clock's offset")

    # --- the recording thread -----------------------------------------------------------------

    def _run(self) -> None:
        writer = self._writer
        next_flush = time.monotonic() + self.flush_s
        try:
            while True:
                stopping = self._stopping.wait(POLL_S)  # what came meanwhile is taken together: few, large batches
                self._take_daq()
                if self._clock.origin is None and time.time() - self._started_at > ORIGIN_WAIT_S:
                    self._clock.fix(self._axis_start)  # no DAQ sample yet: CAN frames must not wait longer
                self._take_frames()
                stopping = stopping or self._gate.done  # the stop condition ends the recording here
                now = time.monotonic()
                if stopping or now >= next_flush or writer.pending_bytes > MAX_PENDING_BYTES:
                    writer.flush()
                    next_flush = now + self.flush_s
                if stopping:
                    return
        except BaseException as exc:  # kept for stop(), which raises it where the caller sees it
            self._error = exc
            lost = isinstance(exc, ConnectionLostError)  # the end of the recording, not a failure of it
            log.log(logging.INFO if lost else logging.ERROR, "recording to %s %s: %s", self.path,
                    "ended" if lost else "failed", exc)
        finally:
            self._finished.set()

    def _take_daq(self) -> None:
        measurement = self.measurement
        if measurement is None or measurement.stream is None:
            return
        timed = []
        for batch in measurement.stream.read(0.0):  # the conditions judged on every list's samples first
            index, group = self._daq_index[batch.daq_list.event]
            first = self._clock.origin is None
            times = self._clock.daq(batch.time, batch.host_time)
            if first:
                self._writer.set_start_time(self._clock.origin)
            watched = self._trigger_names.intersection(group.names)
            if watched and not self._gate.done:
                self._gate.observe(times, group.physical(batch, watched))
            timed.append((index, group, batch, times))
        for index, group, batch, times in timed:
            self._write(index, times, group.columns(batch), {"samples": 1, "values": len(group.signals)})
            if self.on_samples is not None:
                self._deliver(group, batch)

    def _deliver(self, group: DaqGroup, batch) -> None:
        try:
            self.on_samples(SampleBatch(group.event, group.event_name, batch.time, batch.host_time,
                                        group.physical(batch)))
        except Exception:  # the caller's callback: log it with its traceback, do not call it again
            log.exception("the on_samples callback failed; it is not called again")
            self.on_samples = None

    def _take_frames(self) -> None:
        if self._clock.origin is None or not self._frames:
            return
        frames = []
        while self._frames:
            frame = self._frames.popleft()  # one sent before the recording began may reach the listener late: not ours
            if not (frame.is_error_frame or frame.is_remote_frame or frame.timestamp < self._axis_start):
                frames.append(frame)
        if not frames:
            return
        times = self._clock.host(np.array([frame.timestamp for frame in frames]))
        if self._raw is not None:
            self._append_frames(self._raw_index, times, [self._raw.records(frames)], "raw_frames")
        if self._messages is not None:
            self._decode(frames, times)

    def _decode(self, frames: list, times: np.ndarray) -> None:
        by_group: dict[int, list[int]] = {}
        for position, frame in enumerate(frames):
            index = self._messages.index_of(frame)
            if index is not None:
                by_group.setdefault(index, []).append(position)
        for index, positions in by_group.items():
            decoded, columns = self._messages.columns(index, [frames[p] for p in positions])
            self._counts["undecoded"] += len(positions) - len(decoded)
            if decoded:
                self._append_frames(self._message_base + index, times[positions][decoded], columns, "can_frames")

    def _append_frames(self, index: int, times: np.ndarray, columns: list[np.ndarray], counted: str) -> None:
        """Host clocks may step back (a frame queued on another socket): a group's times never fall."""
        rising = np.maximum.accumulate(np.concatenate(([self._last_frame_time.get(index, -np.inf)], times)))[1:]
        self._last_frame_time[index] = float(rising[-1])
        self._write(index, rising, columns, {counted: 1})

    def _write(self, index: int, times: np.ndarray, columns: list, counts: dict[str, int]) -> None:
        """Records of group ``index`` to the file, through the trigger's gate; ``counts``: what one record counts."""
        for group, written, values, counted in self._gate.passed(index, times, columns, counts):
            self._writer.append(group, written, values)
            for key, per_record in counted.items():
                self._counts[key] += per_record * len(written)
            self._last_time = max(self._last_time, float(written[-1]))

    # --- stopping -----------------------------------------------------------------------------

    @property
    def running(self) -> bool:
        return self._thread is not None and not self._finished.is_set() and not self._stopping.is_set()

    @property
    def failure(self) -> BaseException | None:
        """What ended the recording before it was stopped (a :class:`ConnectionLostError`: the ECU was lost),
        until :meth:`stop` raises it; None while it runs."""
        return self._error

    def wait(self, duration_s: float | None = None, progress: Progress | None = None) -> None:
        """Block until ``duration_s`` seconds of recording, counted from when DAQ ran (None: until the
        recording stops), ``progress`` is cancelled (the recording goes on until :meth:`stop`), or the
        recording stops or fails.
        ``progress`` sees milliseconds recorded of ``duration_s`` (total 0 when open-ended) and a summary.

        :raises WorkbenchError: the recording failed (the file holds what was flushed before).
        """
        while self.running:
            elapsed = time.monotonic() - self._measuring_since
            if progress is not None:
                progress.update(int(elapsed * 1000), int(duration_s * 1000) if duration_s else 0, self._label())
                if progress.cancelled:
                    return
            if duration_s is not None and elapsed >= duration_s:
                return
            self._finished.wait(POLL_S * 2 if duration_s is None else min(POLL_S * 2, duration_s - elapsed))
        if self._error is not None:
            self.stop()

    def _label(self) -> str:
        counts = self._counts
        text = f"recording: {counts['samples']:,} samples"
        if self._messages is not None:
            text += f", {counts['can_frames']:,} CAN2 frames"
        if self._raw is not None:
            text += f", {counts['raw_frames']:,} raw frames"
        return text

    def stop(self) -> RecordingStats:
        """Stop DAQ and the CAN bus, write what is left and finalize the file; safe to call twice.

        :raises ConnectionLostError: the ECU was lost: the recording ended there (the file is finalized with
            everything that came before).
        :raises WorkbenchError: the recording failed on the way (the file holds what was flushed before).
        """
        with self._lock:
            if self._stopped or self._thread is None:
                return self.stats
            self._stopped = True
            try:
                if self.measurement is not None:
                    self.measurement.stop()  # what already arrived is still read below
            finally:
                self._close_bus()
                self._stopping.set()
                self._finished.wait()
                self._finish()
        if self._error is not None:
            error, self._error = self._error, None
            if isinstance(error, ConnectionLostError):
                raise ConnectionLostError(error.what, f"{error.reason}; {self.stats.describe()} recorded before",
                                          error.when) from None
            raise WorkbenchError(f"recording to {self.path} failed: {error}") from error
        return self.stats

    def _finish(self) -> None:
        try:
            self._writer.close()
        except WorkbenchError as exc:
            self._error = self._error or exc
        if self._writing_path != self.path:
            os.replace(self._writing_path, self.path)
            self._writing_path = self.path

    def _close_bus(self) -> None:
        listening, self._listening = self._listening, None
        if listening is not None:
            listening.close()

    @property
    def stats(self) -> RecordingStats:
        daq = self.measurement.stats if self.measurement is not None else None
        writer = self._writer
        started = self._gate.started_s
        return RecordingStats(self.path, self._last_time, lost=daq.lost if daq else 0,
                              overloads=daq.overloads if daq else 0,
                              file_bytes=writer.file_bytes if writer is not None else 0, **self._counts,
                              started_s=None if started is None else max(started, 0.0),
                              trigger=self.trigger.describe() if self.trigger else "",
                              multiplexed=tuple(self._messages.multiplexed) if self._messages is not None else ())

    def __enter__(self) -> Recorder:
        return self.start()

    def __exit__(self, *exc_info) -> None:
        self.stop()


def record(session: Session, path: str | Path, signals: Sequence[str] = (), *, duration: float | None = None,
           progress: Progress | None = None, **options) -> RecordingStats:
    """Record for ``duration`` seconds (None: until ``progress`` is cancelled or the session closes) and
    return what the file holds. Cancelling ``progress`` ends the recording normally (the file is complete).
    ``options`` are :class:`Recorder`'s.

    :raises InputError: see :class:`Recorder`. :raises WorkbenchError: the recording failed.
    """
    if duration is None and progress is None:
        raise InputError("record() needs a duration or a progress object that can cancel it")
    with Recorder(session, path, signals, **options) as recorder:
        recorder.wait(duration, progress)
    return recorder.stats
