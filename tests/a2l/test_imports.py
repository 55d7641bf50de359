"""A cached `workbench a2l update` loads only what it uses: no pyelftools, no other tool's library."""

import json
import subprocess
import sys
from pathlib import Path

FIXTURES = Path(__file__).parent / "fixtures"
ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"
NOT_NEEDED = ["elftools", "cantools", "pyxcp", "asammdf", "pya2l", "rich", "PySide6", "can", "platformdirs"]

SCRIPT = """
import json, sys
from workbench.cli import main
code = main(sys.argv[1:])
print(json.dumps([code, sorted({name.split(".")[0] for name in sys.modules} & set(%r))]))
""" % NOT_NEEDED


def run_update(tmp_path: Path) -> tuple[int, list[str]]:
    argv = ["a2l", "update", str(FIXTURES / "types.a2l"), str(ELF), "-o", str(tmp_path / "out.a2l"),
            "--cache-dir", str(tmp_path / "cache")]
    run = subprocess.run([sys.executable, "-c", SCRIPT, *argv], capture_output=True, text=True, timeout=60, check=True)
    return tuple(json.loads(run.stdout.splitlines()[-1]))


def test_a_cached_update_imports_no_heavy_library(tmp_path):
    code, first = run_update(tmp_path)
    assert code == 0 and "elftools" in first  # the first run reads DWARF
    code, cached = run_update(tmp_path)
    assert (code, cached) == (0, [])
