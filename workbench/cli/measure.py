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

examples:
  workbench measure zsRailPressure xsDC                       # polled 10 times a second
  workbench measure zsRailPressure zsSensVolt --daq --duration 5 --json > rail.jsonl
  workbench measure xsDC --daq --event Task100ms --host 127.0.0.1 --protocol tcp
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
    add_ecu_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.event is not None and not args.daq:
        args.daq = True  # an event only means something to DAQ
    with open_session(args) as session:
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
