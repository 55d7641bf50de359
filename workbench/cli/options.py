"""Options and output shared by the commands (DESIGN: CLI conventions): the bus options of every
command that talks to an ECU or a bus (python-can's own, plus ``--host/--port/--protocol`` for XCP
on Ethernet), ``--json``, and how reports and JSON are printed."""

from __future__ import annotations

import argparse
import os
import re
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from workbench.bus_defaults import BusSpec
    from workbench.findings import Report

__all__ = ["CommandParser", "add_bus_arguments", "add_can2_bus_arguments", "add_can2_bus_kwargs_argument",
           "add_ethernet_arguments", "add_output_arguments", "bus_settings", "bus_spec", "can2_bus_spec",
           "integer_within", "json_printed", "non_negative_float", "output_file", "port_number", "positive_float",
           "positive_int", "print_json", "print_report", "usage_error", "words_before_key_values"]

# the Namespace keys ``can.cli.create_bus_from_namespace`` turns into ``can.Bus`` keyword arguments
PYTHON_CAN_KEYS = ("channel", "interface", "bitrate", "fd", "data_bitrate", "can_filters", "timing")
PROTOCOLS = ("udp", "tcp")


class CommandParser(argparse.ArgumentParser):
    """A command's parser whose costly options are added when the command runs or shows its help, or only
    when its command line may hold one of them.

    python-can's bus options need ``import can`` (half a second: it loads asammdf and pandas for its MF4
    logger), which ``workbench --help``, the commands that talk to no bus, and those that give none of its
    options and open no CAN bus (XCP on Ethernet, a flash image) should not pay.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._deferred: list[tuple[Callable[[], None], bool]] = []

    def defer(self, add_options: Callable[[], None], *, only_if_named: bool = False) -> None:
        """Run ``add_options`` before this parser parses or formats anything; ``only_if_named``: before it
        parses a command line only when that holds an option this parser does not know yet (one of those,
        an abbreviation of one, or a mistake that argparse then reports with every option in view)."""
        self._deferred.append((add_options, only_if_named))

    def _add_deferred(self, args: list[str] | None = None) -> None:
        unknown = args is None or self._names_unknown_option(args)
        for entry in list(self._deferred):
            add_options, only_if_named = entry
            if unknown or not only_if_named:
                self._deferred.remove(entry)
                add_options()

    def _names_unknown_option(self, args: list[str]) -> bool:
        for word in args:
            if word == "--":
                return False
            if _is_option(word) and word.split("=", 1)[0] not in self._option_string_actions:
                return True
        return False

    def parse_known_args(self, args=None, namespace=None):
        self._add_deferred(args)
        if args is not None and any(option in self._option_string_actions for option in KEY_VALUE_LISTS) and \
                any(not action.option_strings for action in self._actions):
            # a command's own parser with NAMEs or a VALUE (a group's passes its words on whole; a command without
            # any keeps 'port' in the list, where python-can names it: 'Unable to parse bus keyword argument')
            args = words_before_key_values(args)
        namespace, extras = super().parse_known_args(args, namespace)
        if not any(isinstance(action, argparse._SubParsersAction) for action in self._actions):
            namespace._command_parser = self  # the command's own: what a word it does not take is reported by
        return namespace, extras

    def parse_args(self, args=None, namespace=None):
        """As argparse's, but a word no option takes is refused by the command that got it (``workbench cal set:
        error: unrecognized arguments: --raw``, with that command's usage), not by ``workbench`` itself."""
        namespace, extras = self.parse_known_args(args, namespace)
        if extras:
            getattr(namespace, "_command_parser", self).error(f"unrecognized arguments: {' '.join(extras)}")
        return namespace

    def error(self, message: str):
        """argparse's usage error (usage and the message on stderr, exit 2), remembered for ``--json``'s report."""
        global usage_error
        usage_error = f"{self.prog}: {message}"
        super().error(message)

    def format_usage(self) -> str:
        self._add_deferred()
        return super().format_usage()

    def format_help(self) -> str:
        self._add_deferred()
        return super().format_help()

    def _get_formatter(self) -> argparse.HelpFormatter:
        # argparse asks shutil for the width, an import (2-4 ms with its own) a batch command needs nowhere else
        return self.formatter_class(prog=self.prog, width=_terminal_columns() - 2)


KEY_VALUE_LISTS = ("--bus-kwargs", "--can2-bus-kwargs", "--timing")  # python-can's: nargs="+" of KEY=VALUE


def _is_option(word: str) -> bool:
    """Whether argparse reads ``word`` as an option: it starts with '-' and is no negative number (-5, -.5)."""
    return word.startswith("-") and not re.fullmatch(r"-\d+|-\d*\.\d+", word)


def words_before_key_values(args: list[str]) -> list[str]:
    """``measure --bus-kwargs port=43200 zsRailPressure``: a KEY=VALUE list takes every word after it, and
    python-can's action then refuses the name ('Unable to parse bus keyword argument'). A word without
    ``=`` after such a list is none of its items: it is the command's own (a NAME, a VALUE) and moves in
    front of the options, where argparse takes it. Nothing else moves (``--`` ends the search)."""
    words, moved, in_list = [], [], False
    for at, word in enumerate(args):
        option = _is_option(word)
        if word == "--":
            words += args[at:]
            break
        if word in KEY_VALUE_LISTS:
            in_list = True
        elif in_list and not option and "=" not in word:
            moved.append(word)
            continue
        elif option:
            in_list = False
        words.append(word)
    return moved + words if moved else list(args)


def _terminal_columns() -> int:
    """The terminal's width as :func:`shutil.get_terminal_size` gives it: $COLUMNS, the terminal, else 80."""
    try:
        if (columns := int(os.environ["COLUMNS"])) > 0:
            return columns
    except (KeyError, ValueError):
        pass
    try:
        return os.get_terminal_size(sys.__stdout__.fileno()).columns or 80
    except (AttributeError, ValueError, OSError):
        return 80


def output_file(text: str) -> str:
    """argparse type: a file to write; ``-`` (stdout elsewhere) is refused, not written as a file named ``-``."""
    if text == "-":
        raise argparse.ArgumentTypeError("'-' is not a file: the output is written atomically to a file you name; "
                                         "the report goes to the terminal")
    return text


def integer_within(text: str, what: str, low: int, high: int | None, rule: str) -> int:
    """An argparse type's work: ``text`` as an integer (decimal or 0x hex) from ``low`` to ``high`` (None: no
    limit); else a usage error (exit 2), ``not <what>: 'text'`` or ``<rule>, got <value>``."""
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not {what}: {text!r}") from None
    if value < low or high is not None and value > high:
        raise argparse.ArgumentTypeError(f"{rule}, got {value}")
    return value


def positive_int(text: str) -> int:
    """argparse type: an integer above 0 (anything else is a usage error, exit 2)."""
    return integer_within(text, "an integer", 1, None, "must be positive")


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


def port_number(text: str) -> int:
    """argparse type: a TCP/UDP port, 0..65535 (0: any free port)."""
    return integer_within(text, "a port number", 0, 0xFFFF, "must be 0..65535")


def add_bus_arguments(parser: argparse.ArgumentParser) -> None:
    """python-can's own bus options (``can.cli.add_bus_arguments``): ``--interface``, ``--channel``,
    ``--bitrate``, ``--fd``, ``--data-bitrate``, ``--timing`` and ``--bus-kwargs KEY=VALUE ...``
    (udp_multicast's ``port``, Vector's ``app_name`` ...), all optional.

    Two of them are checked the workbench's way: ``--bitrate`` must be positive, and an unknown
    ``--interface`` is reported by the library in one line naming the known ones (python-can's
    ``choices`` would print them as a usage error). On a :class:`CommandParser` they are added
    when its help is shown or its command line names an option it does not know yet: a namespace
    parsed without them lacks their keys (:func:`bus_settings` reads none then).
    """
    if isinstance(parser, CommandParser):
        parser.defer(lambda: _add_python_can_arguments(parser), only_if_named=True)
    else:
        _add_python_can_arguments(parser)


def _add_python_can_arguments(parser: argparse.ArgumentParser) -> None:
    from can.cli import add_bus_arguments as add_python_can_bus_arguments

    add_python_can_bus_arguments(parser, group_title="CAN bus (python-can's options)")
    actions = parser._option_string_actions  # argparse keeps no public handle on an option once added
    actions["--interface"].choices = None
    actions["--interface"].help = ("python-can interface: udp_multicast (the default), virtual, socketcan, vector, pcan, "
                                   "kvaser, ...")
    actions["--channel"].help = "python-can channel (default: 239.74.163.2 on udp_multicast, workbench on virtual)"
    actions["--bitrate"].type = positive_int
    actions["--bitrate"].help = "CAN bit rate in bit/s (default: the A2L's BAUDRATE)"


def bus_settings(args: argparse.Namespace) -> dict[str, Any] | None:
    """The ``can.Bus(**settings)`` keyword arguments the bus options name, read as python-can's
    ``create_bus_from_namespace`` reads them (``--bus-kwargs`` last), or None when none was given.

    The bus itself is opened by the library, which first fills in the workbench's defaults and the
    A2L's bit rate and reports a failure in one line (``create_bus_from_namespace`` opens it at once
    and reports an ``ArgumentError`` quoting the whole namespace).
    """
    settings = {key: getattr(args, key) for key in PYTHON_CAN_KEYS if key in args}
    settings.update(getattr(args, "bus_kwargs", {}))
    return settings or None


def add_can2_bus_arguments(group) -> None:
    """``--can2-interface``, ``--can2-channel`` and ``--can2-bus-kwargs``: the CAN2 bus, when it is not the XCP bus."""
    group.add_argument("--can2-interface", metavar="NAME", help="python-can interface of the CAN2 bus "
                                                               "(default: the XCP bus's)")
    group.add_argument("--can2-channel", metavar="CHANNEL", help="channel of the CAN2 bus (default: the XCP bus's)")
    add_can2_bus_kwargs_argument(group)


def add_can2_bus_kwargs_argument(group) -> None:
    """``--can2-bus-kwargs KEY=VALUE ...``: the CAN2 bus's python-can keyword arguments, as ``--bus-kwargs``."""
    group.add_argument("--can2-bus-kwargs", nargs="+", type=_bus_kwarg, metavar="KEY=VALUE",
                       help="python-can keyword arguments of the CAN2 bus, as --bus-kwargs (udp_multicast's port=N, "
                            "bitrate=N ...; on the XCP bus's interface the rest of its options stay)")


def _bus_kwarg(text: str) -> tuple[str, Any]:
    from workbench.bus_defaults import parse_bus_kwargs

    try:
        return next(iter(parse_bus_kwargs([text]).items()))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def can2_bus_spec(args: argparse.Namespace, xcp_bus: BusSpec | None) -> BusSpec | None:
    """The CAN2 bus ``--can2-interface``, ``--can2-channel`` and ``--can2-bus-kwargs`` name beside the XCP bus
    (:func:`~workbench.bus_defaults.bus_beside`); None: they name none."""
    from workbench.bus_defaults import bus_beside

    return bus_beside(xcp_bus, args.can2_interface, args.can2_channel, dict(args.can2_bus_kwargs or ()))


def bus_spec(args: argparse.Namespace) -> BusSpec | None:
    """The bus the options name, whole (None: none given; the session takes the default bus then)."""
    from workbench.bus_defaults import BusSpec  # here: most commands talk to no bus

    settings = bus_settings(args) or {}
    given = {key: value for key, value in settings.items() if value is not None and value is not False}  # --fd: False
    return BusSpec.from_kwargs(given) if given else None


def add_ethernet_arguments(parser: argparse.ArgumentParser) -> None:
    """``--host``, ``--port`` and ``--protocol udp|tcp``: XCP on Ethernet instead of CAN."""
    group = parser.add_argument_group("XCP on Ethernet")
    group.add_argument("--host", help="XCP on Ethernet at this host (instead of XCP on CAN)")
    group.add_argument("--port", type=port_number, help="XCP on Ethernet port (default: the A2L's)")
    group.add_argument("--protocol", type=str.lower, choices=PROTOCOLS, help="udp (the default) or tcp")


def add_output_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print machine-readable JSON instead of text")


json_printed = False  # a report went out as JSON (see :func:`workbench.cli.main`: a failure after it adds none)
json_lines = False  # the command streams JSON Lines (measure --json): what it prints at the end is one line too
usage_error: str | None = None  # the last usage error argparse reported (main prints it as JSON under --json)


def print_json(data: Any) -> None:
    """``data`` as indented JSON on stdout (anything JSON has no type for as its ``str``), in one write.

    ``json.dump`` would write each of its pieces: 355,000 writes for the table of a 1 MiB DBC.
    """
    import json  # here: most runs print text

    global json_printed
    sys.stdout.write(json.dumps(data, indent=None if json_lines else 2, default=str) + "\n")
    json_printed = True


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
