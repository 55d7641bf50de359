"""Measurements decoded one sample or many at a time; the rules a calibration value is checked against;
pya2ldb placing the same record layouts."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from workbench.a2l import load_a2l, load_a2l_string
from workbench.calib import Axis, CalValue, check_cells, check_limits, measurement_codec, object_layout
from workbench.calib.cells import index_problem
from workbench.errors import ConversionError, UnknownSymbolError

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def demo():
    return load_a2l(ROOT / "assets" / "FLCU.a2l").model()


def module(body: str, common: str = "BYTE_ORDER MSB_FIRST"):
    return load_a2l_string(f'/begin PROJECT P "" /begin MODULE M "" /begin MOD_COMMON "" {common} /end MOD_COMMON\n'
                           f'{body}\n/end MODULE /end PROJECT', "signals.a2l").model()


# -- measurements ---------------------------------------------------------------------------------------------

def test_demo_measurements(demo):
    volts = measurement_codec(demo, "zsSensVolt")
    assert (volts.span.address, volts.span.size, volts.shape, volts.unit) == (0x4002001C, 16, (4,), "V")
    data = np.array([0.5, 1.25, 2.0, 4.5], dtype="<f4").tobytes()
    assert list(volts.decode(data)) == [0.5, 1.25, 2.0, 4.5]
    state = measurement_codec(demo, "xsTankCtrlState")
    assert state.decode(b"\x02") == "TANK2_ON" and state.dtype == np.dtype("u1")
    assert list(state.to_physical(np.array([0, 1, 2, 9], dtype=np.uint8))) == ["OFF", "TANK1_ON", "TANK2_ON", 9]
    rail = measurement_codec(demo, "zsRailPressure")
    assert rail.dtype == np.dtype("<f4") and rail.to_physical(25.5) == 25.5


def test_many_samples_at_once_equal_one_at_a_time():
    model = module('/begin COMPU_METHOD L "" LINEAR "%5.2" "bar" COEFFS_LINEAR 0.01 -5 /end COMPU_METHOD\n'
                   '/begin MEASUREMENT p "" SWORD L 0 0 -400 400 ECU_ADDRESS 0x100 /end MEASUREMENT')
    codec = measurement_codec(model, "p")
    raw = np.random.default_rng(3).integers(-32768, 32767, 1000).astype(">i2")
    many = codec.decode_samples(raw.tobytes(), 1000)
    one_by_one = [codec.decode(raw[i:i + 1].tobytes()) for i in range(1000)]
    assert many.shape == (1000,) and np.array_equal(many, one_by_one)
    assert np.array_equal(codec.to_physical(raw.astype(np.int64)), many)


def test_bit_masks_bit_operations_and_sign():
    model = module('/begin MEASUREMENT flags "" UWORD NO_COMPU_METHOD 0 0 0 15 ECU_ADDRESS 0x10 BIT_MASK 0x00F0 '
                   '/end MEASUREMENT\n'
                   '/begin MEASUREMENT delta "" SBYTE NO_COMPU_METHOD 0 0 -8 7 ECU_ADDRESS 0x12 BIT_MASK 0x0F '
                   '/end MEASUREMENT\n'
                   '/begin MEASUREMENT shifted "" UWORD NO_COMPU_METHOD 0 0 -512 511 ECU_ADDRESS 0x14 BIT_MASK 0x0FFC\n'
                   '  /begin BIT_OPERATION /begin RIGHT_SHIFT 2 /end RIGHT_SHIFT /begin SIGN_EXTEND /end SIGN_EXTEND '
                   '/end BIT_OPERATION /end MEASUREMENT\n'
                   '/begin MEASUREMENT wide "" A_UINT64 NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x20 '
                   'BIT_MASK 0x8000000000000000 /end MEASUREMENT')
    assert measurement_codec(model, "flags").decode(b"\x12\x34") == 3  # 0x1234 & 0xF0 = 0x30 -> 3
    assert measurement_codec(model, "delta").decode(b"\x0e") == -2  # 4-bit two's complement
    assert measurement_codec(model, "shifted").decode(b"\x0f\xfc") == -1  # 0x3FF over 10 bits, SIGN_EXTEND
    wide = measurement_codec(model, "wide")
    assert wide.decode(b"\x80" + bytes(7)) == 1 and wide.decode(b"\x7f" + b"\xff" * 7) == 0
    assert list(wide.to_physical(np.array([2**63, 5], dtype=np.uint64))) == [1, 0]


@pytest.mark.parametrize("layout, expected", [("ROW_DIR", [[1, 2, 3], [4, 5, 6]]), ("COLUMN_DIR", [[1, 3, 5], [2, 4, 6]])])
def test_measurement_arrays_follow_their_layout(layout, expected):
    model = module(f'/begin MEASUREMENT a "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x10 MATRIX_DIM 2 3 '
                   f'LAYOUT {layout} /end MEASUREMENT')
    codec = measurement_codec(model, "a")
    assert codec.decode(bytes([1, 2, 3, 4, 5, 6])).tolist() == expected
    samples = codec.decode_samples(bytes([1, 2, 3, 4, 5, 6]) * 3, 3)
    assert samples.shape == (3, 2, 3) and samples[2].tolist() == expected


def test_measurements_that_cannot_be_read():
    model = module('/begin MEASUREMENT v "" UBYTE NO_COMPU_METHOD 0 0 0 255 /begin VIRTUAL a /end VIRTUAL /end MEASUREMENT\n'
                   '/begin MEASUREMENT w "" ULONG NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0 BYTE_ORDER MSB_FIRST_MSW_LAST '
                   '/end MEASUREMENT')
    with pytest.raises(ConversionError, match="MEASUREMENT v has no ECU_ADDRESS"):
        measurement_codec(model, "v").span
    swapped = measurement_codec(model, "w")
    assert swapped.dtype is None and swapped.decode(bytes.fromhex("5678 1234")) == 0x12345678
    with pytest.raises(ConversionError, match="1 ULONG need 4 bytes, 2 given"):
        swapped.decode(b"\x00\x01")
    with pytest.raises(UnknownSymbolError, match="did you mean 'v'"):
        measurement_codec(model, "vv")


# -- limits -----------------------------------------------------------------------------------------------------

def test_demo_limits(demo):
    assert check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", 25.0)) == []
    assert check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", 800.00001)) == []  # float32 precision
    (above,) = check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", 900.0))
    assert (above.name, above.rule, str(above)) == ("xsSWITCH_TANK_THR", "limits",
                                                    "xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00 bar")
    (nan,) = check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", float("nan")))
    assert "is not a number" in str(nan)
    assert check_limits(demo, CalValue("zfRAILPRESSURE_EN", "VALUE", "ON")) == []
    (kind,) = check_limits(demo, CalValue("xsSWITCH_TANK_THR", "CURVE", np.zeros(3)))
    assert kind.rule == "kind"


def test_a_value_just_beyond_a_limit_reads_other_than_the_limit(demo):
    """The limit in the A2L's format (CM_bar: %8.2), the value with the digits it takes to differ from it."""
    (just,) = check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", 800.0004))
    assert str(just) == "xsSWITCH_TANK_THR: 800.0004 is above the upper limit 800.00 bar"
    (below,) = check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", -1e-6))
    assert str(below) == "xsSWITCH_TANK_THR: -0.000001 is below the lower limit 0.00 bar"  # not "-0.00 ... 0.00"
    cells = check_cells(demo, "xvPRV_DC_FF", {(1, 0): 100.004})  # CM_Percent: %6.2
    assert [str(v) for v in cells] == ["xvPRV_DC_FF[1, 0]: 100.004 is above the upper limit 100.00 %"]
    plain = module("/begin CHARACTERISTIC k \"\" VALUE 0x10 L 0 NO_COMPU_METHOD 0 100 /end CHARACTERISTIC\n"
                   "/begin RECORD_LAYOUT L FNC_VALUES 1 FLOAT32_IEEE ROW_DIR DIRECT /end RECORD_LAYOUT")
    (unformatted,) = check_limits(plain, CalValue("k", "VALUE", 100.0001))  # no FORMAT: the shortest text
    assert str(unformatted) == "k: 100.0001 is above the upper limit 100"
    (text,) = check_limits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", "abc"))
    assert str(text) == "xsSWITCH_TANK_THR: 'abc' is not a number (a value from 0.00 to 800.00 bar)"


def test_map_limits_axes_and_shape(demo):
    target = Axis(np.array([0, 10, 20, 30, 40, 50.0]), "COM_AXIS", "xaPRV_FF_TARGET", "bar")
    manifold = Axis(np.array([50, 100, 200, 400, 700.0]), "COM_AXIS", "xaPRV_FF_MANIFOLD", "bar")
    values = np.full((6, 5), 50.0)
    assert check_limits(demo, CalValue("xvPRV_DC_FF", "MAP", values, (target, manifold))) == []
    values[3, 1], values[4, 4] = 120.0, 130.0
    bent = Axis(np.array([50, 100, 90, 400, 900.0]), "COM_AXIS", "xaPRV_FF_MANIFOLD", "bar")
    found = check_limits(demo, CalValue("xvPRV_DC_FF", "MAP", values, (target, bent)))
    messages = [str(v) for v in found]
    assert "xvPRV_DC_FF axis Y (xaPRV_FF_MANIFOLD): 900.00 at [4] is above the upper limit 800.00 bar" in messages
    assert "xvPRV_DC_FF axis Y (xaPRV_FF_MANIFOLD): points 1 and 2 (100, 90) break MON_INCREASE" in messages
    assert "xvPRV_DC_FF: 2 values, first 120.00 at [3, 1] is above the upper limit 100.00 %" in messages
    assert found[-1].index == (3, 1)
    short = check_limits(demo, CalValue("xvPRV_DC_FF", "MAP", values[:5], (target, manifold)))
    assert [v.rule for v in short] == ["shape", "limits"]
    assert "the values have shape (5, 5), the axes (6, 5)" in str(short[0])


def test_rules_of_the_features_file():
    model = load_a2l(ROOT / "tests" / "a2l" / "fixtures" / "model_features.a2l").model()
    (read_only,) = check_limits(model, CalValue("kReadOnly", "VALUE", 1))
    assert (read_only.rule, str(read_only)) == ("read-only", "kReadOnly cannot be written (READ_ONLY)")
    assert check_limits(model, CalValue("kValue", "VALUE", 150.0))[0].rule == "limits"
    assert check_limits(model, CalValue("kValue", "VALUE", 150.0), extended=True) == []  # EXTENDED_LIMITS -20 200
    assert "above the upper extended limit 200" in str(check_limits(model, CalValue("kValue", "VALUE", 250.0),
                                                                     extended=True)[0])
    (block,) = check_limits(model, CalValue("kBlock", "VAL_BLK", np.zeros((2, 3))))
    assert str(block) == "kBlock has shape (2, 3, 4) (MATRIX_DIM), the value (2, 3)"
    (text,) = check_limits(model, CalValue("kText", "ASCII", "x" * 17))
    assert str(text) == "kText holds 16 characters, the value has 17"
    fix = Axis(np.array([0, 10, 20.0]), "FIX_AXIS")
    std = Axis(np.array([100, 100, 300.0]))
    found = [str(v) for v in check_limits(model, CalValue("kMap", "MAP", np.zeros((3, 3)), (std, fix)))]
    assert found == ["kMap axis X: points 0 and 1 (100, 100) break STRICT_INCREASE",
                     "kMap axis Y is fixed at 4 points, the value has 3"]
    axis = [str(v) for v in check_limits(model, CalValue("aSpeed", "AXIS_PTS", np.arange(7.0) * 100))]
    assert axis == ["aSpeed cannot be written (READ_ONLY)", "aSpeed: 7 points, MAX_AXIS_POINTS is 5"]
    assert [v.rule for v in check_limits(model, CalValue("nEngine", "VALUE", 1))] == ["kind"]


# -- pya2ldb places the same items ----------------------------------------------------------------------------

def test_pya2ldb_puts_the_fields_at_the_same_addresses(tmp_path, demo):
    from pya2l_oracle import pya2l_describe

    text = ('ASAP2_VERSION 1 71\n/begin PROJECT P "" /begin MODULE M ""\n'
            '/begin MOD_COMMON "" BYTE_ORDER MSB_LAST ALIGNMENT_WORD 2 ALIGNMENT_LONG 4 ALIGNMENT_FLOAT32_IEEE 4 '
            '/end MOD_COMMON\n'
            '/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 UWORD INDEX_INCR DIRECT FNC_VALUES 3 FLOAT32_IEEE '
            'ROW_DIR DIRECT STATIC_RECORD_LAYOUT /end RECORD_LAYOUT\n'
            '/begin RECORD_LAYOUT I IDENTIFICATION 1 UWORD AXIS_PTS_X 2 ULONG INDEX_INCR DIRECT FNC_VALUES 3 UBYTE '
            'ROW_DIR DIRECT /end RECORD_LAYOUT\n'
            '/begin CHARACTERISTIC k "" CURVE 0x1000 K 0 NO_COMPU_METHOD 0 1 /begin AXIS_DESCR STD_AXIS '
            'NO_INPUT_QUANTITY NO_COMPU_METHOD 5 0 1 /end AXIS_DESCR /end CHARACTERISTIC\n'
            '/begin CHARACTERISTIC i "" CURVE 0x2000 I 0 NO_COMPU_METHOD 0 1 /begin AXIS_DESCR STD_AXIS '
            'NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 1 /end AXIS_DESCR /end CHARACTERISTIC\n'
            '/end MODULE /end PROJECT\n')
    path = tmp_path / "placed.a2l"
    path.write_text(text)
    model = load_a2l(path).model()
    oracle = pya2l_describe(path, {"layouts": ["k", "i"]})["addresses"]
    for name in ("k", "i"):
        layout = object_layout(model, name)
        ours = layout.resolve({s: bytes([5]) + bytes(s.size - 1) for s in layout.fixed_part()})
        places = {f.keyword.lower(): layout.address + f.offset for f in ours.fields}
        assert places == {key: oracle[name][key] for key in places}, name
    demo_oracle = pya2l_describe(ROOT / "assets" / "FLCU.a2l", {"layouts": ["zvTankPConv"]})["addresses"]
    curve = object_layout(demo, "zvTankPConv").resolve()
    assert {f.keyword.lower(): curve.address + f.offset for f in curve.fields} == demo_oracle["zvTankPConv"]


@pytest.mark.parametrize(("shape", "index", "message"), [
    ((4,), (3,), None), ((4,), (7,), "c has 4 values: index 7 is beyond (0-3)"),  # a CURVE, a VAL_BLK
    ((2, 3), (1, 3), "c has 2 x 3 values: y index 3 is beyond (0-2)"),  # a MAP, a VAL_BLK of MATRIX_DIM 2 3
    ((2, 3, 4), (0, 0), "c has 2 x 3 x 4 values: give 3 indices [x, y, z], not 2"),
    ((1,), (1,), "c has 1 value: index 1 is beyond (0)"), ((), (0,), "c has one value: name it without an index"),
])
def test_an_index_beyond_an_array_says_how_many_values_it_has(shape, index, message):
    assert index_problem("c", shape, index) == message
