"""``workbench test``: run requirement tests (the shipped FLCU suite by default) with pytest and the workbench plugin."""

from __future__ import annotations

import argparse
import importlib.util
import re
from pathlib import Path

from workbench.cli.ecu_options import add_ecu_arguments
from workbench.cli.options import add_can2_bus_kwargs_argument, bus_settings, positive_int
from workbench.errors import InputError, WorkbenchError

__all__ = ["add_subparser", "pytest_arguments", "run", "suite_path"]

EPILOG = """\
Without PATH the FLCU's software requirements (SW_REQ_ID_001-008, the demo application's 29
sub-requirements) are tested. Without bus options every test gets a fresh simulated demo ECU on a
virtual bus of its own; with them (--interface/--channel/--bus-kwargs, or --host/--port) the tests run
against that ECU: a real one, or `workbench sim` in another process, whose fault injection the tests
find by the same bus options (against a real ECU the tests that need it are skipped).

--report DIR writes DIR/junit.xml (a testcase property 'requirement' per requirement id),
DIR/report.html (traceability, each test's steps, plots of its signals with the expectation bands)
and each test's MDF4 evidence under DIR/evidence; --verdict-log FILE a JSON line per test as it ends.
-n N spreads the tests over N processes (pytest-xdist), each test with its own simulated ECU. --req ID
runs the tests that verify a requirement (or those below it), --repeat N runs each test N times, and
what follows -- goes to pytest as it is (-x, -v, --lf, -m MARK, --junitxml PATH ...).
Exit 0: every test passed; 1: a test failed, or broke before it judged (its requirements NOT JUDGED);
2: bad input (options, a path, no tests found, a test file that does not import).

examples:
  workbench test --report out/
  workbench test -n 2 --report out/
  workbench test -k tank_ctrl
  workbench test --req SW_REQ_ID_001 --req SW_REQ_ID_002.2 --repeat 3
  workbench test my_tests/ --report out/ -- -x -v
  workbench test --interface udp_multicast --channel 239.74.163.2 --bus-kwargs port=43200
  workbench test my_tests/ --a2l project.a2l --interface socketcan --channel can0 --dbc vehicle.dbc
  workbench test --interface udp_multicast --bus-kwargs port=43200 --can2-channel 239.74.163.3 --can2-bus-kwargs port=43201
"""

_PYTEST_EXIT = {0: 0, 1: 1, 2: 130, 3: 1, 4: 2, 5: 2}


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(
        name, help=help_text, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Run requirement tests (pytest with the workbench plugin): scripted steps on the ECU by name, "
                    "each test's signals recorded to MDF4, results traced to requirement ids.")
    parser.add_argument("paths", nargs="*", metavar="PATH", help="test files or folders (default: the FLCU suite)")
    parser.add_argument("--report", metavar="DIR", help="write DIR/junit.xml, DIR/report.html and the MF4 evidence")
    parser.add_argument("--verdict-log", metavar="FILE", help="write a JSON line per test to FILE as it ends (verdict, "
                                                              "requirements, failure), for a program following the run")
    parser.add_argument("-n", dest="workers", type=positive_int, metavar="N",
                        help="run the tests in N worker processes (pytest-xdist; simulated ECUs only)")
    parser.add_argument("-k", dest="keyword", metavar="EXPR", help="only the tests whose names match EXPR (pytest -k)")
    parser.add_argument("--req", action="append", metavar="ID",
                        help="only the tests that verify requirement ID or one below it (SW_REQ_ID_001: "
                             "SW_REQ_ID_001.1 ...); repeatable")
    parser.add_argument("--repeat", type=positive_int, metavar="N", help="run each test N times (pytest-repeat's "
                                                                          "--count; one testcase per run)")
    parser.add_argument("--requirements", metavar="CSV", help="requirements catalogue (id,name,description) to trace "
                                                               "(default for the FLCU suite: its own)")
    parser.add_argument("--dbc", metavar="DBC", help="CAN2 database (default: the demo's)")
    parser.add_argument("--can2-interface", metavar="NAME", help="python-can interface of CAN2 (default: the XCP bus's)")
    parser.add_argument("--can2-channel", metavar="CHANNEL", help="CAN2 on its own bus (default: the XCP bus)")
    add_can2_bus_kwargs_argument(parser)
    parser.add_argument("--sim-s19", metavar="S19", help="flash image of the simulated demo ECU (default: the demo's)")
    parser.add_argument("--sim-control", metavar="HOST:PORT",
                        help="a workbench sim's control channel (default: found by the bus options)")
    add_ecu_arguments(parser, json_output=False)
    parser.set_defaults(func=run, pytest_args=[])
    parse_known_args = parser.parse_known_args

    def parse_with_pytest_args(args=None, namespace=None):
        """What follows ``--`` is pytest's, as it is (argparse would take it for PATHs, or refuse it after one)."""
        extra = []
        if args is not None and "--" in args:
            at = args.index("--")
            args, extra = args[:at], args[at + 1:]
        namespace, rest = parse_known_args(args, namespace)
        namespace.pytest_args = extra
        return namespace, rest

    parser.parse_known_args = parse_with_pytest_args


def suite_path() -> Path:
    """The shipped FLCU requirement suite."""
    from workbench.testbench.run import FLCU_SUITE

    return FLCU_SUITE


def pytest_arguments(args: argparse.Namespace) -> list[str]:
    """The pytest command line for ``args``. :raises InputError: options that cannot work together."""
    paths = [str(path) for path in args.paths] or [str(suite_path())]
    for path in args.paths:
        if not Path(path.split("::")[0]).exists():
            raise InputError(f"{path}: no such test file or folder")
    bus = {key: value for key, value in (bus_settings(args) or {}).items() if value is not None}
    if "timing" in bus:
        raise InputError("--timing cannot be passed to the tests; give --bitrate (and --bus-kwargs)")
    real_ecu = bool(bus) or bool(args.host)
    argv = [*paths, "-p", "workbench.testbench.plugin", "-p", "no:cacheprovider", "-rfEs", "-o", "junit_family=xunit1",
            # this command imported the workbench before pytest could mark its plugin's package for rewriting
            "-W", "ignore:Module already imported so cannot be rewritten:pytest.PytestAssertRewriteWarning"]
    for option, value in (("--interface", bus.pop("interface", None)), ("--channel", bus.pop("channel", None)),
                          ("--bitrate", bus.pop("bitrate", None)), ("--a2l", args.a2l), ("--host", args.host),
                          ("--port", args.port), ("--protocol", args.protocol), ("--key-function", args.key_function),
                          ("--dbc", args.dbc), ("--can2-interface", args.can2_interface),
                          ("--can2-channel", args.can2_channel), ("--sim-s19", args.sim_s19),
                          ("--sim-control", args.sim_control), ("--report", args.report), ("-k", args.keyword),
                          ("--verdict-log", args.verdict_log)):
        if value is not None:  # --option=VALUE: pytest takes a separate word naming a file for a test path (its root)
            argv += [option, str(value)] if option == "-k" else [f"{option}={value}"]
    if bus:
        argv += ["--bus-kwargs", *(f"{key}={value}" for key, value in bus.items())]
    if args.can2_bus_kwargs:
        argv += ["--can2-bus-kwargs", *(f"{key}={value}" for key, value in args.can2_bus_kwargs)]
    if args.accept_epk_mismatch:
        argv.append("--accept-epk-mismatch")
    requirements = args.requirements or (str(suite_path() / "requirements.csv") if not args.paths else None)
    if requirements:
        argv.append(f"--requirements={requirements}")
    for requirement_id in args.req or ():
        argv += ["--req", requirement_id]
    if args.repeat:
        if importlib.util.find_spec("pytest_repeat") is None:
            raise InputError("--repeat needs pytest-repeat: pip install pytest-repeat")
        argv += ["-p", "repeat", "--count", str(args.repeat)]  # pytest-repeat, by its entry point's name
    if real_ecu and importlib.util.find_spec("xdist") is not None:
        argv += ["-n", "0"]  # one master: whatever -n the addopts of a pytest.ini or pyproject.toml near the tests give
    if args.workers:
        if real_ecu:
            raise InputError("-n runs a simulated ECU per worker; a real ECU (bus options) takes one master at a time")
        if importlib.util.find_spec("xdist") is None:
            raise InputError("-n needs pytest-xdist: pip install pytest-xdist")
        argv += ["-p", "xdist", "-n", str(args.workers)]  # its entry point's name
    return argv + list(args.pytest_args)


def run(args: argparse.Namespace) -> int:
    import pytest

    argv = pytest_arguments(args)
    if args.report:
        report = Path(args.report)
        if report.exists() and not report.is_dir():
            raise InputError(f"--report {report}: is a file; name a folder")
        try:  # before the tests run: junit.xml and the report would fail at the end, a traceback after them
            report.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"--report {report}: cannot be created ({exc.strerror or exc})") from None
        if args.requirements:  # as the plugin would refuse it, but in the command's words
            from workbench.testbench.report import read_requirements

            read_requirements(args.requirements)
    if args.verdict_log and Path(args.verdict_log).is_dir():  # as the plugin would refuse it, in the command's words
        raise InputError(f"--verdict-log {args.verdict_log}: is a folder; name a file")
    collection = _CollectionErrors()
    code = int(pytest.main(argv, plugins=[collection]))
    if collection.errors and code in (1, 2) and "--continue-on-collection-errors" not in argv:
        # pytest's "Interrupted: 1 error during collection" exits as Ctrl-C does (xdist's as a failed test), no test ran
        more = len(collection.errors) - 1
        raise InputError(collection.errors[0] + (f" (and {more} more: see above)" if more else ""))
    if code == 5:
        raise InputError("no tests found (check PATH, -k and --req)")
    if code == 3:
        raise WorkbenchError("pytest stopped with an internal error (see above)")
    return _PYTEST_EXIT.get(code, 1)


class _CollectionErrors:
    """The test files pytest could not import (a syntax error, a missing module), each as one line
    ``FILE:LINE: cannot be collected: ERROR``."""

    def __init__(self):
        self.errors: list[str] = []
        self.root = Path.cwd()

    def pytest_sessionstart(self, session) -> None:
        self.root = session.config.rootpath

    def pytest_collectreport(self, report) -> None:
        if not report.failed:
            return
        text = report.longreprtext.strip()
        lines = [line.lstrip("E").strip() for line in text.splitlines() if line.strip()]
        path = self.root / report.nodeid.split("::")[0] if report.nodeid else None
        where = str(path) if path is not None else "a test file"
        if path is not None:  # the line: a syntax error's File "...", line N, an import's "test_x.py:N: in <module>"
            lines_at = [n for file, n in re.findall(r'File "([^"]+)", line (\d+)', text) if Path(file) == path]
            lines_at += re.findall(rf"^\S*{re.escape(path.name)}:(\d+): in <module>", text, re.MULTILINE)
            where += f":{lines_at[-1]}" if lines_at else ""
        self.errors.append(f"{where}: cannot be collected: {lines[-1] if lines else 'see above'}")
