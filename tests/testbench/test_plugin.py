"""The pytest plugin as plain pytest meets it: requirement ids as JUnit properties, the ecu fixture on a fresh
simulated ECU, its evidence and the report; ECU options checked at once; tests that need the simulator skipped
on another ECU; nothing heavy imported by a test run that does not use it."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

from workbench.sim import serve_demo

pytest_plugins = ["pytester"]
PLUGIN = ("-p", "workbench.testbench.plugin", "-p", "no:cacheprovider")  # also where its entry point is not installed
_channels = itertools.count()

TESTS = '''
from workbench.testbench import needs_simulator, requirement, within

@requirement("R1", "R2")
def test_on_the_ecu(ecu):
    ecu.watch("xsDC")
    ecu.expect("xsDC", within(0, 100), for_s=0.1)

@requirement("R3")
def test_without_the_ecu():
    assert 1 + 1 == 3

@requirement("R4")
@needs_simulator
def test_with_a_fault(ecu):
    ecu.sim.sensor_voltage("rail", 4.9)
'''


def _properties(junit) -> dict[str, list[str]]:
    return {case.get("name"): [p.get("value") for p in case.iter("property") if p.get("name") == "requirement"]
            for case in ET.parse(junit).iter("testcase")}


def test_requirements_evidence_and_report(pytester):
    pytester.makepyfile(test_flcu=TESTS)
    result = pytester.runpytest_inprocess("--report", "out", *PLUGIN)
    result.assert_outcomes(passed=2, failed=1)
    result.stdout.fnmatch_lines(["*requirements*", "3 verified, 1 failed", "FAILED R3: test_flcu.py::test_without_the_ecu",
                                 "report: out*report.html"])
    out = pytester.path / "out"
    assert _properties(out / "junit.xml") == {"test_on_the_ecu": ["R1", "R2"], "test_without_the_ecu": ["R3"],
                                              "test_with_a_fault": ["R4"]}
    assert sorted(p.name for p in (out / "evidence").iterdir()) == ["test_flcu.py-test_on_the_ecu.mf4",
                                                                      "test_flcu.py-test_with_a_fault.mf4"]
    record = json.loads((out / "tests" / "test_flcu.py-test_on_the_ecu.json").read_text())
    assert [step["passed"] for step in record["steps"] if step["kind"] == "expect"] == [True]
    html = (out / "report.html").read_text()
    assert html.index("<h2>Traceability</h2>") < html.index("<svg") and "assert (1 + 1) == 3" in html


def test_bad_ecu_options_are_usage_errors(pytester):
    pytester.makepyfile(test_flcu=TESTS)
    result = pytester.runpytest_inprocess("--sim-s19", "missing.s19", *PLUGIN)
    assert result.ret == pytest.ExitCode.USAGE_ERROR
    result.stderr.fnmatch_lines(["*missing.s19: no such file*"])
    result = pytester.runpytest_inprocess("--interface", "virtual", "--host", "127.0.0.1", *PLUGIN)
    assert result.ret == pytest.ExitCode.USAGE_ERROR
    result.stderr.fnmatch_lines(["*either CAN options*or Ethernet ones*"])
    result = pytester.runpytest_inprocess("--report", "out", "--requirements", "missing.csv", *PLUGIN)
    assert result.ret == pytest.ExitCode.USAGE_ERROR  # before a test ran, not after all of them
    result.stderr.fnmatch_lines(["*missing.csv: no such file*"])
    pytester.makefile(".txt", afile="")
    for option in ("--report", "--verdict-log"):  # below a file: refused before a test ran, not a traceback after
        result = pytester.runpytest_inprocess(option, "afile.txt/out", *PLUGIN)
        assert result.ret == pytest.ExitCode.USAGE_ERROR
        result.stderr.fnmatch_lines([f"*{option} afile.txt/out: cannot be *"])


def test_worker_processes_on_one_real_ecu_are_refused_from_an_ini_too(pytester):
    """-n 2 from a project's addopts (this repository has -n auto) ran the tests in two processes against one
    real ECU: two masters, seed & key and DAQ failing at random (user trial 7). workbench test gives -n 0;
    plain pytest is told."""
    pytester.makeini("[pytest]\naddopts = -n 2\n")
    pytester.makepyfile(test_flcu=TESTS)
    result = pytester.runpytest_inprocess("--interface", "virtual", "--channel", "nowhere", *PLUGIN)
    assert result.ret == pytest.ExitCode.USAGE_ERROR
    result.stderr.fnmatch_lines(["*-n 2 (from the addopts of tox.ini): the tests would share the ECU on "
                                 "interface=virtual channel=nowhere from 2 processes*give -n 0"])


def test_an_ecu_without_simulator_control_skips_what_needs_it(pytester):
    channel = f"plugin-test-{next(_channels)}"
    pytester.makepyfile(test_flcu=TESTS)
    with serve_demo({"interface": "virtual", "channel": channel}):  # served, but registers no control channel
        result = pytester.runpytest_inprocess("--interface", "virtual", "--channel", channel, "-k", "on_the_ecu or fault",
                                              *PLUGIN, "-rs")
    result.assert_outcomes(passed=1, skipped=1)
    result.stdout.fnmatch_lines(["*needs the simulated ECU: no simulator registered a control channel for XCP on CAN*"])


def test_a_misspelt_name_fails_its_test_in_one_line_at_the_test_line(pytester):
    """A step's WorkbenchError is shown at the test's line with its message, not as two chained library
    tracebacks ending in the DBC's signals (user trial 6)."""
    pytester.makepyfile(test_typo="""
from workbench.testbench import requirement

@requirement("R9")
def test_typo(ecu):
    ecu.watch("zsRailPresure")

@requirement("R9", "R10")
def test_judged(ecu):
    assert ecu.read("xsSWITCH_TANK_THR") == 20.0
""")
    result = pytester.runpytest_inprocess("--report", "out", *PLUGIN)
    result.assert_outcomes(errors=1, passed=1)  # pytest's ERROR, as the docs say (it was FAILED: user trial 7)
    result.stdout.fnmatch_lines(['>*ecu.watch("zsRailPresure")',
                                 "E*UnknownSymbolError: unknown symbol 'zsRailPresure' in the A2L's objects nor the "
                                 "CAN2 signals of FLCU_CAN2.dbc; did you mean 'zsRailPressure'*",
                                 "1 verified, 0 failed, 1 not judged (a test broke)",
                                 "NOT JUDGED R9: test_typo.py::test_typo"])  # judged nothing: no requirement FAILED
    output = result.stdout.str()
    assert "During handling" not in output and "a2l/model.py" not in output and "testbench/bench.py" not in output
    junit = ET.parse(pytester.path / "out" / "junit.xml")
    verdicts = {case.get("name"): ([p.get("value") for p in case.iter("property") if p.get("name") == "verdict"],
                                   [child.tag for child in case if child.tag in ("failure", "error")])
                for case in junit.iter("testcase")}
    assert verdicts == {"test_typo": (["error"], ["error"]), "test_judged": ([], [])}  # a CI server's error, not
    suite = junit.find(".//testsuite")  # a failure of the ECU (the property never reached JUnit: user trial 7)
    assert (suite.get("errors"), suite.get("failures")) == ("1", "0")
    html = (pytester.path / "out" / "report.html").read_text()
    assert ('test_typo.py::test_typo</a> <span class="badge error">ERROR</span></td><td><span class="badge error">'
            'NOT JUDGED</span></td></tr>') in html  # R9: one test passed, one judged nothing
    assert 'test_typo.py::test_judged</a> <span class="badge passed">PASSED</span></td><td><span class="badge passed">' \
           in html  # R10


def test_no_ecu_is_one_line_per_test(pytester, free_tcp_port):
    """No ECU there (not powered, or lost in an earlier test): each test's setup error is the one line of the
    library, not its traceback (user trial 6)."""
    pytester.makepyfile(test_flcu=TESTS)
    result = pytester.runpytest_inprocess("--host", "127.0.0.1", "--port", str(free_tcp_port), "--protocol", "tcp",
                                          "-k", "on_the_ecu", *PLUGIN)
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*ERROR at setup of test_on_the_ecu*",
                                 f"cannot reach the ECU: XCP on TCP (127.0.0.1:{free_tcp_port}): nothing listens at*"])
    assert "session.py" not in result.stdout.str()


def test_an_ecu_with_other_software_than_the_a2l_is_not_tested(pytester, tmp_path):
    """The ECU's EPK differs from the A2L's: every test's setup says so in one line, instead of the tests that only
    read passing (verdicts on other software) and the writing ones failing with a restore error after them (user
    trial 7); --accept-epk-mismatch tests it anyway."""
    from workbench import demo

    a2l = tmp_path / "other.a2l"
    text = demo.a2l().read_text(encoding="latin-1")
    a2l.write_text(text.replace('"10300020250301"', '"10300020259999"'), encoding="latin-1")
    channel = f"plugin-test-{next(_channels)}"
    pytester.makepyfile(test_flcu=TESTS)
    with serve_demo({"interface": "virtual", "channel": channel}):
        refused = pytester.runpytest_inprocess("--a2l", str(a2l), "--interface", "virtual", "--channel", channel,
                                               "-k", "on_the_ecu", *PLUGIN)
        accepted = pytester.runpytest_inprocess("--a2l", str(a2l), "--interface", "virtual", "--channel", channel,
                                                "--accept-epk-mismatch", "-k", "on_the_ecu", *PLUGIN)
    refused.assert_outcomes(errors=1)
    refused.stdout.fnmatch_lines(["EPK mismatch: file has '10300020259999', ECU has '10300020250301'; the tests would "
                                  "judge other software than the A2L describes*--accept-epk-mismatch*"])
    assert "During handling" not in refused.stdout.str()
    accepted.assert_outcomes(passed=1)


def test_an_ecu_lost_in_a_test_is_one_error_with_what_it_left_undone(pytester, tmp_path):
    """The ECU lost during a test: the teardown's 'not restored' was a second ERROR of the test (a second JUnit
    testcase: a CI server counted 3 tests of 2), its text replaced the test's own reason in the report, and the
    step read FAILED (user trial 10). Now one error, the reason first, what was not undone after it."""
    channel = f"plugin-test-{next(_channels)}"
    pytester.makeconftest(f"""
import pytest
from workbench.sim import serve_demo

@pytest.fixture
def sim():
    with serve_demo({{"interface": "virtual", "channel": "{channel}"}}) as simulator:
        yield simulator
""")
    pytester.makepyfile(test_lost="""
from workbench.testbench import at_least, requirement

@requirement("R1")
def test_lost(sim, ecu):
    ecu.watch("zsRailPressure")
    ecu.write("xsSWITCH_TANK_THR", 22.0)
    ecu.write("xsPRV_KP", 6.0)
    sim.power_off()
    ecu.expect("zsRailPressure", at_least(0.0), for_s=30.0)
""")
    result = pytester.runpytest_inprocess("--interface", "virtual", "--channel", channel, "--report", "out", *PLUGIN)
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["after test_lost.py::test_lost: xsPRV_KP, xsSWITCH_TANK_THR not restored: "
                                 "connection to the ECU lost*"])
    cases = list(ET.parse(pytester.path / "out" / "junit.xml").iter("testcase"))
    assert len(cases) == 1 and [p.get("value") for p in cases[0].iter("property") if p.get("name") == "teardown"][0] \
        .startswith("xsPRV_KP, xsSWITCH_TANK_THR not restored: connection to the ECU lost at ")
    html = (pytester.path / "out" / "report.html").read_text()
    assert "expect zsRailPressure &gt;= 0 bar for 30 s: no samples after" in html
    assert "; after the test: xsPRV_KP, xsSWITCH_TANK_THR not restored" in html and ">NOT JUDGED (no samples" in html


def test_requirements_of_the_catalogue_no_test_traces_are_named(pytester):
    """The report said NOT TESTED, the terminal only '1 verified, 0 failed' (exit 0: a CI log that reads as all done;
    user trial 10)."""
    pytester.makefile(".csv", catalogue="id;name;description\nR1;one;\nR8;eight;\nR9;nine;\n")
    pytester.makepyfile(test_few="""
from workbench.testbench import requirement

@requirement("R1")
def test_one():
    pass
""")
    result = pytester.runpytest_inprocess("--report", "out", "--requirements", "catalogue.csv", *PLUGIN)
    assert result.ret == 0
    result.stdout.fnmatch_lines(["1 verified, 0 failed, 2 of the catalogue not tested", "NOT TESTED: R8, R9"])


def test_a_band_written_backwards_is_one_line_at_the_test_s_line(pytester):
    """As a misspelt name: the test's line and the error, not the condition's code (user trial 10)."""
    pytester.makepyfile(test_band="""
from workbench.testbench import requirement, within

@requirement("R1")
def test_band():
    within(26, 24)
""")
    result = pytester.runpytest_inprocess(*PLUGIN)
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["E *InputError: within(26, 24): the low bound is above the high one",
                                 "test_band.py:5: InputError"])
    assert "def within" not in result.stdout.str()


def test_a_run_stopped_within_a_test_verifies_nothing(pytester):
    """Ctrl-C while a test runs: it has no call report, and its requirement counted as verified ('1 verified,
    0 failed' of a run that stopped; user trial 6). It is INTERRUPTED now."""
    pytester.makepyfile(test_stop="""
import pytest
from workbench.testbench import requirement

@requirement("R1")
def test_stopped():
    pytest.exit("stopped in the middle of it", returncode=2)  # as Ctrl-C: the test ends without a call report
""")
    result = pytester.runpytest_inprocess("--report", "out", *PLUGIN)
    assert result.ret == 2
    result.stdout.fnmatch_lines(["0 verified, 0 failed"])
    html = (pytester.path / "out" / "report.html").read_text()
    assert ('test_stop.py::test_stopped</a> <span class="badge interrupted">INTERRUPTED</span></td><td><span '
            'class="badge interrupted">INTERRUPTED</span></td></tr>') in html


def test_a_test_run_that_does_not_use_it_loads_nothing_heavy():
    code = ("import sys, json, workbench.testbench.plugin, workbench.testbench; "
            "print(json.dumps(sorted({m.split('.')[0] for m in sys.modules} & "
            "{'numpy', 'can', 'cantools', 'asammdf', 'pyxcp', 'elftools'})))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(run.stdout) == []


def test_verdicts_are_written_a_line_each_as_the_tests_end(pytester):
    """--verdict-log: what a window follows while the run goes on (JUnit is written at the end): the tests collected,
    each start and verdict with its requirements and one-line reason, whether the ECU was lost or not there, the end."""
    pytester.makepyfile(test_live='''
from workbench.errors import ConnectionLostError
from workbench.testbench import requirement

@requirement("R1")
def test_passes():
    pass

@requirement("R2", "R3")
def test_fails():
    assert 1 + 1 == 3

@requirement("R3")
def test_loses_the_ecu():
    raise ConnectionLostError("XCP on CAN", "no DTO for 900 ms")

@requirement("R4")
def test_without_an_ecu(ecu):
    pass
''')
    channel = f"plugin-test-{next(_channels)}"  # no ECU there
    result = pytester.runpytest_inprocess("--verdict-log", "live/verdicts.jsonl", "--interface", "virtual", "--channel",
                                          channel, *PLUGIN)
    result.assert_outcomes(passed=1, failed=1, errors=2)
    events = [json.loads(line) for line in (pytester.path / "live" / "verdicts.jsonl").read_text().splitlines()]
    assert [event["event"] for event in events] == ["collected", *["started", "verdict"] * 4, "finished"]
    assert events[0]["tests"][1] == {"nodeid": "test_live.py::test_fails", "requirements": ["R2", "R3"]}
    assert events[0]["root"] == str(pytester.path)  # what the node ids are relative to
    verdicts = {event["nodeid"].split("::")[1]: event for event in events if event["event"] == "verdict"}
    assert {name: (v["verdict"], v["ecu"]) for name, v in verdicts.items()} == {
        "test_passes": ("passed", None), "test_fails": ("failed", None), "test_loses_the_ecu": ("not judged", "lost"),
        "test_without_an_ecu": ("error", "unreachable")}
    assert verdicts["test_fails"]["message"] == "assert (1 + 1) == 3"
    assert verdicts["test_fails"]["requirements"] == ["R2", "R3"]
    assert verdicts["test_without_an_ecu"]["message"].startswith("Failed: XCP CONNECT: no response within")
    assert verdicts["test_without_an_ecu"]["ecu_error"].startswith("XCP CONNECT: no response within")
    assert verdicts["test_loses_the_ecu"]["ecu_error"].endswith(": XCP on CAN: no DTO for 900 ms")
    assert events[-1] == {"event": "finished", "exitstatus": 1}
    result.stdout.fnmatch_lines(["1 verified, 2 failed, 1 not judged (a test broke)"])
