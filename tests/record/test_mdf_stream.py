"""The stream writer: records appended across flushes read back exactly, the file is readable between flushes,
and a writer killed at any of its writes leaves a file asammdf reads with every record of the last flush, which
finalize() then marks finalized in place."""

from __future__ import annotations

import os
from pathlib import Path

from xml.etree import ElementTree

import numpy as np
import pytest

from workbench import __version__
from workbench.errors import InputError
from workbench.record import ChannelSpec, GroupSpec, HeaderSpec, MdfStreamWriter, finalize

GROUPS = [
    GroupSpec("fast", (ChannelSpec("pressure", np.dtype("<f4"), "bar", "rail pressure", {"a": 0.5, "b": 1.0}),
                       ChannelSpec("state", np.dtype("<u1"), "", "tank state",
                                   {"val_0": 0, "text_0": "OFF", "val_1": 1, "text_1": "ON",
                                    "default_addr": {"a": 1.0, "b": 0.0}}))),
    GroupSpec("slow", (ChannelSpec("count", np.dtype("<i4"), "", "a counter"),)),
]


def chunk(start: int, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    index = np.arange(start, start + count)
    return index * 0.004, (index % 500).astype("<f4"), (index % 2).astype("<u1")


def append(writer: MdfStreamWriter, start: int, count: int) -> None:
    times, pressure, state = chunk(start, count)
    writer.append(0, times, [pressure, state])
    writer.append(1, times[::10], [np.arange(start, start + count, 10, dtype="<i4")])


def check(mdf, records: int, slow: int | None = None) -> None:
    """``records`` records of group 0 and ``slow`` (default: a tenth of them) of group 1, values as appended."""
    slow = records // 10 if slow is None else slow
    times, pressure, state = chunk(0, records)
    signal = mdf.get("pressure", raw=True)
    assert np.array_equal(signal.timestamps, times) and np.array_equal(signal.samples, pressure)
    assert np.array_equal(mdf.get("pressure").samples, pressure * 0.5 + 1.0)
    assert np.array_equal(mdf.get("state", raw=True).samples, state)
    assert np.array_equal(mdf.get("count").samples, np.arange(0, slow * 10, 10, dtype="<i4"))


@pytest.mark.parametrize("compress", [True, False])
def test_records_read_back_exactly_after_every_flush(tmp_path, read_mdf, compress):
    path = tmp_path / "stream.mf4"
    writer = MdfStreamWriter(path, GROUPS, HeaderSpec("test", author="tester", properties={"bench": "yes"}),
                             compress=compress)
    check(read_mdf(path), 0)  # complete before the first record
    for flush in range(4):
        append(writer, flush * 250, 250)
        assert writer.records(0) == flush * 250  # appended is not yet written
        writer.flush()
        check(read_mdf(path), (flush + 1) * 250)  # read while the writer still holds the file
    writer.set_start_time(1_700_000_000.25)
    assert path.read_bytes()[:8] == b"UnFinMF "  # while written: cycle counters may lag behind the data
    writer.close()
    assert path.read_bytes()[:8] == b"MDF     " and not finalize(path)
    mdf = read_mdf(path)
    check(mdf, 1000)
    assert mdf.header.start_time.timestamp() == 1_700_000_000.25
    assert "<e name=\"bench\">yes</e>" in mdf.header.comment
    assert [group.channel_group.acq_name for group in mdf.groups] == ["fast", "slow"]
    assert writer.file_bytes == path.stat().st_size
    (history,) = mdf.file_history  # names the writer (a viewer's file info), not asammdf
    assert "<tool_id>workbench</tool_id>" in history.comment and f"<tool_version>{__version__}<" in history.comment
    assert "<user_name>tester</user_name>" in history.comment


class Killed(Exception):
    """The process died here."""


class _DyingFile:
    """The writer's file, dying before its ``dies_at``-th write: what it had not flushed to the OS is lost, as a
    kill -9 loses a process's buffers."""

    def __init__(self, handle, dies_at: int):
        self.handle, self.left = handle, dies_at

    def write(self, data):
        self.left -= 1
        if self.left < 0:
            raise Killed
        return self.handle.write(data)

    def __getattr__(self, name):
        return getattr(self.handle, name)


def writes_of_a_flush(tmp_path) -> int:
    writer = MdfStreamWriter(tmp_path / "count.mf4", GROUPS)
    append(writer, 0, 250)
    writer.flush()
    append(writer, 250, 250)
    writer._file = counting = _DyingFile(writer._file, 10**6)
    writer.flush()
    writer.close()
    return 10**6 - counting.left


@pytest.mark.parametrize("compress", [True, False])
def test_a_kill_at_any_write_leaves_the_last_flush_readable(tmp_path, read_mdf, compress):
    writes = writes_of_a_flush(tmp_path)
    assert writes >= 10  # blocks, lists and header list of two groups, then links and counters
    for dies_at in range(writes + 1):
        path = tmp_path / f"killed{dies_at}.mf4"
        writer = MdfStreamWriter(path, GROUPS, compress=compress)
        append(writer, 0, 250)
        writer.flush()  # the first flush is on disk; the second one dies at write ``dies_at``
        append(writer, 250, 250)
        handle = writer._file
        writer._file = _DyingFile(handle, dies_at)
        try:
            writer.flush()
        except Killed:
            pass
        on_disk = path.read_bytes()  # before Python's buffer could reach the file: the kill loses it
        handle.raw.close()  # close the descriptor under the buffer: nothing more reaches the file
        survived = tmp_path / f"survived{dies_at}.mf4"
        survived.write_bytes(on_disk)
        for finalized in (False, True):  # as killed, then finalized in place
            mdf = read_mdf(survived)
            counts = [group.channel_group.cycles_nr for group in mdf.groups]
            assert counts in ([250, 25], [500, 25], [250, 50], [500, 50]), (dies_at, counts)
            check(mdf, *counts)
            if not finalized:
                assert finalize(survived) == (on_disk[:8] == b"UnFinMF ")
        assert survived.read_bytes()[:8] == b"MDF     "


def test_finalize_refuses_what_is_no_mdf(tmp_path):
    (tmp_path / "text.mf4").write_text("not a measurement")
    with pytest.raises(InputError, match="text.mf4: not an MDF4 file"):
        finalize(tmp_path / "text.mf4")
    with pytest.raises(InputError, match="missing.mf4: no such file"):
        finalize(tmp_path / "missing.mf4")
    with pytest.raises(InputError, match="is a folder, not an MDF4 file$"):
        finalize(tmp_path)


def test_channels_are_placed_by_position_not_by_name(tmp_path, read_mdf):
    """An A2L may name a signal ``time``, as asammdf names every master."""
    writer = MdfStreamWriter(tmp_path / "names.mf4", [GroupSpec("g", (ChannelSpec("time", np.dtype("<u2")),
                                                                      ChannelSpec("time", np.dtype("<f4"))))])
    writer.append(0, np.arange(5) * 0.1, [np.arange(5, dtype="<u2") + 7, np.full(5, 0.5, "<f4")])
    writer.close()
    mdf = read_mdf(tmp_path / "names.mf4")
    assert np.array_equal(mdf.get_master(0), np.arange(5) * 0.1)
    assert mdf.get("time", 0, 1).samples.tolist() == [7, 8, 9, 10, 11] and mdf.get("time", 0, 2).samples[0] == 0.5


def test_the_file_is_unfinalized_from_its_first_moment(tmp_path, monkeypatch):
    """A reader that opens the new file before the writer's first record (a script polling for it) must take it
    for unfinalized: asammdf maps a finalized file as it is at opening and follows links into what grew since
    ('Expected "##DL" block' in a test that polled the recording)."""
    import workbench.record.mdf_stream as mdf_stream

    seen = []
    replace = os.replace

    def watching_replace(source, target):
        seen.append(Path(source).read_bytes()[:8])
        replace(source, target)

    monkeypatch.setattr(mdf_stream.os, "replace", watching_replace)
    MdfStreamWriter(tmp_path / "new.mf4", GROUPS).close()
    assert seen == [b"UnFinMF "]


def test_a_header_property_xml_cannot_hold_is_written_escaped(tmp_path, read_mdf):
    """An ECU whose EPK holds NUL bytes (flash never programmed, two slaves answering at once): the header's XML
    was written with them and no reader could parse it."""
    path = tmp_path / "epk.mf4"
    writer = MdfStreamWriter(path, GROUPS, HeaderSpec("test", properties={"epk_ecu": "FLCU\x00\x01\x1f end"}))
    writer.close()
    comment = read_mdf(path).header.comment
    assert "FLCU\\x00\\x01\\x1f end" in comment
    ElementTree.fromstring(comment)  # well-formed: the characters escaped
