"""``workbench measure``: signals by name, polled or by DAQ, as a live table or JSON lines."""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import time
from contextlib import contextmanager
from typing import Any

from workbench.a2l.display_format import format_decimals
from workbench.bus_defaults import BusSpec
from workbench.cli.ecu_options import a2l_document, add_ecu_arguments, can2_dbc, open_session
from workbench.cli import options
from workbench.cli.options import add_can2_bus_arguments, can2_bus_spec, non_negative_float, positive_float
from workbench.cli.render import jsonable, value_text

__all__ = ["add_recording_arguments", "add_subparser", "run"]

EPILOG = """\
A NAME is an A2L object, or a CAN2 signal of the DBC as the window names it (Message.Signal, or the
signal's name when one message alone has it; the DBC is --can2, by default the demo's with the demo's
A2L): its newest value beside the polled ones, or with --daq a row of its own per frame (event CAN2).

In a terminal the values refresh in place; piped (or with --json) every sample is a line: with
--json a JSON object {"time": s, "event": ..., "values": {name: value}}, else "time name=value ...".
Ctrl-C or --duration ends the measurement (exit 0); with --daq the samples and losses are
summed up on stderr, and DTOs of no list of ours (another master's DAQ) when any came.

With --record the samples go to an MDF4 file instead (DAQ, ECU time, or the receive time when the
ECU sends no timestamps, as the file says; raw values with the A2L's conversions): --can2 adds the
CAN2 bus's frames decoded with a DBC, --raw-can every frame of that bus raw (ASAM MDF bus logging,
which asammdf and CANape decode again with a DBC). The file is complete after every second of
recording, also when the process is killed (`workbench record --repair FILE` finalizes it then, for
MATLAB); Ctrl-C, SIGTERM or --duration end it. The CAN2 bus is the XCP bus unless
--can2-interface/--can2-channel/--can2-bus-kwargs name another (e.g. --can2-channel 239.74.163.3
--can2-bus-kwargs port=43201).

examples:
  workbench measure zsRailPressure xsDC                       # polled 10 times a second
  workbench measure zsRailPressure RailPressure               # the sensor and the CAN2 signal the ECU sends
  workbench measure zsRailPressure zsSensVolt --daq --duration 5 --json > rail.jsonl
  workbench measure xsDC --daq --event Task100ms --host 127.0.0.1 --protocol tcp
  workbench measure zsRailPressure xsTankCtrlState --record run.mf4 --can2 dbc/FLCU_CAN2.dbc --raw-can
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                                   description="Measure signals by name in physical units: polled (SHORT_UPLOAD/UPLOAD "
                                               "of neighbouring addresses together) or sampled by the ECU with DAQ "
                                               "(each signal on its A2L event, with the ECU's timestamps).")
    parser.add_argument("names", nargs="+", metavar="NAME", help="an A2L name, one element of an array ('zsSensVolt[2]'), "
                        "a glob ('zsRail*': with --daq or --record its measurements) or a CAN2 signal (Signal or "
                        "Message.Signal)")
    parser.add_argument("--daq", action="store_true", help="sample by DAQ instead of polling")
    parser.add_argument("--event", help="DAQ event (name or number) for every signal (default: each signal's own)")
    parser.add_argument("--rate", type=positive_float, metavar="HZ", help="polling rate (default 10 Hz; DAQ samples on "
                        "the ECU's events instead)")
    parser.add_argument("--duration", type=positive_float, metavar="S", help="stop after S seconds (default: Ctrl-C)")
    parser.add_argument("--raw", action="store_true", help="raw values, as the ECU holds them (no conversion)")
    recording = parser.add_argument_group("recording and CAN2")
    recording.add_argument("--record", metavar="OUT.mf4", help="record by DAQ to this MDF4 file (implies --daq)")
    add_recording_arguments(recording, "its signals by name, and with --record its frames decoded in the file")
    add_ecu_arguments(parser)
    parser.set_defaults(func=run)


def add_recording_arguments(group, can2_help: str) -> None:
    """--can2, --raw-can, the CAN2 bus and --overwrite: how ``measure --record`` and ``record`` take them."""
    group.add_argument("--can2", metavar="DBC", help=f"the CAN2 DBC: {can2_help}")
    group.add_argument("--raw-can", action="store_true",
                       help="also log every frame of the CAN2 bus raw (ASAM MDF bus logging)")
    add_can2_bus_arguments(group)
    group.add_argument("--overwrite", action="store_true",
                       help="replace an existing OUT.mf4 when the recording ends (it stays until then)")
    group.add_argument("--start-when", metavar="COND", help="record from when a recorded signal meets COND "
                       "('zsRailPressure > 20', '... > 20 bar', 'zsSensVolt[2] < 0.5', 'xsTankCtrlState == "
                       "TANK2_ON'; OP: > >= < <= == !=)")
    group.add_argument("--stop-when", metavar="COND", help="end the recording when COND is met (after the start)")
    group.add_argument("--pre-trigger", type=non_negative_float, default=0.0, metavar="S",
                       help="with --start-when: keep the S seconds before the start too")


def run(args: argparse.Namespace) -> int:
    if args.event is not None and not args.daq:
        args.daq = True  # an event only means something to DAQ
    _check_recording_options(args)
    doc = a2l_document(args)
    dbc = can2_dbc(args) if args.can2 else None  # a wrong --can2 file: before connecting too
    names, can2, databases, shown, elements = _split_names(args, doc.model(), dbc)  # unknown names: before connecting
    if args.event is not None:
        from workbench.a2l.xcp import read_xcp_config
        from workbench.session.measure import event_number

        event_number(read_xcp_config(doc), args.event)  # an event the A2L lacks: before connecting too
    if args.record and args.trigger is not None:
        from workbench.record.trigger import checked_trigger

        checked_trigger(args.trigger, doc.model())  # a signal, element, unit or text the A2L refuses: before too
    with open_session(args, doc, reading=True) as session, _terminate_as_interrupt():
        if args.record:
            return _record(args, session, names, can2, dbc)
        view = _view(args, session, shown, can2, elements)
        monitor = _can2_monitor(args, session, can2, databases) if can2 else None
        try:
            if args.daq and names:
                _sample(args, session, names, view, monitor, elements)
            else:
                _poll(args, session, names, view, monitor, elements)
        except KeyboardInterrupt:
            pass  # Ctrl-C is how a measurement ends
        finally:
            if monitor is not None:
                monitor.close()
            view.close()
    return 0


@contextmanager
def _terminate_as_interrupt():
    """SIGTERM (a service manager, ``kill``, a CI timeout) ends a measurement as Ctrl-C does: a recording is
    finalized and summed up, the bus closed. Only the main thread can take signals."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _interrupt(number, frame) -> None:
    raise KeyboardInterrupt


def _split_names(args: argparse.Namespace, model, dbc) -> tuple[list[str], dict[str, Any], list, list[str], dict]:
    """The A2L's names among NAME... (globs expanded; an array's for NAME[i]), the CAN2 signals (``Message.Signal``
    -> cantools signal) of the DBC (--can2, or the demo's with the demo's A2L) as the window names and plots them,
    the DBC's databases, every name as shown, in the order given, and the elements shown (``NAME[i]`` -> the
    array's name and the index). ``dbc``: the --can2 DBC, loaded."""
    from workbench.a2l.model import closest_names, is_glob
    from workbench.can.naming import dbc_signal_name, find_dbc_signal
    from workbench.cli.cal_values import split_cell
    from workbench.errors import UnknownSymbolError

    names, can2, databases, shown, elements = [], {}, None, [], {}
    if dbc is not None and not args.record:  # named: its signals are found even if no NAME is in the A2L
        databases = [dbc.database]
    sampled = "MEASUREMENT" if args.daq or args.record else ("MEASUREMENT", "CHARACTERISTIC", "AXIS_PTS")
    for name in args.names:
        array, index = split_cell(model, name)
        if index is not None and array in model:  # one element of an array, as CANape lists them: the array is read
            label = _element(model, array, index)
            names.append(array)
            shown.append(label)
            elements[label] = (array, index)
            continue
        if name in model:
            names.append(name)
            shown.append(name)
            continue
        if is_glob(name):  # as cal get and cal list take them: what DAQ samples, else every value that reads
            matched = model.expand([name], sampled, what="measurement" if args.daq or args.record else "object")
            names += matched
            shown += matched
            continue
        if databases is None:
            databases = _can2_databases(args, dbc)
        try:
            message, signal = find_dbc_signal(databases, name)
        except UnknownSymbolError as in_dbc:
            known = [known for kind in ("MEASUREMENT", "CHARACTERISTIC", "AXIS_PTS") for known in model.names(kind)]
            where = "the A2L's objects" + (" or the CAN2 DBC's signals" if databases else " (CAN2 signals: --can2 DBC)")
            alike = closest_names(name, known, 2) + list(in_dbc.suggestions[:2])
            raise UnknownSymbolError(name, where, alike) from None
        qualified = dbc_signal_name(message.name, signal.name)
        can2[qualified] = signal
        shown.append(qualified)
    return list(dict.fromkeys(names)), can2, databases or [], list(dict.fromkeys(shown)), elements


def _element(model, array: str, index: tuple[int, ...]) -> str:
    """``NAME[i, j]`` as shown. :raises InputError: ``array`` has no element there."""
    from workbench.calib.cells import index_problem
    from workbench.errors import InputError

    problem = index_problem(array, getattr(model.object(array), "shape", ()), index, "elements")
    if problem is not None:
        raise InputError(problem)
    return f"{array}[{', '.join(map(str, index))}]"


def _picked(values: dict[str, Any], elements: dict[str, tuple[str, tuple[int, ...]]], order: list[str]) -> dict:
    """The values shown: those of ``order``, each ``NAME[i]`` taken from its array's value (one value or a row
    of samples)."""
    picked = {name: value for name, value in values.items() if name in order}
    for label, (array, index) in elements.items():
        if array in values:
            picked[label] = values[array][index]
    return picked


def _can2_databases(args: argparse.Namespace, dbc) -> list:
    """The CAN2 DBC's database: ``dbc`` (--can2, loaded), else the demo's with the demo's A2L (none: an empty list)."""
    from workbench.can import load_dbc

    dbc = dbc if dbc is not None else can2_dbc(args)
    return [(load_dbc(dbc) if isinstance(dbc, str) else dbc).database] if dbc else []


def _can2_monitor(args: argparse.Namespace, session, can2: dict[str, Any], databases: list):
    """A listener on the CAN2 bus (the XCP bus unless --can2-interface/--can2-channel) decoding the DBC, as the
    window's; the newest value of each signal, the samples since the last look."""
    bus = _can2_bus(args, session)
    if bus is None and not session.link.is_can:
        from workbench.errors import InputError

        raise InputError(f"the session runs {session.link.describe()}: name the CAN2 bus of "
                         f"{', '.join(can2)} (--can2-interface/--can2-channel/--can2-bus-kwargs)")
    return _Can2Samples(session, bus, can2, databases, time.time())


def _deadline(args: argparse.Namespace) -> float:
    return time.monotonic() + args.duration if args.duration else float("inf")


def _poll(args: argparse.Namespace, session, names: list[str], view, monitor, elements: dict) -> None:
    """Every 1/rate s: the A2L's names read, the CAN2 signals' newest values beside them."""
    started, deadline, period = time.monotonic(), _deadline(args), 1.0 / (args.rate or 10.0)
    next_at = started
    while time.monotonic() < deadline:
        values = session.read_many(names) if names else {}
        if args.raw:
            values = _raw(session, values)
        if monitor is not None:
            values.update(monitor.latest(raw=args.raw))
        values = _picked(values, elements, view.order)
        view.show(time.monotonic() - started, "poll", {name: values[name] for name in view.order})
        next_at += period
        time.sleep(max(0.0, min(next_at, deadline) - time.monotonic()))


def _sample(args: argparse.Namespace, session, names: list[str], view, monitor, elements: dict) -> None:
    """DAQ samples as the ECU sends them; each CAN2 frame's signals as a row of their own (event CAN2)."""
    with session.measure(names, event=args.event) as live:
        deadline = _deadline(args)  # from when DAQ runs: connecting and configuring it count for nothing
        try:
            while time.monotonic() < deadline:
                for batch in live.read(0.05):
                    values = _raw(session, batch.values) if args.raw else batch.values
                    for row in range(len(batch)):
                        view.show(float(batch.time[row]), batch.event_name,
                                  _picked({name: column[row] for name, column in values.items()}, elements, view.order))
                for when, values in monitor.drain(raw=args.raw) if monitor is not None else ():
                    view.show(when, "CAN2", values)
        finally:
            stats, cause, stray = live.stats, live.loss_cause(), live.stray_dtos()
            print(f"measure: {stats.samples} samples, {stats.lost} lost, {stats.overloads} overload indications"
                  + (f" ({cause})" if cause else "") + (f"; {stray}" if stray else ""), file=sys.stderr)


def _check_recording_options(args: argparse.Namespace) -> None:
    from workbench.errors import InputError

    if getattr(args, "rate", None) is not None and (args.daq or args.record):  # `record` has no --rate
        raise InputError("--rate HZ: only when polling; DAQ samples each signal on its event (--event)")
    if args.record is None:
        given = [option for option, value in (("--raw-can", args.raw_can), ("--overwrite", args.overwrite),
                                              ("--start-when", args.start_when), ("--stop-when", args.stop_when),
                                              ("--pre-trigger", args.pre_trigger)) if value]
        if given:
            raise InputError(f"{', '.join(given)}: only with --record OUT.mf4")
    elif args.raw:
        raise InputError("--raw does not go with --record: the file holds the raw values with their conversions")
    elif args.pre_trigger and not args.start_when:
        raise InputError("--pre-trigger S: only with --start-when COND (the seconds kept from before the start)")
    args.trigger = _trigger(args)  # a malformed condition: before connecting


def _record(args: argparse.Namespace, session, names: list[str], can2: dict[str, Any], dbc) -> int:
    """Record the A2L's ``names`` by DAQ; the CAN2 bus is recorded whole, its signals decoded by the DBC (that of
    --can2, or the demo's when ``can2`` signals were named by it)."""
    from workbench.cli.progressbar import ProgressBar
    from workbench.record import Recorder

    dbc = dbc if dbc is not None else can2_dbc(args) if can2 else None
    recorder = Recorder(session, args.record, names, event=args.event, can2=dbc, can_bus=_can2_bus(args, session),
                        raw_can=args.raw_can, overwrite=args.overwrite, trigger=args.trigger)
    with ProgressBar("recording") as progress, recorder:
        try:
            recorder.wait(args.duration, progress)
        except KeyboardInterrupt:
            pass  # Ctrl-C ends the recording; leaving the block finalizes the file
    stats = recorder.stats
    if args.json:
        print(json.dumps({"path": str(stats.path), "seconds": round(stats.seconds, 6), "samples": stats.samples,
                          "values": stats.values, "lost": stats.lost, "overloads": stats.overloads,
                          "can_frames": stats.can_frames, "raw_frames": stats.raw_frames,
                          "undecoded": stats.undecoded, "file_bytes": stats.file_bytes,
                          **({"trigger": stats.trigger, "started_s": stats.started_s} if stats.trigger else {}),
                          **({"multiplexed": list(stats.multiplexed)} if stats.multiplexed else {})}))
    else:
        measurement = recorder.measurement
        cause, stray = (measurement.loss_cause(), measurement.stray_dtos()) if measurement is not None else ("", "")
        print(f"recorded {stats.describe()}" + (f" ({cause})" if cause else "") + (f"; {stray}" if stray else ""))
    return 0


def _trigger(args: argparse.Namespace):
    """The recording's trigger of --start-when, --stop-when and --pre-trigger (None: none given)."""
    from workbench.record import Condition, Trigger

    if not (args.start_when or args.stop_when):
        return None
    return Trigger(Condition.parse(args.start_when) if args.start_when else None,
                   Condition.parse(args.stop_when) if args.stop_when else None, args.pre_trigger)


def _can2_bus(args: argparse.Namespace, session) -> BusSpec | None:
    """The CAN2 bus the options name; None: the XCP bus. Another channel of the XCP bus's interface keeps its
    options (a udp_multicast ``port`` given with --bus-kwargs) unless --can2-bus-kwargs give others."""
    return can2_bus_spec(args, session.bus_spec)


def _raw(session, values: dict[str, Any]) -> dict[str, Any]:
    return {name: session.to_raw(name, value) for name, value in values.items()}


def _step_places(signal) -> int | None:
    """The decimals of one raw step of a CAN2 signal's DBC factor (0.01 -> 2, 0.5 -> 1, 10 -> 0); None for a
    signal with value texts or no factor."""
    from decimal import Decimal

    scale = getattr(signal, "scale", None)
    if not scale or getattr(signal, "choices", None):
        return None
    return max(0, -Decimal(repr(float(scale))).normalize().as_tuple().exponent)


def _view(args: argparse.Namespace, session, order: list[str], can2: dict[str, Any], elements: dict):
    model = session.model
    formats = {name: ("", None) if args.raw else (signal.unit or "", _step_places(signal)) for name, signal in can2.items()}
    objects = {name: model.object(elements[name][0] if name in elements else name) for name in order
               if name not in formats}
    formats.update({name: ("", None) if args.raw else (model.unit_of(obj), format_decimals(model.format_of(obj)))
                    for name, obj in objects.items()})
    if args.json:
        options.json_lines = True  # a failure's {"ok": false, ...} then comes as one line of the stream
        return _JsonLines(order)
    if sys.stdout.isatty():
        return _LiveTable(order, formats)
    return _TextLines(order, formats)


class _Can2Samples:
    """The window's CAN monitor on the CAN2 bus, keeping what ``measure`` shows of ``signals``
    (``Message.Signal`` -> cantools signal): the newest physical value of each, and the frames' samples since the
    last :meth:`drain` (host time of reception, s since ``origin``)."""

    def __init__(self, session, bus: BusSpec | None, signals: dict[str, Any], databases: list, origin: float):
        import threading

        from workbench.gui.can_monitor import CanMonitor  # no Qt: the window's listener, the window's names

        self.signals = signals
        self.newest: dict[str, float] = {}
        self.pending: list[tuple[float, dict[str, float]]] = []
        self._lock = threading.Lock()
        self.monitor = CanMonitor(session, databases, self._sink, origin, bus=bus)

    def _sink(self, name: str, times, values) -> None:
        if name not in self.signals:
            return
        with self._lock:
            self.newest[name] = float(values[-1])
            if self.pending and self.pending[-1][0] == float(times[-1]):
                self.pending[-1][1][name] = float(values[-1])
            else:
                self.pending.append((float(times[-1]), {name: float(values[-1])}))

    def latest(self, *, raw: bool = False) -> dict[str, Any]:
        """Every signal's newest value (None before its first frame)."""
        with self._lock:
            return {name: self._shown(name, self.newest.get(name), raw) for name in self.signals}

    def drain(self, *, raw: bool = False) -> list[tuple[float, dict[str, Any]]]:
        with self._lock:
            pending, self.pending = self.pending, []
        return [(when, {name: self._shown(name, value, raw) for name, value in values.items()})
                for when, values in pending]

    def _shown(self, name: str, value: float | None, raw: bool) -> Any:
        """Physical (a VAL_ table's text), or raw as the frame carries it."""
        if value is None:
            return None
        signal = self.signals[name]
        if raw:
            return signal.conversion.numeric_scaled_to_raw(value)
        choices = signal.choices or {}
        return str(choices[value]) if value in choices else value

    def close(self) -> None:
        self.monitor.close()


class _JsonLines:
    def __init__(self, order: list[str]):
        self.order = order

    def show(self, when: float, event: str, values: dict[str, Any]) -> None:
        line = {"time": round(when, 6), "event": event, "values": {n: jsonable(v) for n, v in values.items()}}
        print(json.dumps(line), flush=True)

    def close(self) -> None:
        pass


class _TextLines:
    def __init__(self, order: list[str], formats: dict[str, tuple[str, int | None]]):
        self.order, self.formats = order, formats

    def show(self, when: float, event: str, values: dict[str, Any]) -> None:
        shown = " ".join(f"{name}={'-' if value is None else value_text(value, *self.formats[name])}"
                         for name, value in values.items())
        print(f"{when:.4f} {shown}", flush=True)

    def close(self) -> None:
        pass


class _LiveTable:
    """A table that refreshes in place (rich), a few times a second whatever the sample rate."""

    REFRESH_S = 0.1

    def __init__(self, names: list[str], formats: dict[str, tuple[str, int | None]]):
        from rich.console import Console
        from rich.live import Live

        self.names, self.order, self.formats = names, names, formats
        self.latest: dict[str, tuple[float, str, Any]] = {}
        self.counts: dict[str, int] = dict.fromkeys(names, 0)
        self._shown_at = 0.0
        self._live = Live(self._table(), console=Console(), auto_refresh=False)
        self._live.start()

    def _table(self):
        from rich.table import Table

        table = Table(show_edge=False)
        for column, justify in (("signal", "left"), ("value", "right"), ("unit", "left"), ("time s", "right"),
                                ("event", "left"), ("samples", "right")):
            table.add_column(column, justify=justify)
        for name in self.names:
            when, event, value = self.latest.get(name, (0.0, "", None))
            unit, places = self.formats[name]
            table.add_row(name, "-" if value is None else value_text(value, "", places), unit, f"{when:.3f}", event,
                          str(self.counts[name]))
        return table

    def show(self, when: float, event: str, values: dict[str, Any]) -> None:
        for name, value in values.items():
            self.latest[name] = (when, event, value)
            self.counts[name] += 1
        now = time.monotonic()
        if now - self._shown_at >= self.REFRESH_S:
            self._shown_at = now
            self._live.update(self._table(), refresh=True)

    def close(self) -> None:
        self._live.update(self._table(), refresh=True)
        self._live.stop()
