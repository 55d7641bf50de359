"""insert: MEASUREMENTs and CHARACTERISTICs from an ELF's variables, as a2ltool makes them (its option names).

The objects are compared field by field with what the installed a2ltool inserts for the same patterns;
the result must pass ``check --elf`` and pya2ldb; the input's text stays as it was (only additions).
"""

import difflib
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from pya2l_oracle import pya2l_import

from workbench.a2l import load_a2l, load_a2l_string
from workbench.a2l.check import check_file
from workbench.a2l.insert import Selection, insert_document, insert_file
from workbench.cli import main
from workbench.elf.debugdata import DebugData
from workbench.errors import InputError

A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")
ELF_DIR = Path(__file__).parents[1] / "elf"
TYPES_ELF = ELF_DIR / "fixtures" / "types_dwarf5.elf"
WILD_ELF = ELF_DIR / "matrix" / "c-gcc-dwarf5-m64-O0.elf"  # function statics, names two variables share
EMPTY = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n    /begin MOD_COMMON "" BYTE_ORDER MSB_LAST '
         '/end MOD_COMMON\n  /end MODULE\n/end PROJECT\n')
# disjoint: a variable that is both kinds is an overlap check reports (as are the members of a union: u)
MEASURED = r"outer\..*|bits\..*|node\..*|state|zsScalar|matrix|big|EPK|hidden_counter"
CALIBRATED = r"csConstant|vector|zvLut\..*|expected_size"
KEYWORDS = {"EPK"}
FIELDS = ("datatype", "conversion", "lower_limit", "upper_limit", "address", "matrix_dim", "bit_mask", "type",
          "symbol_link", "long_identifier")


def _insert(tmp_path: Path, elf: Path, measured: str, calibrated: str, text: str = EMPTY) -> tuple[Path, object]:
    source = tmp_path / "in.a2l"
    source.write_text(text)
    out = tmp_path / "ours.a2l"
    report = insert_file(source, elf, out, measurements=Selection((measured,)),
                         characteristics=Selection((calibrated,)), use_cache=False)
    return out, report


@pytest.fixture(scope="module")
def inserted(tmp_path_factory) -> tuple[Path, object]:
    return _insert(tmp_path_factory.mktemp("insert"), TYPES_ELF, MEASURED, CALIBRATED)


def _a2ltool(tmp_path: Path, elf: Path, *options: str) -> Path:
    source, out = tmp_path / "in.a2l", tmp_path / "theirs.a2l"
    source.write_text(EMPTY)
    subprocess.run([A2LTOOL, str(source), "--elffile", str(elf), *options, "--output", str(out)], check=True,
                   capture_output=True)
    return out


def _fields(model, name: str) -> dict:
    obj = model.object(name)
    found = {field: getattr(obj, field, None) for field in FIELDS}
    if obj.kind == "CHARACTERISTIC":
        layout = model.record_layout_of(obj)
        found["layout"] = [(entry.keyword, entry.datatype, entry.mode, entry.addressing) for entry in layout.entries]
    if obj.conversion != "NO_COMPU_METHOD":
        found["values"] = model.compu_table(obj.conversion).pairs
    return found


@pytest.mark.skipif(A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
@pytest.mark.parametrize("elf, measured, calibrated", [
    (TYPES_ELF, MEASURED, CALIBRATED),
    (WILD_ELF, ".*", "zzz"),  # function statics; the first of two variables of one name, Vector's SYMBOL_LINK
    (WILD_ELF, "zzz", ".*"),
    # C++: namespaces, static members, base classes' members, an anonymous namespace (gcc's DWARF of a struct
    # another unit defines makes a2ltool 3.4 insert that variable as SWORD: clang's is compared)
    (ELF_DIR / "matrix" / "cpp-clang-dwarf4-m32-O0.elf", "zzz", ".*"),
], ids=["types", "wild-measurements", "wild-characteristics", "cpp"])
def test_the_objects_are_those_a2ltool_inserts(tmp_path, elf, measured, calibrated):
    ours = load_a2l(_insert(tmp_path, elf, measured, calibrated)[0]).model()
    theirs = load_a2l(_a2ltool(tmp_path, elf, "--measurement-regex", measured, "--characteristic-regex",
                               calibrated)).model()
    _same_objects(ours, theirs)


@pytest.mark.skipif(A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
def test_sections_and_ranges_select_as_a2ltools_do(tmp_path):
    source, out = tmp_path / "in.a2l", tmp_path / "ours.a2l"
    source.write_text(EMPTY)
    insert_file(source, TYPES_ELF, out, characteristics=Selection(sections=(".bss",)),
                measurements=Selection(ranges=((0x403000, 0x403010), (0x402000, 0x402080))), use_cache=False)
    theirs = _a2ltool(tmp_path, TYPES_ELF, "--characteristic-section", ".bss", "--measurement-range", "0x403000",
                      "0x403010", "--measurement-range", "0x402000", "0x402080")
    _same_objects(load_a2l(out).model(), load_a2l(theirs).model())


def _same_objects(ours, theirs) -> None:
    for kind in ("MEASUREMENT", "CHARACTERISTIC"):
        # a variable named as an ASAP2 keyword (EPK), which pya2ldb refuses as a name, is a2ltool's KIND.EPK
        names = {f"{kind}.{name}" if name in KEYWORDS else name: name for name in theirs.names(kind)}
        assert sorted(ours.names(kind)) == sorted(names)
        for name, their_name in names.items():
            assert _fields(ours, name) == _fields(theirs, their_name), name
    assert len(ours.names()) > 20


def test_the_objects_have_their_c_types(inserted):
    model = load_a2l(inserted[0]).model()
    bits = model.measurement("bits.mid")
    assert (bits.datatype, bits.bit_mask, bits.lower_limit, bits.upper_limit) == ("ULONG", 0xF8, 0, 31)
    assert model.measurement("matrix").matrix_dim == (5, 6)
    assert model.measurement("outer.arr[2].d").address == DebugData(TYPES_ELF, use_cache=False).resolve(
        "outer.arr[2].d").address
    state = model.measurement("state")
    assert (state.conversion, model.compu_table("tState").pairs) == ("tState", ((0, "OFF"), (1, "ON"),
                                                                                 (200, "BROKEN")))
    table = model.characteristic("zvLut.Table")
    assert (table.type, table.matrix_dim, table.record_layout) == ("VAL_BLK", (9,), "__FLOAT32_IEEE_Z")
    assert model.characteristic("csConstant").record_layout == "__UBYTE_Z"
    assert "node.next" not in model  # a pointer is no value
    assert [f.name for f in inserted[1].problems] == []


def test_the_result_passes_check_and_pya2ldb(inserted):
    assert check_file(inserted[0], TYPES_ELF, use_cache=False).problems == []
    counts = pya2l_import(inserted[0])
    assert (counts["MEASUREMENT"], counts["CHARACTERISTIC"]) == (len(inserted[1].inserted["MEASUREMENT"]),
                                                                 len(inserted[1].inserted["CHARACTERISTIC"]))


FILE = (
    "/* kept as it is */\r\nASAP2_VERSION 1 61\r\n/begin PROJECT P \"\"\r\n\t/begin MODULE M \"\"\r\n"
    "\t\t/begin RECORD_LAYOUT RL_U16 FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\r\n"
    "\t\t/begin MEASUREMENT zsScalar \"mine\" FLOAT32_IEEE NO_COMPU_METHOD 0 0 0 10\r\n"
    "\t\t\tECU_ADDRESS 0x403000\r\n\t\t/end MEASUREMENT\r\n"
    "\t\t/begin CHARACTERISTIC MyAxis \"the same variable, another name\" VAL_BLK 0x403140 RL_U16 0 "
    "NO_COMPU_METHOD 0 1000\r\n\t\t\tMATRIX_DIM 10 1 1\r\n\t\t\tSYMBOL_LINK \"vector\" 0\r\n\t\t/end CHARACTERISTIC\r\n"
    "\t\t/begin GROUP Calib \"\"\r\n\t\t\t/begin REF_CHARACTERISTIC MyAxis\r\n\t\t\t/end REF_CHARACTERISTIC\r\n"
    "\t\t/end GROUP\r\n\t/end MODULE\r\n/end PROJECT\r\n")


def test_only_additions_in_the_files_style_and_nothing_twice(tmp_path):
    source, out = tmp_path / "in.a2l", tmp_path / "out.a2l"
    source.write_bytes(FILE.encode())
    args = ["a2l", "insert", str(source), str(TYPES_ELF), "-o", str(out), "--measurement-regex", "zsScalar|outer.*",
            "--characteristic-regex", "vector|csConstant", "--characteristic-range", "0x403010", "0x403018",
            "--target-group", "Calib", "--no-cache", "--json"]
    assert main(args) == 0
    data = out.read_bytes()
    assert b"\n" not in data.replace(b"\r\n", b"")  # the file's newlines
    removed = [line for line in difflib.ndiff(FILE.splitlines(), data.decode().splitlines()) if line[:1] in "-?"]
    assert removed == []
    doc = load_a2l(out)
    model = doc.model()
    assert model.measurement("zsScalar").long_identifier == "mine"  # left alone
    assert "CHARACTERISTIC.vector" not in model and "vector" not in model  # described by MyAxis already
    # before 1.70: element names ._2_, MATRIX_DIM of three
    assert model.measurement("outer.arr._2_.d").matrix_dim == (3, 1, 1)
    assert model.characteristic("csConstant").record_layout == "__UBYTE_Z"
    group = model.group("Calib")
    assert group.ref_characteristics == ("MyAxis", "csConstant")
    assert "outer.arr._3_.c" in group.ref_measurements and "zsScalar" not in group.ref_measurements
    assert b"\t\t/begin MEASUREMENT outer.a " in data  # the MODULE's indentation
    # a second run finds everything there
    assert main(["a2l", "insert", str(out), *args[3:]]) == 0  # in place
    assert out.read_bytes() == data


def test_a_module_on_one_line_and_a_layout_to_reuse():
    doc = load_a2l_string('ASAP2_VERSION 1 71 /begin PROJECT P "" /begin MODULE M "" /begin RECORD_LAYOUT '
                          "Same FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT /end MODULE /end PROJECT")
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        result = insert_document(doc, debug, characteristics=Selection(paths=("csConstant", "bits")))
    model = load_a2l_string(result.data.decode()).model()
    assert model.characteristic("csConstant").record_layout == "Same"
    assert model.characteristic("bits.high").bit_mask == 0xFFF00
    assert sorted(result.report.inserted["CHARACTERISTIC"]) == ["bits.after", "bits.high", "bits.low", "bits.mid",
                                                               "csConstant"]


def test_a_path_named_with_a_typo_gets_the_closest_name():
    doc = load_a2l_string(EMPTY)
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        report = insert_document(doc, debug, measurements=Selection(paths=("zsScalr",))).report
    assert [f.message for f in report.of_kind("symbol-not-found")] == [
        f"MEASUREMENT zsScalr: not in {TYPES_ELF.name}; did you mean 'zsScalar'?"]


def test_old_arrays_names_elements_as_before_asap2_1_70(tmp_path, capsys):
    """a2ltool's --old-arrays in a 1.71 file: ``outer.arr._2_.d`` and MATRIX_DIM with three numbers."""
    source, out = tmp_path / "in.a2l", tmp_path / "out.a2l"
    source.write_text(EMPTY)
    assert main(["a2l", "insert", str(source), str(TYPES_ELF), "-o", str(out), "--old-arrays", "--no-cache",
                 "--measurement-regex", r"outer\.arr.*"]) == 0
    model = load_a2l(out).model()
    assert "outer.arr._2_.d" in model.names("MEASUREMENT") and "outer.arr[2].d" not in model.names("MEASUREMENT")
    assert re.search(r"MATRIX_DIM 3 1 1\b", out.read_text())
    assert check_file(out, TYPES_ELF).ok


def test_new_blocks_take_the_indentation_most_blocks_of_the_module_have():
    """The demo's merged A2L starts its MODULE with XCP.aml's A2ML, inlined at column 0; its blocks are at 4."""
    blocks = "".join(f'    /begin MEASUREMENT m{n} "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x0 '
                     '/end MEASUREMENT\n'
                     for n in range(3))
    text = (f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n/begin A2ML\nblock "IF_DATA" int;\n'
            f'/end A2ML\n{blocks}  /end MODULE\n/end PROJECT\n')
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        result = insert_document(load_a2l_string(text), debug, measurements=Selection(paths=("zsScalar",)))
    assert "\n    /begin MEASUREMENT zsScalar " in result.data.decode()  # was at column 0, as the A2ML


def test_errors_for_people(tmp_path, capsys):
    source = tmp_path / "in.a2l"
    source.write_text(EMPTY)
    out = tmp_path / "out.a2l"
    base = ["a2l", "insert", str(source), str(TYPES_ELF), "-o", str(out), "--no-cache"]
    assert main([*base, "--measurement-regex", "zs("]) == 2
    assert "--measurement-regex" in capsys.readouterr().err
    assert main([*base, "--characteristic-range", "0x500", "0x400"]) == 2
    assert "--characteristic-range 0x500 0x400" in capsys.readouterr().err
    assert main([*base, "--target-group", "no group"]) == 2
    assert main(base[:4] + ["--measurement-regex", "zsScalar"]) == 2  # no -o, no --dry-run
    assert main(["a2l", "insert", str(source), str(ELF_DIR / "fixtures" / "types_symtab.elf"), "-o", str(out),
                 "--measurement-regex", ".*", "--no-cache"]) == 2
    assert "DWARF" in capsys.readouterr().err
    assert not out.exists()
    assert main([*base, "--measurement-regex", "nothing_like_this", "--measurement", "zsScalar", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["inserted"]["MEASUREMENT"] == ["zsScalar"]
    assert [f["message"] for f in report["findings"] if f["severity"] == "warning"] == [
        "--measurement-regex 'nothing_like_this' matches no variable of types_dwarf5.elf"]
    assert main([*base[:4], "--dry-run", "--measurement-regex", "outer.*"]) == 0
    assert "would insert 12 MEASUREMENT" in capsys.readouterr().err
    with pytest.raises(InputError, match="measurement-regex"):
        insert_file(source, TYPES_ELF, None, measurements=Selection(("[",)), use_cache=False)


@pytest.mark.parametrize("pattern, names", [
    (r"outer\.arr\[2\]\..*", ["outer.arr[2].c", "outer.arr[2].d"]),  # the walk skips what the pattern cannot name
    (r"vector\[[3-4]\]|zv.*\.BP1", ["vector[3]", "vector[4]", "zvLut.BP1"]),  # elements of an array not selected whole
    ("(?i)ZSSCALAR|HIDDEN_counter", ["zsScalar", "hidden_counter"]),  # global flags stay in front
    ("^zs", ["zsScalar"]),  # with ^ or $: searched as written (a2ltool's rule)
    ("b.*s", ["bits"]),  # a struct it names brings its members: not bits.after (its own name does not match)
])
def test_patterns_select_whole_names(pattern, names):
    doc = load_a2l_string(EMPTY)
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        result = insert_document(doc, debug, measurements=Selection((pattern,)))
    expected = ["bits.low", "bits.mid", "bits.high", "bits.after"] if names == ["bits"] else names
    assert sorted(result.report.inserted["MEASUREMENT"]) == sorted(expected)


@pytest.mark.parametrize("version, pattern, name", [("1 71", r"outer\.arr\[2\]\.d", "outer.arr[2].d"),
                                                    ("1 61", r"outer\.arr\._2_\.d", "outer.arr._2_.d")])
def test_a_pattern_names_an_element_in_either_naming(version, pattern, name):
    """The variables none of whose paths a pattern matches are left out before the walk: the paths it tries
    are named as the file's version names elements."""
    doc = load_a2l_string(EMPTY.replace("ASAP2_VERSION 1 71", f"ASAP2_VERSION {version}"))
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        result = insert_document(doc, debug, measurements=Selection((pattern,)))
    assert result.report.inserted["MEASUREMENT"] == [name]


@pytest.mark.parametrize("elf", [TYPES_ELF, WILD_ELF, ELF_DIR / "matrix" / "cpp-gcc-dwarf5-m64-O0.elf"],
                         ids=["types", "wild", "cpp"])
def test_the_variables_left_out_before_the_walk_are_those_it_would_leave(elf, monkeypatch):
    """The variables none of whose paths a pattern matches, and of which no range holds a byte, are left out
    before the walk (by their names, the text each match of a pattern holds, the name alone for a pattern that
    cannot match past it, the bounds of their addresses): the same objects come out as when every one is walked."""
    from workbench.a2l import insert

    patterns = [".*", r"outer\..*|bits", "^z", "(?i)ZS.*|b.*s", r"vector\[[3-4]\]|zv.*\.BP1", r"\w+_\w+", "[a-m]",
                r"^\w*(?!\.)", r"s[^.]*", "(big|EPK)", ".*ow.*", "[a-z]+e.*"]  # "ow": in bits.low's member name
    doc = load_a2l_string(EMPTY)
    with DebugData(elf, use_cache=False) as debug:
        variables = [variable for variable in debug.variables() if variable.address]
        addresses = sorted({variable.address for variable in variables})
        ranges = ((addresses[1] + 1, addresses[4] + 2), (addresses[-2] - 1, addresses[-2]))  # parts of variables
        firsts: dict = {}
        seconds = [variable for variable in variables if firsts.setdefault(variable.name, variable) is not variable]
        ranges += tuple((variable.address, variable.address + 1) for variable in seconds[:1])
        selections = [(Selection((pattern,)), Selection()) for pattern in patterns] + [
            (Selection(), Selection(ranges=ranges)), (Selection(("z.*",)), Selection(ranges=ranges[:1]))]
        chosen = [insert_document(doc, debug, measurements=measured, characteristics=calibrated)
                  for measured, calibrated in selections]
        monkeypatch.setattr(insert._Names, "may_name_any", lambda self, variables: variables)
        monkeypatch.setattr(insert._Names, "match_one", lambda self, variable, suffixes: True)
        for (measured, calibrated), result in zip(selections, chosen):
            walked = insert_document(doc, debug, measurements=measured, characteristics=calibrated)
            assert result.data == walked.data, (measured, calibrated)
            assert result.report.inserted == walked.report.inserted, (measured, calibrated)
            assert result.report.findings == walked.report.findings, (measured, calibrated)


def test_every_variable_of_the_demo_that_its_a2l_lacks(tmp_path):
    """The demo's A2L describes most variables (calibrations as CHARACTERISTICs): those are left alone, the rest
    come in, and the file stays clean against its ELF."""
    from workbench import demo

    out = tmp_path / "FLCU.a2l"
    report = insert_file(demo.a2l(), demo.elf(), out, measurements=Selection((".*",)), use_cache=False)
    assert report.problems == []
    before = load_a2l(demo.a2l()).model()
    inserted = report.inserted["MEASUREMENT"]
    assert inserted and not any(name in before for name in inserted)
    assert "zsEWMA_ALPHA" in before and "MEASUREMENT.zsEWMA_ALPHA" not in inserted  # a CHARACTERISTIC already
    assert check_file(out, demo.elf(), use_cache=False).problems == []


def test_a_file_of_several_modules_needs_module():
    doc = load_a2l_string(EMPTY.replace("/end PROJECT", '/begin MODULE N "" /end MODULE /end PROJECT'))
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        with pytest.raises(InputError, match="--module"):
            insert_document(doc, debug, measurements=Selection(("zsScalar",)))
        result = insert_document(doc, debug, measurements=Selection(("zsScalar",)), module="N")
    assert load_a2l_string(result.data.decode()).model("N").measurement("zsScalar").address == 0x403000


def test_a_member_of_a_variable_an_object_describes_is_not_described_again():
    described = ('/begin RECORD_LAYOUT RL FNC_VALUES 1 FLOAT32_IEEE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                 '/begin AXIS_PTS Axis "" 0x403020 NO_INPUT_QUANTITY RL 0 NO_COMPU_METHOD 9 0 1\n'
                 '  SYMBOL_LINK "zvLut.BP1" 0 /end AXIS_PTS\n'
                 '/begin MEASUREMENT Outer "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x403080\n'
                 '  SYMBOL_LINK "outer" 0 /end MEASUREMENT\n')
    doc = load_a2l_string(EMPTY.replace("  /end MODULE", described + "  /end MODULE"))
    with DebugData(TYPES_ELF, use_cache=False) as debug:
        result = insert_document(doc, debug, characteristics=Selection(("zvLut.*",)),
                                 measurements=Selection((r"outer\.b\..*|zvLut.*",)))
    assert result.report.inserted == {"MEASUREMENT": ["zvLut.BP1", "zvLut.Table"],
                                      "CHARACTERISTIC": ["CHARACTERISTIC.zvLut.Table"],  # both kinds: a2ltool's name
                                      "INSTANCE": []}
    assert {f.message for f in result.report.of_kind("already-described")} == {
        "CHARACTERISTIC zvLut.BP1: AXIS_PTS Axis describes zvLut.BP1 already: not inserted",
        "MEASUREMENT outer.b.c: it lies in outer, which MEASUREMENT Outer describes: not inserted",
        "MEASUREMENT outer.b.d: it lies in outer, which MEASUREMENT Outer describes: not inserted"}
    assert {(f.name, f.line, f.column) for f in result.report.of_kind("already-described")} == {
        ("zvLut.BP1", 6, 17), ("outer.b.c", 8, 20), ("outer.b.d", 8, 20)}  # at the describing object's name
