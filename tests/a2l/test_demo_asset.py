"""assets/FLCU.a2l: the demo's master and fragments merged and updated from assets/FLCU.elf.

Regenerate it with:
    workbench a2l merge a2l/FLCU_master.a2l a2l/modules/*.a2l -o /tmp/FLCU_merged.a2l
    workbench a2l update /tmp/FLCU_merged.a2l assets/FLCU.elf -o assets/FLCU.a2l --strict
"""

import pytest
from elf_oracle import PyelftoolsOracle
from pya2l_oracle import pya2l_import

from workbench import demo
from workbench.a2l import load_a2l
from workbench.a2l.merge import merge_files
from workbench.a2l.reports import UpdateMode
from workbench.a2l.update import update_file

REGENERATE = __doc__.split("Regenerate it with:")[1].strip()


def test_the_committed_file_is_what_merge_and_update_produce_now(tmp_path):
    merged = tmp_path / "merged.a2l"
    merge_files(demo.master_a2l(), demo.fragment_a2ls(), merged)
    fresh = tmp_path / "FLCU.a2l"
    update_file(merged, demo.elf(), fresh, mode=UpdateMode.STRICT, use_cache=False)
    assert fresh.read_bytes() == demo.a2l().read_bytes(), f"assets/FLCU.a2l is stale; regenerate it:\n{REGENERATE}"


@pytest.fixture(scope="module")
def oracle():
    oracle = PyelftoolsOracle(demo.elf())
    yield oracle
    oracle.close()


def test_every_address_is_the_elf_symbols_address(oracle):
    doc = load_a2l(demo.a2l())
    checked = 0
    for keyword, index in (("MEASUREMENT", None), ("CHARACTERISTIC", 3), ("AXIS_PTS", 2)):
        for block in doc.objects(keyword):
            token = block.option("ECU_ADDRESS")[0] if index is None else block.args[index]
            link = block.option("SYMBOL_LINK")
            symbol = doc.text(link[0]) if link else block.name
            offset = doc.int_value(link[1]) if link else 0
            assert doc.int_value(token) == oracle.address(symbol) + offset, f"{keyword} {block.name}"
            checked += 1
    assert checked > 100  # the loop saw the whole demo (85 measurements alone)


def test_epk_matches_the_elf(oracle):
    doc = load_a2l(demo.a2l())
    epk = oracle.elf.get_section_by_name(".epk")
    assert doc.addr_epk() == epk["sh_addr"]
    assert doc.epk().encode() == epk.data().rstrip(b"\0")
    header = oracle.elf.get_section_by_name(".app_header")  # AppHeader.Epk: the application's own EPK
    first, second = (place.address for place in doc.epk_addresses())
    assert first == epk["sh_addr"] and header["sh_addr"] <= second < header["sh_addr"] + header["sh_size"]
    offset = second - header["sh_addr"]
    assert header.data()[offset:offset + len(doc.epk()) + 1] == doc.epk().encode() + b"\0"


def test_pya2ldb_imports_it_without_errors():
    counts = pya2l_import(demo.a2l())
    assert (counts["MEASUREMENT"], counts["CHARACTERISTIC"], counts["AXIS_PTS"]) == (
        len(load_a2l(demo.a2l()).objects("MEASUREMENT")), len(load_a2l(demo.a2l()).objects("CHARACTERISTIC")), 2)
