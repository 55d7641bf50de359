"""Fixtures of the CAN tests: crafted DBC files and the demo's DBCs."""

from __future__ import annotations

from pathlib import Path

import pytest
from crafted import ATTRIBUTE_DEFINITIONS, HEADER


@pytest.fixture
def write_dbc(tmp_path: Path):
    """``write_dbc(messages, attributes="", name=..., nodes="ECU PEER")`` → the path of a DBC file."""

    def write(messages: str, attributes: str = "", name: str = "crafted_CAN2.dbc", nodes: str = "ECU PEER") -> Path:
        path = tmp_path / name
        path.write_text(HEADER.format(nodes=nodes) + messages + "\n" + ATTRIBUTE_DEFINITIONS + attributes)
        return path

    return write

