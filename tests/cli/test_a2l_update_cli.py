"""``workbench a2l update --remove-missing`` end to end: a kept object that needs a missing one refuses (exit 1,
nothing written, file:line:column), ``--drop-optional-references`` drops an INPUT_QUANTITY, usage errors exit 2."""

from __future__ import annotations

from pathlib import Path

from cli_helpers import run

FIXTURES = Path(__file__).parents[1] / "a2l" / "fixtures"
ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"


def _a2l(tmp_path, axis: str = "zsScalar_gone") -> Path:
    """types.a2l with zsScalar missing from the ELF (renamed) and named as zvLut's axis input."""
    path = tmp_path / "in.a2l"
    path.write_text((FIXTURES / "types.a2l").read_text().replace("MEASUREMENT zsScalar ", "MEASUREMENT zsScalar_gone ")
                    .replace("REF_MEASUREMENT zsScalar ", "REF_MEASUREMENT zsScalar_gone ")
                    .replace("STD_AXIS NO_INPUT_QUANTITY", f"STD_AXIS {axis}"))
    return path


def test_remove_missing_refuses_a_needed_reference_and_writes_nothing(tmp_path, capsys):
    source, out = _a2l(tmp_path), tmp_path / "out.a2l"
    code, stdout, stderr = run(capsys, "a2l", "update", source, ELF, "-o", out, "--remove-missing", "--no-cache")
    line = next(n for n, text in enumerate(source.read_text().splitlines(), 1) if "STD_AXIS" in text)
    assert code == 1 and not out.exists()
    assert f"{source}:{line}:34: error: CHARACTERISTIC zvLut AXIS_DESCR: its input quantity zsScalar_gone would " \
           "name a removed object; --drop-optional-references drops it" in stdout
    assert stderr.startswith("1 kept reference(s) to objects --remove-missing would remove") and \
        stderr.rstrip().endswith("; nothing written") and stderr.count("\n") == 1
    code, stdout, stderr = run(capsys, "a2l", "update", source, ELF, "-o", out, "--remove-missing",
                               "--drop-optional-references", "--no-cache")
    text = out.read_text()
    assert code == 0 and "zsScalar_gone" not in text and "STD_AXIS NO_INPUT_QUANTITY" in text
    assert "INPUT_QUANTITY zsScalar_gone is removed: now NO_INPUT_QUANTITY" in stdout
    assert run(capsys, "a2l", "check", out)[:2] == (0, "")  # no reference names the removed object


def test_drop_optional_references_needs_remove_missing(tmp_path, capsys):
    out = tmp_path / "out.a2l"
    code, stdout, stderr = run(capsys, "a2l", "update", _a2l(tmp_path), ELF, "-o", out, "--drop-optional-references",
                               "--no-cache")
    assert (code, stdout, not out.exists()) == (2, "", True)
    assert stderr.count("\n") == 1 and "--drop-optional-references: goes with --remove-missing" in stderr
