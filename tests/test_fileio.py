import errno
import os

import pytest

from workbench.errors import InputError, WorkbenchError
from workbench.fileio import atomic_write_bytes, atomic_write_text, read_input, write_output


def test_replaces_content_and_keeps_mode(tmp_path):
    target = tmp_path / "out.a2l"
    target.write_text("old")
    os.chmod(target, 0o640)
    atomic_write_text(target, "new\n")
    assert target.read_text() == "new\n"
    assert target.stat().st_mode & 0o777 == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["out.a2l"]


def test_a_new_file_gets_the_usual_mode_not_a_temporary_files(tmp_path):
    umask = os.umask(0o027)
    try:
        atomic_write_bytes(tmp_path / "new.a2l", b"x")
    finally:
        os.umask(umask)
    assert (tmp_path / "new.a2l").stat().st_mode & 0o777 == 0o640  # 0o666 minus the umask


@pytest.mark.skipif(not hasattr(os, "symlink") or os.name == "nt", reason="symbolic links")
def test_a_symbolic_link_is_written_through_and_stays_a_link(tmp_path):
    """`a2l update app.a2l app.elf -o app.a2l` where app.a2l links into a shared folder: the shared file
    changes, the link stays (a rename onto the link would have replaced it with a copy)."""
    shared = tmp_path / "shared"
    shared.mkdir()
    (shared / "app.a2l").write_text("old")
    os.chmod(shared / "app.a2l", 0o640)
    link = tmp_path / "app.a2l"
    link.symlink_to(shared / "app.a2l")
    chained = tmp_path / "chained.a2l"
    chained.symlink_to(link)
    write_output(chained, b"new")
    assert link.is_symlink() and chained.is_symlink()
    assert (shared / "app.a2l").read_bytes() == b"new" and (shared / "app.a2l").stat().st_mode & 0o777 == 0o640
    assert sorted(p.name for p in shared.iterdir()) == ["app.a2l"]  # no temporary file left beside it


def test_failed_write_leaves_old_file(tmp_path, monkeypatch):
    target = tmp_path / "out.bin"
    target.write_bytes(b"old")

    def boom(*args):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OSError):
        atomic_write_bytes(target, b"new")
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.bin"]


def test_read_input_names_the_file_in_one_line(tmp_path):
    (tmp_path / "in.a2l").write_bytes(b"x")
    assert read_input(tmp_path / "in.a2l", "an A2L file") == b"x"
    with pytest.raises(InputError, match=r"none\.a2l: no such file$"):
        read_input(tmp_path / "none.a2l", "an A2L file")
    with pytest.raises(InputError, match=r": is a folder, not an A2L file$"):
        read_input(tmp_path, "an A2L file")


def test_write_output_tells_a_wrong_place_from_a_failed_write(tmp_path, monkeypatch):
    with pytest.raises(InputError, match=r": is a folder; name the file to write$"):
        write_output(tmp_path, b"x")
    (tmp_path / "file").write_bytes(b"")
    with pytest.raises(InputError, match=r"file/out\.a2l: cannot write \("):
        write_output(tmp_path / "file" / "out.a2l", b"x")

    def full(*args):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "replace", full)
    with pytest.raises(WorkbenchError, match=r"out\.a2l: cannot write \(No space left on device\)$") as error:
        write_output(tmp_path / "out.a2l", b"x")
    assert error.value.exit_code == 1


def test_write_output_leaves_a_read_only_file_as_it_was(tmp_path):
    target = tmp_path / "released.a2l"
    target.write_bytes(b"old")
    target.chmod(0o444)
    with pytest.raises(InputError, match=r"released\.a2l: the file is read-only; not overwritten"):
        write_output(target, b"new")
    assert target.read_bytes() == b"old"
    target.chmod(0o644)
    write_output(target, b"new")
    assert target.read_bytes() == b"new"
