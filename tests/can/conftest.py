"""Fixtures of the CAN tests: crafted DBC files and the demo's DBCs."""

from __future__ import annotations

from pathlib import Path

import pytest
from agreement import assert_reads_as_cantools
from crafted import ATTRIBUTE_DEFINITIONS, HEADER


@pytest.fixture
def write_dbc(tmp_path: Path):
    """``write_dbc(messages, attributes="", name=..., nodes="ECU PEER")`` → the path of a DBC file.

    After the test, each file written is read as cantools reads it (:mod:`agreement`).
    """
    written: list[Path] = []

    def write(messages: str, attributes: str = "", name: str = "crafted_CAN2.dbc", nodes: str = "ECU PEER") -> Path:
        path = tmp_path / name
        path.write_text(HEADER.format(nodes=nodes) + messages + "\n" + ATTRIBUTE_DEFINITIONS + attributes)
        written.append(path)
        return path

    yield write
    for path in dict.fromkeys(written):
        if path.exists():
            assert_reads_as_cantools(path)

