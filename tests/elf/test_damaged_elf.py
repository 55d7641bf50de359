"""Damaged ELF files: random bytes changed in the headers, DWARF and symbol table give an InputError, never a traceback."""

import random
from collections import Counter
from pathlib import Path

from workbench.a2l import load_a2l
from workbench.a2l.update import update_document
from workbench.elf.debugdata import DebugData
from workbench.elf.symbols import ElfSymbols
from workbench.errors import InputError

FIXTURES = Path(__file__).parent / "fixtures"
A2L = Path(__file__).parents[1] / "a2l" / "fixtures" / "types.a2l"
ELFS = ["types_dwarf5.elf", "types_dwarf2.elf", "types_m32.elf"]
REGIONS = ["header", "section table", ".debug_info", ".debug_abbrev", ".debug_str", ".symtab", ".strtab"]


def regions(path: Path) -> dict[str, tuple[int, int]]:
    """(file offset, size) of the parts of the file that are damaged."""
    elf = ElfSymbols(path)
    table = max(s.file_offset + (s.size if s.loaded else 0) for s in elf.sections.values())
    found = {"header": (0, 64), "section table": (table, path.stat().st_size - table)}
    found.update((name, (elf.sections[name].file_offset, elf.sections[name].size)) for name in REGIONS[2:])
    return found


def test_damaged_elf_updates_or_raises_input_error(tmp_path):
    a2l = load_a2l(A2L)
    outcomes = Counter()
    for elf in ELFS:
        source = (FIXTURES / elf).read_bytes()
        parts = regions(FIXTURES / elf)
        for seed in range(60):
            rng = random.Random(seed)
            where = REGIONS[seed % len(REGIONS)]
            start, size = parts[where]
            data = bytearray(source)
            for _ in range(rng.randint(1, 12)):
                data[start + rng.randrange(size)] = rng.randrange(256)
            damaged = tmp_path / f"{elf}.{seed}"
            damaged.write_bytes(bytes(data))
            try:
                with DebugData(damaged, use_cache=False) as debug:
                    update_document(a2l, debug, types=True)
                outcomes["updated"] += 1
            except InputError as error:
                assert str(error).startswith(str(damaged)) and "\n" not in str(error), str(error)
                outcomes["input error"] += 1
    assert outcomes["input error"] >= 20 and outcomes["updated"] >= 20, outcomes  # both paths were exercised


def test_a_folder_is_not_an_elf(tmp_path):
    try:
        DebugData(tmp_path, use_cache=False)
    except InputError as error:
        assert str(error) == f"{tmp_path}: is a folder, not an ELF file"
    else:
        raise AssertionError("no error")
