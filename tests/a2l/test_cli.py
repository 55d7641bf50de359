"""workbench a2l: exit codes 0/1/2, one-line errors, JSON reports."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import run

from workbench.cli import main
from workbench.errors import A2lParseError

ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"


@pytest.fixture
def types_a2l(fixtures):
    return fixtures / "types.a2l"



def test_update_writes_and_reports(capsys, tmp_path, types_a2l):
    out = tmp_path / "out.a2l"
    code, stdout, stderr = run(capsys, "a2l", "update", str(types_a2l), str(ELF), "-o", str(out),
                               "--cache-dir", str(tmp_path / "cache"))
    assert code == 0 and out.exists()
    assert "warning: MEASUREMENT missing_var: not in types_dwarf5.elf" in stdout
    assert "address" not in stdout  # info findings only with -v
    assert stderr.startswith(f"wrote {out}: MEASUREMENT 1 not-found, 6 updated")


def test_update_json_and_strict(capsys, tmp_path, types_a2l):
    out = tmp_path / "out.a2l"
    code, stdout, _ = run(capsys, "a2l", "update", str(types_a2l), str(ELF), "-o", str(out), "--strict",
                          "--no-cache", "--json")
    report = json.loads(stdout)
    assert code == 1 and not out.exists()
    assert report["ok"] is False and report["counts"]["symbol-not-found"] == 1
    (missing,) = [f for f in report["findings"] if f["kind"] == "symbol-not-found"]
    assert (missing["name"], missing["line"], missing["severity"]) == ("missing_var", 36, "error")


def test_bad_input_exits_2_with_one_line(capsys, tmp_path, types_a2l):
    bad = tmp_path / "bad.a2l"
    bad.write_text('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n')
    code, stdout, stderr = run(capsys, "a2l", "update", str(bad), str(ELF), "-o", str(tmp_path / "o.a2l"))
    assert code == 2 and stderr == f"error: {bad}:2:1: /begin PROJECT is never closed (missing /end PROJECT)\n"
    code, _, stderr = run(capsys, "a2l", "update", str(types_a2l), str(types_a2l), "-o", str(tmp_path / "o.a2l"))
    assert code == 2 and "not a readable ELF file" in stderr and stderr.count("\n") == 1
    code, _, stderr = run(capsys, "a2l", "update", str(types_a2l), str(ELF))
    assert code == 2 and "-o/--output" in stderr


def test_debug_may_follow_the_command(tmp_path):
    """``--debug`` belongs to ``workbench`` itself; given after the command it still shows the traceback."""
    bad = tmp_path / "bad.a2l"
    bad.write_text('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n')
    with pytest.raises(A2lParseError):
        main(["a2l", "update", str(bad), str(ELF), "-o", str(tmp_path / "o.a2l"), "--debug"])


def test_an_output_that_cannot_be_written_exits_2_with_one_line(capsys, tmp_path, types_a2l):
    code, _, stderr = run(capsys, "a2l", "update", str(types_a2l), str(ELF), "-o", str(tmp_path), "--no-cache")
    assert (code, stderr) == (2, f"error: {tmp_path}: is a folder; name the file to write\n")
    (tmp_path / "file").write_text("")
    code, _, stderr = run(capsys, "a2l", "merge", str(types_a2l), str(types_a2l), "-o", str(tmp_path / "file" / "o.a2l"))
    assert code == 2 and stderr.startswith(f"error: {tmp_path / 'file' / 'o.a2l'}: cannot write (") and stderr.count("\n") == 1
    for command in (["update", str(types_a2l), str(ELF)], ["merge", str(types_a2l), str(types_a2l)]):
        code, _, stderr = run(capsys, "a2l", *command, "-o", "-")  # not a file named '-' (stdout is the report's)
        assert code == 2 and "'-' is not a file" in stderr and not (Path.cwd() / "-").exists()


def test_a_read_only_a2l_is_not_updated_in_place(capsys, tmp_path, types_a2l):
    """A file made read-only (not checked out of a version control system, a released A2L) is left as it was,
    although its folder would let a rename replace it."""
    released = tmp_path / "released.a2l"
    released.write_bytes(types_a2l.read_bytes())
    released.chmod(0o444)
    code, _, stderr = run(capsys, "a2l", "update", str(released), str(ELF), "-o", str(released), "--no-cache")
    assert (code, stderr) == (2, f"error: {released}: the file is read-only; not overwritten (make it writable, "
                                 "or write another file)\n")
    assert released.read_bytes() == types_a2l.read_bytes()


def test_merge_conflict_exits_1(capsys, tmp_path):
    text = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n /begin MODULE M ""\n'
            '  /begin COMPU_METHOD CM "" IDENTICAL "%{}" "" /end COMPU_METHOD\n /end MODULE\n/end PROJECT\n')
    (tmp_path / "a.a2l").write_text(text.format("4.1"))
    (tmp_path / "b.a2l").write_text(text.format("4.2"))
    out = tmp_path / "out.a2l"
    code, stdout, stderr = run(capsys, "a2l", "merge", str(tmp_path / "a.a2l"), str(tmp_path / "b.a2l"), "-o", str(out))
    assert code == 1 and not out.exists() and "conflicting definition" in stderr
    assert f"{tmp_path / 'b.a2l'}:4:10: error: COMPU_METHOD CM differs" in stdout
    code, _, _ = run(capsys, "a2l", "merge", str(tmp_path / "a.a2l"), str(tmp_path / "b.a2l"), "-o", str(out),
                     "--on-conflict", "rename")
    assert code == 0 and b"CM_M" in out.read_bytes()


def test_check_exit_codes(capsys, tmp_path, types_a2l):
    code, stdout, stderr = run(capsys, "a2l", "check", str(types_a2l))
    assert code == 1 and "outside every MEMORY_SEGMENT" in stdout and "problem(s)" in stderr
    out = tmp_path / "out.a2l"
    run(capsys, "a2l", "update", str(types_a2l), str(ELF), "-o", str(out), "--remove-missing", "--no-cache")
    code, stdout, stderr = run(capsys, "a2l", "check", str(out), "--elf", str(ELF), "--no-cache")
    # types.a2l has no MOD_COMMON: ASAP2's default byte order MSB_FIRST is not the x86 ELF's
    assert code == 1 and stdout.count("\n") == 1 and "MOD_COMMON says no BYTE_ORDER" in stdout
    out.write_text(out.read_text().replace('/begin MODULE Types ""', '/begin MODULE Types ""\n'
                                           '    /begin MOD_COMMON "" BYTE_ORDER MSB_LAST /end MOD_COMMON'))
    code, stdout, stderr = run(capsys, "a2l", "check", str(out), "--elf", str(ELF), "--no-cache")
    assert (code, stdout, stderr) == (0, "", f"{out}: clean\n")


def test_check_image_holds_the_epk_at_every_addr_epk(capsys, tmp_path):
    from workbench import demo
    from workbench.image import load_image

    code, stdout, stderr = run(capsys, "a2l", "check", str(demo.a2l()), "--image", str(demo.s19()))
    assert (code, stdout) == (0, "")
    image = load_image(demo.s19())
    image.add(0x840008, b"10300020259999", overwrite=True)  # the application of another build, its CALIB this one's
    image.crop(0x840000, 0xFE0000).save(tmp_path / "other_app.s19")
    code, stdout, stderr = run(capsys, "a2l", "check", str(demo.a2l()), "--image", str(tmp_path / "other_app.s19"),
                               "--json")
    found = json.loads(stdout)["findings"]
    assert code == 1 and [(f["kind"], f["severity"], f["message"]) for f in found] == [
        ("epk-differs", "error", "ADDR_EPK 0x840008: other_app.s19 holds '10300020259999' there, MOD_PAR's EPK is "
         "'10300020250301' (an A2L of another build, or an ADDR_EPK not updated: workbench a2l update)")]
    image.crop(0xFC0000, 0xFE0000).save(tmp_path / "calib.s19")  # CALIB only: the application's EPK not compared
    code, stdout, stderr = run(capsys, "a2l", "check", str(demo.a2l()), "--image", str(tmp_path / "calib.s19"))
    assert code == 0 and stdout.endswith(":16: info: ADDR_EPK 0x840008: calib.s19 has no bytes there (or not all 14): "
                                         "not compared\n")
    code, stdout, stderr = run(capsys, "a2l", "check", str(demo.a2l()), "--image", str(demo.elf()))
    assert code == 2 and stdout == "" and stderr.count("\n") == 1 and "is an ELF file, not a flash image" in stderr


def test_diff_exit_codes_and_json(capsys, tmp_path, types_a2l):
    out = tmp_path / "out.a2l"
    run(capsys, "a2l", "update", str(types_a2l), str(ELF), "-o", str(out), "--no-cache")
    code, stdout, _ = run(capsys, "a2l", "diff", str(types_a2l), str(types_a2l))
    assert code == 0 and stdout == ""
    code, stdout, _ = run(capsys, "a2l", "diff", str(types_a2l), str(out), "--json")
    differences = json.loads(stdout)["differences"]
    assert code == 1 and {d["name"] for d in differences} >= {"zsScalar", "MOD_PAR"}
    scalar = next(d for d in differences if d["name"] == "zsScalar")
    assert scalar["changes"] == [{"field": "ECU_ADDRESS", "old": "0x00000000", "new": "0x00403000"}]


def _console_script(*argv, **kwargs):
    """The command as the installed ``workbench`` runs it, its output block-buffered into a pipe."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    return subprocess.run([sys.executable, "-c", "from workbench.cli import entry_point; entry_point()", *argv],
                          capture_output=True, text=True, timeout=60, env=env, **kwargs)


def test_a_batch_process_that_ends_at_once_still_delivers_all_it_printed(tmp_path, types_a2l):
    """A batch command's process ends without Python's teardown: what it buffered for stdout and stderr
    still arrives whole, with its exit code, and its output file is complete."""
    out = tmp_path / "out.a2l"
    run = _console_script("a2l", "update", str(types_a2l), str(ELF), "-o", str(out), "--json", "-v", "--no-cache")
    report = json.loads(run.stdout)  # the whole JSON document, or this fails
    assert (run.returncode, run.stderr, report["output"]) == (0, "", str(out))
    assert report["counts"]["address-updated"] == 10 and report["counts"]["symbol-not-found"] == 1
    assert out.read_bytes() == _library_update(types_a2l)
    run = _console_script("a2l", "update", str(types_a2l), str(ELF), "-o", str(tmp_path / "o.a2l"), "--strict",
                          "--no-cache")
    assert run.returncode == 1 and "missing_var" in run.stdout and "nothing written" in run.stderr


def _library_update(a2l: Path) -> bytes:
    from workbench.a2l import load_a2l
    from workbench.a2l.update import update_document
    from workbench.elf.debugdata import DebugData

    with DebugData(ELF, use_cache=False) as debug:
        return update_document(load_a2l(a2l), debug).data



def test_with_both_files_bad_the_a2l_is_reported_first(capsys, tmp_path, types_a2l):
    """The ELF is read beside the A2L, on a thread: still one line, and the A2L's error as before."""
    bad = tmp_path / "bad.a2l"
    bad.write_text('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n')
    code, _, stderr = run(capsys, "a2l", "update", str(bad), str(types_a2l), "-o", str(tmp_path / "o.a2l"))
    assert (code, stderr) == (2, f"error: {bad}:2:1: /begin PROJECT is never closed (missing /end PROJECT)\n")


def test_check_image_bytes_outside_every_memory_segment_are_a_warning(capsys, tmp_path):
    """A file of another ECU, or an A2L that lacks a MEMORY_SEGMENT: the check was clean."""
    from workbench import demo
    from workbench.image import load_image

    image = load_image(demo.s19())
    image.add(0x700000, b"\x01\x02\x03")
    image.save(tmp_path / "more.s19")
    code, stdout, stderr = run(capsys, "a2l", "check", str(demo.a2l()), "--image", str(tmp_path / "more.s19"), "--json")
    found = json.loads(stdout)["findings"]
    assert code == 1 and [(f["kind"], f["severity"], f["line"], f["message"]) for f in found] == [
        ("image-outside-memory", "warning", 448, "more.s19 holds 3 bytes in no MEMORY_SEGMENT: 700000h-700002h (the "
         "segments: BOOT 800000h-83FFFFh, APPLICATIVE 840000h-FBFFFFh, CALIB FC0000h-FDFFFFh, SHARED FE0000h-FE3FFFh, "
         "CALRAM 40000000h-4001FFFFh, RAM_DATA 40020000h-4007FFFFh): a file of another ECU, or a MEMORY_SEGMENT "
         "missing")]
