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
