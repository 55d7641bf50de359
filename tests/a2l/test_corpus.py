"""Third-party A2L files (tests/corpus/a2l, see its README): what the tool must say about each one.

Every file is checked through the CLI (the findings it must report, no more), loaded and diffed
against itself, merged as a fragment, checked again as UTF-8 with a BOM and as latin-1 with
umlauts; the files whose C source is here are updated against an ELF built from it with gcc, and
the addresses compared with a2ltool's and the ELF's symbol table.
"""

import codecs
import json
import shutil
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest
from cli_helpers import run
from elftools.elf.elffile import ELFFile

from workbench import demo
from workbench.a2l import load_a2l
from workbench.a2l.merge import load_fragment

CORPUS = Path(__file__).parents[1] / "corpus" / "a2l"
A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")
GCC = shutil.which("gcc")

_R = "undefined-reference"
_P = "placeholder-address"  # a file whose every object is at 0: not updated from its ELF
_N = "not-supported"  # an info: what the workbench leaves out (a pointer), no failed check
_B = "component-beyond-structure"


def _pointers(file: str, first: int, struct_b: int) -> list[tuple]:
    """The INSTANCEs reached through a pointer in a2ltool's update_typedef_test files (lines of each file)."""
    return [(_N, name, file, first + line) for name, line in (
        ("TEST_structarr_ptr", 0), ("TEST_structarr_ptr_arr", 7), ("TEST_structptr", 13), ("TEST_structptr_arr", 19),
        ("TEST_structptr_arr_ptr", 25), ("TEST_structptr_ptr", 32))] + [(_N, "struct_b", file, struct_b),
                                                                         (_N, "struct_b", file, struct_b + 6)]


# file -> the check findings as (kind, name, file the finding is in, line); a Counter where there are many
CHECK = {
    "a2ltool/check_test.a2l": [(_P, "Curve_ExternalAxis", "check_test.a2l", 6),
                               (_R, "Curve_ExternalAxis_RecordLayout", "check_test.a2l", 6),
                               (_R, "float_Compu", "check_test.a2l", 6), (_R, "uint32_Compu", "check_test.a2l", 8),
                               (_R, "Axis_0", "check_test.a2l", 9)],
    "a2ltool/cleanup_test.a2l": [],
    "a2ltool/from_source.a2l": Counter({(_P, "parameter_instance[0].Fork.x"): 1, (_R, "__UBYTE_Z"): 16, (_R, "__FLOAT32_IEEE_Z"): 8, (_R, "__SBYTE_Z"): 4,
                                        (_R, "AxisLayout"): 4, (_R, "CurveLayout"): 4}),
    "a2ltool/from_source_structs.a2l": [(_R, "__UBYTE_Z", "from_source_structs.a2l", 18),
                                        (_R, "__FLOAT32_IEEE_Z", "from_source_structs.a2l", 23),
                                        (_R, "AxisLayout", "from_source_structs.a2l", 118),
                                        (_R, "CurveLayout", "from_source_structs.a2l", 122),
                                        (_R, "__UBYTE_Z", "from_source_structs.a2l", 138),
                                        (_R, "__SBYTE_Z", "from_source_structs.a2l", 151),
                                        (_P, "parameter_instance", "from_source_structs.a2l", 156)],  # made from C
    "a2ltool/included.a2l": [(_P, "Measurement_Value", "included.a2l", 3)],
    "a2ltool/merge_inc_test.a2l": [(_P, "Measurement_Value", "included.a2l", 3)],
    "a2ltool/remove_test.a2l": [(_R, "UpdateTest_Map_InternalAxis", "remove_test.a2l", 31)],
    "a2ltool/update_test1.a2l": [(_P, "Curve_ExternalAxis", "update_test1.a2l", 26)],
    "a2ltool/update_test2.a2l": [(_P, "Curve_ExternalAxis_Bad_Recordlayout", "update_test2.a2l", 21),
                                 (_R, "Curve_ExternalAxis_RecordLayout_Nonxistent", "update_test2.a2l", 21),
                                 (_R, "Axis_0", "update_test2.a2l", 24), (_R, "Axis_1", "update_test2.a2l", 47),
                                 (_R, "UpdateTest_Map_InternalAxis_x", "update_test2.a2l", 229)],
    # StructB's s3 lies at its size, 0x38 (the C struct's function pointer: a2ltool's update moves it)
    "a2ltool/update_typedef_test1.a2l": [*_pointers("update_typedef_test1.a2l", 33, 196),
                                         (_B, "StructB", "update_typedef_test1.a2l", 220)],
    "a2ltool/update_typedef_test2.a2l": [*_pointers("update_typedef_test2.a2l", 33, 201),
                                         (_B, "StructB", "update_typedef_test2.a2l", 225)],
    "a2ltool/update_typedef_test3.a2l": [*_pointers("update_typedef_test3.a2l", 98, 261),
                                         (_B, "StructB", "update_typedef_test3.a2l", 285),
                                         (_R, "__ULong_Value", "update_typedef_test3.a2l", 309),
                                         (_R, "AccessType", "update_typedef_test3.a2l", 309)],
    "a2ltool/update_typedef_test4.a2l": _pointers("update_typedef_test4.a2l", 98, 261),
    "xcplite/hello_xcp.a2l": [],
    "xcplite/c_demo.a2l": [],
    "xcplite/cpp_demo.a2l": [("duplicate-name", "C_delay_us", "cpp_demo.a2l", 108),
                             ("duplicate-name", "SigGen1", "cpp_demo.a2l", 114),
                             ("duplicate-name", "SigGen2", "cpp_demo.a2l", 115)],
    "xcplite/struct_demo.a2l": [("duplicate-name", "M_byte_field", "struct_demo.a2l", 97),
                                ("duplicate-name", "M_word_field", "struct_demo.a2l", 98)],
    "xcplite/no_a2l_demo.A2L": [(_R, "params", "no_a2l_demo.A2L", 257)],
    "domohuhn-a2l/simple.a2l": [],
    "domohuhn-a2l/example-ecu.a2l": [],
    "domohuhn-a2l/lights_ecu.a2l": [],
    "domohuhn-a2l/engine_ecu.a2l": [
        (_R, "stdlay", "engine_ecu.a2l", 16),
        ("epk-without-address", "EPK", "engine_ecu.a2l", 26),  # EPK "sda", no ADDR_EPK
        *(("outside-memory", name, "engine_ecu.a2l", line) for name, line in (
            ("CHAR_INT64", 149), ("CHAR_UINT64", 154), ("CHAR_FLOAT", 159), ("CHAR_INT32", 164), ("CHAR_UINT32", 169),
            ("CHAR_INT16", 174), ("CHAR_UINT16", 179), ("CHAR_INT8", 184), ("CHAR_UINT8", 189), ("CHAR_BOOL", 194),
            ("MEAS_ONE", 206))),
        (_R, "U.Other", "engine_ecu.a2l", 222), (_R, "Measure1", "engine_ecu.a2l", 279),
        (_R, "measure2", "engine_ecu.a2l", 279), (_R, "codeMeasure", "engine_ecu.a2l", 297),
        (_R, "codeChar", "engine_ecu.a2l", 298), (_R, "codeMeasure2", "engine_ecu.a2l", 304),
        (_R, "codeChar2", "engine_ecu.a2l", 305)],
}
CHECK["domohuhn-a2l/xcp-sim.a2l"] = CHECK["domohuhn-a2l/engine_ecu.a2l"]  # it includes engine_ecu and lights_ecu
# written for /include: a bare fragment, or MODULE blocks without a PROJECT
INCLUDED = {"a2ltool/included.a2l", "domohuhn-a2l/engine_ecu.a2l", "domohuhn-a2l/lights_ecu.a2l"}
# merging the file as a fragment: definitions that differ within the file itself
MERGE_CONFLICTS = {"xcplite/cpp_demo.a2l": {"C_delay_us", "SigGen1", "SigGen2"}}
NOT_MERGED = {"domohuhn-a2l/xcp-sim.a2l"}  # two MODULEs, neither named like the master's: an error
# a2ltool's files and the C source they describe: the objects update must not find
UPDATES = {
    "a2ltool/update_test1.a2l": ("update_test.c", set()),
    "a2ltool/update_test2.a2l": ("update_test.c", {"Characteristic_Value_nonexistant", "Axis_3_nonexistant",
                                                   "Blob_nonexistant", "Measurement_nonexistant",
                                                   "INSTANCE_nonexistant"}),
    **{f"a2ltool/update_typedef_test{n}.a2l": ("update_typedef_test.c", set()) for n in range(1, 5)},
}
MASTER = 'ASAP2_VERSION 1 71\n/begin PROJECT MASTER ""\n  /begin MODULE MASTER ""\n  /end MODULE\n/end PROJECT\n'
WHOLE_FILES = sorted(set(CHECK) - INCLUDED)


@pytest.fixture(scope="module")
def corpus(tmp_path_factory) -> Path:
    """A copy of the corpus, with the demo's XCP.aml as the XCP_104.aml the XCPlite files include."""
    root = tmp_path_factory.mktemp("corpus") / "a2l"
    shutil.copytree(CORPUS, root)
    shutil.copy(demo.master_a2l().parent / "XCP.aml", root / "xcplite" / "XCP_104.aml")
    return root



def check_findings(capsys, path: Path):
    code, out, _ = run(capsys, "a2l", "check", path, "--json")
    report = json.loads(out)
    assert report["ok"] is (code == 0)
    return code, [(f["kind"], f["name"], Path(f["file"]).name, f["line"], f["column"]) for f in report["findings"]]


def test_every_corpus_file_has_its_expectation():
    files = {str(path.relative_to(CORPUS)) for path in CORPUS.rglob("*") if path.suffix.lower() == ".a2l"}
    assert files == set(CHECK)


@pytest.mark.parametrize("name", sorted(CHECK))
def test_check_says_what_the_file_holds(capsys, corpus, name):
    code, findings = check_findings(capsys, corpus / name)
    expected = CHECK[name]
    if isinstance(expected, Counter):
        assert Counter((kind, finding) for kind, finding, *_ in findings) == expected
    else:
        assert [finding[:4] for finding in findings] == expected
    assert code == (1 if any(finding[0] != _N for finding in expected) else 0)


@pytest.mark.parametrize("name", WHOLE_FILES)
def test_loads_validated_and_diffs_empty_against_itself(capsys, corpus, name):
    doc = load_a2l(corpus / name)
    assert doc.modules
    code, out, _ = run(capsys, "a2l", "diff", corpus / name, corpus / name, "--json")
    assert (code, json.loads(out)["differences"]) == (0, [])


@pytest.mark.parametrize("name", sorted(set(CHECK) - NOT_MERGED))
def test_merges_as_a_fragment(capsys, corpus, tmp_path, name):
    master, out = tmp_path / "master.a2l", tmp_path / "merged.a2l"
    master.write_text(MASTER)
    code, stdout, _ = run(capsys, "a2l", "merge", master, corpus / name, "-o", out)
    conflicts = MERGE_CONFLICTS.get(name, set())
    if conflicts:
        assert code == 1 and not out.exists()
        assert {line.split(": ")[2].split()[1] for line in stdout.splitlines()} == conflicts
        code, _, _ = run(capsys, "a2l", "merge", master, corpus / name, "-o", out, "--on-conflict", "keep-first")
    assert code == 0
    merged = load_a2l(out).module()
    fragment = load_fragment(corpus / name)
    modules = [block for block in fragment.top_blocks() if block.keyword == "MODULE"] if name in INCLUDED else \
        fragment.modules
    owned = [child for module in modules for child in module.children] or fragment.top_blocks()
    expected = {(b.keyword, b.name) for b in owned if b.keyword not in ("MOD_PAR", "MOD_COMMON", "IF_DATA", "A2ML")}
    assert {(b.keyword, b.name) for b in merged.children} == expected


@pytest.mark.parametrize("name", WHOLE_FILES)
@pytest.mark.parametrize("encoding, bom", [("utf-8", codecs.BOM_UTF8), ("latin-1", b"")], ids=["utf8-bom", "latin1"])
def test_the_same_findings_in_another_encoding(capsys, corpus, name, encoding, bom):
    original = corpus / name
    variant = original.with_name(f"{encoding}_{original.name}")
    text = original.read_text(encoding="utf-8")
    variant.write_bytes(bom + (text + "/* Prüfstand: Größe in °C, Öl */\n").encode(encoding))
    expected_code, expected = check_findings(capsys, original)
    located_in_the_variant = [(kind, finding, variant.name if file == original.name else file, line, column)
                              for kind, finding, file, line, column in expected]
    assert check_findings(capsys, variant) == (expected_code, located_in_the_variant)
    assert load_a2l(variant, validate=False).encoding == encoding


@pytest.fixture(scope="module")
def elves(tmp_path_factory) -> dict[str, Path]:
    """The ELFs of the C sources in the corpus, built with the host's gcc (-g -O0, not linked to a libc)."""
    if GCC is None:
        pytest.skip("gcc is not installed")
    folder = tmp_path_factory.mktemp("elf")
    built = {}
    for source in sorted({source for source, _ in UPDATES.values()}):
        elf = folder / source.replace(".c", ".elf")
        subprocess.run([GCC, "-g", "-O0", "-nostdlib", "-static", "-Wl,-e,0", "-o", elf, CORPUS / "a2ltool" / source],
                       check=True, capture_output=True, timeout=120)
        built[source] = elf
    return built


@pytest.mark.parametrize("name", sorted(UPDATES))
def test_update_against_the_elf_of_its_source(capsys, corpus, elves, tmp_path, name):
    source, missing = UPDATES[name]
    out = tmp_path / "updated.a2l"
    code, stdout, _ = run(capsys, "a2l", "update", corpus / name, elves[source], "-o", out, "--no-cache", "--json")
    report = json.loads(stdout)
    assert code == 0 and report["ok"]
    assert {f["name"] for f in report["findings"] if f["kind"] == "symbol-not-found"} == missing
    assert sum(tally.get("updated", 0) for tally in report["tally"].values()) > 0
    doc = load_a2l(out)
    with open(elves[source], "rb") as handle:  # plain variables: the address is the symbol's in .symtab
        symbols = {symbol.name: symbol["st_value"] for symbol in ELFFile(handle).get_section_by_name(".symtab").iter_symbols()}
    for block in doc.objects("MEASUREMENT"):
        address = block.option("ECU_ADDRESS")
        if block.name in symbols and block.option("SYMBOL_LINK") is None:
            assert doc.int_value(address[0]) == symbols[block.name], block.name
    if A2LTOOL is not None:  # a2ltool's addresses are ours (it also resets the type fields of CANape's LINK_MAP)
        theirs = tmp_path / "a2ltool.a2l"
        subprocess.run([A2LTOOL, corpus / name, "--elffile", elves[source], "--update", "ADDRESSES", "--output",
                        theirs], check=True, capture_output=True, timeout=120)
        code, stdout, _ = run(capsys, "a2l", "diff", out, theirs, "--json")
        changes = [(d["name"], c["field"]) for d in json.loads(stdout)["differences"] if d["status"] == "changed"
                   for c in d["changes"] if "CANAPE_EXT" not in c["field"]]
        removed = {d["name"] for d in json.loads(stdout)["differences"] if d["status"] == "removed"}
        assert changes == [] and removed == missing  # a2ltool drops the objects it cannot find


@pytest.mark.skipif(A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
@pytest.mark.parametrize("name", sorted(UPDATES))
def test_types_agree_with_a2ltools_full_update(capsys, corpus, elves, tmp_path, name):
    """`update --types --remove-missing` sets what a2ltool's FULL update sets, block by block (`a2l diff`):
    a CURVE/MAP/AXIS_PTS whose C variable is a struct takes the member at its RECORD_LAYOUT's positions
    (FNC_VALUES: data type, limits; AXIS_PTS_X ...: point counts, FIX_NO_AXIS_PTS), a COM_AXIS the count of
    the AXIS_PTS it names, an enum a COMPU_METHOD TAB_VERB with its COMPU_VTAB, a pointer INSTANCE its
    ADDRESS_TYPE, CANape's LINK_MAP the element type."""
    source, _ = UPDATES[name]
    ours, theirs = tmp_path / "ours.a2l", tmp_path / "theirs.a2l"
    code, _, _ = run(capsys, "a2l", "update", corpus / name, elves[source], "-o", ours, "--types", "--remove-missing",
                     "--no-cache")
    assert code == 0
    subprocess.run([A2LTOOL, corpus / name, "--elffile", elves[source], "--update", "FULL", "--output", theirs],
                   check=True, capture_output=True, timeout=120)
    code, stdout, _ = run(capsys, "a2l", "diff", ours, theirs, "--json")
    assert (code, json.loads(stdout)["differences"]) == (0, [])
    blocks = load_a2l(theirs).blocks
    assert len(blocks) > 30  # what was compared: every named block of the file
