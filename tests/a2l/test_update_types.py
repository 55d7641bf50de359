"""update --types on every kind of object, through the CLI, against a compiler-built ELF.

The A2L states wrong element types and shapes for objects of tests/elf/matrix/wild.c;
--types corrects what is local to each object (its data type, MATRIX_DIM/NUMBER,
MaxAxisPoints of its axes, the layout it names when an equal one of the right type
exists, a layout only it uses), reports what is not (a shared RECORD_LAYOUT), and never
narrows limits to the range of a data type that was wrong.
"""

import json
from pathlib import Path

import pytest

from workbench.a2l import load_a2l
from workbench.cli import main

ELF = Path(__file__).parents[1] / "elf" / "matrix" / "c-gcc-dwarf5-m64-O0.elf"
A2L = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /begin COMPU_METHOD CM "" IDENTICAL "%8.3" "" /end COMPU_METHOD
    /begin RECORD_LAYOUT RL_U8 FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin RECORD_LAYOUT RL_F32 FNC_VALUES 1 FLOAT32_IEEE ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin RECORD_LAYOUT RL_SHARED_U16 FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin RECORD_LAYOUT RL_MAP_ONLY FNC_VALUES 1 FLOAT32_IEEE COLUMN_DIR DIRECT /end RECORD_LAYOUT
    /begin RECORD_LAYOUT RL_AXIS_U8 AXIS_PTS_X 1 UBYTE INDEX_INCR DIRECT /end RECORD_LAYOUT
    /begin RECORD_LAYOUT RL_AXIS_F32 AXIS_PTS_X 1 FLOAT32_IEEE INDEX_INCR DIRECT /end RECORD_LAYOUT

    /begin MEASUREMENT ctrlReg.Value "uint32_t stated as UBYTE" UBYTE CM 1 0 0 100000
      ECU_ADDRESS 0x0
    /end MEASUREMENT
    /begin MEASUREMENT variant.high "uint16_t, limits beyond its range" UWORD CM 1 0 -5 1e6
      ECU_ADDRESS 0x0
    /end MEASUREMENT
    /begin MEASUREMENT signedMatrix "int8_t[2][3][4] with a wrong MATRIX_DIM" SBYTE CM 1 0 -128 127
      ECU_ADDRESS 0x0
      MATRIX_DIM 2 12
    /end MEASUREMENT
    /begin MEASUREMENT wild_tick.history "uint8_t[4] without MATRIX_DIM" UBYTE CM 1 0 0 255
      ECU_ADDRESS 0x0
    /end MEASUREMENT

    /begin CHARACTERISTIC gain "float with a UBYTE layout: RL_F32 is the same but for the type" VALUE 0x0 RL_U8 0 CM 0 10 /end CHARACTERISTIC
    /begin CHARACTERISTIC valueBlock "uint8_t[3][4] stated 2 x 2" VAL_BLK 0x0 RL_U8 0 CM 0 255
      MATRIX_DIM 2 2
    /end CHARACTERISTIC
    /begin CHARACTERISTIC curveValues "int16_t[6]: shared UWORD layout, wrong point count" CURVE 0x0 RL_SHARED_U16 0 CM -30000 30000
      /begin AXIS_DESCR COM_AXIS NO_INPUT_QUANTITY CM 5 0 50
        AXIS_PTS_REF curveAxis
      /end AXIS_DESCR
    /end CHARACTERISTIC
    /begin CHARACTERISTIC engineMap.values "int16_t[4][8], COLUMN_DIR stated, a layout of its own" MAP 0x0 RL_MAP_ONLY 0 CM -30000 30000
      /begin AXIS_DESCR FIX_AXIS NO_INPUT_QUANTITY CM 8 0 100
        FIX_AXIS_PAR_DIST 0 1 8
      /end AXIS_DESCR
      /begin AXIS_DESCR FIX_AXIS NO_INPUT_QUANTITY CM 8 0 100
        FIX_AXIS_PAR_DIST 0 1 8
      /end AXIS_DESCR
    /end CHARACTERISTIC
    /begin AXIS_PTS curveAxis "float[6] stated as 4 UBYTE points" 0x0 NO_INPUT_QUANTITY RL_AXIS_U8 0 CM 4 0 50 /end AXIS_PTS
    /begin AXIS_PTS sharedAxis "uint16_t[5], the UWORD layout shared with curveValues" 0x0 NO_INPUT_QUANTITY RL_SHARED_U16 0 CM 5 0 400 /end AXIS_PTS
  /end MODULE
/end PROJECT
"""


@pytest.fixture
def updated(tmp_path, capsys):
    source = tmp_path / "in.a2l"
    source.write_text(A2L)
    out = tmp_path / "out.a2l"
    assert main(["a2l", "update", str(source), str(ELF), "-o", str(out), "--types", "--no-cache", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    return load_a2l(out), {(f["name"], f["kind"]): f["message"] for f in report["findings"]}


def _texts(doc, tokens):
    return [doc.text(token) for token in tokens]


def test_measurement_type_dims_and_limits(updated):
    doc, findings = updated
    value, high, matrix, history = doc.objects("MEASUREMENT")
    assert _texts(doc, value.args[2:]) == ["ULONG", "CM", "1", "0", "0", "100000"]  # not narrowed to UBYTE's 255
    assert _texts(doc, high.args[6:]) == ["0", "65535"]  # the C type's range
    assert [doc.int_value(t) for t in matrix.option("MATRIX_DIM")] == [2, 3, 4]
    assert [doc.int_value(t) for t in history.option("MATRIX_DIM")] == [4]
    assert "data type UBYTE -> ULONG" in findings[("ctrlReg.Value", "datatype-updated")]


def test_value_and_value_block(updated):
    doc, findings = updated
    gain, block, _, _ = doc.objects("CHARACTERISTIC")
    assert doc.text(gain.args[4]) == "RL_F32"  # switched to the equal layout of the right type
    assert _texts(doc, gain.args[7:]) == ["0", "10"]
    assert "RECORD_LAYOUT RL_U8 -> RL_F32" in findings[("gain", "record-layout-updated")]
    assert doc.text(block.args[4]) == "RL_U8" and [doc.int_value(t) for t in block.option("MATRIX_DIM")] == [3, 4]


def test_curve_on_a_shared_layout_is_reported_and_its_axis_fixed(updated):
    doc, findings = updated
    curve = doc.objects("CHARACTERISTIC")[2]
    assert doc.text(curve.args[4]) == "RL_SHARED_U16"  # shared with sharedAxis: not edited
    layout = {b.name: b for b in doc.blocks_named("RECORD_LAYOUT")}["RL_SHARED_U16"]
    assert doc.text(layout.option("FNC_VALUES")[1]) == "UWORD"
    assert "2 objects share the layout" in findings[("curveValues", "datatype-mismatch")]
    assert _texts(doc, curve.args[7:]) == ["-30000", "30000"]  # not narrowed to UWORD, which is wrong here
    [axis] = curve.children_named("AXIS_DESCR")
    assert doc.int_value(axis.args[3]) == 6


def test_map_layout_of_its_own_is_corrected_and_its_axes_follow_the_index_mode(updated):
    doc, findings = updated
    values = doc.objects("CHARACTERISTIC")[3]
    layout = {b.name: b for b in doc.blocks_named("RECORD_LAYOUT")}["RL_MAP_ONLY"]
    assert doc.text(layout.option("FNC_VALUES")[1]) == "SWORD"
    assert "no other object uses the layout" in findings[("engineMap.values", "datatype-updated")]
    # int16_t values[4][8] stored COLUMN_DIR: x runs fastest, the inner dimension (as calib.layout reads it)
    assert [doc.int_value(axis.args[3]) for axis in values.children_named("AXIS_DESCR")] == [8, 4]


def test_axis_points_count_and_type(updated):
    doc, findings = updated
    curve_axis, shared_axis = doc.objects("AXIS_PTS")
    assert doc.text(curve_axis.args[4]) == "RL_AXIS_F32" and doc.int_value(curve_axis.args[7]) == 6
    assert doc.text(shared_axis.args[4]) == "RL_SHARED_U16" and ("sharedAxis", "datatype-mismatch") not in findings


def test_the_demo_map_keeps_its_axes(tmp_path):
    """xvPRV_DC_FF is real32_T[5][6] with COLUMN_DIR: X (target, 6 points) runs fastest; --types must agree."""
    from workbench import demo
    from workbench.a2l import update_file

    out = tmp_path / "types.a2l"
    update_file(demo.a2l(), demo.elf(), out, types=True)
    assert out.read_bytes() == demo.a2l().read_bytes()


STRUCTS = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /begin COMPU_METHOD CM "" IDENTICAL "%8.3" "" /end COMPU_METHOD
    /begin RECORD_LAYOUT RL_MAP AXIS_PTS_X 1 UWORD INDEX_INCR DIRECT AXIS_PTS_Y 2 UWORD INDEX_INCR DIRECT
      FNC_VALUES 3 UBYTE ROW_DIR DIRECT FIX_NO_AXIS_PTS_X 5 FIX_NO_AXIS_PTS_Y 5 /end RECORD_LAYOUT
    /begin RECORD_LAYOUT RL_SHARED AXIS_PTS_X 1 UWORD INDEX_INCR DIRECT AXIS_PTS_Y 2 UWORD INDEX_INCR DIRECT
      FNC_VALUES 3 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin CHARACTERISTIC engineMap "tMap {float xAxis[8]; float yAxis[4]; int16_t values[4][8]}" MAP 0x0 RL_MAP 0 CM -40000 40000
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM 5 0 100 /end AXIS_DESCR
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM 5 0 100 /end AXIS_DESCR
    /end CHARACTERISTIC
    /begin CHARACTERISTIC sharedMap "the same struct, a layout shared" MAP 0x0 RL_SHARED 0 CM 0 1
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM 5 0 100 /end AXIS_DESCR
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM 5 0 100 /end AXIS_DESCR
      SYMBOL_LINK "engineMap" 0
    /end CHARACTERISTIC
    /begin CHARACTERISTIC otherMap "" MAP 0x0 RL_SHARED 0 CM 0 1
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM 8 0 100 /end AXIS_DESCR
      /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM 4 0 100 /end AXIS_DESCR
      SYMBOL_LINK "engineMap" 0
    /end CHARACTERISTIC
  /end MODULE
/end PROJECT
"""


def test_a_struct_of_axes_and_values_is_read_member_by_member(tmp_path, capsys):
    """The RECORD_LAYOUT's positions name the struct's members (a2ltool's reading): the axes' point counts
    and the layout's types and FIX_NO_AXIS_PTS counts follow them; a layout other objects share is reported."""
    source, out = tmp_path / "in.a2l", tmp_path / "out.a2l"
    source.write_text(STRUCTS)
    assert main(["a2l", "update", str(source), str(ELF), "-o", str(out), "--types", "--no-cache", "--json"]) == 0
    findings = {(f["name"], f["kind"]): f["message"] for f in json.loads(capsys.readouterr().out)["findings"]}
    doc = load_a2l(out)
    engine, shared, _ = doc.objects("CHARACTERISTIC")
    assert [doc.int_value(axis.args[3]) for axis in engine.children_named("AXIS_DESCR")] == [8, 4]
    assert _texts(doc, engine.args[7:]) == ["-32768", "32767"]  # int16_t values
    layouts = {block.name: doc.model().record_layout(block.name) for block in doc.blocks_named("RECORD_LAYOUT")}
    assert [(e.keyword, e.axis, e.datatype, e.count) for e in layouts["RL_MAP"].entries] == [
        ("AXIS_PTS", "X", "FLOAT32_IEEE", None), ("AXIS_PTS", "Y", "FLOAT32_IEEE", None),
        ("FNC_VALUES", None, "SWORD", None), ("FIX_NO_AXIS_PTS", "X", None, 8), ("FIX_NO_AXIS_PTS", "Y", None, 4)]
    assert "no other object uses the layout" in findings[("engineMap", "datatype-updated")]
    assert [doc.int_value(axis.args[3]) for axis in shared.children_named("AXIS_DESCR")] == [8, 4]
    assert layouts["RL_SHARED"].entries[2].datatype == "UBYTE"  # shared by two objects: not edited
    assert "2 objects share the layout" in findings[("sharedMap", "datatype-mismatch")]


def test_an_enum_becomes_one_verbal_conversion_for_every_object_of_it(tmp_path, capsys):
    """tState is an anonymous enum behind a typedef (OFF 0, ON 1, BROKEN 200): the objects without a conversion
    get COMPU_METHOD tState (TAB_VERB), added once with its COMPU_VTAB; one with a conversion keeps it."""
    elf = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"
    source, out = tmp_path / "in.a2l", tmp_path / "out.a2l"
    source.write_text("""ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /begin COMPU_METHOD CM "" IDENTICAL "%8.3" "" /end COMPU_METHOD
    /begin MEASUREMENT state "enum" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x0 /end MEASUREMENT
    /begin MEASUREMENT stateAgain "the same enum" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x0
      SYMBOL_LINK "state" 0
    /end MEASUREMENT
    /begin MEASUREMENT stateIdentical "the same enum, a conversion of its own" UBYTE CM 1 0 0 255 ECU_ADDRESS 0x0
      SYMBOL_LINK "state" 0
    /end MEASUREMENT
  /end MODULE
/end PROJECT
""")
    assert main(["a2l", "update", str(source), str(elf), "-o", str(out), "--types", "--no-cache", "--json"]) == 0
    findings = [(f["name"], f["kind"]) for f in json.loads(capsys.readouterr().out)["findings"]]
    assert findings.count(("state", "conversion-added")) == 1 and ("stateAgain", "conversion-added") not in findings
    model = load_a2l(out).model()  # validated: the added blocks are well-formed
    assert [model.measurement(name).conversion for name in ("state", "stateAgain", "stateIdentical")] == [
        "tState", "tState", "CM"]
    assert model.names("COMPU_METHOD") == ["CM", "tState"] and model.names("COMPU_VTAB") == ["tState"]
    assert model.compu_method("tState").conversion_type == "TAB_VERB"
    assert model.compu_table("tState").pairs == ((0, "OFF"), (1, "ON"), (200, "BROKEN"))
    assert model.conversion(model.measurement("state")).to_physical(200) == "BROKEN"
