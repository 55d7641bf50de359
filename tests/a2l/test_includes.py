"""/include in update and merge output: kept as written, changes in included files reported,
written in place or inline as asked."""

from pathlib import Path

import pytest

from workbench.a2l import load_a2l
from workbench.a2l.merge import merge_files
from workbench.a2l.reports import ConflictPolicy, IncludeMode
from workbench.a2l.update import update_file
from workbench.cli import main
from workbench.elf.symbols import ElfSymbols
from workbench.errors import InputError

ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"
SYMBOLS = ElfSymbols(ELF).symbols

MAIN = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /include "XCP.aml"
    /begin MEASUREMENT zsScalar "in the main file" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1
      ECU_ADDRESS 0x00000000
    /end MEASUREMENT
    /include "objects/signals.a2l"
  /end MODULE
/end PROJECT
"""
AML = '    /begin A2ML\n      block "IF_DATA" taggedunion { "XCP" struct { uint; }; };\n    /end A2ML\n'
SIGNALS = ('/* Größe: latin-1 and CRLF, as some generators write */\r\n'
           '/begin MEASUREMENT csConstant "included" UBYTE NO_COMPU_METHOD 1 0 0 1\r\n'
           '  ECU_ADDRESS 0x0\r\n/end MEASUREMENT\r\n'
           '/begin MEASUREMENT state "ECU_ADDRESS to insert" SLONG NO_COMPU_METHOD 1 0 0 1\r\n/end MEASUREMENT\r\n')


@pytest.fixture
def project(tmp_path) -> Path:
    (tmp_path / "objects").mkdir()
    (tmp_path / "main.a2l").write_text(MAIN)
    (tmp_path / "XCP.aml").write_text(AML)
    (tmp_path / "objects" / "signals.a2l").write_bytes(SIGNALS.encode("latin-1"))
    return tmp_path


def updated_signals() -> bytes:
    return (SIGNALS.replace("ECU_ADDRESS 0x0\r\n", f"ECU_ADDRESS 0x{SYMBOLS['csConstant'].address:X}\r\n")
            .replace('SLONG NO_COMPU_METHOD 1 0 0 1\r\n', 'SLONG NO_COMPU_METHOD 1 0 0 1\r\n'
                     f'  ECU_ADDRESS 0x{SYMBOLS["state"].address:X}\r\n')).encode("latin-1")


def test_update_keeps_include_lines_and_reports_changes_it_cannot_write(project):
    out = project / "out.a2l"
    report = update_file(project / "main.a2l", ELF, out, use_cache=False, epk=False)
    assert out.read_text() == MAIN.replace("0x00000000", f"0x{SYMBOLS['zsScalar'].address:08X}")
    assert (project / "objects" / "signals.a2l").read_bytes() == SIGNALS.encode("latin-1")
    (error,) = report.of_kind("include-not-updated")  # the output's includes keep stale addresses: a build fails
    assert error.file.endswith("signals.a2l") and (error.line, error.column) == (3, 15)
    assert "2 change(s)" in error.message and "--update-includes" in error.message and not report.ok
    assert {f.name for f in report.of_kind("address-updated")} == {"zsScalar", "csConstant", "state"}


def test_update_includes_rewrites_the_included_file_in_its_own_encoding_and_newlines(project):
    report = update_file(project / "main.a2l", ELF, project / "main.a2l", use_cache=False, epk=False,
                         includes=IncludeMode.UPDATE)
    assert (project / "objects" / "signals.a2l").read_bytes() == updated_signals()
    assert (project / "XCP.aml").read_text() == AML  # unchanged files are not rewritten
    assert b'/include "objects/signals.a2l"' in (project / "main.a2l").read_bytes()
    assert [f.file.endswith("signals.a2l") for f in report.of_kind("include-updated")] == [True]
    assert load_a2l(project / "main.a2l").objects("MEASUREMENT")[2].option("ECU_ADDRESS") is not None


def test_merge_includes_writes_everything_inline(project):
    out = project / "out.a2l"
    report = update_file(project / "main.a2l", ELF, out, use_cache=False, epk=False, includes=IncludeMode.MERGE)
    text = out.read_bytes().decode("utf-8")
    assert "/include" not in text and "block \"IF_DATA\"" in text and "/* Größe" in text
    assert report.of_kind("includes-inlined") and not report.of_kind("include-not-updated")
    assert (project / "objects" / "signals.a2l").read_bytes() == SIGNALS.encode("latin-1")


def test_an_output_in_another_folder_warns_about_its_include_lines(project):
    elsewhere = project / "build"
    elsewhere.mkdir()
    report = update_file(project / "main.a2l", ELF, elsewhere / "out.a2l", use_cache=False, epk=False)
    assert [f.name for f in report.of_kind("include-not-found-from-output")] == ["XCP.aml", "objects/signals.a2l"]
    assert report.of_kind("include-not-found-from-output")[0].line == 4


def test_cli_update_includes_options(project, capsys):
    out = project / "out.a2l"
    code = main(["a2l", "update", str(project / "main.a2l"), str(ELF), "-o", str(out), "--no-cache", "--no-epk"])
    stdout = capsys.readouterr().out
    assert code == 1 and "signals.a2l:3:15: error: " in stdout and "change(s) in this included file" in stdout
    code = main(["a2l", "update", str(project / "main.a2l"), str(ELF), "-o", str(out), "--no-cache", "--no-epk",
                 "--update-includes"])
    assert code == 0 and (project / "objects" / "signals.a2l").read_bytes() == updated_signals()
    assert main(["a2l", "update", str(project / "main.a2l"), str(ELF), "-o", str(out), "--update-includes",
                 "--merge-includes"]) == 2


MASTER = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /include "XCP.aml"
    /include "shared.a2l"
  /end MODULE
/end PROJECT
"""
SHARED = '    /begin COMPU_METHOD CM "" IDENTICAL "%6.2" "" /end COMPU_METHOD\n'
FRAGMENT = """ASAP2_VERSION 1 71
/begin PROJECT F ""
  /begin MODULE F ""
    /include "../shared.a2l"
    /begin MEASUREMENT m "" UBYTE CM 1 0 0 1 ECU_ADDRESS 0x0 /end MEASUREMENT
  /end MODULE
/end PROJECT
"""


@pytest.fixture
def fragments(project) -> Path:
    (project / "master.a2l").write_text(MASTER)
    (project / "shared.a2l").write_text(SHARED)
    (project / "fragments").mkdir()
    (project / "fragments" / "f.a2l").write_text(FRAGMENT)
    return project


def test_merge_inlines_by_default_and_keeps_the_masters_includes_when_asked(fragments):
    out = fragments / "out.a2l"
    merge_files(fragments / "master.a2l", [fragments / "fragments" / "f.a2l"], out)
    assert b"/include" not in out.read_bytes()
    report = merge_files(fragments / "master.a2l", [fragments / "fragments" / "f.a2l"], out, keep_includes=True)
    text = out.read_text()
    assert text.startswith(MASTER.split("  /end MODULE")[0]) and text.count("/include") == 2
    assert "/begin MEASUREMENT m" in text and "COMPU_METHOD CM" not in text  # the fragment's copy: identical, left out
    doc = load_a2l(out)
    assert [b.name for b in doc.objects("COMPU_METHOD")] == ["CM"] and [b.name for b in doc.objects("MEASUREMENT")] == ["m"]
    assert report.of_kind("duplicate-identical") and not report.of_kind("include-not-found-from-output")


def test_cli_merge_keep_includes(fragments, capsys):
    out = fragments / "out.a2l"
    argv = ["a2l", "merge", str(fragments / "master.a2l"), str(fragments / "fragments" / "f.a2l"), "-o", str(out)]
    assert main(argv) == 0 and b"/include" not in out.read_bytes()
    assert main([*argv, "--keep-includes"]) == 0 and out.read_text().count("/include") == 2


def test_keep_includes_cannot_replace_a_definition_inside_an_included_file(fragments):
    (fragments / "fragments" / "f.a2l").write_text(FRAGMENT.replace('    /include "../shared.a2l"\n',
                                                                     SHARED.replace("%6.2", "%8.3")))
    with pytest.raises(InputError, match=r"shared.a2l:1:5: the merge must change this file, which the master includes"):
        merge_files(fragments / "master.a2l", [fragments / "fragments" / "f.a2l"], fragments / "out.a2l",
                    policy=ConflictPolicy.KEEP_LAST, keep_includes=True)
    assert not (fragments / "out.a2l").exists()
