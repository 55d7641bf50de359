from pathlib import Path

import pytest

FIXTURES = Path(__file__).parent / "fixtures"
DWARF_ELFS = ["types_dwarf5.elf", "types_dwarf4.elf", "types_dwarf2.elf", "types_m32.elf"]


@pytest.fixture
def elf_fixtures() -> Path:
    return FIXTURES
