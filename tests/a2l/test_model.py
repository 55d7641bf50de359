"""The typed object model: what each block means, names, lookups, located errors."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from workbench.a2l import load_a2l, load_a2l_string
from workbench.a2l.objects import Alignments, AxisDescr, Characteristic, Location, Measurement
from workbench.errors import A2lParseError, UnknownSymbolError

ROOT = Path(__file__).resolve().parents[2]
DEMO = ROOT / "assets" / "FLCU.a2l"
FEATURES = Path(__file__).parent / "fixtures" / "model_features.a2l"


@pytest.fixture(scope="module")
def demo():
    return load_a2l(DEMO).model()


@pytest.fixture(scope="module")
def features():
    return load_a2l(FEATURES).model()


def _line_of(path: Path, text: str, occurrence: int = 1) -> int:
    """1-based line of the ``occurrence``-th line containing ``text``."""
    lines = [n for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1) if text in line]
    return lines[occurrence - 1]


# -- the demo A2L ------------------------------------------------------------------------------------

def test_a_demo_scalar_reads_as_the_file_says(demo):
    thr = demo.characteristic("xsSWITCH_TANK_THR")
    assert (thr.type, thr.address, thr.record_layout, thr.conversion) == (
        "VALUE", 0x400000E0, "Scalar_FLOAT32_IEEE", "CM_bar")
    assert (thr.lower_limit, thr.upper_limit, thr.extended_limits) == (0.0, 800.0, None)
    assert thr.byte_order == "MSB_LAST"  # from MOD_COMMON: the object has none
    assert thr.functions == ("TankCtrl",) and thr.writable
    assert demo.unit_of(thr) == "bar" and demo.datatype_of(thr) == "FLOAT32_IEEE"
    assert thr.location == Location(str(DEMO), _line_of(DEMO, "/* Name                   */ xsSWITCH_TANK_THR") - 1, 5)


def test_the_demo_map_has_its_two_shared_axes(demo):
    ff = demo.characteristic("xvPRV_DC_FF")
    assert ff.type == "MAP" and ff.shape == (6, 5)
    x, y = ff.axes
    assert (x.axis, x.attribute, x.axis_pts_ref, x.max_axis_points, x.upper_limit) == (
        "X", "COM_AXIS", "xaPRV_FF_TARGET", 6, 50.0)
    assert (y.axis, y.attribute, y.axis_pts_ref, y.max_axis_points) == ("Y", "COM_AXIS", "xaPRV_FF_MANIFOLD", 5)
    assert demo.resolve(x, "axis_pts_ref", "AXIS_PTS") is demo.axis_pts("xaPRV_FF_TARGET")
    layout = demo.record_layout_of(ff)
    assert layout.fnc_values.mode == "COLUMN_DIR" and layout.fnc_values.datatype == "FLOAT32_IEEE"


def test_demo_measurements_and_conversion_tables(demo):
    volts = demo.measurement("zsSensVolt")
    assert (volts.datatype, volts.address, volts.shape, volts.conversion) == (
        "FLOAT32_IEEE", 0x4002001C, (4,), "CM_V")
    state = demo.measurement("xsTankCtrlState")
    method = demo.compu_method(state.conversion)
    assert method.conversion_type == "TAB_VERB"
    table = demo.compu_table(method.compu_tab_ref)
    assert table.pairs == ((0.0, "OFF"), (1.0, "TANK1_ON"), (2.0, "TANK2_ON"))


def test_the_document_entry_points_share_one_model(demo):
    doc = load_a2l(DEMO)
    assert doc.model() is doc.model(doc.model().name)
    assert doc.characteristic("xsSWITCH_TANK_THR") is doc.model().characteristic("xsSWITCH_TANK_THR")
    assert doc.measurement("zsRailPressure").address == 0x4002004C
    assert doc.axis_pts("xaPRV_FF_MANIFOLD").max_axis_points == 5
    assert doc.compu_method("CM_bar").unit == "bar"
    assert doc.record_layout("Lookup1D_Struct_FLOAT32_IEEE").entry("AXIS_PTS", "X").position == 1
    assert "xvPRV_DC_FF" in doc.function("PRVCtrl").def_characteristics


def test_every_addr_epk_with_the_part_it_lies_in(demo):
    first, second = demo.epk_addresses()
    assert (first.address, first.part, second.address, second.part) == (0xFC0000, "CALIB", 0x840008, "APPLICATIVE")
    assert demo.addr_epk() == 0xFC0000 and demo.epk_parts() == (first, second)
    assert demo.doc.token_position(second.token)[1:] == (_line_of(DEMO, "ADDR_EPK 0x840008"), 16)
    text = DEMO.read_text(encoding="utf-8")
    outside = load_a2l_string(text.replace("ADDR_EPK 0x840008", "ADDR_EPK 0x30000000")).model()
    assert [(e.address, e.part) for e in outside.epk_addresses()] == [(0xFC0000, "CALIB"), (0x30000000, "")]
    assert outside.epk_parts() == ()  # one part with its own EPK: it stands for the whole software
    assert load_a2l_string(text.replace("ADDR_EPK 0x840008", "ADDR_EPK 0xFC0100")).model().epk_parts() == ()


def test_every_demo_object_reads_and_its_summary_agrees(demo):
    objects = list(demo)
    assert len(objects) == len(demo) == len(demo.names()) == 85 + 56 + 2
    summaries = demo.summaries()
    assert [s.name for s in summaries] == [o.name for o in objects]
    for summary, obj in zip(summaries, objects):
        assert summary.kind == obj.kind and summary.address == obj.address
        assert summary.conversion == obj.conversion and summary.unit == demo.unit_of(obj)
        assert summary.long_identifier == obj.long_identifier


# -- every feature, on a hand-written file ------------------------------------------------------------

def test_mod_common_defaults_and_overrides(features):
    common = features.mod_common
    assert common.byte_order == "MSB_FIRST" and common.deposit == "ABSOLUTE"
    assert common.alignments == Alignments(byte=1, word=1, long=2, float32=2)  # the rest: ASAP2's defaults
    assert common.alignments.of("A_UINT64") == 8
    layout = features.record_layout("RL_map_dyn")
    assert layout.alignments_over(common.alignments).of("UWORD") == 2 and layout.static_record_layout
    bare = load_a2l_string('/begin PROJECT P "" /begin MODULE M "" /end MODULE /end PROJECT').model()
    assert bare.mod_common.byte_order == "MSB_FIRST" and bare.mod_common.alignments == Alignments()


def test_a_characteristic_with_every_option(features):
    value = features.characteristic("kValue")
    assert value.bit_mask == 0xFFFF000000000000  # 64 bits
    assert value.byte_order == "MSB_LAST"  # its own, over MOD_COMMON's MSB_FIRST
    assert (value.address, value.address_extension, value.extended_limits) == (0x10004, 2, (-20.0, 200.0))
    assert (value.calibration_access, value.writable, value.discrete, value.step_size) == (
        "OFFLINE_CALIBRATION", True, True, 0.5)
    assert (value.format, value.phys_unit, value.display_identifier, value.symbol_link) == (
        "%7.2", "kPa", "k_value", ("k_value_c", 4))
    assert value.functions == ("Fuel",)  # named by Fuel's REF_CHARACTERISTIC and its own FUNCTION_LIST: once
    assert features.unit_of(value) == "kPa"  # PHYS_UNIT over the COMPU_METHOD's "bar"
    assert features.format_of(value) == "%7.2"  # its FORMAT over the COMPU_METHOD's "%8.3"
    assert features.format_of(features.characteristic("kBlock")) == "%6.1"
    assert features.format_of(features.characteristic("kReadOnly")) is None
    assert not features.characteristic("kReadOnly").writable
    assert features.characteristic("kBlock").shape == (2, 3, 4)
    assert features.characteristic("kText").shape == (16,)  # legacy NUMBER
    assert features.unit_of(features.characteristic("kBlock")) == "rpm"  # the COMPU_METHOD's REF_UNIT


def test_axis_descriptions(features):
    std, fix = features.characteristic("kMap").axes
    assert (std.attribute, std.input_quantity, std.deposit, std.monotony, std.read_only) == (
        "STD_AXIS", "nEngine", "DIFFERENCE", "STRICT_INCREASE", True)
    assert (std.extended_limits, std.byte_order, std.max_grad, std.phys_unit) == (
        (-100.0, 9000.0), "MSB_LAST", 50.0, "1/min")
    assert fix.input_quantity is None and fix.fix_axis_points == (0.0, 10.0, 20.0, 30.0)
    par, par_list, com = features.characteristic("kCube").axes
    assert [a.axis for a in (par, par_list, com)] == ["X", "Y", "Z"]
    assert par.fix_axis_points == (1.0, 5.0, 9.0)  # offset 1, shift 2: 1 + i * 4
    assert par_list.fix_axis_points == (2.0, 5.0)
    assert com.axis_pts_ref == "aSpeed"
    curve_axis = features.characteristic("kCurve").axes[0]
    assert curve_axis.curve_axis_ref == "kMap" and curve_axis.fix_axis_points is None


def test_measurements(features):
    speed = features.measurement("nEngine")
    assert (speed.address, speed.address_extension, speed.bit_mask, speed.bit_operation) == (
        0x20000, 1, 0x0FFF, (0, 2, True))
    assert (speed.read_write, speed.discrete, speed.error_mask, speed.max_refresh) == (True, True, 0x8000, (3, 10))
    assert speed.functions == ("Fuel", "Idle") and speed.groups == ("Favourites", "Others")
    array = features.measurement("mArray")
    assert (array.matrix_dim, array.shape, array.layout) == ((2, 1, 3), (2, 3), "COLUMN_DIR")
    assert features.measurement("mLegacy").shape == (6,)
    virtual = features.measurement("mVirtual")
    assert virtual.address is None and virtual.virtual == ("nEngine", "mArray")


def test_membership_lists_the_owners_of_a_name_in_document_order_as_the_objects_do(demo):
    """The reverse index the variable browser lists every object's functions from, without building each FUNCTION."""
    model = load_a2l_string(
        '/begin PROJECT P "" /begin MODULE M ""\n'
        '/begin FUNCTION F1 "" /begin REF_CHARACTERISTIC k /end REF_CHARACTERISTIC\n'
        '  /begin LOC_MEASUREMENT m /end LOC_MEASUREMENT /end FUNCTION\n'
        '/begin FUNCTION F2 "" /begin DEF_CHARACTERISTIC k m /end DEF_CHARACTERISTIC\n'
        '  /begin IN_MEASUREMENT m /end IN_MEASUREMENT /end FUNCTION\n'
        '/begin GROUP G "" /begin REF_MEASUREMENT m /end REF_MEASUREMENT /end GROUP\n'
        '/end MODULE /end PROJECT').model()
    assert model.membership("k") == (("F1", "F2"), ())  # F2's DEF_ list comes before F1's REF_ in _LISTS: not here
    assert model.membership("m") == (("F1", "F2"), ("G",)) and model.membership("none") == ((), ())
    listed: dict[str, list[str]] = {}  # what the FUNCTIONs read one by one say
    for name in demo.names("FUNCTION"):
        function = demo.function(name)
        for member in (*function.def_characteristics, *function.ref_characteristics, *function.in_measurements,
                       *function.out_measurements, *function.loc_measurements):
            owners = listed.setdefault(member, [])
            if name not in owners:
                owners.append(name)
    assert listed and {member: list(demo.membership(member)[0]) for member in listed} == listed


def test_objects_located_one_by_one_count_newlines_until_a_line_table_is_cheaper():
    """Every object built is located. A window opening objects one by one from a 20 MB file counted the newlines from
    the file's start for each of the first thousand (seconds); the counting stops once it has read the file twice,
    and the line table gives the same lines and columns."""
    blocks = "".join(f'  /begin MEASUREMENT m{i} "" UBYTE NO_COMPU_METHOD 1 0 0 255 /end MEASUREMENT\n'
                     for i in range(200))
    model = load_a2l_string(f'/begin PROJECT P ""\n /begin MODULE M ""\n{blocks} /end MODULE\n/end PROJECT').model()
    source = model.doc.source_map.main
    assert model.measurement("m199").location[1:] == (202, 3) and source._line_starts is None  # one: counted
    located = [model.measurement(f"m{i}").location[1:] for i in (198, 197, 196)]
    assert source._line_starts is not None  # the counting read the file twice: the table from then on
    assert located + [model.measurement(f"m{i}").location[1:] for i in (0, 100)] == [
        (201, 3), (200, 3), (199, 3), (3, 3), (103, 3)]


def test_record_layouts_keep_every_item_in_position_order(features):
    layout = features.record_layout("RL_items")
    spelled = [(e.spelled, e.position, e.datatype) for e in layout.entries]
    assert spelled == [("IDENTIFICATION", 1, "UWORD"), ("RESERVED", 2, "BYTE"), ("SRC_ADDR_X", 3, "ULONG"),
                       ("OFFSET_X", 5, "SWORD"), ("DIST_OP_X", 6, "SWORD"), ("FNC_VALUES", 7, "FLOAT32_IEEE"),
                       ("FIX_NO_AXIS_PTS_X", None, None)]
    assert layout.entry("FIX_NO_AXIS_PTS", "X").count == 4 and layout.static_address_offsets
    assert features.record_layout("RL_map_dyn").entry("AXIS_PTS", "Y").mode == "INDEX_DECR"


def test_conversion_tables_units_functions_groups(features):
    assert features.compu_table("TAB_volts").default_value_numeric == -1.0
    assert features.compu_table("VT_gear").default_value == "invalid"
    assert features.compu_table("VTR_level").triples == ((0.0, 9.0, "low"), (10.0, 20.0, "high"))
    form = features.compu_method("CM_form")
    assert (form.formula, form.formula_inv, form.decimals) == ("X1 * 0.1 - 40", "(X1 + 40) * 10", 4)
    assert features.unit("U_rpm").unit_conversion == (60.0, 0.0)
    assert features.unit("U_hz").si_exponents == (0, 0, -1, 0, 0, 0, 0)
    fuel = features.function("Fuel")
    assert (fuel.version, fuel.def_characteristics, fuel.sub_functions) == ("2.1", ("kMap", "kCube"), ("Idle",))
    favourites = features.group("Favourites")
    assert favourites.root and favourites.ref_measurements == ("nEngine", "mArray")
    assert features.blob("bImage").size == 64


# -- names ----------------------------------------------------------------------------------------------

def test_names_find_and_lookup_by_any_kind(features):
    assert features.names("MEASUREMENT") == ["nEngine", "mArray", "mLegacy", "mVirtual"]
    assert features.names("COMPU_METHOD")[:2] == ["CM_lin", "CM_rat"]
    assert [o.name for o in features.find("k*", kind="CHARACTERISTIC")][:2] == ["kValue", "kReadOnly"]
    assert [o.name for o in features.find("m[A-Z]*")] == ["mArray", "mLegacy", "mVirtual"]
    assert [o.name for o in features.find(r"k(Map|Cube)", regex=True)] == ["kMap", "kCube"]
    assert [o.name for o in features.find("NENGINE", ignore_case=True)] == ["nEngine"]
    assert isinstance(features["nEngine"], Measurement) and isinstance(features.object("kMap"), Characteristic)
    assert features.kind_of("aSpeed") == "AXIS_PTS" and "bImage" in features and "CM_lin" not in features
    with pytest.raises(ValueError, match="unknown kind"):
        features.names("CHARACTERISTICS")
    with pytest.raises(ValueError, match="bad pattern"):
        features.find("(", regex=True)


def test_an_unknown_name_suggests_the_closest(features, demo):
    with pytest.raises(UnknownSymbolError) as caught:
        demo.characteristic("xsSWITCH_TANK_TH")
    assert isinstance(caught.value, KeyError) and caught.value.suggestions[0] == "xsSWITCH_TANK_THR"
    assert "did you mean 'xsSWITCH_TANK_THR'" in str(caught.value)
    with pytest.raises(UnknownSymbolError, match="'zsRailPressure'"):
        demo.object("zsRailPresure")
    with pytest.raises(UnknownSymbolError) as caught:
        features.measurement("nengine")  # a case slip comes first
    assert caught.value.suggestions[0] == "nEngine"
    with pytest.raises(UnknownSymbolError) as caught:
        features.characteristic("nEngine")  # a measurement is no characteristic
    assert "CHARACTERISTIC names" in str(caught.value)


def test_many_modules_need_a_name():
    text = ('/begin PROJECT P "" /begin MODULE A "" /end MODULE /begin MODULE B "" '
            '/begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x10 /end MEASUREMENT '
            '/end MODULE /end PROJECT')
    doc = load_a2l_string(text)
    with pytest.raises(A2lParseError, match="exactly one MODULE"):
        doc.model()
    assert doc.measurement("m", module="B").address == 0x10
    assert doc.model("A").names() == []


# -- located errors ---------------------------------------------------------------------------------------

def test_a_broken_reference_is_located_at_the_reference(features):
    broken = features.characteristic("kBrokenLayout")
    line = _line_of(FEATURES, "kBrokenLayout")
    with pytest.raises(A2lParseError) as caught:
        features.record_layout_of(broken)
    assert (caught.value.line, caught.value.column) == (line, 58)
    assert "RECORD_LAYOUT 'RL_missing' is not defined" in str(caught.value)
    assert "did you mean RL_items" in str(caught.value) or "RL_" in str(caught.value)
    with pytest.raises(A2lParseError, match=r":71: CHARACTERISTIC kBrokenLayout: COMPU_METHOD 'CM_nothing'"):
        features.resolve(broken, "conversion", "COMPU_METHOD")


def test_a_malformed_number_is_located():
    text = ('/begin PROJECT P "" /begin MODULE M ""\n'
            '  /begin CHARACTERISTIC c "" VALUE 0x10 RL 0 NO_COMPU_METHOD zero 10 /end CHARACTERISTIC\n'
            '  /begin CHARACTERISTIC d "" VALUE 0x10 /end CHARACTERISTIC\n'
            '/end MODULE /end PROJECT')
    model = load_a2l_string(text, "bad.a2l", validate=False).model()
    with pytest.raises(A2lParseError, match=re.escape("bad.a2l:2:62: CHARACTERISTIC c: expected a number, found 'zero'")):
        model.characteristic("c")
    with pytest.raises(A2lParseError, match=re.escape("bad.a2l:3:10: CHARACTERISTIC d: 9 parameters expected, found 4")):
        model.characteristic("d")


def test_objects_are_frozen_values(features):
    axis = features.characteristic("kMap").axes[0]
    assert isinstance(axis, AxisDescr)
    with pytest.raises(AttributeError):
        axis.max_axis_points = 3
    again = load_a2l(FEATURES).model().characteristic("kMap")
    assert again == features.characteristic("kMap") and again is not features.characteristic("kMap")
    assert hash(again) == hash(features.characteristic("kMap"))


# -- pya2ldb's reading of the same objects ---------------------------------------------------------------

def _ours(model, obj) -> dict:
    if isinstance(obj, Characteristic):
        return {"type": obj.type, "address": obj.address, "record_layout": obj.record_layout,
                "conversion": obj.conversion, "limits": [obj.lower_limit, obj.upper_limit],
                "extended_limits": list(obj.extended_limits) if obj.extended_limits else None,
                "extension": obj.address_extension, "read_only": obj.read_only,
                "axes": [[a.attribute, a.max_axis_points, a.axis_pts_ref, a.conversion, a.lower_limit, a.upper_limit]
                         for a in obj.axes]}
    return {"datatype": obj.datatype, "address": obj.address, "conversion": obj.conversion,
            "limits": [obj.lower_limit, obj.upper_limit], "bit_mask": obj.bit_mask, "extension": obj.address_extension,
            "matrix_dim": list(obj.matrix_dim), "array_size": obj.array_size}


@pytest.mark.parametrize("path", [DEMO, FEATURES], ids=["demo", "features"])
def test_pya2ldb_reads_the_same_objects(path):
    from pya2l_oracle import pya2l_describe

    model = load_a2l(path).model()
    characteristics = [n for n in model.names("CHARACTERISTIC") if n != "kBrokenLayout"]
    measurements = [n for n in model.names("MEASUREMENT") if model.measurement(n).address is not None]
    oracle = pya2l_describe(path, {"characteristics": characteristics, "measurements": measurements,
                                   "axis_pts": model.names("AXIS_PTS")})
    unread = {name for kind in oracle.values() for name, entry in kind.items() if "error" in entry}
    assert unread <= {"kCurve"}, unread  # its CURVE_AXIS_REF names a MAP: pya2ldb fails, the layout refuses it
    for kind, names in (("characteristics", characteristics), ("measurements", measurements)):
        for name in sorted(set(names) - unread):
            obj = model.object(name)
            ours, theirs = _ours(model, obj), oracle[kind][name]
            if theirs.get("conversion") is None:  # pya2ldb could not build the method (scipy missing): no name
                theirs["conversion"] = ours["conversion"]
            for axis in theirs.get("axes", []):
                axis[3] = axis[3] or "NO_COMPU_METHOD"
            if obj.kind == "CHARACTERISTIC" and obj.bit_mask is not None and obj.bit_mask >= 2**63:
                assert theirs["bit_mask"] == 2**63 - 1  # pya2ldb saturates 64-bit masks; we keep them
            for field, value in ours.items():
                assert theirs[field] == value, (name, field, theirs[field], value)
            own_order = theirs["byte_order"]
            if own_order is not None:  # pya2ldb leaves MOD_COMMON's order to the caller
                assert {"BIG_ENDIAN": "MSB_FIRST", "LITTLE_ENDIAN": "MSB_LAST"}.get(own_order, own_order) == \
                    obj.byte_order, name
    for name in model.names("AXIS_PTS"):
        axis = model.axis_pts(name)
        assert oracle["axis_pts"][name] == {"address": axis.address, "record_layout": axis.record_layout,
                                            "max": axis.max_axis_points, "conversion": axis.conversion,
                                            "limits": [axis.lower_limit, axis.upper_limit]}


def test_a_name_with_brackets_is_that_object_not_a_glob():
    """ASAP2 names may hold [ and ] (a2ltool names array elements ``arr[1]``): such a name selects its object;
    a glob that is no object's name still matches (``arr[12]`` as a glob is arr1 or arr2)."""
    objects = "\n".join(f'/begin MEASUREMENT {name} "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x{i:X} '
                        "/end MEASUREMENT" for i, name in enumerate(["arr[1]", "arr1", "arr2"]))
    model = load_a2l_string(f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n/begin MODULE M ""\n{objects}\n'
                            "/end MODULE\n/end PROJECT\n").model()
    assert model.expand(["arr[1]"]) == ["arr[1]"]
    assert model.expand(["arr[12]"]) == ["arr1", "arr2"]
    assert model.expand(["arr*"]) == ["arr[1]", "arr1", "arr2"]
