"""workbench.testbench.RequirementRun, as a script follows a run: `workbench test` in a process of its own, its
verdicts line by line, its exit code and the report."""

from __future__ import annotations

import time

from workbench.testbench import RequirementRun, RunOptions


def test_a_script_follows_a_run_verdict_by_verdict(tmp_path, monkeypatch):
    # The run's node ids are relative to pytest's rootdir, which the process's folder takes part in (the folder it
    # shares with the tests, unless that is /): run from the tests' folder they read 'test_two.py::...' wherever
    # this suite runs (from a checkout under /tmp they read 'pytest-of-root/pytest-N/.../test_two.py::...').
    monkeypatch.chdir(tmp_path)
    (tmp_path / "test_two.py").write_text('''
from workbench.testbench import requirement

@requirement("R1")
def test_passes():
    pass

@requirement("R2")
def test_fails():
    assert 2 + 2 == 5
''', encoding="utf-8")
    options = RunOptions(report=tmp_path / "out", paths=[str(tmp_path / "test_two.py")], req=["R1", "R2"])
    run = RequirementRun(options).start()
    try:
        events = []
        deadline = time.monotonic() + 120  # a guard against a hung run, not a measurement
        while run.poll() is None:
            events += run.events()
            assert time.monotonic() < deadline
            time.sleep(0.1)
        events += run.events()
        assert run.exit_code == 1 and run.error() == ""  # a test failed: workbench test's 1, nothing on stderr
        verdicts = {e["nodeid"]: (e["verdict"], e["requirements"]) for e in events if e["event"] == "verdict"}
        assert verdicts == {"test_two.py::test_passes": ("passed", ["R1"]),
                            "test_two.py::test_fails": ("failed", ["R2"])}
        assert events[-1] == {"event": "finished", "exitstatus": 1} and run.report.is_file()
        assert "1 failed, 1 passed" in run.read_output()
    finally:
        run.close()  # a hung run (the deadline) ends with the test, its process too
