"""``workbench measure``: signals by name, polled or by DAQ, as a live table or JSON lines."""

from __future__ import annotations

import argparse
import json
import sys
import time
from typing import Any

from workbench.cli.ecu_options import add_ecu_arguments, open_session
from workbench.cli.options import positive_float
from workbench.cli.render import decimals, jsonable, value_text

EPILOG = """\
In a terminal the values refresh in place; piped (or with --json) every sample is a line: with
--json a JSON object {"time": s, "event": ..., "values": {name: value}}, else "time name=value ...".
Ctrl-C or --duration ends the measurement (exit 0); with --daq the samples and losses are
summed up on stderr.

With --record the samples go to an MDF4 file instead (DAQ, ECU time, raw values with the A2L's
conversions): --can2 adds the CAN2 bus's frames decoded with a DBC, --raw-can every frame of that
bus raw (ASAM MDF bus logging, which asammdf and CANape decode again with a DBC). The file is
complete after every second of recording, also when the process is killed; Ctrl-C or --duration
ends it. The CAN2 bus is the XCP bus unless --can2-interface/--can2-channel name another.

examples:
  workbench measure zsRailPressure xsDC                       # polled 10 times a second
  workbench measure zsRailPressure zsSensVolt --daq --duration 5 --json > rail.jsonl
  workbench measure xsDC --daq --event Task100ms --host 127.0.0.1 --protocol tcp
  workbench measure zsRailPressure xsTankCtrlState --record run.mf4 --can2 dbc/FLCU_CAN2.dbc --raw-can
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
                                   description="Measure signals by name in physical units: polled (SHORT_UPLOAD/UPLOAD "
                                               "of neighbouring addresses together) or sampled by the ECU with DAQ "
                                               "(each signal on its A2L event, with the ECU's timestamps).")
    parser.add_argument("names", nargs="+", metavar="NAME")
    parser.add_argument("--daq", action="store_true", help="sample by DAQ instead of polling")
    parser.add_argument("--event", help="DAQ event (name or number) for every signal (default: each signal's own)")
    parser.add_argument("--rate", type=positive_float, default=10.0, metavar="HZ", help="polling rate (default 10 Hz)")
    parser.add_argument("--duration", type=positive_float, metavar="S", help="stop after S seconds (default: Ctrl-C)")
    parser.add_argument("--raw", action="store_true", help="raw values, as the ECU holds them (no conversion)")
    recording = parser.add_argument_group("recording")
    recording.add_argument("--record", metavar="OUT.mf4", help="record by DAQ to this MDF4 file (implies --daq)")
    recording.add_argument("--can2", metavar="DBC", help="also record the CAN2 frames of this DBC's messages, decoded")
    recording.add_argument("--raw-can", action="store_true",
                           help="also log every frame of the CAN2 bus raw (ASAM MDF bus logging)")
    recording.add_argument("--can2-interface", metavar="NAME", help="python-can interface of the CAN2 bus "
                                                                   "(default: the XCP bus's)")
    recording.add_argument("--can2-channel", metavar="CHANNEL", help="channel of the CAN2 bus (default: the XCP bus's)")
    recording.add_argument("--overwrite", action="store_true",
                           help="replace an existing OUT.mf4 when the recording ends (it stays until then)")
    add_ecu_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.event is not None and not args.daq:
        args.daq = True  # an event only means something to DAQ
    _check_recording_options(args)
    with open_session(args) as session:
        if args.record:
            return _record(args, session)
        view = _view(args, session)
        try:
            if args.daq:
                _sample(args, session, view)
            else:
                _poll(args, session, view)
        except KeyboardInterrupt:
            pass  # Ctrl-C is how a measurement ends
        finally:
            view.close()
    return 0


def _deadline(args: argparse.Namespace) -> float:
    return time.monotonic() + args.duration if args.duration else float("inf")


def _poll(args: argparse.Namespace, session, view) -> None:
    started, deadline, period = time.monotonic(), _deadline(args), 1.0 / args.rate
    next_at = started
    while time.monotonic() < deadline:
        values = session.read_many(args.names)
        view.show(time.monotonic() - started, "poll", _raw(session, values) if args.raw else values)
        next_at += period
        time.sleep(max(0.0, min(next_at, deadline) - time.monotonic()))


def _sample(args: argparse.Namespace, session, view) -> None:
    deadline = _deadline(args)
    with session.measure(args.names, event=args.event) as live:
        try:
            while time.monotonic() < deadline:
                for batch in live.read(0.05):
                    values = _raw(session, batch.values) if args.raw else batch.values
                    for row in range(len(batch)):
                        view.show(float(batch.time[row]), batch.event_name,
                                  {name: column[row] for name, column in values.items()})
        finally:
            stats = live.stats
            print(f"measure: {stats.samples} samples, {stats.lost} lost, {stats.overloads} overload indications",
                  file=sys.stderr)


def _check_recording_options(args: argparse.Namespace) -> None:
    from workbench.errors import InputError

    if args.record is None:
        given = [option for option, value in (("--can2", args.can2), ("--raw-can", args.raw_can),
                                              ("--can2-interface", args.can2_interface),
                                              ("--can2-channel", args.can2_channel), ("--overwrite", args.overwrite))
                 if value]
        if given:
            raise InputError(f"{', '.join(given)}: only with --record OUT.mf4")
    elif args.raw:
        raise InputError("--raw does not go with --record: the file holds the raw values with their conversions")


def _record(args: argparse.Namespace, session) -> int:
    from workbench.cli.progressbar import ProgressBar
    from workbench.record import Recorder

    recorder = Recorder(session, args.record, args.names, event=args.event, can2=args.can2,
                        can_bus=_can2_bus(args, session), raw_can=args.raw_can, overwrite=args.overwrite)
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
                          "undecoded": stats.undecoded, "file_bytes": stats.file_bytes}))
    else:
        print(f"recorded {stats.describe()}")
    return 0


def _can2_bus(args: argparse.Namespace, session) -> dict[str, Any] | None:
    """The CAN2 bus the options name; None: the recorder takes the XCP bus."""
    if args.can2_interface is None and args.can2_channel is None:
        return None
    from workbench.bus_defaults import complete_bus_settings

    xcp_bus = session.link.settings.bus if session.link.settings.transport == "CAN" else {}
    return complete_bus_settings({"interface": args.can2_interface or xcp_bus.get("interface"),
                                  "channel": args.can2_channel})


def _raw(session, values: dict[str, Any]) -> dict[str, Any]:
    return {name: session.to_raw(name, value) for name, value in values.items()}


def _view(args: argparse.Namespace, session):
    model = session.model
    formats = {name: ("", None) if args.raw else
               (model.unit_of(model.object(name)), decimals(model.format_of(model.object(name))))
               for name in args.names}
    if args.json:
        return _JsonLines()
    if sys.stdout.isatty():
        return _LiveTable(args.names, formats)
    return _TextLines(formats)


class _JsonLines:
    def show(self, when: float, event: str, values: dict[str, Any]) -> None:
        line = {"time": round(when, 6), "event": event, "values": {n: jsonable(v) for n, v in values.items()}}
        print(json.dumps(line), flush=True)

    def close(self) -> None:
        pass


class _TextLines:
    def __init__(self, formats: dict[str, tuple[str, int | None]]):
        self.formats = formats

    def show(self, when: float, event: str, values: dict[str, Any]) -> None:
        shown = " ".join(f"{name}={value_text(value, *self.formats[name])}" for name, value in values.items())
        print(f"{when:.4f} {shown}", flush=True)

    def close(self) -> None:
        pass


class _LiveTable:
    """A table that refreshes in place (rich), a few times a second whatever the sample rate."""

    REFRESH_S = 0.1

    def __init__(self, names: list[str], formats: dict[str, tuple[str, int | None]]):
        from rich.console import Console
        from rich.live import Live

        self.names, self.formats = names, formats
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
