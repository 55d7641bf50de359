"""``workbench record``: signals by DAQ and the CAN2 bus to an MDF4 file (``measure --record`` as a command of its
own), and ``--repair`` for the file of a recording whose process was killed."""

from __future__ import annotations

import argparse

from workbench.cli.ecu_options import add_ecu_arguments
from workbench.cli.measure import add_recording_arguments
from workbench.cli.options import positive_float, print_json

__all__ = ["add_subparser", "run"]

EPILOG = """\
Records as `workbench measure NAME... --record OUT.mf4` does (see its help): each signal by DAQ on its A2L event
(or --event), one channel group per event on the ECU's clock, raw values with the A2L's conversions; --can2 adds
the CAN2 messages decoded with a DBC, --raw-can every frame of the bus. Ctrl-C, SIGTERM or --duration end it,
or --stop-when COND; --start-when COND records from when a recorded signal meets COND, with --pre-trigger S
the S seconds before too (COND: NAME OP VALUE, OP one of > >= < <= == !=, VALUE a number or a value-table text).

The file is complete after every second of recording. A recording whose process was killed (kill -9, a crash, the
power) keeps everything up to its last second, in a file marked unfinalized as MDF provides for loggers: asammdf
and python-can read it as it is; MATLAB (mdfInfo, mdfRead), and tools that read finalized files only, need it
finalized first: --repair FILE... does that in place and says what each file holds.

examples:
  workbench record run.mf4 zsRailPressure xsTankCtrlState --can2 dbc/FLCU_CAN2.dbc --duration 60
  workbench record bus.mf4 --raw-can                       # the CAN2 bus alone, every frame
  workbench record fix.mf4 'zs*' --start-when 'zsRailPressure > 35' --pre-trigger 2 --stop-when 'zsRailPressure < 30'
  workbench record --repair run.mf4                        # after the recording was killed
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG,
                                   formatter_class=argparse.RawDescriptionHelpFormatter,
                                   description="Record signals by name (XCP DAQ) and the CAN2 bus to an MDF4 file that "
                                               "asammdf, CANape and MATLAB open, or finalize a killed recording.")
    parser.add_argument("out", nargs="?", metavar="OUT.mf4", help="the MDF4 file to record to")
    parser.add_argument("names", nargs="*", metavar="NAME", help="an A2L MEASUREMENT, one element of an array "
                        "('zsSensVolt[2]': the array is recorded) or a glob ('zsRail*')")
    parser.add_argument("--event", help="DAQ event (name or number) for every signal (default: each signal's own)")
    parser.add_argument("--duration", type=positive_float, metavar="S", help="stop after S seconds (default: Ctrl-C)")
    parser.add_argument("--repair", nargs="+", metavar="FILE", help="finalize these recordings (their process was "
                        "killed) in place and say what each holds; no ECU is needed")
    add_recording_arguments(parser.add_argument_group("CAN2"), "its messages decoded in the file, a group each")
    add_ecu_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workbench.errors import InputError

    if args.repair:
        if args.out is not None or args.names:
            raise InputError("--repair FILE... takes the files to finalize; it records nothing (no OUT.mf4)")
        return _repair(args.repair, args.json)
    if args.out is None:
        raise InputError("name the file to record to: workbench record OUT.mf4 NAME... (or --repair FILE...)")
    if not (args.names or args.can2 or args.raw_can):
        raise InputError(f"nothing to record to {args.out}: name signals, --can2 DBC or --raw-can")
    from workbench.cli import measure

    args.record, args.daq, args.raw = args.out, True, False
    return measure.run(args)


def _repair(paths: list[str], as_json: bool) -> int:
    """Finalize each file and say what it holds. :raises InputError: one is no MDF4 file asammdf reads."""
    from workbench.record import contents, finalize

    reports = []
    for path in paths:
        finalized = finalize(path)
        groups = contents(path)
        reports.append({"path": path, "finalized": finalized,
                        "seconds": round(max((g.last_s for g in groups if g.last_s is not None), default=0.0), 6),
                        "groups": {g.name: g.records for g in groups}})
    if as_json:
        print_json(reports)
        return 0
    for report in reports:
        held = ", ".join(f"{name} {records:,}" for name, records in report["groups"].items())
        state = "finalized" if report["finalized"] else "was finalized already"
        print(f"{report['path']}: {state}; {report['seconds']:.1f} s, records: {held or 'no channel groups'}")
    return 0
