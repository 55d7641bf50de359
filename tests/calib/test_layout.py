"""Record layouts in memory: the demo's calibrations read from its s19, hand-computed bytes for every
layout feature, round trips over data types, byte orders, index modes, alignments and bit masks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from demo_calibrations import demo_dataset

from workbench.a2l import load_a2l, load_a2l_string
from workbench.calib import (
    Axis, ByteEdit, CalValue, Span, object_layout, read_spans, read_value, value_edits,
)
from workbench.errors import A2lParseError, ConversionError, LimitsError, WorkbenchError
from workbench.image import load_image

ROOT = Path(__file__).resolve().parents[2]
CAL_RAM, CAL_ROM = 0x40000000, 0xFC0000


@pytest.fixture(scope="module")
def demo():
    return load_a2l(ROOT / "assets" / "FLCU.a2l").model()


@pytest.fixture(scope="module")
def rom():
    image = load_image(ROOT / "assets" / "FLCU.s19")
    return lambda span: image.read(span.address - CAL_RAM + CAL_ROM, span.size)


class Memory:
    """A sparse byte memory for crafted objects: read spans, apply edits."""

    def __init__(self, content: dict[int, bytes] | None = None, size: int = 0x20000):
        self.bytes = bytearray(size)
        for address, data in (content or {}).items():
            self.bytes[address:address + len(data)] = data

    def read(self, span: Span) -> bytes:
        return bytes(self.bytes[span.address:span.end])

    def apply(self, edits: list[ByteEdit]) -> None:
        for edit in edits:
            self.bytes[edit.address:edit.address + len(edit.data)] = edit.data


def module(body: str, common: str = "BYTE_ORDER MSB_FIRST", name: str = "layout.a2l"):
    text = (f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n/begin MODULE M ""\n/begin MOD_COMMON "" {common} /end MOD_COMMON\n'
            f'{body}\n/end MODULE\n/end PROJECT\n')
    return load_a2l_string(text, name).model()


def resolved(model, name, memory: Memory):
    layout = object_layout(model, name)
    return layout.resolve(read_spans(layout.fixed_part(), memory.read))


# -- the demo ECU: every calibration from its s19 ----------------------------------------------------------

def test_every_demo_calibration_reads_as_its_sources_say(demo, rom):
    expected = demo_dataset()
    names = demo.names("CHARACTERISTIC") + demo.names("AXIS_PTS")
    assert sorted(names) == sorted(expected)
    for name in names:
        value = read_value(demo, name, rom)
        wanted = expected[name]
        assert (value.kind, value.unit) == (wanted.kind, wanted.unit), name
        assert value.same_values(wanted), (name, value.value, wanted.value)
        assert [a.kind for a in value.axes] == [a.kind for a in wanted.axes], name


def test_the_demo_values_the_docs_name(demo, rom):
    assert read_value(demo, "xsSWITCH_TANK_THR", rom).value == 20.0
    assert read_value(demo, "xsEMPTY_TANK_THR", rom).value == 5.0
    assert read_value(demo, "xsPRV_PWM_PERIOD", rom).value == 1000
    assert read_value(demo, "csFLCU_TO_PCM_001_En", rom).value == "ON"  # an enum by its text
    curve = read_value(demo, "zvTankPConv", rom)
    assert np.array_equal(curve.axes[0].values, np.linspace(0.5, 4.5, 9)) and curve.axes[0].unit == "V"
    assert np.array_equal(curve.value, np.linspace(0, 800, 9)) and curve.unit == "bar"
    ff = read_value(demo, "xvPRV_DC_FF", rom)
    target, manifold = ff.axes
    assert (target.name, list(target.values)) == ("xaPRV_FF_TARGET", [0, 10, 20, 30, 40, 50])
    assert (manifold.name, list(manifold.values)) == ("xaPRV_FF_MANIFOLD", [50, 100, 200, 400, 700])
    assert ff.value.shape == (6, 5)
    assert list(ff.value[:, 2]) == [0, 70, 70, 70, 70, 70]  # manifold 200 bar: 70 % once a target is set
    assert list(ff.value[1, :]) == [100, 100, 70, 35, 20]  # target 10 bar over the manifold points


def test_the_demo_map_is_x_fastest_as_the_simulated_ecu_reads_it(demo, rom):
    """COLUMN_DIR: memory is C ``v[manifold][target]``, the target (X) index varying fastest, as
    workbench/sim/flcu/prv_ctrl.py reshapes it (manifold points, target points)."""
    layout = object_layout(demo, "xvPRV_DC_FF").resolve()
    data = read_spans(layout.spans(), rom)
    raw = np.frombuffer(rom(layout.span()), "<f4").reshape(5, 6)  # the simulator's view
    assert np.array_equal(layout.decode(data).value, raw.T)


def test_writing_one_map_value_writes_four_bytes(demo, rom):
    layout = object_layout(demo, "xvPRV_DC_FF").resolve()
    data = read_spans(layout.spans(), rom)
    value = layout.decode(data)
    assert layout.encode(value, data) == []  # unchanged: nothing to write
    changed = value.value.copy()
    changed[2, 3] = 42.5  # target 20 bar, manifold 400 bar
    edits = layout.encode(CalValue(value.name, "MAP", changed, value.axes, value.unit), data)
    # x + nx * y = 2 + 6 * 3 = 20th float after 0x40000128
    assert edits == [ByteEdit(0x40000128 + 20 * 4, np.float32(42.5).tobytes(), 0, "xvPRV_DC_FF", "FNC_VALUES")]
    assert layout.encode(changed, data) == edits  # a bare array: the values alone


def test_a_changed_shared_axis_is_written_to_its_axis_object(demo, rom):
    layout = object_layout(demo, "xvPRV_DC_FF").resolve()
    data = read_spans(layout.spans(), rom)
    value = layout.decode(data)
    target, manifold = value.axes
    moved = Axis(np.array([0, 10, 20, 30, 40, 55.0]), target.kind, target.name, target.unit)
    edits = layout.encode(CalValue(value.name, "MAP", value.value, (moved, manifold), value.unit), data)
    address = demo.axis_pts("xaPRV_FF_TARGET").address + 5 * 4
    assert edits == [ByteEdit(address, np.float32(55).tobytes(), 0, "xaPRV_FF_TARGET", "AXIS_PTS_X")]


def test_the_shared_axis_cannot_change_its_length_through_the_map(demo, rom):
    layout = object_layout(demo, "xvPRV_DC_FF").resolve()
    data = read_spans(layout.spans(), rom)
    value = layout.decode(data)
    shorter = (Axis(value.axes[0].values[:5], "COM_AXIS", "xaPRV_FF_TARGET"), value.axes[1])
    with pytest.raises(ConversionError, match="axis X has 6 points .*xaPRV_FF_TARGET.*cannot change"):
        layout.encode(CalValue(value.name, "MAP", value.value[:5], shorter), data)


def test_enums_write_by_text(demo, rom):
    edits = value_edits(demo, CalValue("zfRAILPRESSURE_EN", "VALUE", "ON"), rom)
    assert edits == [ByteEdit(demo.characteristic("zfRAILPRESSURE_EN").address, b"\x01", 0, "zfRAILPRESSURE_EN",
                              "FNC_VALUES")]
    with pytest.raises(LimitsError, match=r"zfRAILPRESSURE_EN: 'MAYBE' is not one of its values \(OFF, ON\)"):
        value_edits(demo, CalValue("zfRAILPRESSURE_EN", "VALUE", "MAYBE"), rom)
    with pytest.raises(ConversionError, match="'MAYBE' is not one of its texts .*OFF, ON"):  # unchecked: the codec
        value_edits(demo, CalValue("zfRAILPRESSURE_EN", "VALUE", "MAYBE"), rom, check=False)


def test_value_edits_refuse_a_value_beyond_the_limits_before_computing(demo, rom):
    with pytest.raises(LimitsError, match="xsSWITCH_TANK_THR: 900.00 is above the upper limit 800.00") as caught:
        value_edits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", 900.0), rom)
    assert caught.value.violations[0].rule == "limits" and caught.value.exit_code == 2
    edits = value_edits(demo, CalValue("xsSWITCH_TANK_THR", "VALUE", 25.0), rom)
    assert edits == [ByteEdit(0x400000E0, np.float32(25).tobytes(), 0, "xsSWITCH_TANK_THR", "FNC_VALUES")]


# -- hand-computed layouts -----------------------------------------------------------------------------------

def test_a_linear_word_big_endian():
    model = module('/begin COMPU_METHOD L "" LINEAR "%5.1" "bar" COEFFS_LINEAR 0.5 -10 /end COMPU_METHOD\n'
                   '/begin RECORD_LAYOUT W FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC c "" VALUE 0x100 W 0 L -10 1000 /end CHARACTERISTIC')
    memory = Memory({0x100: b"\x00\x46"})  # raw 70
    assert read_value(model, "c", memory.read).value == 25.0  # 0.5 * 70 - 10
    layout = resolved(model, "c", memory)
    assert layout.encode(25.25, None) == [ByteEdit(0x100, b"\x00\x47", 0, "c", "FNC_VALUES")]  # 70.5 -> 71
    assert layout.encode(-9.75, None)[0].data == b"\x00\x01"  # raw 0.5 rounds away from zero
    with pytest.raises(ConversionError, match=r"c: 131072 does not fit UWORD \[0, 65535\]"):
        layout.encode(65526.0, None)


def test_rounding_is_half_away_from_zero():
    model = module('/begin RECORD_LAYOUT S FNC_VALUES 1 SBYTE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC c "" VALUE 0x10 S 0 NO_COMPU_METHOD -128 127 /end CHARACTERISTIC')
    layout = resolved(model, "c", Memory())
    assert [layout.encode(v)[0].data for v in (2.5, -2.5, 0.49999999999999994, -0.5, 126.5)] == [
        b"\x03", b"\xfd", b"\x00", b"\xff", b"\x7f"]
    with pytest.raises(ConversionError, match=r"-128.5 does not fit SBYTE \[-128, 127\]"):
        layout.encode(-128.5)


def test_a_bit_mask_keeps_the_other_bits():
    model = module('/begin RECORD_LAYOUT W FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC c "" VALUE 0x20 W 0 NO_COMPU_METHOD 0 255 BIT_MASK 0x0FF0 /end CHARACTERISTIC',
                   common="BYTE_ORDER MSB_LAST")
    memory = Memory({0x20: bytes.fromhex("5af3")})  # 0xF35A: field 0x35
    layout = resolved(model, "c", memory)
    data = read_spans(layout.spans(), memory.read)
    assert layout.decode(data).value == 0x35
    assert layout.encode(0xAB, data) == [ByteEdit(0x20, bytes.fromhex("bafa"), 0, "c", "FNC_VALUES")]  # 0xFABA
    with pytest.raises(ConversionError, match="BIT_MASK: writing it needs the current bytes"):
        layout.encode(0xAB)
    with pytest.raises(ConversionError, match=r"256 does not fit its BIT_MASK 0xFF0 \(8 bits: \[0, 255\]\)"):
        layout.encode(256, data)


def test_a_64_bit_mask_and_a_signed_field():
    model = module('/begin RECORD_LAYOUT Q FNC_VALUES 1 A_UINT64 ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin RECORD_LAYOUT S FNC_VALUES 1 SLONG ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC top "" VALUE 0x40 Q 0 NO_COMPU_METHOD 0 65535 BIT_MASK 0xFFFF000000000000 '
                   '/end CHARACTERISTIC\n'
                   '/begin CHARACTERISTIC nibble "" VALUE 0x50 S 0 NO_COMPU_METHOD -8 7 BIT_MASK 0xF0 /end CHARACTERISTIC')
    memory = Memory({0x40: bytes.fromhex("BEEF0000000000FF"), 0x50: bytes.fromhex("000000E5")})
    assert read_value(model, "top", memory.read).value == 0xBEEF
    assert read_value(model, "nibble", memory.read).value == -2  # 0xE, sign-extended over 4 bits
    for name, value in (("top", 0x1234), ("nibble", 7)):
        layout = resolved(model, name, memory)
        memory.apply(layout.encode(value, read_spans(layout.spans(), memory.read)))
    assert memory.read(Span(0x40, 8)) == bytes.fromhex("12340000000000FF")
    assert memory.read(Span(0x50, 4)) == bytes.fromhex("00000075")


@pytest.mark.parametrize("mode, stored", [("ROW_DIR", [1, 2, 3, 4, 5, 6]), ("COLUMN_DIR", [1, 4, 2, 5, 3, 6])])
def test_a_val_blk_in_both_index_modes(mode, stored):
    model = module(f'/begin RECORD_LAYOUT B FNC_VALUES 1 UBYTE {mode} DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC blk "" VAL_BLK 0x80 B 0 NO_COMPU_METHOD 0 255 MATRIX_DIM 2 3 /end CHARACTERISTIC')
    values = np.array([[1, 2, 3], [4, 5, 6]])  # shape (x=2, y=3)
    layout = resolved(model, "blk", Memory())
    assert layout.encode(values) == [ByteEdit(0x80, bytes(stored), 0, "blk", "FNC_VALUES")]
    value = layout.decode({layout.span(): bytes(stored)})
    assert np.array_equal(value.value, values) and value.kind == "VAL_BLK"
    with pytest.raises(ConversionError, match=r"shape \(2, 3\), the value has shape \(3, 2\)"):
        layout.encode(values.T)


def test_ascii():
    model = module('/begin RECORD_LAYOUT B FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC name "" ASCII 0x90 B 0 NO_COMPU_METHOD 0 255 NUMBER 8 /end CHARACTERISTIC\n'
                   '/begin CHARACTERISTIC wide "" ASCII 0xA0 B 0 NO_COMPU_METHOD 0 255 MATRIX_DIM 6 ENCODING UTF16 '
                   '/end CHARACTERISTIC')
    memory = Memory({0x90: b"FLCU\0\xff\xff\xff"})
    layout = resolved(model, "name", memory)
    assert layout.decode(read_spans(layout.spans(), memory.read)).value == "FLCU"
    assert layout.encode("ABC") == [ByteEdit(0x90, b"ABC\0\0\0\0\0", 0, "name", "FNC_VALUES")]
    with pytest.raises(ConversionError, match="needs 9 bytes, the string holds 8"):
        layout.encode("ABCDEFGHI")
    wide = resolved(model, "wide", memory)
    assert wide.encode("µs")[0].data == "µs".encode("utf-16-be") + b"\0\0"  # MSB_FIRST module


def test_a_dynamic_curve_reads_its_count_first_and_can_change_it():
    """NO_AXIS_PTS_X UBYTE at 0x100, AXIS_PTS_X SWORD aligned to 0x102, FNC_VALUES right after the
    actual points (no STATIC_RECORD_LAYOUT)."""
    model = module('/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 SWORD INDEX_INCR DIRECT '
                   'FNC_VALUES 3 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC k "" CURVE 0x100 K 0 NO_COMPU_METHOD 0 1000\n'
                   '  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 5 -100 100 /end AXIS_DESCR\n'
                   '/end CHARACTERISTIC')
    memory = Memory({0x100: bytes.fromhex("03 00 FFF6 0000 000A 0064 00C8 012C")})
    layout = object_layout(model, "k")
    assert layout.fixed_part() == [Span(0x100, 1)]
    curve = layout.resolve(read_spans(layout.fixed_part(), memory.read))
    assert [(f.spelled, f.offset, f.count) for f in curve.fields] == [
        ("NO_AXIS_PTS_X", 0, 1), ("AXIS_PTS_X", 2, 3), ("FNC_VALUES", 8, 3)]
    value = curve.decode(read_spans(curve.spans(), memory.read))
    assert list(value.axes[0].values) == [-10, 0, 10] and list(value.value) == [100, 200, 300]
    longer = CalValue("k", "CURVE", np.array([1, 2, 3, 4]), (Axis(np.array([-10, 0, 10, 20])),))
    memory.apply(curve.encode(longer, read_spans(curve.spans(), memory.read)))
    assert memory.read(Span(0x100, 18)) == bytes.fromhex("04 00 FFF6 0000 000A 0014 0001 0002 0003 0004")
    assert read_value(model, "k", memory.read) == CalValue("k", "CURVE", np.array([1.0, 2, 3, 4]),
                                                            (Axis(np.array([-10.0, 0, 10, 20])),))
    with pytest.raises(ConversionError, match="6 points on axis X, MAX_AXIS_POINTS is 5"):
        curve.encode(CalValue("k", "CURVE", np.zeros(6), (Axis(np.arange(6)),)))


def test_a_static_layout_keeps_places_for_max_axis_points():
    model = module('/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 SWORD INDEX_INCR DIRECT '
                   'FNC_VALUES 3 UWORD ROW_DIR DIRECT STATIC_RECORD_LAYOUT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC k "" CURVE 0x100 K 0 NO_COMPU_METHOD 0 1000\n'
                   '  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 5 -100 100 /end AXIS_DESCR\n'
                   '/end CHARACTERISTIC')
    memory = Memory({0x100: bytes([2])})
    curve = resolved(model, "k", memory)
    assert [(f.spelled, f.offset, f.count, f.size) for f in curve.fields] == [
        ("NO_AXIS_PTS_X", 0, 1, 1), ("AXIS_PTS_X", 2, 2, 10), ("FNC_VALUES", 12, 2, 10)]
    assert curve.size == 22


def test_a_map_with_every_axis_option():
    """NO_AXIS_PTS_X/Y, X points increasing, Y points stored last to first as differences, values
    COLUMN_DIR (x fastest), ALIGNMENT_WORD 2 of the record layout over MOD_COMMON's 1."""
    model = module('/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE NO_AXIS_PTS_Y 2 UBYTE '
                   'AXIS_PTS_X 3 UWORD INDEX_INCR DIRECT AXIS_PTS_Y 4 UWORD INDEX_DECR DIRECT '
                   'FNC_VALUES 5 UBYTE COLUMN_DIR DIRECT ALIGNMENT_WORD 2 /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC m "" MAP 0x201 K 0 NO_COMPU_METHOD 0 255\n'
                   '  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 1000 /end AXIS_DESCR\n'
                   '  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 1000 DEPOSIT DIFFERENCE '
                   'MONOTONY MON_INCREASE /end AXIS_DESCR\n'
                   '/end CHARACTERISTIC', common="BYTE_ORDER MSB_FIRST ALIGNMENT_WORD 1")
    # 0x201 nx=3, 0x202 ny=2, X at 0x204 (aligned), Y at 0x20A: [2nd diff, 1st], values at 0x20E
    memory = Memory({0x201: bytes.fromhex("03 02 00") + bytes.fromhex("0001 0002 0003") + bytes.fromhex("0005 000A")
                     + bytes([11, 21, 31, 12, 22, 32])})
    value = read_value(model, "m", memory.read)
    assert list(value.axes[0].values) == [1, 2, 3]
    assert list(value.axes[1].values) == [10, 15]  # differences 10, 5 stored as [5, 10]
    assert value.value.tolist() == [[11, 12], [21, 22], [31, 32]]  # [x, y]
    layout = resolved(model, "m", memory)
    data = read_spans(layout.spans(), memory.read)
    assert layout.encode(value, data) == []
    moved = CalValue("m", "MAP", value.value, (value.axes[0], Axis(np.array([10.0, 17]))))
    assert layout.encode(moved, data) == [ByteEdit(0x20A, b"\x00\x07", 0, "m", "AXIS_PTS_Y")]  # 5 -> 7: one UWORD


def test_static_address_offsets_keep_every_value_at_its_full_size_place():
    model = module('/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE NO_AXIS_PTS_Y 2 UBYTE AXIS_PTS_X 3 UBYTE INDEX_INCR '
                   'DIRECT AXIS_PTS_Y 4 UBYTE INDEX_INCR DIRECT FNC_VALUES 5 UBYTE ROW_DIR DIRECT STATIC_ADDRESS_OFFSETS '
                   '/end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC m "" MAP 0x300 K 0 NO_COMPU_METHOD 0 255\n'
                   '  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 255 /end AXIS_DESCR\n'
                   '  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 255 /end AXIS_DESCR\n'
                   '/end CHARACTERISTIC')
    # 2 x 2 used of 3 x 3; ROW_DIR: v[x][y] with y fastest over the full 3 columns
    values = bytes([1, 2, 0xEE, 3, 4, 0xEE, 0xEE, 0xEE, 0xEE])
    memory = Memory({0x300: bytes([2, 2, 10, 20, 0, 5, 6, 0]) + values})
    value = read_value(model, "m", memory.read)
    assert value.value.tolist() == [[1, 2], [3, 4]]
    layout = resolved(model, "m", memory)
    edits = layout.encode(np.array([[1, 2], [9, 4]]), read_spans(layout.spans(), memory.read))
    assert edits == [ByteEdit(0x308 + 3, b"\x09", 0, "m", "FNC_VALUES")]


def test_fixed_axes_from_the_a2l_and_from_memory():
    model = module('/begin RECORD_LAYOUT V FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin RECORD_LAYOUT F OFFSET_X 1 SWORD DIST_OP_X 2 SWORD FIX_NO_AXIS_PTS_X 3 '
                   'FNC_VALUES 3 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin RECORD_LAYOUT S OFFSET_X 1 UBYTE SHIFT_OP_X 2 UBYTE FNC_VALUES 3 UBYTE ROW_DIR DIRECT '
                   '/end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC par "" CURVE 0x400 V 0 NO_COMPU_METHOD 0 255 /begin AXIS_DESCR FIX_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 100 FIX_AXIS_PAR 10 2 3 /end AXIS_DESCR /end CHARACTERISTIC\n'
                   '/begin CHARACTERISTIC lst "" CURVE 0x410 V 0 NO_COMPU_METHOD 0 255 /begin AXIS_DESCR FIX_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 100 /begin FIX_AXIS_PAR_LIST 1 4 9 /end FIX_AXIS_PAR_LIST '
                   '/end AXIS_DESCR /end CHARACTERISTIC\n'
                   '/begin CHARACTERISTIC mem "" CURVE 0x420 F 0 NO_COMPU_METHOD 0 255 /begin AXIS_DESCR FIX_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 3 -100 100 /end AXIS_DESCR /end CHARACTERISTIC\n'
                   '/begin CHARACTERISTIC shf "" CURVE 0x430 S 0 NO_COMPU_METHOD 0 255 /begin AXIS_DESCR FIX_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 100 /end AXIS_DESCR /end CHARACTERISTIC')
    memory = Memory({0x400: b"\x01\x02\x03", 0x410: b"\x04\x05\x06", 0x420: bytes.fromhex("FFF6 0014 070809"),
                     0x430: bytes([3, 2, 1, 2, 3, 4])})
    assert list(read_value(model, "par", memory.read).axes[0].values) == [10, 14, 18]  # 10 + i * 2**2
    assert list(read_value(model, "lst", memory.read).axes[0].values) == [1, 4, 9]
    fixed = read_value(model, "mem", memory.read)
    assert list(fixed.axes[0].values) == [-10, 10, 30] and list(fixed.value) == [7, 8, 9]
    assert list(read_value(model, "shf", memory.read).axes[0].values) == [3, 7, 11, 15]  # 3 + i * 2**2
    layout = resolved(model, "par", memory)
    data = read_spans(layout.spans(), memory.read)
    with pytest.raises(ConversionError, match="axis X is a FIX_AXIS; its points cannot be written"):
        layout.encode(CalValue("par", "CURVE", np.array([1.0, 2, 3]), (Axis(np.array([0.0, 1, 2]), "FIX_AXIS"),)), data)


def test_com_axis_counts_in_memory():
    model = module('/begin RECORD_LAYOUT A NO_AXIS_PTS_X 1 UWORD AXIS_PTS_X 2 UWORD INDEX_INCR DIRECT /end RECORD_LAYOUT\n'
                   '/begin RECORD_LAYOUT V FNC_VALUES 1 UWORD ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin AXIS_PTS ax "" 0x500 NO_INPUT_QUANTITY A 0 NO_COMPU_METHOD 4 0 1000 /end AXIS_PTS\n'
                   '/begin CHARACTERISTIC cur "" CURVE 0x520 V 0 NO_COMPU_METHOD 0 1000 /begin AXIS_DESCR COM_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 1000 AXIS_PTS_REF ax /end AXIS_DESCR /end CHARACTERISTIC')
    memory = Memory({0x500: bytes.fromhex("0002 0064 00C8"), 0x520: bytes.fromhex("0001 0002")})
    layout = object_layout(model, "cur")
    assert layout.fixed_part() == [Span(0x500, 2)]  # the AXIS_PTS' count
    curve = layout.resolve(read_spans(layout.fixed_part(), memory.read))
    assert curve.spans() == [Span(0x520, 4), Span(0x500, 6)]
    value = curve.decode(read_spans(curve.spans(), memory.read))
    assert list(value.axes[0].values) == [100, 200] and value.axes[0].name == "ax"
    axis = read_value(model, "ax", memory.read)
    assert axis.kind == "AXIS_PTS" and list(axis.value) == [100, 200]
    ax_layout = resolved(model, "ax", memory)
    edits = ax_layout.encode(np.array([100.0, 200, 300]), read_spans(ax_layout.spans(), memory.read))
    # the points grew beyond what was read: written whole, then the count
    assert edits == [ByteEdit(0x502, bytes.fromhex("0064 00C8 012C"), 0, "ax", "AXIS_PTS_X"),
                     ByteEdit(0x500, b"\x00\x03", 0, "ax", "NO_AXIS_PTS_X")]


def test_identification_reserved_and_source_addresses_take_their_place():
    model = module('/begin RECORD_LAYOUT R IDENTIFICATION 1 UWORD RESERVED 2 BYTE SRC_ADDR_X 3 ULONG '
                   'RIP_ADDR_X 4 UWORD AXIS_PTS_X 5 UBYTE INDEX_INCR DIRECT FNC_VALUES 6 FLOAT32_IEEE ROW_DIR DIRECT '
                   '/end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC c "" CURVE 0x600 R 0 NO_COMPU_METHOD 0 10 /begin AXIS_DESCR STD_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 2 0 10 /end AXIS_DESCR /end CHARACTERISTIC',
                   common="BYTE_ORDER MSB_LAST ALIGNMENT_LONG 4 ALIGNMENT_FLOAT32_IEEE 4")
    layout = resolved(model, "c", Memory())
    assert [(f.spelled, f.offset) for f in layout.fields] == [
        ("IDENTIFICATION", 0), ("RESERVED", 2), ("SRC_ADDR_X", 4), ("RIP_ADDR_X", 8), ("AXIS_PTS_X", 10),
        ("FNC_VALUES", 12)]


@pytest.mark.parametrize("byte_order, stored", [("MSB_FIRST_MSW_LAST", "5678 1234"),
                                                ("MSB_LAST_MSW_FIRST", "3412 7856")])
def test_word_swapped_byte_orders(byte_order, stored):
    model = module('/begin RECORD_LAYOUT L FNC_VALUES 1 ULONG ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   f'/begin CHARACTERISTIC c "" VALUE 0x700 L 0 NO_COMPU_METHOD 0 4294967295 BYTE_ORDER {byte_order} '
                   '/end CHARACTERISTIC')
    layout = resolved(model, "c", Memory())
    assert layout.encode(0x12345678)[0].data == bytes.fromhex(stored)
    assert layout.decode({layout.span(): bytes.fromhex(stored)}).value == 0x12345678


@pytest.mark.parametrize("layout_text, message", [
    ("FNC_VALUES 1 UBYTE ROW_DIR PBYTE", "addressed PBYTE .*only DIRECT is supported"),
    ("FNC_VALUES 1 UBYTE ALTERNATE_WITH_X DIRECT", "index mode ALTERNATE_WITH_X is not supported"),
    ("AXIS_RESCALE_X 1 UBYTE 3 INDEX_INCR DIRECT FNC_VALUES 2 UBYTE ROW_DIR DIRECT", "rescale axes are not supported"),
    ("RESERVED 1 WORD", "no FNC_VALUES item"),
])
def test_unsupported_layouts_are_refused_by_name(layout_text, message):
    model = module(f'/begin RECORD_LAYOUT R {layout_text} /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC c "" VALUE 0x10 R 0 NO_COMPU_METHOD 0 255 /end CHARACTERISTIC')
    with pytest.raises(ConversionError, match=r"VALUE c \(RECORD_LAYOUT R\): .*" + message):
        object_layout(model, "c")


def test_broken_references_are_located():
    model = module('/begin CHARACTERISTIC c "" VALUE 0x10 NOPE 0 NO_COMPU_METHOD 0 255 /end CHARACTERISTIC\n'
                   '/begin RECORD_LAYOUT V FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC m "" CURVE 0x20 V 0 NO_COMPU_METHOD 0 255 /begin AXIS_DESCR COM_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 3 0 10 AXIS_PTS_REF gone /end AXIS_DESCR /end CHARACTERISTIC',
                   name="broken.a2l")
    with pytest.raises(A2lParseError, match="broken.a2l:5:39: CHARACTERISTIC c: RECORD_LAYOUT 'NOPE' is not defined"):
        object_layout(model, "c")
    with pytest.raises(A2lParseError, match="broken.a2l:7:146: CHARACTERISTIC m AXIS_DESCR X: AXIS_PTS 'gone' is not defined"):
        object_layout(model, "m")


def test_a_count_in_memory_beyond_max_axis_points_is_refused():
    model = module('/begin RECORD_LAYOUT K NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 UBYTE INDEX_INCR DIRECT '
                   'FNC_VALUES 3 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT\n'
                   '/begin CHARACTERISTIC k "" CURVE 0x100 K 0 NO_COMPU_METHOD 0 255 /begin AXIS_DESCR STD_AXIS '
                   'NO_INPUT_QUANTITY NO_COMPU_METHOD 4 0 255 /end AXIS_DESCR /end CHARACTERISTIC')
    with pytest.raises(ConversionError, match="CURVE k .*255 points on axis X in memory, MAX_AXIS_POINTS is 4"):
        resolved(model, "k", Memory({0x100: b"\xff"}))
    with pytest.raises(WorkbenchError, match="no bytes given"):
        object_layout(model, "k").resolve({})


def test_memory_bytes_read_from_the_first_span_by_address_that_holds_the_range():
    """The index (bisect over the spans' starts and the farthest end so far) answers as a scan of the sorted spans
    does, for every range over nested, overlapping and separate spans in two extensions; one built from another
    shares its index (a dataset of every calibration decodes thousands of objects from one read)."""
    from workbench.calib.memory import MemoryBytes

    spans = [Span(10, 20), Span(12, 4), Span(25, 10), Span(40, 3), Span(10, 5, 1), Span(11, 8, 1), Span(50, 0)]
    data = {span: bytes((span.address + i + 7 * n) % 256 for i in range(span.size)) for n, span in enumerate(spans)}
    memory = MemoryBytes(data)

    def scanned(address: int, size: int, extension: int) -> bytes | None:
        for span in sorted(spans, key=lambda s: (s.extension, s.address)):
            if span.extension == extension and span.address <= address and address + size <= span.end:
                return data[span][address - span.address:address - span.address + size]
        return None

    ranges = [(address, size, extension) for extension in (0, 1, 2) for address in range(5, 56) for size in range(12)]
    assert [memory.get(*r) for r in ranges] == [scanned(*r) for r in ranges]
    assert sum(memory.get(*r) is not None for r in ranges) > 200  # (most of them are held)
    assert MemoryBytes(memory)._spans is memory._spans and MemoryBytes(memory).read(26, 4) == memory.read(26, 4)
    with pytest.raises(WorkbenchError, match="no bytes given"):
        memory.read(28, 8)
