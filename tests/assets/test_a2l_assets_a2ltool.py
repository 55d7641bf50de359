"""A second, independent opinion on the demo A2L files: a2ltool (Rust, a dev dependency).

a2ltool's strict parser checks the files and their cross references, its IF_DATA
parser checks the XCP blocks against the A2ML of ``a2l/XCP.aml``, and its ELF reader
updates the merged file from ``assets/FLCU.elf``.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from workbench import demo

_A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")
pytestmark = pytest.mark.skipif(_A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")


def _a2ltool(*args) -> str:
    result = subprocess.run([_A2LTOOL, *map(str, args)], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout + result.stderr


def _merged(tmp_path: Path) -> Path:
    merged = tmp_path / "merged.a2l"
    fragments = [arg for path in demo.fragment_a2ls() for arg in ("--merge", path)]
    _a2ltool(demo.master_a2l(), "--merge-includes", *fragments, "--output", merged)
    return merged


_OUTSIDE = re.compile(r"Cross-reference error: CHARACTERISTIC (\w+) on line \d+ references a non-existent MEASUREMENT "
                      r"(\w+)")


@pytest.mark.parametrize("path", demo.fragment_a2ls(), ids=lambda p: p.stem)
def test_fragment_passes_a2ltools_strict_check(path):
    """Each fragment alone, where only a fix's COMPARISON_QUANTITY may name a measurement of another module (the
    sources of the signals CANTX sends are FuelLevel's, PressSens' and Utils'); the merged file resolves them."""
    _a2ltool("--strict", path)
    report = _a2ltool("--check", path)
    problems = [line.strip() for line in report.splitlines() if line.startswith(" ")]
    text = path.read_text(encoding="utf-8")
    others = "".join(p.read_text(encoding="utf-8") for p in demo.fragment_a2ls() if p != path)
    for problem in problems:
        outside = _OUTSIDE.fullmatch(problem)
        assert outside, problem
        characteristic, measurement = outside.groups()
        assert re.search(rf"\*/ {characteristic}\n(?:(?!/end CHARACTERISTIC).)*COMPARISON_QUANTITY {measurement}\n",
                         text, re.S), problem
        assert re.search(rf"/begin MEASUREMENT\s+/\*[^*]*\*/ {measurement}\n", others), problem
    assert problems or "No problems found" in report
    assert len(problems) == (11 if path.stem == "CANTX" else 0)


def test_merged_a2l_passes_a2ltools_strict_check(tmp_path):
    assert "No problems found" in _a2ltool("--strict", "--check", _merged(tmp_path))


def test_master_if_data_matches_its_a2ml(tmp_path):
    """--ifdata-cleanup drops every IF_DATA that does not parse against the A2ML."""
    cleaned = tmp_path / "cleaned.a2l"
    _a2ltool(demo.master_a2l(), "--ifdata-cleanup", "--output", cleaned)
    before = demo.master_a2l().read_text(encoding="utf-8").count("/begin IF_DATA")
    assert before == 2
    assert re.sub(r"/begin A2ML.*?/end A2ML", "", cleaned.read_text(encoding="utf-8"), flags=re.S).count("/begin IF_DATA") == before


def test_a2ltool_updates_every_object_from_the_elf_and_changes_only_addresses(tmp_path):
    merged = _merged(tmp_path)
    formatted, updated = tmp_path / "formatted.a2l", tmp_path / "updated.a2l"
    _a2ltool(merged, "--output", formatted)
    report = _a2ltool("--strict", merged, "--elffile", demo.elf(), "--update", "FULL", "--update-mode", "STRICT",
                      "--verbose", "--output", updated)
    counts = dict(re.findall(r"(characteristic|measurement|axis_pts): \d+ updated, (\d+) not found", report))
    assert counts == {"characteristic": "0", "measurement": "0", "axis_pts": "0"}
    # a FULL update rewrites data types, record layouts and dimensions that disagree with the ELF
    def without_addresses(text: str) -> list[str]:
        lines = [line.strip() for line in text.splitlines() if not line.strip().startswith("SYMBOL_LINK")]
        return [re.sub(r"\b0x[0-9A-Fa-f]+\b", "ADDRESS", line) for line in lines]

    assert without_addresses(formatted.read_text(encoding="utf-8")) == without_addresses(updated.read_text(encoding="utf-8"))
