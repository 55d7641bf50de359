"""The ELF headers read with struct agree with pyelftools' reading; compressed DWARF sections read alike."""

import shutil
import subprocess
from pathlib import Path

import pytest
from elftools.elf.elffile import ELFFile

from workbench.elf.debugdata import DebugData
from workbench.elf.headers import read_headers, read_section

FIXTURES = Path(__file__).parent / "fixtures"
# types_zdebug.elf and types_zstd.elf: types_dwarf5.elf compressed in the ways pyelftools does not read (test below)
ELFS = sorted(set(FIXTURES.glob("*.elf")) - set(FIXTURES.glob("types_z*.elf"))) + \
    sorted((Path(__file__).parent / "matrix").glob("*-O2.elf"))


@pytest.mark.parametrize("path", ELFS, ids=lambda path: path.name)
def test_headers_and_sections_are_pyelftools(path):
    headers = read_headers(path)
    with open(path, "rb") as handle:
        elf = ELFFile(handle)
        assert (headers.little_endian, headers.elfclass) == (elf.little_endian, elf.elfclass)
        assert [(s.name, s.type, s.flags, s.address, s.offset, s.size, s.link) for s in headers.sections] == [
            (s.name, _number(s["sh_type"]), s["sh_flags"], s["sh_addr"], s["sh_offset"], s["sh_size"], s["sh_link"])
            for s in elf.iter_sections()]
        loads = [(g["p_vaddr"], g["p_paddr"], g["p_filesz"], g["p_memsz"]) for g in elf.iter_segments()
                 if g["p_type"] == "PT_LOAD"]
        assert [(g.vaddr, g.paddr, g.filesz, g.memsz) for g in headers.segments if g.type == 1] == loads
        for section in headers.sections:
            if section.name.startswith(".debug"):
                assert read_section(path, section, headers) == elf.get_section_by_name(section.name).data()


def _number(sh_type) -> int:
    """pyelftools gives a section's type by name where it knows it: the number ELF gives it."""
    from elftools.elf.enums import ENUM_SH_TYPE_AMD64, ENUM_SH_TYPE_BASE

    return sh_type if isinstance(sh_type, int) else {**ENUM_SH_TYPE_BASE, **ENUM_SH_TYPE_AMD64}[sh_type]


@pytest.mark.skipif(shutil.which("objcopy") is None, reason="objcopy (binutils) is not installed")
def test_compressed_debug_sections_are_read(tmp_path):
    compressed = tmp_path / "compressed.elf"
    subprocess.run(["objcopy", "--compress-debug-sections=zlib-gabi", FIXTURES / "types_dwarf5.elf", compressed],
                   check=True, capture_output=True, timeout=60)
    [info] = [section for section in read_headers(compressed).sections if section.name == ".debug_info"]
    assert info.flags & 0x800  # SHF_COMPRESSED: the test reads what it means to
    plain = DebugData(FIXTURES / "types_dwarf5.elf", use_cache=False)
    again = DebugData(compressed, use_cache=False)
    assert again._variables == plain._variables
    assert again.resolve("outer.arr[2].d[1]") == plain.resolve("outer.arr[2].d[1]")


@pytest.mark.parametrize("name, compressed", [("types_zdebug.elf", ".zdebug_info"), ("types_zstd.elf", ".debug_info")])
def test_debug_sections_compressed_the_gnu_way_or_with_zstd_are_read(name, compressed):
    """objcopy --compress-debug-sections=zlib-gnu (.zdebug_*, older toolchains) and =zstd (gcc -gz=zstd): the
    sections read as types_dwarf5.elf's, which they were made from (pyelftools reads neither)."""
    plain = read_headers(FIXTURES / "types_dwarf5.elf")
    headers = read_headers(FIXTURES / name)
    [section] = [section for section in headers.sections if section.name == compressed]
    assert compressed.startswith(".zdebug") or section.flags & 0x800  # compressed, as the test means
    for section in headers.sections:
        if section.name.startswith((".debug", ".zdebug")):
            [twin] = [twin for twin in plain.sections if twin.name == section.name.replace(".zdebug", ".debug")]
            assert read_section(FIXTURES / name, section, headers) == \
                read_section(FIXTURES / "types_dwarf5.elf", twin, plain), section.name
