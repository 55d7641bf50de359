"""INSTANCEs of typedefs read as the objects they stand for: names, addresses, what the instance changes, errors."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from workbench.a2l import load_a2l, load_a2l_string
from workbench.a2l.check import check_document
from workbench.errors import A2lParseError, InputError, UnknownSymbolError

ROOT = Path(__file__).parents[2]
XCPLITE = ROOT / "tests" / "corpus" / "a2l" / "xcplite"


@pytest.fixture(scope="module")
def xcplite(tmp_path_factory) -> Path:
    """XCPlite's A2Ls with the AML they include (ours serves)."""
    root = tmp_path_factory.mktemp("xcplite")
    for name in ("struct_demo.a2l", "cpp_demo.a2l", "c_demo.a2l"):
        shutil.copy(XCPLITE / name, root)
    shutil.copy(ROOT / "a2l" / "XCP.aml", root / "XCP_104.aml")
    return root


# struct_demo.a2l, read by hand: struct1_t is 0x130 bytes, struct2_t 4; the instances' addresses and extensions
STRUCT1 = {"byte_field": 0x0, "word_field": 0x2, "array_field": 0x4, "struct_field": 0x104, "array_struct_field": 0x108}
STRUCT2 = {"byte_field": 0x2, "word_field": 0x0}
INSTANCES = {"local_struct2": (0xF518, 2, None), "local_struct1": (0xFEB8, 2, None),
             "local_struct1_array": (0xF538, 2, 8), "static_struct2": (0x2C000, 1, None),
             "static_struct1": (0x2C00E, 1, None), "static_struct1_array": (0x2C188, 1, 8),
             "heap_struct1": (0x400000, 3, None)}


def _expected_address(name: str) -> tuple[int, int]:
    """(address, extension) of an object of struct_demo by ASAP2's rule, from the numbers above."""
    head, *members = name.split(".")
    instance, _, index = head.partition("[")
    address, extension, _ = INSTANCES[instance]
    struct = STRUCT2 if instance.endswith("struct2") else STRUCT1
    if index:
        address += int(index.rstrip("]")) * 0x130
    for member in members:
        field, _, element = member.partition("[")
        address += struct[field]
        if element:
            address += int(element.rstrip("]")) * 4
        struct = STRUCT2 if field.endswith("struct_field") else struct
    return address, extension


def test_every_object_of_xcplite_struct_demo_is_where_the_a2l_puts_it(xcplite):
    model = load_a2l(xcplite / "struct_demo.a2l").model()
    placed = [obj for obj in model if model.placed(obj.name)]
    # 2 struct2_t instances of 2 members; 19 struct1_t (3 single, 2 arrays of 8) of 5 + 2 + 8 * 2 members
    assert len(placed) == 2 * 2 + 19 * 21 and model.instance_errors() == []
    for obj in placed:
        assert obj.kind == "MEASUREMENT" and (obj.address, obj.address_extension) == _expected_address(obj.name), obj.name
        assert obj.read_write  # the INSTANCE's READ_WRITE
    word = model.measurement("local_struct1_array[7].array_struct_field[3].word_field")
    assert (word.address, word.datatype, word.long_identifier) == (0xF538 + 7 * 0x130 + 0x108 + 3 * 4, "SWORD",
                                                                    "Word field")
    array = model.measurement("static_struct1.array_field")
    assert (array.shape, model.datatype_of(array)) == ((256,), "UBYTE")  # a component's MATRIX_DIM: one array
    assert model.kind_of("local_struct1") == "INSTANCE"
    assert "local_struct1.struct_field.byte_field" in model.names("MEASUREMENT")
    assert [o.name for o in model.find(r"heap_struct1\.\w+", regex=True)] == [
        "heap_struct1.byte_field", "heap_struct1.word_field", "heap_struct1.array_field"]
    # its IF_DATA (the DAQ event) is the INSTANCE's
    assert model.block("heap_struct1.word_field").name == "heap_struct1"
    with pytest.raises(InputError, match=r"INSTANCE local_struct1 is a structure: name one of its 21 objects \("
                                         r"local_struct1.byte_field, local_struct1.word_field, "):
        model.object("local_struct1")


def test_xcplite_cpp_demo_calibrations_are_its_instances_components(xcplite):
    model = load_a2l(xcplite / "cpp_demo.a2l").model()
    rows = {row.name: (row.kind, row.type, row.address) for row in model.summaries("CHARACTERISTIC")}
    assert rows == {
        "kParameters.counter_max": ("CHARACTERISTIC", "VALUE", 0x80010000),
        "kParameters.delay_us": ("CHARACTERISTIC", "VALUE", 0x80010004),
        **{f"SigGen{n}.{member}": ("CHARACTERISTIC", kind, base + offset)
           for n, base in ((1, 0x80020000), (2, 0x80030000))
           for member, kind, offset in (("signal_type", "VALUE", 0x50), ("ampl", "VALUE", 0x0),
                                        ("phase", "VALUE", 0x8), ("offset", "VALUE", 0x10), ("period", "VALUE", 0x18),
                                        ("delay_us", "VALUE", 0x4C), ("lookup.values", "CURVE", 0x20))},
    }
    ampl = model.characteristic("SigGen2.ampl")
    assert (ampl.lower_limit, ampl.upper_limit, model.unit_of(ampl), model.datatype_of(ampl)) == (
        0, 100, "Volt", "FLOAT64_IEEE")
    curve = model.characteristic("SigGen1.lookup.values")
    assert curve.shape == (11,) and curve.axes[0].fix_axis_points == tuple(float(i) for i in range(11))
    assert model.characteristic("SigGen1.delay_us").long_identifier == "Mainloop delay time in us"  # first wins
    assert model.measurement("SigGen1.value_").address == 0x18  # a plain MEASUREMENT beside the INSTANCE


def test_xcplite_c_demo_params_are_calibrations_and_its_copy_measurements(xcplite):
    model = load_a2l(xcplite / "c_demo.a2l").model()
    placed = {obj.name: (obj.kind, getattr(obj, "type", None), obj.address, obj.address_extension)
              for obj in model if model.placed(obj.name)}
    assert placed == {
        **{f"params.{member}": ("CHARACTERISTIC", kind, 0x80010000 + offset, 0) for member, kind, offset in (
            ("test_byte1", "VALUE", 0x8), ("test_byte2", "VALUE", 0x9), ("counter_max", "VALUE", 0x0),
            ("delay_us", "VALUE", 0x4), ("map", "MAP", 0xA), ("curve", "CURVE", 0x4C))},
        **{f"params_copy.{member}": ("MEASUREMENT", None, 0x2A270 + offset, 1) for member, offset in (
            ("test_byte1", 0x8), ("test_byte2", 0x9), ("counter_max", 0x0), ("delay_us", 0x4))},
    }
    assert model.characteristic("params.map").shape == (8, 8)


TEXT = '''/begin PROJECT P "" /begin MODULE M ""
/begin RECORD_LAYOUT RL_U16 FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT
/begin RECORD_LAYOUT RL_AX AXIS_PTS_X 1 UWORD INDEX_INCR DIRECT /end RECORD_LAYOUT
/begin RECORD_LAYOUT RL_CURVE FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT
/begin COMPU_METHOD CM_TENTH "" LINEAR "%6.1" "bar" COEFFS_LINEAR 0.1 0 /end COMPU_METHOD
/begin COMPU_METHOD CM_HALF "" LINEAR "%6.2" "V" COEFFS_LINEAR 0.5 0 /end COMPU_METHOD
/begin TYPEDEF_CHARACTERISTIC T_THR "threshold" VALUE RL_U16 0 CM_TENTH 0 100 /end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_AXIS T_AX "axis" NO_INPUT_QUANTITY RL_AX 0 NO_COMPU_METHOD 4 0 1000 /end TYPEDEF_AXIS
/begin TYPEDEF_CHARACTERISTIC T_CURVE "curve" CURVE RL_CURVE 0 CM_TENTH 0 100
  /begin AXIS_DESCR COM_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 1000 AXIS_PTS_REF THIS.ax /end AXIS_DESCR
/end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_MEASUREMENT T_SIG "signal" UWORD CM_TENTH 0 0 0 6553 /end TYPEDEF_MEASUREMENT
/begin TYPEDEF_BLOB T_RAW "raw" 3 /end TYPEDEF_BLOB
/begin TYPEDEF_STRUCTURE S_INNER "" 0x10
  /begin STRUCTURE_COMPONENT thr T_THR 0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT gains T_THR 2 MATRIX_DIM 3 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT ax T_AX 8 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE S_OUTER "" 0x40
  /begin STRUCTURE_COMPONENT sig T_SIG 0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT inner S_INNER 0x10 MATRIX_DIM 2 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT raw T_RAW 0x30 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE S_MAPPED "" 0x10
  /begin STRUCTURE_COMPONENT ax T_AX 0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT curve T_CURVE 8 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin INSTANCE box "" S_OUTER 0x1000 ECU_ADDRESS_EXTENSION 1 CALIBRATION_ACCESS CALIBRATION
  /begin OVERWRITE inner.thr 0 CONVERSION CM_HALF LIMITS 0 50 PHYS_UNIT "kV" /end OVERWRITE
/end INSTANCE
/begin INSTANCE grid "" S_INNER 0x2000 MATRIX_DIM 2 3 /end INSTANCE
/begin INSTANCE mapped "" S_MAPPED 0x3000 /end INSTANCE
/begin INSTANCE single "" T_THR 0x4000 /end INSTANCE
/begin RECORD_LAYOUT RL_STD NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 UWORD INDEX_INCR DIRECT
  FNC_VALUES 3 ULONG ROW_DIR DIRECT /end RECORD_LAYOUT
/begin TYPEDEF_CHARACTERISTIC T_STD "" CURVE RL_STD 0 NO_COMPU_METHOD 0 100
  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 1000 /end AXIS_DESCR
/end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_CHARACTERISTIC T_MAP "" MAP RL_CURVE 0 NO_COMPU_METHOD 0 100
  /begin AXIS_DESCR FIX_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 2 FIX_AXIS_PAR_DIST 0 1 3 /end AXIS_DESCR
  /begin AXIS_DESCR FIX_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 2 0 1 FIX_AXIS_PAR_DIST 0 1 2 /end AXIS_DESCR
/end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_STRUCTURE S_CURVES "" 0x50
  /begin STRUCTURE_COMPONENT axes T_AX 0 MATRIX_DIM 2 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT curves T_STD 0x10 MATRIX_DIM 2 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin INSTANCE curves "" S_CURVES 0x5000 /end INSTANCE
/begin INSTANCE maps "" T_MAP 0x6000 MATRIX_DIM 2 3 /end INSTANCE
/begin GROUP G "" /begin REF_CHARACTERISTIC box /end REF_CHARACTERISTIC /end GROUP
/end MODULE /end PROJECT
'''


@pytest.fixture(scope="module")
def model():
    return load_a2l_string(TEXT, "inst.a2l").model()


def test_names_and_addresses_of_nested_structures_and_arrays(model):
    assert [name for name in model.names("CHARACTERISTIC") if name.startswith("box")] == [
        "box.inner[0].thr", "box.inner[0].gains", "box.inner[1].thr", "box.inner[1].gains"]
    assert model.characteristic("box.inner[1].thr").address == 0x1000 + 0x10 + 0x10
    assert (model.measurement("box.sig").address, model.axis_pts("box.inner[0].ax").address) == (0x1000, 0x1018)
    assert model.blob("box.raw").size == 3 and model.blob("box.raw").address == 0x1030
    # an array of structures (2 x 3, row-major): element [1][2] is the sixth, 5 * 0x10 bytes on
    assert model.characteristic("grid[1][2].thr").address == 0x2000 + 5 * 0x10
    # MATRIX_DIM on a VALUE component: one VAL_BLK of 3 values
    gains = model.characteristic("box.inner[0].gains")
    assert (gains.type, gains.shape, gains.address) == ("VAL_BLK", (3,), 0x1012)
    single = model.object("single")  # an INSTANCE of a characteristic typedef is that characteristic
    assert (single.kind, single.address, model.kind_of("single")) == ("CHARACTERISTIC", 0x4000, "CHARACTERISTIC")
    assert model.characteristic("box.inner[0].thr").address_extension == 1


def test_arrays_of_curves_maps_and_axes_are_one_object_per_element_their_record_layouts_size_apart(model):
    # RL_STD at 4 points: a UBYTE count, 4 UWORD points from offset 2, 4 ULONG values from offset 12: 28 bytes
    assert {name: (model.kind_of(name), model.object(name).address) for name in model.names()
            if name.startswith("curves")} == {
        "curves.curves[0]": ("CHARACTERISTIC", 0x5010), "curves.curves[1]": ("CHARACTERISTIC", 0x5010 + 28),
        "curves.axes[0]": ("AXIS_PTS", 0x5000), "curves.axes[1]": ("AXIS_PTS", 0x5008)}
    curve = model.characteristic("curves.curves[1]")
    assert (curve.type, curve.shape, curve.axes[0].attribute) == ("CURVE", (4,), "STD_AXIS")
    # an INSTANCE of a MAP typedef with MATRIX_DIM 2 3: six 3 x 2 maps of UWORD, 12 bytes each, row-major
    assert model.characteristic("maps[1][2]").address == 0x6000 + 5 * 12 and len(model.find("maps*")) == 6
    assert (model.characteristic("maps[0][1]").type, model.characteristic("maps[0][1]").shape) == ("MAP", (3, 2))
    assert model.typedef_sizes().of("T_STD") == 28 and model.instance_errors() == model.instance_limits() == []


def test_an_array_of_curves_whose_layout_size_is_not_known_is_a_limit_not_an_error():
    text = TEXT.replace("FNC_VALUES 3 ULONG ROW_DIR DIRECT /end RECORD_LAYOUT",
                        "FNC_VALUES 3 ULONG ROW_DIR DIRECT AXIS_RESCALE_X 4 UWORD 5 INDEX_INCR DIRECT /end RECORD_LAYOUT")
    model = load_a2l_string(text, "inst.a2l").model()
    (limit,) = model.instance_limits()
    assert model.instance_errors() == [] and str(limit).startswith(
        f"{_located(text, 'T_STD 0x10')}: INSTANCE curves: STRUCTURE_COMPONENT curves: an array (MATRIX_DIM) of "
        "typedef T_STD: the size of its RECORD_LAYOUT is not supported by the workbench")
    assert "curves.axes[1]" in model and "curves.curves[0]" not in model  # only that component left out


def test_overwrite_changes_one_component_in_one_instance(model):
    changed = model.characteristic("box.inner[1].thr")
    assert (changed.conversion, changed.upper_limit, model.unit_of(changed)) == ("CM_HALF", 50, "kV")
    assert model.conversion(changed).to_physical(10) == 5
    plain = model.characteristic("grid[0][0].thr")
    assert (plain.conversion, plain.upper_limit, model.unit_of(plain)) == ("CM_TENTH", 100, "bar")
    assert model.characteristic("box.inner[0].gains").conversion == "CM_TENTH"  # another component: untouched


def test_this_names_the_sibling_axis_and_the_instance_gives_access_and_groups(model):
    curve = model.characteristic("mapped.curve")
    assert curve.axes[0].axis_pts_ref == "mapped.ax"
    assert model.resolve(curve.axes[0], "axis_pts_ref", "AXIS_PTS").address == 0x3000
    assert model.characteristic("box.inner[0].thr").calibration_access == "CALIBRATION"
    assert model.characteristic("box.inner[0].thr").groups == ("G",)


def _located(text: str, needle: str) -> str:
    """``inst.a2l:line:column`` of the first ``needle`` in ``text``."""
    before = text[:text.index(needle)]
    return f"inst.a2l:{before.count(chr(10)) + 1}:{len(before) - before.rfind(chr(10))}"


@pytest.mark.parametrize("old, new, at, name, message", [
    ('"" S_OUTER 0x1000 ECU', '"" S_OUTR 0x1000 ECU', "S_OUTR", "box.sig",
     "INSTANCE box: typedef S_OUTR is not defined (did you mean S_OUTER"),
    ("T_RAW 0x30", "T_RAW 0x40", "0x40 /end", "box.raw",
     "INSTANCE box: STRUCTURE_COMPONENT raw: offset 0x40 + 3 bytes is beyond the size of TYPEDEF_STRUCTURE S_OUTER (0x40 bytes)"),
    ("thr T_THR 0", "thr S_OUTER 0", "S_OUTER 0 /end", "box.inner[0].thr",
     "INSTANCE box: STRUCTURE_COMPONENT thr: TYPEDEF_STRUCTURE contains itself: S_OUTER -> S_INNER -> S_OUTER"),
])
def test_what_cannot_be_placed_is_said_at_its_position(old, new, at, name, message):
    text = TEXT.replace(old, new, 1)
    model = load_a2l_string(text, "inst.a2l").model()
    where = _located(text, at)
    with pytest.raises(A2lParseError, match=re.escape(f"{where}: {message}")):
        model.object(name)
    assert str(model.instance_errors()[0]).startswith(f"{where}: {message}")
    assert "single" in model and "mapped.curve" in model  # the other instances are placed


def test_a_pointer_is_refused_and_an_unknown_component_suggests(model):
    text = TEXT.replace("/begin INSTANCE mapped \"\" S_MAPPED 0x3000", "/begin INSTANCE mapped \"\" S_MAPPED 0x3000 "
                        "ADDRESS_TYPE PLONG")
    broken = load_a2l_string(text, "inst.a2l").model()
    with pytest.raises(A2lParseError, match=r"INSTANCE mapped: reached through a pointer \(ADDRESS_TYPE PLONG\): "
                                            "not supported"):
        broken.object("mapped.curve")
    with pytest.raises(UnknownSymbolError, match="did you mean 'box.inner"):
        model.object("box.iner[0].thr")


STRUCTURE_ERRORS = '''/begin PROJECT P "" /begin MODULE M ""
/begin RECORD_LAYOUT RL_U16 FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT
/begin TYPEDEF_CHARACTERISTIC T_THR "" VALUE RL_U16 0 NO_COMPU_METHOD 0 100 /end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_STRUCTURE S_A "" 0x10
  /begin STRUCTURE_COMPONENT x T_THR 0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT x T_THR 2 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT y T_THR 0xF /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT arr T_THR 8 MATRIX_DIM 4 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT b S_B 4 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE S_B "" 0x4
  /begin STRUCTURE_COMPONENT a S_A 0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT z T_THRX 0 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE S_OK "" 0x8
  /begin STRUCTURE_COMPONENT arr T_THR 0 MATRIX_DIM 4 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin INSTANCE ptr "" S_OK 0x1000 ADDRESS_TYPE PLONG /end INSTANCE
/begin INSTANCE fine "" S_OK 0x2000 /end INSTANCE
/end MODULE /end PROJECT
'''


def test_check_reports_the_errors_of_structures_at_their_place_and_a_pointer_as_not_supported():
    text = STRUCTURE_ERRORS
    report = check_document(load_a2l_string(text, "inst.a2l"))
    found = {(f.kind, f"inst.a2l:{f.line}:{f.column}", f.severity.name) for f in report.findings}
    assert found == {
        ("duplicate-component", _located(text, "/begin STRUCTURE_COMPONENT x T_THR 2"), "ERROR"),
        ("component-beyond-structure", _located(text, "0xF /end"), "ERROR"),  # 0xF + 2 bytes > 0x10
        ("recursive-structure", _located(text, "S_B 4"), "ERROR"),  # S_A -> S_B -> S_A, said once
        ("undefined-reference", _located(text, "T_THRX"), "ERROR"),
        ("not-supported", _located(text, "/begin INSTANCE ptr"), "INFO"),
    }  # arr: 8 + 4 * 2 bytes end at 0x10, in the structure
    assert "did you mean T_THR?" in report.of_kind("undefined-reference")[0].message
    model = load_a2l_string(text, "inst.a2l").model()
    limit = (f"{_located(text, '/begin INSTANCE ptr')}: INSTANCE ptr: reached through a pointer (ADDRESS_TYPE PLONG): "
             "not supported by the workbench (the pointer's target is known only at run time)")
    assert model.instance_errors() == [] and [str(e) for e in model.instance_limits()] == [limit]
    assert model.characteristic("fine.arr").address == 0x2000  # the rest works
    pointer_only = text[:text.index("/begin TYPEDEF_STRUCTURE S_A")] + text[text.index("/begin TYPEDEF_STRUCTURE S_OK"):]
    assert check_document(load_a2l_string(pointer_only, "inst.a2l")).ok  # a limit of ours is no failed check


def test_an_instance_named_whole_says_whether_it_is_a_structure_or_an_array(tmp_path):
    from demo_instances import write_demo_instances_a2l

    model = load_a2l(write_demo_instances_a2l(tmp_path)).model()
    with pytest.raises(InputError, match=r"^INSTANCE convs is an array: name one of its 2 objects \(convs\[0\], "):
        model.object("convs")  # T_CONV MATRIX_DIM 2: two curves (was "is a structure")
    with pytest.raises(InputError, match=r"^INSTANCE pconv is a structure: name one of its 2 objects \(pconv.curves"):
        model.object("pconv")
