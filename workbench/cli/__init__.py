"""The ``workbench`` command: one sub-command group per module of this package.

Each group module has ``add_subparser(subparsers)`` that registers its commands and
sets ``func`` to a handler taking the parsed namespace and returning an exit code.
Handlers import the library lazily, so ``workbench --help`` stays fast.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys

from workbench import __version__
from workbench.cli import options
from workbench.cli.options import CommandParser, print_json
from workbench.errors import WorkbenchError

__all__ = ["GROUPS", "build_parser", "entry_point", "main"]

# (group, one-line help); the group's commands live in ``workbench.cli.<group>``.
GROUPS: list[tuple[str, str]] = [
    ("a2l", "merge, update from ELF, check, diff and insert into A2L files"),
    ("sim", "run the simulated FLCU ECU (XCP slave) on CAN or Ethernet"),
    ("dbc", "CAN database tools: message table, fix calibrations, driver callbacks"),
    ("info", "show ECU identification, EPK and protection state"),
    ("scan", "find the XCP on CAN slaves on a bus and their CAN ids (GET_SLAVE_ID)"),
    ("measure", "read signals by name (polling or DAQ), optionally record MDF4"),
    ("record", "record signals (DAQ) and the CAN2 bus to MDF4; --repair a killed recording"),
    ("cal", "read/write calibrations by name, fix overrides, datasets"),
    ("flash", "flash the CALIB or APPLICATIVE region from an s19/hex"),
    ("gui", "open the calibration workbench window"),
    ("demo", "start the simulated ECU and the GUI connected to it"),
    ("test", "run requirement tests on the ECU, with MDF4 evidence and a traced report"),
]


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The ``workbench`` parser; with ``only``, that group's commands alone (the other groups are
    listed by name): ``workbench a2l update`` need not import and build every group."""
    parser = CommandParser(
        prog="workbench",
        description="XCP/A2L calibration and measurement workbench.",
    )
    parser.add_argument("--version", action="version", version=f"workbench {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks and debug logging")
    subparsers = parser.add_subparsers(title="command groups", dest="group", metavar="GROUP", parser_class=CommandParser)
    for group, help_text in GROUPS:
        if only is not None and group != only:
            subparsers.add_parser(group, help=help_text)
            continue
        try:
            importlib.import_module(f"{__name__}.{group}").add_subparser(subparsers, group, help_text)
        except ImportError as exc:  # an optional dependency is missing
            sub = subparsers.add_parser(group, help=f"{help_text} (unavailable)")
            sub.set_defaults(func=_unavailable(group, exc))
    return parser


def _group_named(argv: list[str]) -> str | None:
    """The command group ``argv`` runs: its first word that is no option (the options before a group
    take no value), None when that is no group."""
    word = next((word for word in argv if not word.startswith("-")), None)
    return word if word in dict(GROUPS) else None


def _debug_first(argv: list[str]) -> list[str]:
    """``--debug`` anywhere before a ``--`` (``workbench a2l check x.a2l --debug`` as ``workbench --debug a2l ...``):
    it is the top-level parser's option, which argparse would take only before the group."""
    end = argv.index("--") if "--" in argv else len(argv)
    if "--debug" not in argv[:end]:
        return argv
    return ["--debug", *[word for at, word in enumerate(argv) if at >= end or word != "--debug"]]


def _unavailable(group: str, exc: ImportError):
    def handler(args: argparse.Namespace) -> int:
        raise WorkbenchError(f"'workbench {group}' is unavailable: {exc}")

    return handler


_process_may_end_at_once = False  # set by main() when the command run is a batch (see entry_point)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 1 failed, 2 bad input)."""
    global _process_may_end_at_once
    argv = _debug_first(sys.argv[1:] if argv is None else list(argv))
    try:
        parser = build_parser(_group_named(argv))
        options.usage_error = None
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help/--version exit 0, usage errors 2
        if exc.code and options.usage_error and "--json" in argv[:argv.index("--") if "--" in argv else None]:
            print_json({"ok": False, "error": options.usage_error, "exit_code": int(exc.code)})  # bad input, too
        return int(exc.code or 0)
    except KeyboardInterrupt:  # Ctrl-C at once, while the parser imports python-can and the command's modules
        if argv[:1] == ["--debug"]:
            raise
        print("error: interrupted", file=sys.stderr)
        return 130
    if args.debug:
        import logging

        logging.basicConfig(level=logging.DEBUG, format="%(levelname)s %(name)s: %(message)s")
    func = getattr(args, "func", None)
    if func is None:
        parser.print_help(sys.stderr if args.group is None else sys.stdout)
        return 2
    _process_may_end_at_once = getattr(func, "batch", False)
    options.json_printed = options.json_lines = False
    try:
        return int(func(args) or 0)
    except WorkbenchError as exc:
        if args.debug:
            raise
        return _failed(args, str(exc), exc.exit_code)
    except KeyboardInterrupt:
        return _failed(args, "interrupted", 130)
    except BrokenPipeError:  # `workbench ... | head`: the reader left; stop quietly, as git does
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


def _failed(args: argparse.Namespace, message: str, code: int) -> int:
    """The one line on stderr; under ``--json`` also a report on stdout, so that a script reading it
    finds ``ok`` false and why (a refused flash, an ECU that does not answer) instead of nothing."""
    print(f"error: {message}", file=sys.stderr)
    if getattr(args, "json", False) and not options.json_printed:  # a command's report that says why is enough
        print_json({"ok": False, "error": message, "exit_code": code})
    return code


def entry_point() -> None:
    # No command does linear algebra: the worker threads numpy's OpenBLAS starts on import (one per core)
    # only cost each command about 30 ms of CPU. A user's own setting is kept.
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        # A background job of a non-interactive shell (`workbench sim &` in a script) starts with SIGINT
        # ignored, and Python then leaves it so: Ctrl-C and kill -INT would not stop what says they do.
        signal.signal(signal.SIGINT, signal.default_int_handler)
    code = main()
    if _process_may_end_at_once:
        _end_at_once(code)
    sys.exit(code)


def _end_at_once(code: int) -> None:
    """End a batch command's process without Python's teardown (modules, objects, one by one): the system
    frees the memory whole. That teardown took 10-25 ms of a cached update of 65,000 objects. A batch
    leaves nothing that needs Python's exit (its outputs are written and closed), so only the streams and
    logging are flushed."""
    if "logging" in sys.modules:
        sys.modules["logging"].shutdown()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:
        code = 141
    os._exit(code)
