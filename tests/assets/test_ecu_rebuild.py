"""Rebuilding the demo ECU from its sources gives the committed FLCU.elf and FLCU.s19.

Needs gcc (32-bit freestanding mode) and make; skipped with the reason otherwise. The
layout (fixed sections, every variable's address and size) must match whatever the gcc
version, because variables keep their source order; code and the s19 byte for byte only
with the gcc version that built the committed ELF (its DW_AT_producer), the CALIB range
(EPK, calibrations, trailer) always.
"""

from __future__ import annotations

import ctypes
import re
import shutil
import subprocess

import bincopy
import pytest
from elftools.elf.elffile import ELFFile

from workbench import demo
from workbench.elf import ElfSymbols

pytestmark = pytest.mark.gcc

ECU = demo.path("assets", "ecu")
CALIB = (0xFC0000, 0xFE0000)
# sections whose address and size depend on the sources only; .text/.rodata (and so the
# .data load address behind them) depend on the code generator
FIXED_SECTIONS = (".app_header", ".epk", ".cal_ram", ".cal_trailer", ".app_key", ".bss")
CODE_SECTIONS = (".text", ".rodata")
BSW_PREFIXES = ("API_", "CanNetwork_")


def _probe(*args: str) -> str | None:
    """Why gcc cannot build the demo here, or None."""
    if shutil.which("gcc") is None or shutil.which("make") is None:
        return "gcc and make are needed to rebuild the demo ECU"
    result = subprocess.run(
        ["gcc", *args, "-x", "c", "-c", "-o", "/dev/null", "-"], input=b"int x;\n", capture_output=True
    )
    return None if result.returncode == 0 else f"gcc {' '.join(args)} does not work here: {result.stderr.decode()[:200]}"


def _gcc_version_of(elf_path) -> str:
    with open(elf_path, "rb") as handle:
        cu = next(ELFFile(handle).get_dwarf_info().iter_CUs())
        producer = cu.get_top_DIE().attributes["DW_AT_producer"].value.decode()
    return re.search(r"GNU C\S* (\d+\.\d+\.\d+)", producer).group(1)


@pytest.fixture(scope="module")
def rebuilt(tmp_path_factory):
    reason = _probe("-m32", "-ffreestanding")
    if reason:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp("flcu_build")
    subprocess.run(["make", "-s", "-C", str(ECU), f"OUT={out}", f"OBJ={out / 'obj'}"], check=True, capture_output=True)
    return out


@pytest.fixture(scope="module")
def same_gcc() -> bool:
    version = subprocess.run(["gcc", "-dumpfullversion"], capture_output=True, text=True).stdout.strip()
    return version == _gcc_version_of(demo.elf())


def _layout(section) -> tuple:
    """Where a section is and how big (not where its bytes lie in the file)."""
    return section.address, section.load_address, section.size, section.loaded, section.allocated


def test_fixed_sections_match(rebuilt):
    committed, fresh = ElfSymbols(demo.elf()).sections, ElfSymbols(rebuilt / "FLCU.elf").sections
    assert [n for n, s in committed.items() if s.allocated] == [n for n, s in fresh.items() if s.allocated]
    for name in FIXED_SECTIONS:
        assert _layout(fresh[name]) == _layout(committed[name]), name
    assert (fresh[".data"].address, fresh[".data"].size) == (committed[".data"].address, committed[".data"].size)


def test_every_data_symbol_keeps_its_address_and_size(rebuilt, same_gcc):
    committed, fresh = ElfSymbols(demo.elf()).symbols, ElfSymbols(rebuilt / "FLCU.elf").symbols
    # the BSW stubs' statics (linked after the models) are the compiler's to keep or drop
    data = {
        n: s
        for n, s in committed.items()
        if s.kind == "object" and (same_gcc or (s.section not in CODE_SECTIONS and not n.startswith(BSW_PREFIXES)))
    }
    assert len(data) > 100
    for name, symbol in data.items():
        assert (fresh[name].address, fresh[name].size, fresh[name].section) == (
            symbol.address,
            symbol.size,
            symbol.section,
        ), name


def test_s19_matches(rebuilt, same_gcc):
    committed, fresh = bincopy.BinFile(str(demo.s19())), bincopy.BinFile(str(rebuilt / "FLCU.s19"))
    assert fresh[CALIB[0] : CALIB[1]] == committed[CALIB[0] : CALIB[1]]
    if same_gcc:
        assert (rebuilt / "FLCU.s19").read_bytes() == demo.s19().read_bytes()
        for name in (*CODE_SECTIONS, ".data"):
            assert _layout(ElfSymbols(rebuilt / "FLCU.elf").sections[name]) == _layout(ElfSymbols(demo.elf()).sections[name])


def test_cal_rom_holds_the_initial_values_of_the_c_sources(tmp_path):
    """Each calibration's bytes as the C compiler initialises them in a host program (no linker
    script, no s19 involved) equal the s19's CAL ROM bytes at the calibration's load address."""
    reason = _probe()
    if reason:
        pytest.skip(reason)
    library = tmp_path / "libflcu_host.so"
    subprocess.run(
        ["make", "-s", "-C", str(ECU), "host", f"HOSTLIB={library}", f"OBJ={tmp_path / 'obj'}"],
        check=True,
        capture_output=True,
    )
    host = ctypes.CDLL(str(library))
    elf = ElfSymbols(demo.elf())
    s19 = bincopy.BinFile(str(demo.s19()))
    cal_ram = elf.sections[".cal_ram"]
    calibrations = [s for s in elf.symbols.values() if s.section == ".cal_ram" and s.kind == "object"]
    assert len(calibrations) > 50
    for symbol in calibrations:
        rom = symbol.address - cal_ram.address + cal_ram.load_address
        in_c = bytes((ctypes.c_ubyte * symbol.size).in_dll(host, symbol.name))
        assert s19[rom : rom + symbol.size] == in_c, symbol.name
