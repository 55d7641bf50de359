"""The step vocabulary of a requirement test on a :class:`~workbench.session.Session`, in physical units by name.

::

    from workbench import Session
    from workbench.testbench import Bench, within, equals

    with Session.open(interface="udp_multicast", channel="239.74.163.2") as session, \\
            Bench(session, dbc="dbc/FLCU_CAN2.dbc", evidence="run.mf4") as ecu:
        ecu.watch("zsRailPressure", "xsTankCtrlState")
        ecu.send("PCM_TO_FLCU_001", period=0.1, EnableFLCU=1)                 # stimulate
        ecu.send("PCM_TO_FLCU_002", period=0.1, TargetRailPressure=25.0)
        ecu.wait_until("zsRailPressure", within(24.0, 26.0), timeout=3.0)      # wait
        ecu.expect("zsRailPressure", within(24.0, 26.0), for_s=1.0)            # expect
        ecu.expect("FLCU_TO_PCM_002.RailPressure", within(24.0, 26.0), for_s=0.3)
        ecu.expect_period("FLCU_TO_PCM_002", 0.100, tolerance_s=0.010)
        ecu.write("xsSWITCH_TANK_THR", 5.0)
        ecu.expect_edge("xsTankCtrlState", equals("TANK2_ON"), within=0.2)

Signals are MEASUREMENTs of the A2L (sampled by DAQ on their A2L event, recorded to the evidence file)
or CAN2 signals as ``MESSAGE.SIGNAL`` (every frame the bench hears, decoded with the DBC). Time is the
bench's: seconds since it started, on the host's clock (DAQ samples carry the ECU's time mapped to it).
Every step logs one line (logger ``workbench.testbench``) and is kept in :attr:`Bench.steps` for the
report; a failed expectation raises :class:`ExpectationFailed` (an ``AssertionError``) in one line:
what was expected, the value, the time. Closing the bench stops what it sends, clears the simulator's
faults and writes back every calibration it changed, as it was before.
"""

from __future__ import annotations

import functools
import tempfile
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from workbench.a2l.objects import Measurement
from workbench.can.naming import dbc_signal_name, find_dbc_signal
from workbench.errors import ConnectionLostError, InputError, UnknownSymbolError, WorkbenchError
from workbench.logs import logger
from workbench.testbench.conditions import Condition, as_condition
from workbench.testbench.evidence import Evidence
from workbench.testbench.simulator import NoSimulator, SimSteps, SimulatorControl
from workbench.testbench.timeline import Timeline

if TYPE_CHECKING:
    from workbench.can.dbc_file import DbcFile
    from workbench.calib.values import CalValue
    from workbench.session import Session
    from workbench.testbench.can2 import Can2Port

__all__ = ["Bench", "ExpectationFailed", "NotJudged", "Step"]

log = logger("workbench.testbench")

DATA_LATENCY_S = 2.0  # how long past a window the bench waits for its samples before it calls them missing
LATE_EDGE_S = 1.0  # how long past a missed deadline a failed expect_edge looks for the edge, to say when it came


class ExpectationFailed(AssertionError):
    """An expectation or a wait that did not hold: one line naming the signal, what was expected, the value and the time."""


class NotJudged(WorkbenchError):
    """An expectation or a wait the bench could not judge: the ECU was lost before its samples came, or the
    bench's CAN2 stimuli reached no ECU (it heard no other node on CAN2). The test breaks (pytest's ERROR, its
    requirements NOT JUDGED), as the ECU was not shown to break the requirement; the line says why."""


def _one_line_errors(step):
    """A step whose input is wrong (a name misspelt, a value beyond its limits, a text the signal does not
    have) raises its WorkbenchError from the test's line: pytest shows that line and the message, not the
    library's frames below it (a bug's exception keeps its traceback)."""

    @functools.wraps(step)
    def run(*args, **kwargs):
        __tracebackhide__ = True
        try:
            return step(*args, **kwargs)
        except WorkbenchError as exc:
            raise exc.with_traceback(None) from None

    return run


@dataclass
class Step:
    """One step as the log and the report show it; times in s on the bench's clock."""

    kind: str  # "stimulus", "wait", "expect", "note"
    text: str
    t_start: float
    t_end: float
    signal: str | None = None
    unit: str = ""
    band: tuple[float, float] | None = None  # the numeric band an expectation drew (inf: open)
    target: str | None = None  # a text value it expected ("TANK1_ON"), or "!= value"
    reference: str | None = None  # the signal an expect_follows compared with
    tolerance: float | None = None  # ... and how far from it the signal may be (0: exactly; the report draws a line)
    passed: bool | None = None
    detail: str = ""
    judged: bool = True  # False: it could not judge (the ECU lost, CAN2 silent): NOT JUDGED, not FAILED

    def to_dict(self) -> dict[str, Any]:
        data = asdict(self)
        if self.band is not None:
            data["band"] = [None if not np.isfinite(b) else float(b) for b in self.band]
        return data


@dataclass
class _Signal:
    name: str
    source: str  # "daq" or "can"
    unit: str = ""
    choices: dict[str, float] = field(default_factory=dict)  # CAN: VAL_ text -> physical value

    def show(self, value: Any) -> str:
        """A value as a failure names it: a CAN2 value table's text (``Low``), else the value and its unit."""
        if self.choices and isinstance(value, (int, float, np.number)):
            text = next((text for text, number in self.choices.items() if float(value) == number), None)
            if text is not None:
                return text
        return f"{_text(value)}{_unit(self.unit)}"


class Bench:
    """Steps on ``session``: stimulate, wait, expect. A context manager; :meth:`close` restores what it changed.

    :param dbc: the CAN2 database (path or :class:`~workbench.can.DbcFile`) for CAN2 steps.
    :param can2_bus: the CAN2 bus as python-can ``Bus`` settings (default: the session's XCP on CAN bus).
    :param simulator: the simulated ECU's controls (default: none, as for a real ECU).
    :param evidence: the MF4 file the test's signals are recorded to (default: one in a new temporary folder).
    """

    def __init__(self, session: Session, *, dbc: DbcFile | str | Path | None = None,
                 can2_bus: dict[str, Any] | None = None, simulator: SimulatorControl | None = None,
                 evidence: str | Path | None = None):
        self.session = session
        self.timeline = Timeline()
        self.steps: list[Step] = []
        self.last_stimulus: float | None = None  # when the latest stimulus began (bench s)
        self._stimulus_done: float | None = None  # ... and when it was complete
        # the latest sample time a step acted on: DAQ times are the ECU's mapped onto the host's clock, ahead of it
        # for a while when the first samples queued on a loaded host; the next step does not begin before it
        self._seen = -np.inf
        self._signals: dict[str, _Signal] = {}
        self._watched: list[str] = []
        self._journal: dict[str, CalValue] = {}  # calibration -> its value before the bench first wrote it
        self.can2: Can2Port | None = None
        self._no_can2 = "give the CAN2 database (--dbc; Bench(dbc=...))"
        if dbc is not None:
            from workbench.can import load_dbc
            from workbench.testbench.can2 import Can2Port

            dbc = load_dbc(dbc) if isinstance(dbc, (str, Path)) else dbc
            can2_bus = can2_bus or _session_can_bus(session)
            if can2_bus is not None:
                self.can2 = Can2Port(can2_bus, dbc, self.timeline)
            else:  # XCP on Ethernet (or on a bus the caller opened): CAN2 is no bus the session knows
                self._no_can2 = (f"XCP runs on {session.link.settings.describe()}; give the CAN2 bus "
                                 "(--can2-interface/--can2-channel/--can2-bus-kwargs; Bench(can2_bus=...))")
        self.sim = SimSteps(simulator or NoSimulator("this ECU is not simulated"), self._begin, self._stimulated, self.now)
        path = Path(evidence) if evidence is not None else Path(tempfile.mkdtemp(prefix="workbench-bench-")) / "evidence.mf4"
        self.evidence = Evidence(session, path, self.timeline, dbc=self.can2.dbc if self.can2 else None,
                                 can_bus=self.can2.settings if self.can2 else None)
        self.closed = False

    # --- time and the log ---------------------------------------------------------------------

    def now(self) -> float:
        """Seconds since the bench started, and not before the latest sample a step acted on (a DAQ sample's
        time is the ECU's mapped onto the host's clock, ahead of it for a while after a start on a loaded host):
        a mark taken here for ``since=``/``after=`` comes after what the test saw."""
        return max(self.timeline.now(), self._seen)

    def _add(self, step: Step) -> Step:
        self.steps.append(step)
        result = "" if step.passed is None else (" -> ok" if step.passed else " -> FAILED" if step.judged
                                                 else " -> NOT JUDGED")
        log.info("%7.3f s  %-8s %s%s%s", step.t_start, step.kind, step.text, result,
                 f" ({step.detail})" if step.detail else "")
        return step

    def note(self, text: str) -> None:
        """A line of the test's own in the log and the report."""
        self._add(Step("note", text, self.now(), self.now()))

    def _stimulated(self, text: str, t_start: float | None = None) -> None:
        done = self.now()
        moment = max(done if t_start is None else min(t_start, done), self._seen)
        done = max(done, moment)
        self.last_stimulus, self._stimulus_done = moment, max(done, moment)
        self._add(Step("stimulus", text, moment, done))

    def _fail(self, step: Step, detail: str, *, observed: bool = False) -> None:
        """Fail ``step``: :class:`ExpectationFailed`, or :class:`NotJudged` when the ECU was lost before a sample
        broke it (``observed``: one did) or when its CAN2 stimuli reached no ECU."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        others = self.can2.competing() if self.can2 is not None else {}
        if others:  # the likely cause of a stimulus without effect: the ECU hears two senders
            detail += "; " + ", ".join(f"another node sends {name} too ({count} frames not the bench's)"
                                       for name, count in sorted(others.items())) + " (workbench sim --pcm?)"
        silent = self.can2 is not None and self.can2.silent()
        if silent:
            detail += (f"; CAN2 is silent: the bench sent there but heard no ECU frame since it started "
                       f"({self.can2.describe()}; is the ECU on this bus? --can2-interface/--can2-channel)")
        step.passed, step.detail, step.t_end = False, detail, max(step.t_end, step.t_start)
        step.judged = not (silent or (self.evidence.failure is not None and not observed))
        self._add(step)
        if not step.judged:
            raise NotJudged(f"{step.text}: {detail}")
        raise ExpectationFailed(f"{step.text}: {detail}")

    # --- signals --------------------------------------------------------------------------------

    def signal(self, name: str) -> _Signal:
        """A MEASUREMENT of the A2L, or ``MESSAGE.SIGNAL`` of the CAN2 DBC. :raises UnknownSymbolError, InputError:"""
        known = self._signals.get(name)
        if known is not None:
            return known
        model = self.session.model
        try:
            obj = model.object(name)
        except UnknownSymbolError as unknown:
            found = self._can_signal(name, unknown)  # or a CAN2 signal: Message.Signal, or a name one message alone has
            if found is None:
                raise
            self._signals[name] = found
            return found
        if not isinstance(obj, Measurement):
            raise InputError(f"{name} is a {type(obj).__name__.upper()}: a calibration is written (write, override), "
                             "the MEASUREMENT it acts on is watched")
        self._signals[name] = _Signal(name, "daq", model.unit_of(obj))
        return self._signals[name]

    def _can_signal(self, name: str, unknown: UnknownSymbolError) -> _Signal | None:
        """The CAN2 signal ``name`` names; None without CAN2. :raises UnknownSymbolError: neither in the A2L
        (``unknown``) nor in the DBC, the closest names of both suggested."""
        if self.can2 is None:
            return None
        try:
            message, signal = find_dbc_signal([self.can2.database], name)
        except UnknownSymbolError as not_can:
            raise UnknownSymbolError(name, f"the A2L's objects nor the CAN2 signals of {self.can2.dbc.path.name}",
                                     (unknown.suggestions + not_can.suggestions)[:4]) from None
        choices = {str(text): float(raw) * signal.scale + signal.offset for raw, text in (signal.choices or {}).items()}
        return _Signal(dbc_signal_name(message.name, signal.name), "can", signal.unit or "", choices)

    @_one_line_errors
    def watch(self, *names: str) -> None:
        """Sample and record these MEASUREMENTs (and check these CAN2 signals exist) from now on.
        Watch before the first step, and a test's evidence is one file."""
        for name in names:
            if self.signal(name).source == "daq" and name not in self._watched:
                self._watched.append(name)
        if self.evidence.recording:
            self._begin()

    def _sampled(self, name: str) -> _Signal:
        signal = self.signal(name)
        if signal.source == "daq" and name not in self._watched:
            self._watched.append(name)
        self._begin()
        return signal

    def _begin(self) -> None:
        """Start the recording at the first step (of what is watched, and CAN2), and let every watched
        signal be sampled once before the step, so that an edge after it has a "before"."""
        if not (self._watched or self.can2 is not None) or not self.evidence.ensure(self._watched):
            return
        missing = self.timeline.wait_started(self._watched, self.now() + DATA_LATENCY_S)
        if missing:
            raise WorkbenchError(f"no DAQ samples of {', '.join(missing)} within {DATA_LATENCY_S:g} s of starting "
                                 "the recording")

    def _condition(self, signal: _Signal, wanted: Any) -> Condition:
        """``wanted`` as the signal's samples are compared: a text of its table (refused when it has none such:
        a misspelt state would fail every expectation, or pass every ``other_than``), a number turned into its
        text. :raises InputError: a text the signal does not have, a band on a verbal signal, a text on a number."""
        condition = as_condition(wanted)
        if signal.source == "can":
            if condition.is_text:
                value = condition.value
                if value not in signal.choices:
                    raise InputError(f"{signal.name} has no value {value!r} (its DBC values: "
                                     f"{', '.join(signal.choices) or 'none'})")
                return replace(condition, value=signal.choices[value], label=value)
            return condition
        model = self.session.model
        conversion = model.conversion(model.object(signal.name))
        if not conversion.verbal:
            if condition.is_text:
                raise InputError(f"{signal.name} is a number{_unit(signal.unit)}, not a text: {condition.value!r} "
                                 "is none of its values")
            return condition
        if condition.tolerance:
            raise InputError(f"{signal.name} is verbal ({conversion.allowed_shown}): a tolerance compares numbers, "
                             "its texts are equal or not")
        if not condition.is_value:
            raise InputError(f"{signal.name} is verbal ({conversion.allowed_shown}): compare it with one of its texts "
                             f"(equals, other_than), not {condition.describe()}")
        value = condition.value
        if not isinstance(value, str):
            return replace(condition, value=conversion.to_physical(value))  # a number: the text it stands for
        text = conversion.text_of(value)
        if text is None and value != conversion.default:
            raise InputError(f"{signal.name} has no text {value!r} (its texts: {conversion.allowed_shown})")
        return replace(condition, value=text or value)

    # --- stimulate ------------------------------------------------------------------------------

    @_one_line_errors
    def write(self, name: str, value: Any) -> None:
        """Write a calibration in physical units (restored when the bench closes)."""
        self._begin()
        start = self.now()
        self._remember(name)
        written = self.session.write(name, value)
        self._stimulated(f"write {name} = {_text(written.value)}{_unit(written.unit)}", start)

    @_one_line_errors
    def override(self, signal: str, value: Any) -> None:
        """Replace a signal by its fix calibration's value (``_VALUE``, then ``_EN`` = 1). Its live
        MEASUREMENT, if the A2L has one, is watched from the start of the recording when the recording has
        not started yet (a recording is not restarted for it: watch it first to have it in any case)."""
        pair = self.session.fix(signal)
        if (pair.live is not None and not self.evidence.recording
                and isinstance(self.session.model.object(pair.live), Measurement)):
            self.watch(pair.live)
        self._begin()
        start = self.now()
        self._remember(pair.value)
        self._remember(pair.enable)
        state = self.session.override(signal, value)
        self._stimulated(f"override {pair.stem} = {_text(state.override)}{_unit(self._unit_of(pair.value))}", start)

    @_one_line_errors
    def release(self, signal: str) -> None:
        """Give a signal back to the ECU (``_EN`` = 0)."""
        pair = self.session.fix(signal)
        self._begin()
        start = self.now()
        self._remember(pair.enable)
        self.session.release(signal)
        self._stimulated(f"release {pair.stem}", start)

    def _unit_of(self, name: str) -> str:
        model = self.session.model
        return model.unit_of(model.object(name))

    def _remember(self, name: str) -> None:
        if name not in self._journal:
            self._journal[name] = self.session.read_value(name)

    @_one_line_errors
    def send(self, message: str, period: float | None = None, *, dlc: int | None = None, **signals: float) -> None:
        """Send a CAN2 frame of ``message`` with ``signals`` (physical; the others keep their values), once or
        every ``period`` s; a message sent periodically gets new values from its next frame on, in its rhythm,
        and the step returns when that frame is due (an ``expect_edge`` counts from it). ``dlc``
        sends it with another length than the DBC's (a fault; the next send without it is right again). Values outside the DBC range are sent as given."""
        port = self._port()
        self._begin()
        start = self.now()
        done, delay = port.send(message, signals, period_s=period, dlc=dlc)
        values = " ".join(f"{name}={_text(value)}" for name, value in signals.items())
        self._stimulated(f"send {message} {values}".rstrip() + (f" DLC {dlc}" if dlc is not None else "") + f" {done}",
                         start + delay)

    @_one_line_errors
    def stop(self, message: str) -> None:
        """Stop sending ``message`` periodically (the ECU sees its RX timeout)."""
        port = self._port()
        self._begin()
        if not port.stop(message):
            raise InputError(f"{message} is not being sent periodically")
        self._stimulated(f"stop sending {message}")

    def _port(self) -> Can2Port:
        if self.can2 is None:
            raise InputError(f"the bench has no CAN2 bus: {self._no_can2}")
        return self.can2

    @_one_line_errors
    def read(self, name: str) -> Any:
        """Poll a value (a MEASUREMENT or a calibration) once, in physical units."""
        value = self.session.read(name)
        self.note(f"read {name} = {_text(value)}")
        return value

    # --- wait -----------------------------------------------------------------------------------

    @_one_line_errors
    def wait(self, seconds: float) -> None:
        """Let ``seconds`` pass. :raises NotJudged: the ECU is lost meanwhile (said then, not at the wait's end)."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        _check_times("wait()", seconds=(seconds, True))
        self._begin()
        start = self.now()
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0 and not self._ended():
            time.sleep(min(left, 0.05))
        step = Step("wait", f"wait {seconds:g} s", start, self.now())
        if self._ended():  # a soak's wait of minutes on an ECU gone: the test breaks now
            step.passed, step.judged, step.detail = False, False, str(self.evidence.failure)
            self._add(step)
            raise NotJudged(f"{step.text}: {step.detail}")
        self._add(step)

    @_one_line_errors
    def wait_until(self, name: str, condition: Any, timeout: float) -> float:
        """Wait until ``name`` meets ``condition``; returns the time (bench s) of the first sample that did.
        :raises ExpectationFailed: not within ``timeout`` s."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        _check_times(f"wait_until({name})", timeout=(timeout, False))
        signal = self._sampled(name)
        name = signal.name  # a CAN2 signal by its qualified name, as the timeline keeps it
        wanted = self._condition(signal, condition)
        start = self.now()
        step = self._step("wait", f"wait until {name} {wanted.describe(signal.unit)} (timeout {timeout:g} s)",
                          start, signal, wanted)
        hit, last = self._first(name, wanted, start, start + timeout)
        if hit is None:
            self._fail(step, f"not within {timeout:g} s; {_last_seen(last, signal)}{self._lost()}")
        step.passed, step.t_end, step.detail = True, hit, f"at t={hit:.3f} s"
        self._seen = max(self._seen, hit)
        self._add(step)
        return hit

    # --- expect ---------------------------------------------------------------------------------

    @_one_line_errors
    def expect(self, name: str, condition: Any, for_s: float, *, since: float | None = None) -> tuple[float, float] | None:
        """``name`` meets ``condition`` in every sample of the ``for_s`` seconds from ``since`` (bench s;
        default: now), at least one. Returns the (min, max) it took (None for texts).
        :raises ExpectationFailed: at the first sample that did not."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        _check_times(f"expect({name})", for_s=(for_s, False))
        signal = self._sampled(name)
        name = signal.name  # a CAN2 signal by its qualified name, as the timeline keeps it
        wanted = self._condition(signal, condition)
        start = self._step_start(since)
        end = start + for_s
        self._check_window(f"expect({name})", name, end)
        step = self._step("expect", f"expect {name} {wanted.describe(signal.unit)} for {for_s:.3g} s", start, signal, wanted)
        step.t_end = end
        values = self._window(step, name, start, end, lambda times, values: (times, ~wanted.test(values)), signal)
        step.passed = True
        self._seen = max(self._seen, end)
        span = None
        if values.dtype.kind in "fiub":
            span = float(np.min(values)), float(np.max(values))
            step.detail = f"{len(values)} samples, {_text(span[0])}..{_text(span[1])}{_unit(signal.unit)}"
        else:
            step.detail = f"{len(values)} samples"
        self._add(step)
        return span

    @_one_line_errors
    def expect_follows(self, name: str, reference: str, tolerance: float, for_s: float, *,
                       since: float | None = None) -> float:
        """Every sample of ``name`` in the ``for_s`` seconds from ``since`` (default: now) equals the latest
        sample of ``reference`` at or before it, within ``tolerance`` (texts: the same text), e.g. a command
        and the value it is computed from, a CAN2 signal and the measurement it carries. Returns the largest
        difference (0 for texts)."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        _check_times(f"expect_follows({name})", for_s=(for_s, False), tolerance=(tolerance, True))
        signal = self._sampled(name)
        name = signal.name  # a CAN2 signal by its qualified name, as the timeline keeps it
        reference = self._sampled(reference).name
        start = self._step_start(since)
        end = start + for_s
        self._check_window(f"expect_follows({name})", name, end)
        step = Step("expect", f"expect {name} = {reference} ± {tolerance:g}{_unit(signal.unit)} for {for_s:g} s",
                    start, end, name, signal.unit, reference=reference, tolerance=float(tolerance))
        differences: list[np.ndarray] = []

        def judge(times, values):
            ref_times, ref_values = self.timeline.samples(reference, -np.inf, end)
            index = np.searchsorted(ref_times, times, side="right") - 1
            held = ref_values[np.maximum(index, 0)] if len(ref_values) else np.full(len(times), np.nan)
            if values.dtype.kind in "fiub" and held.dtype.kind in "fiub":
                apart = np.abs(values.astype(float) - held.astype(float))
                apart[index < 0] = np.inf
                differences[:] = [apart]
                return times, ~(apart <= tolerance)
            return times, (index < 0) | (values.astype(str) != held.astype(str))

        values = self._window(step, name, start, end, judge, signal, reference)
        largest = float(np.max(differences[0])) if differences else 0.0
        step.passed, step.detail = True, f"{len(values)} samples, at most {largest:.4g}{_unit(signal.unit)} apart"
        self._seen = max(self._seen, end)
        self._add(step)
        return largest

    def _window(self, step: Step, name: str, start: float, end: float, judge, signal: _Signal,
                reference: str | None = None) -> np.ndarray:
        """The samples of ``name`` in [start, end] once all have come; fails at the first one ``judge`` marks."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        times, values = np.empty(0), np.empty(0)
        for times, values in self._arriving(name, start, end):
            bad = np.flatnonzero(judge(times, values)[1])
            if len(bad):
                first = bad[0]
                against = ""
                if reference is not None:
                    before = self.timeline.last_before(reference, times[first])
                    shown = self.signal(reference).show(before[1]) if before else "no sample"  # in its unit
                    against = f" against {shown} of {reference}"
                prior = self.timeline.last_before(name, float(np.nextafter(times[first], -np.inf)))
                after = f", after {signal.show(prior[1])} at t={prior[0]:.3f} s" if prior is not None else ""
                self._fail(step, f"{signal.show(values[first])}{against} at t={times[first]:.3f} s{after}",
                           observed=True)
        horizon = self.timeline.horizon(name)
        if horizon is None or horizon < end:
            lost = self.evidence.failure
            self._fail(step, f"no samples after t={max(start, horizon or start):.3f} s "
                       + (f"({lost})" if lost is not None else "(is DAQ running?)"))
        if not len(values):
            self._fail(step, f"no samples between t={start:.3f} s and t={end:.3f} s")
        return values

    def _arriving(self, name: str, start: float, end: float):
        """(times, values) of ``name`` in [start, end] each time more came; the last once a sample past ``end``
        came, or none for DATA_LATENCY_S past it."""
        seen = start
        while True:
            yield self.timeline.samples(name, start, end)
            horizon = self.timeline.horizon(name)
            if horizon is not None and horizon >= end:
                return
            if not self.timeline.wait_past(name, max(seen, horizon or seen), end + DATA_LATENCY_S, self._ended):
                return
            seen = self.timeline.horizon(name) or seen

    @_one_line_errors
    def expect_edge(self, name: str, condition: Any, within: float, *, after: float | None = None) -> float:
        """``name`` comes to meet ``condition`` within ``within`` s of the last stimulus (or of ``after``),
        having not met it when the stimulus began. The deadline counts from the end of the stimulus (a
        write is complete when the ECU answered it). Returns the latency in s. The signal must be sampled
        before the stimulus: watch it first. :raises ExpectationFailed: no edge, or too late."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        _check_times(f"expect_edge({name})", within=(within, False))
        signal = self._sampled(name)
        name = signal.name  # a CAN2 signal by its qualified name, as the timeline keeps it
        wanted = self._condition(signal, condition)
        reference, done = (after, after) if after is not None else (self.last_stimulus, self._stimulus_done)
        if after is not None and after > self.now():
            raise InputError(f"expect_edge({name}): after=t={after:.3f} s is later than now (t={self.now():.3f} s): "
                             "give a mark taken with ecu.now() when the stimulus began")
        if reference is None:
            raise InputError(f"expect_edge({name}): no stimulus yet to measure from (or give after=)")
        step = self._step("expect", f"expect {name} {wanted.describe(signal.unit)} within {within * 1000:g} ms "
                          f"of t={done:.3f} s", reference, signal, wanted)
        step.t_end = done + within
        before = self.timeline.last_before(name, reference)
        if before is None:
            raise InputError(f"{name} was not sampled before t={reference:.3f} s: watch it before the stimulus "
                             f"(ecu.watch({name!r}))")
        if wanted.test(np.array([before[1]]))[0]:
            self._fail(step, f"no edge: it was already {signal.show(before[1])} at t={before[0]:.3f} s",
                       observed=True)
        hit, last = self._first(name, wanted, reference, done + within)
        if hit is None:
            late = None if self.evidence.failure is not None else self._first(name, wanted, done + within,
                                                                               done + within + LATE_EDGE_S)[0]
            when = (f"it came {(late - done) * 1000:.0f} ms after t={done:.3f} s, at t={late:.3f} s"
                    if late is not None else f"nor in the {LATE_EDGE_S:g} s after")
            self._fail(step, f"not within {within * 1000:g} ms; {_last_seen(last or before, signal)}; {when}"
                       f"{self._lost()}", observed=late is not None)
        step.passed, step.detail = True, f"after {max(hit - done, 0.0) * 1000:.0f} ms, at t={hit:.3f} s"
        self._seen = max(self._seen, hit)
        self._add(step)
        return max(hit - done, 0.0)

    @_one_line_errors
    def expect_period(self, message: str, period_s: float, tolerance_s: float, *, for_s: float = 1.0,
                      jitter_s: float | None = None) -> float:
        """Frames of ``message`` heard over the next ``for_s`` s come every ``period_s`` ± ``tolerance_s``, and
        no two are further apart than ``period_s`` ± ``jitter_s``. The period is the median of the slopes
        between every two frames (a frame the host delayed does not move it); the default jitter, 90 % of
        the period, fails a missing frame (a gap of two periods) or a doubled one (no gap), not the host's
        scheduling. Returns the period found."""
        __tracebackhide__ = True  # pytest shows the test's line and this one-line failure, not the bench's
        _check_times(f"expect_period({message})", period_s=(period_s, False), tolerance_s=(tolerance_s, True),
                     for_s=(for_s, False), jitter_s=(0.0 if jitter_s is None else jitter_s, True))
        port = self._port()
        jitter = 0.9 * period_s if jitter_s is None else jitter_s
        frame_id = port.message(message).frame_id
        self._begin()
        start = self.timeline.now()  # the host's clock, as the frames' receive times
        step = Step("expect", f"expect {message} (0x{frame_id:X}) every {period_s * 1000:g} ± {tolerance_s * 1000:g} ms "
                    f"(each gap {period_s * 1000:g} ± {jitter * 1000:.0f} ms) for {for_s:g} s", start, start + for_s)
        time.sleep(max(0.0, start + for_s + period_s / 2 - self.timeline.now()))  # the frame closing it may come late
        times = port.frame_times(message, start, start + for_s)
        if len(times) < 3:
            self._fail(step, f"{len(times)} frame(s) between t={start:.3f} s and t={start + for_s:.3f} s")
        gaps = np.diff(times)
        wrong = np.flatnonzero(np.abs(gaps - period_s) > jitter)
        if len(wrong):
            first = wrong[0]
            self._fail(step, f"{gaps[first] * 1000:.1f} ms between the frames at t={times[first]:.3f} s and "
                       f"t={times[first + 1]:.3f} s")
        i, j = np.triu_indices(len(times), k=1)
        period = float(np.median((times[j] - times[i]) / (j - i)))
        if abs(period - period_s) > tolerance_s:
            self._fail(step, f"{period * 1000:.1f} ms (the median over {len(times)} frames from t={times[0]:.3f} s)")
        step.passed, step.detail = True, f"{len(times)} frames, {period * 1000:.1f} ms"
        self._add(step)
        return period

    # --- internals of waiting -----------------------------------------------------------------

    def _step(self, kind: str, text: str, start: float, signal: _Signal, wanted: Condition) -> Step:
        target = None
        if wanted.is_text:
            target = f"{'!= ' if wanted.negate else ''}{wanted.value}"
        band = None if wanted.negate else wanted.band()
        return Step(kind, text, start, start, signal.name, signal.unit, band, target)

    def _check_window(self, step: str, name: str, end: float) -> None:
        """:raises InputError: the window ends before ``name`` was sampled (a ``since=`` from before the watch): it
        would fail on no samples, as if the ECU sent none."""
        first = self.timeline.sampled_from(name)
        if first is not None and end < first:
            raise InputError(f"{step}: the window ends at t={end:.3f} s, before {name} was sampled (from t={first:.3f} "
                             "s): watch it first, and take since= with ecu.now() after that")

    def _step_start(self, since: float | None) -> float:
        """Where a window begins: ``since``, or now and not before what the steps before it saw (a sample the
        wait before found, mapped ahead of the host's clock: the window must not judge the samples before it)."""
        return self.now() if since is None else since

    def _ended(self) -> bool:
        """The recording ended early (the ECU lost): no more samples come, a step waits no longer for them."""
        return self.evidence.failure is not None

    def _lost(self) -> str:
        """``; connection to the ECU lost at ...`` when the recording ended so (the reason samples stopped)."""
        lost = self.evidence.failure
        return f"; {lost}" if lost is not None else ""

    def _first(self, name: str, wanted: Condition, start: float, end: float) -> tuple[float | None, tuple | None]:
        """The first sample time in [start, end] meeting ``wanted`` (None: none), and the last sample seen."""
        last = None
        for times, values in self._arriving(name, start, end):
            hits = np.flatnonzero(wanted.test(values))
            if len(hits):
                return float(times[hits[0]]), None
            last = (float(times[-1]), values[-1]) if len(times) else last
        return None, last

    # --- closing --------------------------------------------------------------------------------

    def close(self) -> None:
        """Stop sending, clear the simulator's faults, write back the calibrations changed, stop the recording.
        Safe to call twice. :raises WorkbenchError: something could not be restored (everything else still is)."""
        if self.closed:
            return
        self.closed = True
        problems: list[str] = []
        if self.sim.touched:
            try:
                self.sim.clear()
            except WorkbenchError as exc:
                problems.append(str(exc))
        if self.can2 is not None:
            self.can2.stop_all()
        journal = {} if self.session.read_only else self._journal  # read-only (EPKs differ): nothing was written
        lost: ConnectionLostError | None = None
        unrestored: list[str] = []  # as the ECU is gone: named together, the loss once
        for name, value in reversed(list(journal.items())):
            if lost is None:
                try:
                    self.session.write(name, value, allow_extended_limits=True)
                    self.note(f"restore {name} = {_text(value.value)}{_unit(value.unit)}")
                    continue
                except ConnectionLostError as exc:
                    lost = exc
                except WorkbenchError as exc:
                    problems.append(f"{name} not restored: {exc}")
                    continue
            unrestored.append(name)
        if unrestored:
            problems.append(f"{', '.join(unrestored)} not restored: {lost}")
        try:
            self.evidence.stop()
        except WorkbenchError as exc:
            problems.append(str(exc))
        if self.can2 is not None:
            self.can2.close()
        self.sim.control.close()
        if problems:
            raise WorkbenchError("; ".join(problems))

    def __enter__(self) -> Bench:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def _check_times(step: str, **given: tuple[float, bool]) -> None:
    """Each of ``given`` (argument: (seconds or tolerance, 0 allowed)) a number above 0, or 0 or more.

    :raises InputError: one that is not: the test's mistake (``for_s=-1`` would judge no sample, ``tolerance=-1``
        fail every one), not the ECU's; the test breaks rather than failing its requirement."""
    for argument, (value, zero) in given.items():
        if not isinstance(value, (int, float, np.number)) or not (value >= 0 if zero else value > 0):
            raise InputError(f"{step}: {argument}={value!r}: give a number {'of 0 or more' if zero else 'above 0'}")


def _session_can_bus(session: Session) -> dict[str, Any] | None:
    settings = session.link.settings
    return settings.bus.kwargs() if settings.transport == "CAN" and settings.bus else None


def _text(value: Any) -> str:
    if isinstance(value, bytes):
        value = value.decode(errors="replace")
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, np.ndarray):
        return np.array2string(value, precision=6, separator=", ")
    return str(value.item() if isinstance(value, np.generic) else value)


def _unit(unit: str) -> str:
    return f" {unit}" if unit else ""


def _last_seen(last: tuple | None, signal: _Signal) -> str:
    return "no samples" if last is None else f"last {signal.show(last[1])} at t={last[0]:.3f} s"
