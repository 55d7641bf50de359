"""Options and output shared by the commands (DESIGN: CLI conventions): the bus options of every
command that talks to an ECU or a bus, ``--json``, and how reports and JSON are printed."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from workbench.findings import Report

DEFAULT_CHANNELS = {"virtual": "workbench", "udp_multicast": "239.74.163.2"}


def positive_int(text: str) -> int:
    """argparse type: an integer above 0 (anything else is a usage error, exit 2)."""
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number above 0 (anything else is a usage error, exit 2)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be positive, got {text}")
    return value


def non_negative_float(text: str) -> float:
    """argparse type: a finite number of 0 or more (anything else is a usage error, exit 2)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0 <= value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {text}")
    return value


def add_bus_arguments(parser: argparse.ArgumentParser) -> None:
    """``--interface/--channel/--bitrate`` as python-can spells them, plus ``--host/--port`` for Ethernet."""
    group = parser.add_argument_group("bus")
    group.add_argument("--interface", "-i", default="udp_multicast",
                       help="python-can interface: udp_multicast (default), virtual, socketcan, vector, pcan, kvaser, ...")
    group.add_argument("--channel", "-c", default=None,
                       help="python-can channel (default: 239.74.163.2 for udp_multicast)")
    group.add_argument("--bitrate", "-b", type=positive_int, default=None,
                       help="CAN bit rate in bit/s (default: from the A2L)")
    group.add_argument("--host", default=None, help="XCP on Ethernet: ECU host (instead of CAN)")
    group.add_argument("--port", type=positive_int, default=None, help="XCP on Ethernet: ECU port")


def bus_config(args: argparse.Namespace, bitrate: int | None = None) -> dict[str, Any]:
    """The python-can ``Bus(**config)`` keyword arguments the options select."""
    config: dict[str, Any] = {"interface": args.interface}
    channel = args.channel or DEFAULT_CHANNELS.get(args.interface)
    if channel is not None:
        config["channel"] = channel
    if args.bitrate or bitrate:
        config["bitrate"] = args.bitrate or bitrate
    if args.interface == "udp_multicast":
        config["receive_own_messages"] = False
    return config


def add_output_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print machine-readable JSON instead of text")


def print_json(data: Any) -> None:
    json.dump(data, sys.stdout, indent=2, default=str)
    sys.stdout.write("\n")


def print_report(report: "Report", *, as_json: bool, verbose: bool, summary: str, output: str | None = None) -> None:
    """A report of findings, as JSON (its fields plus ``summary`` and ``output``) or as text.

    Text: one finding a line on stdout (warnings and errors; every finding when ``verbose``),
    then ``summary`` on stderr.
    """
    if as_json:
        data = report.to_dict()
        data["summary"] = summary
        if output is not None:
            data["output"] = str(output)
        print_json(data)
        return
    for finding in report.findings if verbose else report.problems:
        print(finding)
    print(summary, file=sys.stderr)
