"""`workbench a2l update` loads only what it uses: no pyelftools, no other tool's library."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from workbench import demo

FIXTURES = Path(__file__).parent / "fixtures"
ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"
NOT_NEEDED = ["elftools", "cantools", "pyxcp", "asammdf", "pya2l", "rich", "PySide6", "can", "platformdirs",
              "logging", "tempfile", "shutil"]  # these: 12 ms of a small update (workbench.logs, fileio, cli.options)
# what an address update from a cached index does not run: the type checker (--types), the DWARF decoder,
# index and type reader, the .symtab names, the bus options
NOT_RUN_WHEN_CACHED = ["workbench.a2l.update.typecheck", "workbench.elf.dwarf", "workbench.elf.dwarf_index",
                       "workbench.elf.die_readers", "workbench.elf.type_resolver", "workbench.elf.symtab_names",
                       "workbench.elf.paths", "workbench.bus_defaults", "workbench.elf.ctypes_model"]

SCRIPT = """
import json, sys
from workbench.cli import main
code = main(sys.argv[1:])
print(json.dumps([code, sorted(sys.modules)]))
"""


def run_update(tmp_path: Path, a2l: Path = FIXTURES / "types.a2l", elf: Path = ELF,
               default_cache: bool = False) -> tuple[int, list[str], list[str]]:
    """The exit code, the heavy libraries and the modules of NOT_RUN_WHEN_CACHED that one update loads;
    ``default_cache``: into the user's cache folder (``$XDG_CACHE_HOME``: ``tmp_path/cache``), as users run it."""
    argv = ["a2l", "update", str(a2l), str(elf), "-o", str(tmp_path / "out.a2l")]
    env = {key: value for key, value in os.environ.items() if key != "WORKBENCH_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(tmp_path / "cache")
    if not default_cache:
        argv += ["--cache-dir", str(tmp_path / "cache")]
    run = subprocess.run([sys.executable, "-c", SCRIPT, *argv], capture_output=True, text=True, timeout=60, check=True,
                         env=env)
    code, modules = json.loads(run.stdout.splitlines()[-1])
    return code, sorted({name.split(".")[0] for name in modules} & set(NOT_NEEDED)), \
        sorted(set(modules) & set(NOT_RUN_WHEN_CACHED))


def test_an_update_imports_no_heavy_library(tmp_path):
    """Neither the first update (which reads the headers and DWARF itself) nor a cached one; the cached one
    loads neither the DWARF index nor the type checker."""
    code, first, ours = run_update(tmp_path)
    assert (code, first) == (0, []) and len(list((tmp_path / "cache").iterdir())) == 1  # the first run read DWARF
    assert "workbench.elf.dwarf_index" in ours  # so the check below can fail
    code, cached, ours = run_update(tmp_path)
    assert (code, cached, ours) == (0, [], [])


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="elsewhere platformdirs names the folder")
def test_an_update_into_the_default_cache_folder_imports_no_heavy_library(tmp_path):
    """Users give no --cache-dir: finding their cache folder must not import platformdirs (and its tempfile)."""
    assert run_update(tmp_path, default_cache=True)[:2] == (0, [])
    assert len(list((tmp_path / "cache" / "workbench" / "elf-index").iterdir())) == 1
    assert run_update(tmp_path, default_cache=True) == (0, [], [])


def test_a_cached_update_reads_its_epk_without_loading_a_type(tmp_path):
    """The demo's EPK variable is a cached symbol: its address and size come without its C type."""
    run_update(tmp_path, demo.a2l(), demo.elf())
    assert run_update(tmp_path, demo.a2l(), demo.elf()) == (0, [], [])
    assert b"EPK" in (tmp_path / "out.a2l").read_bytes()


def test_a_cached_update_reads_neither_the_variables_nor_writes_the_cache_again(tmp_path):
    """The cache answers every path of the file (those the ELF lacks included): the second update
    leaves the variables pickled and the cache file as it was."""
    from workbench.a2l import load_a2l
    from workbench.a2l.update import update_document
    from workbench.elf.debugdata import DebugData

    text = (FIXTURES / "types.a2l").read_text().replace("/end MODULE", '/begin MEASUREMENT gone "a removed variable" '
                                                        "UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x0 /end MEASUREMENT"
                                                        "\n/end MODULE")
    (tmp_path / "in.a2l").write_text(text)
    doc = load_a2l(tmp_path / "in.a2l")
    with DebugData(ELF, cache_dir=tmp_path / "cache") as debug:
        first = update_document(doc, debug)
    assert any(f.kind == "symbol-not-found" and f.name == "gone" for f in first.report.findings)
    entry = next((tmp_path / "cache").iterdir())
    written = entry.stat().st_mtime_ns
    with DebugData(ELF, cache_dir=tmp_path / "cache") as debug:
        again = update_document(doc, debug)
        assert debug.from_cache and debug._variables is None
    assert again.data == first.data and entry.stat().st_mtime_ns == written


def test_the_did_you_mean_of_a_missing_symbol_costs_nothing_while_none_is_missing(tmp_path):
    """The suggestion for a symbol the ELF lacks (workbench.elf.suggest, its name index) is loaded only when one is."""
    def modules(a2l: Path) -> set[str]:
        argv = ["a2l", "update", str(a2l), str(ELF), "-o", str(tmp_path / "out.a2l"), "--cache-dir", str(tmp_path)]
        run = subprocess.run([sys.executable, "-c", SCRIPT, *argv], capture_output=True, text=True, timeout=60,
                             check=True)
        return set(json.loads(run.stdout.splitlines()[-1])[1])

    text = (FIXTURES / "types.a2l").read_text()
    start = text.index("    /begin MEASUREMENT missing_var")
    found = tmp_path / "found.a2l"
    found.write_text(text[:start] + text[text.index("/end MEASUREMENT\n", start) + len("/end MEASUREMENT\n"):])
    assert "workbench.elf.suggest" not in modules(found)
    assert "workbench.elf.suggest" in modules(FIXTURES / "types.a2l")  # missing_var: so the line above can fail
