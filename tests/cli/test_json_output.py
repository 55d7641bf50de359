"""``--json`` output: indented JSON on stdout, written whole in one write (a 1 MiB DBC's table once took 355,000)."""

from __future__ import annotations

import datetime
import io
import json
from pathlib import Path

from workbench import demo
from workbench.cli import main
from workbench.cli.options import print_json


class _CountingStdout(io.StringIO):
    def __init__(self) -> None:
        super().__init__()
        self.writes = 0

    def write(self, text: str) -> int:
        self.writes += 1
        return super().write(text)


def test_print_json_writes_what_json_dump_writes_in_one_write(monkeypatch):
    data = {"path": Path("a/b.dbc"), "when": datetime.date(2024, 5, 1), "rows": [{"id": 16, "ok": True}, None],
            "text": "Ölstand ±1"}
    expected = io.StringIO()
    json.dump(data, expected, indent=2, default=str)
    out = _CountingStdout()
    monkeypatch.setattr("sys.stdout", out)
    print_json(data)
    assert out.getvalue() == expected.getvalue() + "\n"
    assert out.writes == 1


def test_dbc_table_json_is_one_write(monkeypatch):
    out = _CountingStdout()
    monkeypatch.setattr("sys.stdout", out)
    assert main(["dbc", "table", str(demo.path("dbc", "FLCU_CAN2.dbc")), "--json"]) == 0
    assert out.writes == 1
    assert "FLCU_TO_PCM_003" in [message["Name"] for message in json.loads(out.getvalue())["messages"]]


def test_a_usage_error_under_json_is_a_report_too(capsys):
    """Bad input argparse finds (a missing -o, a bad pattern) gives the {ok, error, exit_code} every other failure
    gives under --json: a script reading stdout found nothing."""
    assert main(["a2l", "update", str(demo.a2l()), str(demo.elf()), "--json"]) == 2
    out, err = capsys.readouterr()
    assert json.loads(out) == {"ok": False, "error": "workbench a2l update: the following arguments are required: "
                                                     "-o/--output", "exit_code": 2}
    assert err.endswith("workbench a2l update: error: the following arguments are required: -o/--output\n")
    assert main(["a2l", "remove", str(demo.a2l()), "-R", "("]) == 2  # without --json: stdout stays empty
    assert capsys.readouterr().out == ""


def test_a_word_no_option_takes_is_refused_by_the_command_that_got_it(capsys):
    """`cal set ... --raw`: argparse's top-level parser said `workbench: error: unrecognized arguments` with the
    groups' usage, not which command it was or what that one takes."""
    assert main(["cal", "set", "xsSWITCH_TANK_THR", "5", "--raw", "--json"]) == 2
    out, err = capsys.readouterr()
    assert json.loads(out)["error"] == "workbench cal set: unrecognized arguments: --raw"
    assert err.startswith("usage: workbench cal set ") and err.endswith(
        "workbench cal set: error: unrecognized arguments: --raw\n")
    assert main(["--bogus"]) == 2 and capsys.readouterr().err.endswith("workbench: error: unrecognized arguments: "
                                                                      "--bogus\n")
