"""The pytest plugin of requirement tests (entry point ``pytest11``, so plain ``pytest`` finds it).

* the ``ecu`` fixture: a :class:`~workbench.testbench.Bench` on the ECU the options name (``--a2l``,
  ``--interface``, ``--channel``, ``--bitrate``, ``--bus-kwargs``, ``--host``, ``--port``, ``--protocol``,
  as ``workbench`` takes them), or on a fresh simulated demo ECU per test without bus options; the
  test's signals recorded to MDF4 as its evidence; its calibrations restored after it;
* ``@requirement("SW_REQ_ID_002.2")`` -> the JUnit testcase property ``requirement`` (one per id);
* ``--report DIR``: DIR/junit.xml, DIR/report.html (traceability, steps, plots) and the evidence under DIR;
* ``--verdict-log FILE``: a JSON line per test as it ends (:mod:`workbench.testbench.verdicts`), for a window that
  follows the run.

Costs nothing to a test that does not use it: this module imports only pytest; the fixture imports the
rest when a test asks for it.
"""

from __future__ import annotations

import json
import logging
import re
from contextlib import ExitStack
from pathlib import Path

import pytest

from workbench.testbench.markers import REQUIREMENT_MARK, SIMULATOR_MARK

__all__ = ["ecu"]

_TARGET = pytest.StashKey()
_REPORT_DIR = pytest.StashKey()
_CATALOGUE = pytest.StashKey()  # the --requirements of a --report
_CALL_FAILED = pytest.StashKey()  # the test's body failed or broke: the teardown's problems do not make a second error
TEARDOWN = "teardown"  # the user property that holds them then (JUnit writes it; the report adds it to the message)
_ECU_STATE = pytest.StashKey()  # a test's ("lost": the ECU stopped answering during it, or "unreachable" at its
# start; the error that said so)


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("workbench", "workbench requirement tests (the ecu fixture)")
    group.addoption("--a2l", metavar="A2L", help="the ECU's A2L (default: the built-in demo ECU's)")
    group.addoption("--interface", help="python-can interface of XCP on CAN (no bus options: a simulated demo "
                                        "ECU per test)")
    group.addoption("--channel", help="python-can channel")
    group.addoption("--bitrate", type=int, help="CAN bit rate in bit/s (default: the A2L's BAUDRATE)")
    group.addoption("--bus-kwargs", nargs="+", metavar="KEY=VALUE", help="python-can bus keyword arguments "
                                                                        "(udp_multicast's port=N ...)")
    group.addoption("--host", help="XCP on Ethernet at this host")
    group.addoption("--port", type=int, help="XCP on Ethernet port (default: the A2L's)")
    group.addoption("--protocol", choices=("udp", "tcp"), help="XCP on Ethernet: udp (default) or tcp")
    group.addoption("--key-function", metavar="NAME", help="seed & key function (default: the A2L's)")
    group.addoption("--accept-epk-mismatch", action="store_true", help="write although the EPKs differ")
    group.addoption("--dbc", metavar="DBC", help="CAN2 database (default: the demo's FLCU_CAN2.dbc)")
    group.addoption("--can2-interface", metavar="NAME", help="python-can interface of CAN2 (default: the XCP bus's)")
    group.addoption("--can2-channel", metavar="CHANNEL", help="channel of CAN2 (default: the XCP bus)")
    group.addoption("--can2-bus-kwargs", nargs="+", metavar="KEY=VALUE",
                    help="python-can bus keyword arguments of CAN2, as --bus-kwargs (port=N, bitrate=N ...)")
    group.addoption("--sim-s19", metavar="S19", help="flash image of the simulated demo ECU (default: the demo's)")
    group.addoption("--sim-control", metavar="HOST:PORT", help="a workbench sim's control channel (default: found by "
                                                               "the bus options)")
    group.addoption("--report", metavar="DIR", help="write DIR/junit.xml, DIR/report.html and the MF4 evidence")
    group.addoption("--requirements", metavar="CSV", help="the requirements (id,name,description) the report traces")
    group.addoption("--verdict-log", metavar="FILE", help="write a JSON line per test to FILE as it ends (its "
                                                          "verdict, requirements and failure), for a window following "
                                                          "the run")
    group.addoption("--req", action="append", metavar="ID",
                    help="only the tests that verify requirement ID or one below it (SW_REQ_ID_001: SW_REQ_ID_001.1 "
                         "...); repeatable")


@pytest.hookimpl(tryfirst=True)
def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", f"{REQUIREMENT_MARK}(*ids): the requirements a test verifies (JUnit property "
                                       "'requirement')")
    config.addinivalue_line("markers", f"{SIMULATOR_MARK}: needs the simulated ECU's faults/plant (skipped elsewhere)")
    report = config.getoption("report")
    if report:
        directory = Path(report)
        if directory.exists() and not directory.is_dir():
            raise pytest.UsageError(f"--report {report}: is a file; name a folder")
        try:  # before the tests run: the report and junit.xml would fail at the session's end
            directory.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise pytest.UsageError(f"--report {report}: cannot be created ({exc.strerror or exc})") from None
        config.stash[_REPORT_DIR] = directory
        config.stash[_CATALOGUE] = _catalogue(config.getoption("requirements"))
        if not config.option.xmlpath:
            config.option.xmlpath = str(directory / "junit.xml")
    verdict_log = config.getoption("verdict_log")
    outcomes = _Outcomes(config, keep_all=bool(report or verdict_log))
    config.pluginmanager.register(outcomes, "workbench-testbench-outcomes")
    if verdict_log and not hasattr(config, "workerinput"):
        live = _LiveVerdicts(_verdict_log(verdict_log), outcomes)
        config.pluginmanager.register(live, "workbench-testbench-verdicts")
    if any(getattr(config.option, dest, None) for dest in _ECU_OPTIONS):  # bad ECU options: a usage error at once
        target = _target(config)
        workers = getattr(config.option, "numprocesses", None)  # pytest-xdist's -n, maybe from an ini's addopts
        if not target.simulated and workers and not hasattr(config, "workerinput"):
            source = f" (from the addopts of {config.inipath.name})" if config.inipath else ""
            raise pytest.UsageError(f"-n {workers}{source}: the tests would share {target.describe()} from {workers} "
                                    "processes, and XCP takes one master at a time: give -n 0")


def _verdict_log(path: str):
    """The ``--verdict-log`` file, opened for writing. :raises pytest.UsageError: it cannot be (a folder, no access)."""
    from workbench.testbench.verdicts import VerdictLog

    if Path(path).is_dir():
        raise pytest.UsageError(f"--verdict-log {path}: is a folder; name a file")
    try:
        return VerdictLog(path)
    except OSError as exc:
        raise pytest.UsageError(f"--verdict-log {path}: cannot be written ({exc.strerror or exc}: "
                                f"{exc.filename})") from None


def _catalogue(path: str | None) -> list:
    """The ``--requirements`` catalogue, read before the tests run. :raises pytest.UsageError: it cannot be read."""
    if not path:
        return []
    from workbench.errors import InputError
    from workbench.testbench.report import read_requirements

    try:
        return read_requirements(path)
    except InputError as exc:
        raise pytest.UsageError(str(exc)) from None


@pytest.hookimpl(tryfirst=True)  # --req judges the tests collected, before -k takes some away
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        for mark in item.iter_markers(REQUIREMENT_MARK):
            for requirement_id in mark.args:
                item.user_properties.append(("requirement", str(requirement_id)))
    wanted = config.getoption("req")
    if wanted:
        _select_requirements(config, items, wanted)


def traces(requirement_id: str, wanted: str) -> bool:
    """``requirement_id`` is ``wanted`` or below it: SW_REQ_ID_001.1 is below SW_REQ_ID_001, SW_REQ_ID_0011 is not."""
    return requirement_id == wanted or requirement_id.startswith(wanted + ".")


def _select_requirements(config: pytest.Config, items: list[pytest.Item], wanted: list[str]) -> None:
    """Keep the tests that verify a ``--req`` requirement. :raises pytest.UsageError: an id no test verifies (a
    misspelt id would run less than asked and pass)."""
    ids = {item: [value for key, value in item.user_properties if key == "requirement"] for item in items}
    missing = [want for want in wanted if not any(traces(i, want) for each in ids.values() for i in each)]
    if missing:
        import difflib

        known = sorted({i for each in ids.values() for i in each})
        close = difflib.get_close_matches(missing[0], known, n=3)
        raise pytest.UsageError(f"--req {missing[0]}: no test collected verifies it"
                                + (f"; did you mean {', '.join(close)}?" if close else
                                   f" ({len(known)} requirement ids in the tests collected)"))
    selected = [item for item in items if any(traces(i, want) for i in ids[item] for want in wanted)]
    kept = set(selected)
    deselected = [item for item in items if item not in kept]
    if deselected:
        config.hook.pytest_deselected(items=deselected)
        items[:] = selected


VERDICT_ERROR = ("verdict", "error")  # a user property of a call that broke before it judged (JUnit shows it too)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo):
    """A test that fails on an exception other than an expectation's or an assert's (a misspelt name, a value
    beyond its limits, a lost ECU, a bug in the test) judged nothing: its requirements are not judged rather
    than failed, as pytest tells a failure from an error."""
    outcome = yield
    report = outcome.get_result()
    if call.when == "call" and report.failed:
        item.stash[_CALL_FAILED] = True
    if (call.when == "call" and report.failed and call.excinfo is not None
            and not call.excinfo.errisinstance((AssertionError, pytest.fail.Exception))):
        report.user_properties.append(VERDICT_ERROR)
        item.user_properties.append(VERDICT_ERROR)  # JUnit writes the properties of the teardown's report
    if call.excinfo is not None and call.excinfo.errisinstance(_connection_lost()):
        item.stash[_ECU_STATE] = ("lost", str(call.excinfo.value))
    if _ECU_STATE in item.stash:  # a report's attribute travels from an xdist worker with it
        report.workbench_ecu = item.stash[_ECU_STATE]


def _connection_lost() -> type:
    from workbench.errors import ConnectionLostError

    return ConnectionLostError


def _broke(report: pytest.TestReport) -> bool:
    return report.when == "call" and report.failed and VERDICT_ERROR in [tuple(p) for p in report.user_properties]


def pytest_report_teststatus(report: pytest.TestReport, config: pytest.Config):
    """A test that broke before it judged is pytest's ERROR (E), as a setup that broke is, not FAILED."""
    if _broke(report):
        return "error", "E", "ERROR"
    return None


def _junit_errors(path: Path) -> None:
    """JUnit's ``<error>`` for the tests that broke before they judged (pytest writes ``<failure>`` for
    anything raised in a test's body): a CI server then counts them as errors, not as failures of the ECU."""
    import xml.etree.ElementTree as ET

    from workbench.fileio import atomic_write_bytes

    tree = ET.parse(path)
    moved_any = False
    for suite in tree.iter("testsuite"):
        moved = 0
        for case in suite.iter("testcase"):
            if VERDICT_ERROR in [(p.get("name"), p.get("value")) for p in case.iter("property")]:
                for failure in case.findall("failure"):
                    failure.tag = "error"
                    moved += 1
        if moved:
            suite.set("failures", str(int(suite.get("failures", "0")) - moved))
            suite.set("errors", str(int(suite.get("errors", "0")) + moved))
            moved_any = True
    if moved_any:
        atomic_write_bytes(path, ET.tostring(tree.getroot(), encoding="utf-8", xml_declaration=True))


_ECU_OPTIONS = ("a2l", "interface", "channel", "bitrate", "bus_kwargs", "host", "port", "protocol", "key_function",
                "dbc", "can2_interface", "can2_channel", "can2_bus_kwargs", "sim_s19", "sim_control")


def _target(config: pytest.Config):
    """The ECU of this run (built once per process from the options). :raises pytest.UsageError: bad options."""
    if _TARGET not in config.stash:
        from workbench.errors import InputError
        from workbench.testbench.options import target_from_options

        try:
            config.stash[_TARGET] = target_from_options(config.option)
        except InputError as exc:
            raise pytest.UsageError(str(exc)) from None
    return config.stash[_TARGET]


def _evidence_dir(config: pytest.Config) -> Path:
    report = config.stash.get(_REPORT_DIR, None)
    if report is not None:
        return report
    if not hasattr(config, "_workbench_evidence"):
        config._workbench_evidence = config._tmp_path_factory.mktemp("workbench-evidence", numbered=True)
    return config._workbench_evidence


def safe_name(nodeid: str) -> str:
    """A test's node id as a file name: ``test_canrx.py::test_x[a]`` -> ``test_canrx.py-test_x-a``."""
    return re.sub(r"[^\w.]+", "-", nodeid).strip("-")


@pytest.fixture
def ecu(request: pytest.FixtureRequest):
    """A :class:`~workbench.testbench.Bench` on the ECU under test (see the plugin's options)."""
    logging.getLogger("workbench.testbench").setLevel(logging.INFO)
    config = request.config
    target = _target(config)
    directory = _evidence_dir(config)
    name = safe_name(request.node.nodeid)
    from workbench.errors import ConnectionLostError, WorkbenchError, XcpTimeoutError

    stack = ExitStack()
    try:  # no ECU (not powered, lost in an earlier test), a restore that failed: one line, no library traceback
        bench = stack.enter_context(target.bench(directory / "evidence" / f"{name}.mf4"))
    except WorkbenchError as exc:
        problem = str(exc)  # failed outside the except: pytest would show the error twice, chained
        if isinstance(exc, (XcpTimeoutError, ConnectionLostError)):
            request.node.stash[_ECU_STATE] = ("unreachable", problem)
    else:
        problem = None
    if problem is not None:
        pytest.fail(problem, pytrace=False)
    try:
        if request.node.get_closest_marker(SIMULATOR_MARK) and not bench.sim.available:
            pytest.skip(f"needs the simulated ECU: {bench.sim.control.where}")
        try:
            yield bench
        finally:
            _write_record(directory, name, request.node, bench)
            if bench.evidence.failure is not None:  # its samples stopped: the ECU was lost
                request.node.stash[_ECU_STATE] = ("lost", str(bench.evidence.failure))
    finally:
        problem = None
        try:
            stack.close()
        except WorkbenchError as exc:
            problem = str(exc)
        if problem is not None and request.node.stash.get(_CALL_FAILED, False):
            # a consequence of what the test already reported (the ECU lost): a second error would be a second
            # JUnit testcase of the same test (pytest's schema), and its message would replace the test's own
            request.node.user_properties.append((TEARDOWN, problem))
            logging.getLogger("workbench.testbench").warning("after the test: %s", problem)
        elif problem is not None:
            pytest.fail(problem, pytrace=False)


def _write_record(directory: Path, name: str, node: pytest.Item, bench) -> None:
    """What the report needs of a test beyond its outcome: its steps and evidence (workers write it, the
    controller reads it)."""
    record = {
        "nodeid": node.nodeid,
        "epoch": bench.timeline.epoch,
        "steps": [step.to_dict() for step in bench.steps],
        "evidence": [str(path) for path in bench.evidence.parts],
    }
    path = directory / "tests" / f"{name}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(record, indent=1), encoding="utf-8")


def _one_line(report: pytest.TestReport) -> str:
    if report.skipped and isinstance(report.longrepr, tuple):
        return str(report.longrepr[2]).removeprefix("Skipped: ")
    crash = getattr(report.longrepr, "reprcrash", None)
    if crash is not None:
        return crash.message.splitlines()[0] if crash.message else ""
    return str(report.longrepr).splitlines()[-1] if report.longrepr else ""


class _Outcomes:
    """The outcome of every test, on the controller (xdist forwards the workers' reports), for the report
    and the requirements' summary."""

    def __init__(self, config: pytest.Config, keep_all: bool):
        self.config = config
        self.keep_all = keep_all  # for a report; else only the tests that trace requirements
        self.results: dict[str, dict] = {}

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        requirements = [str(value) for key, value in report.user_properties if key == "requirement"]
        if not requirements and not self.keep_all:
            return
        entry = self.results.setdefault(report.nodeid, {"outcome": "interrupted", "duration": 0.0,  # until its call
                                                        "message": "the run stopped before this test's end (Ctrl-C)",
                                                        "requirements": requirements})
        entry["duration"] += report.duration
        if getattr(report, "workbench_ecu", None) and not entry.get("ecu"):
            entry["ecu"], entry["ecu_error"] = report.workbench_ecu
        if report.when == "call":
            entry["outcome"], entry["message"] = "error" if _broke(report) else report.outcome, _one_line(report)
            entry["when"] = report.when
        elif report.failed and entry["outcome"] != "failed":  # an error in setup or teardown
            entry["outcome"], entry["message"], entry["when"] = "error", _one_line(report), report.when
        elif report.when == "teardown":  # what the teardown could not undo after a failed test
            entry["after"] = [str(value) for key, value in report.user_properties if key == TEARDOWN]
            entry["message"] += "".join(f"; after the test: {after}" for after in entry["after"])
        elif report.skipped:
            entry["outcome"], entry["message"] = "skipped", _one_line(report)

    @pytest.hookimpl(trylast=True)  # after pytest's junitxml wrote its file
    def pytest_sessionfinish(self, session: pytest.Session) -> None:
        config = self.config
        if hasattr(config, "workerinput"):
            return
        junit = Path(config.option.xmlpath) if getattr(config.option, "xmlpath", None) else None
        if junit is not None and junit.is_file():
            _junit_errors(junit)
        directory = config.stash.get(_REPORT_DIR, None)
        if directory is None:
            return
        from workbench.testbench.report import write_report

        target = config.stash.get(_TARGET, None)
        write_report(directory, self.results, catalogue=config.stash.get(_CATALOGUE, []),
                     ecu=target.describe() if target is not None else "")

    def pytest_terminal_summary(self, terminalreporter) -> None:
        traced = {nodeid: entry for nodeid, entry in self.results.items() if entry["requirements"]}
        if not traced or hasattr(self.config, "workerinput"):
            return
        failed: dict[str, list[str]] = {}
        broke: dict[str, list[str]] = {}
        verified: set[str] = set()
        for nodeid, entry in traced.items():
            for requirement_id in entry["requirements"]:
                if entry["outcome"] in ("failed", "error"):
                    (failed if entry["outcome"] == "failed" else broke).setdefault(requirement_id, []).append(nodeid)
                elif entry["outcome"] == "passed":
                    verified.add(requirement_id)
        verified -= set(failed) | set(broke)
        unjudged = {key: nodeids for key, nodeids in broke.items() if key not in failed}
        traced_ids = {requirement_id for entry in traced.values() for requirement_id in entry["requirements"]}
        untested = [r.id for r in self.config.stash.get(_CATALOGUE, []) if r.id not in traced_ids]  # as the report
        terminalreporter.section("requirements")
        terminalreporter.write_line(f"{len(verified)} verified, {len(failed)} failed"
                                    + (f", {len(unjudged)} not judged (a test broke)" if unjudged else "")
                                    + (f", {len(untested)} of the catalogue not tested" if untested else ""))
        for requirement_id, nodeids in sorted(failed.items()):
            terminalreporter.write_line(f"FAILED {requirement_id}: {', '.join(nodeids)}", red=True)
        for requirement_id, nodeids in sorted(unjudged.items()):
            terminalreporter.write_line(f"NOT JUDGED {requirement_id}: {', '.join(nodeids)}", red=True)
        if untested:
            shown = ", ".join(untested[:10]) + (f" and {len(untested) - 10} more" if len(untested) > 10 else "")
            terminalreporter.write_line(f"NOT TESTED: {shown}", yellow=True)
        for nodeid, entry in traced.items():
            for after in entry.get("after", ()):
                terminalreporter.write_line(f"after {nodeid}: {after}", red=True)
        directory = self.config.stash.get(_REPORT_DIR, None)
        if directory is not None:
            terminalreporter.write_line(f"report: {directory / 'report.html'}")


class _LiveVerdicts:
    """``--verdict-log``: the tests to run, each test's start and verdict as it ends, the run's end (on the controller:
    xdist forwards the workers' starts, reports and ends)."""

    def __init__(self, log, outcomes: _Outcomes):
        self.log = log
        self.outcomes = outcomes
        self.collected = False

    def pytest_collection_finish(self, session: pytest.Session) -> None:
        self._collected([(item.nodeid, [v for k, v in item.user_properties if k == "requirement"])
                         for item in session.items])

    @pytest.hookimpl(optionalhook=True)
    def pytest_xdist_node_collection_finished(self, node, ids: list[str]) -> None:
        self._collected([(nodeid, []) for nodeid in ids])  # each worker collects the same tests

    def _collected(self, tests: list[tuple[str, list[str]]]) -> None:
        if not self.collected:
            self.collected = True
            self.log.write("collected", root=str(self.outcomes.config.rootpath),  # what the node ids are relative to
                           tests=[{"nodeid": nodeid, "requirements": ids} for nodeid, ids in tests])

    def pytest_runtest_logstart(self, nodeid: str, location) -> None:
        self.log.write("started", nodeid=nodeid)

    def pytest_runtest_logfinish(self, nodeid: str, location) -> None:
        from workbench.testbench.verdicts import verdict_of

        entry = self.outcomes.results.get(nodeid)
        if entry is not None:
            self.log.write("verdict", nodeid=nodeid, verdict=verdict_of(entry), requirements=entry["requirements"],
                           message=entry["message"], duration=round(entry["duration"], 3), ecu=entry.get("ecu"),
                           ecu_error=entry.get("ecu_error"))

    @pytest.hookimpl(wrapper=True)  # after the report is written: a window may open it at this line
    def pytest_sessionfinish(self, session: pytest.Session, exitstatus):
        try:
            return (yield)
        finally:
            self.log.write("finished", exitstatus=int(session.exitstatus))
            self.log.close()
