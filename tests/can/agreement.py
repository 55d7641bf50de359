"""What a DBC loads to, read by the workbench's reader and by cantools: the two must agree."""

from __future__ import annotations

import json
from pathlib import Path
from unittest import mock

from workbench.can import dbc_file
from workbench.can.dbc_read import Unreadable


def outcome(path: Path, *, by_cantools: bool = False) -> tuple:
    """What ``load_dbc(path)`` gives: its content (with the JSON of its messages) and warnings, or its error.

    ``by_cantools``: the reader declines, so the content comes from cantools' database.
    """
    declined = mock.patch.object(dbc_file, "read_content", side_effect=Unreadable("by cantools"))
    try:
        if by_cantools:
            with declined:
                dbc = dbc_file.load_dbc(path)
        else:
            dbc = dbc_file.load_dbc(path)
    except Exception as exc:  # noqa: BLE001 - an error, whatever its class, must be the same either way
        return ("refused", type(exc).__name__, str(exc))
    content = dbc.content
    return ("read", content, json.dumps([message.to_dict() for message in content.messages]),
            tuple(str(warning) for warning in dbc.warnings))


def assert_reads_as_cantools(path: Path) -> None:
    """The reader's content of ``path`` is cantools' (or both refuse the file alike)."""
    assert outcome(path) == outcome(path, by_cantools=True), path
