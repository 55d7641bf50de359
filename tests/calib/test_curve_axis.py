"""CURVE_AXIS: the rescale curve maps the axis' input to a map index (ASAM MCD-2MC, AXIS_DESCR and its
Appendix B), so point k of the map's axis is the input at which the curve gives k.

The worked example is the standard's Appendix B (as asamint's tests/test_curve_axis.py carries it):
X_NORM takes 850 to index 3.9 and Y_NORM takes 60 to 1.7, and the 7 x 6 map Z_MAP gives 2.194 there."""

from __future__ import annotations

import numpy as np
import pytest

from workbench.a2l import load_a2l_string
from workbench.calib import Axis, CalValue, Span, object_layout, read_spans, read_value
from workbench.calib.codec import curve_axis_points
from workbench.calib.limits import check_limits
from workbench.errors import ConversionError

X_NORM = ([0.0, 200.0, 400.0, 1000.0, 5700.0], [2.0, 2.7, 3.0, 4.2, 4.9])
Y_NORM = ([0.0, 50.0, 70.0, 100.0], [0.5, 1.0, 2.4, 4.2])
Z_MAP = np.array([[3.4, 4.5, 2.1, 5.4, 1.2, 3.4, 4.4],  # 6 rows (Y) of 7 columns (X), as the standard prints it
                  [2.3, 1.2, 1.2, 5.6, 3.2, 2.1, 7.8],
                  [3.2, 1.5, 3.2, 2.2, 1.6, 1.7, 1.7],
                  [2.1, 0.4, 1.1, 1.5, 1.8, 3.2, 1.5],
                  [1.1, 4.3, 2.1, 4.6, 1.2, 1.4, 3.2],
                  [1.2, 5.3, 3.2, 3.5, 2.1, 1.4, 4.2]])
CURVE = '''/begin CHARACTERISTIC {name} "" CURVE {address} NORM 0 NO_COMPU_METHOD 0 10
  /begin AXIS_DESCR STD_AXIS {quantity} NO_COMPU_METHOD {points} 0 10000 PHYS_UNIT "{unit}" /end AXIS_DESCR
/end CHARACTERISTIC'''
A2L = f'''ASAP2_VERSION 1 71
/begin PROJECT P ""
/begin MODULE M ""
/begin MOD_COMMON "" BYTE_ORDER MSB_LAST /end MOD_COMMON
/begin RECORD_LAYOUT NORM NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 FLOAT64_IEEE INDEX_INCR DIRECT
  FNC_VALUES 3 FLOAT64_IEEE COLUMN_DIR DIRECT /end RECORD_LAYOUT
/begin RECORD_LAYOUT FIXED3 AXIS_PTS_X 1 FLOAT64_IEEE INDEX_INCR DIRECT FNC_VALUES 2 FLOAT64_IEEE COLUMN_DIR DIRECT
  FIX_NO_AXIS_PTS_X 3 /end RECORD_LAYOUT
/begin RECORD_LAYOUT VALUES FNC_VALUES 1 FLOAT64_IEEE COLUMN_DIR DIRECT /end RECORD_LAYOUT
{CURVE.format(name="X_NORM", address="0x100", quantity="N", points=8, unit="rpm")}
{CURVE.format(name="Y_NORM", address="0x200", quantity="L", points=8, unit="%")}
/begin CHARACTERISTIC Z_MAP "" MAP 0x300 VALUES 0 NO_COMPU_METHOD 0 10
  /begin AXIS_DESCR CURVE_AXIS N NO_COMPU_METHOD 7 0 6 CURVE_AXIS_REF X_NORM /end AXIS_DESCR
  /begin AXIS_DESCR CURVE_AXIS L NO_COMPU_METHOD 6 0 5 CURVE_AXIS_REF Y_NORM /end AXIS_DESCR
/end CHARACTERISTIC
/begin CHARACTERISTIC N3 "" CURVE 0x500 FIXED3 0 NO_COMPU_METHOD 0 10
  /begin AXIS_DESCR STD_AXIS N NO_COMPU_METHOD 3 0 10000 /end AXIS_DESCR
/end CHARACTERISTIC
/begin CHARACTERISTIC ON_N3 "" CURVE 0x600 VALUES 0 NO_COMPU_METHOD 0 255
  /begin AXIS_DESCR CURVE_AXIS N NO_COMPU_METHOD 3 0 2 CURVE_AXIS_REF N3 /end AXIS_DESCR
/end CHARACTERISTIC
/begin CHARACTERISTIC WIDE_ON_N3 "" CURVE 0x700 VALUES 0 NO_COMPU_METHOD 0 255
  /begin AXIS_DESCR CURVE_AXIS N NO_COMPU_METHOD 4 0 3 CURVE_AXIS_REF N3 /end AXIS_DESCR
/end CHARACTERISTIC
/end MODULE
/end PROJECT
'''


def _curve(xs, ys) -> bytes:
    """NO_AXIS_PTS_X, then (aligned to 8) the axis points and the values, each as many as there are points."""
    return bytes([len(xs)]) + bytes(7) + np.array(xs + ys, "<f8").tobytes()


class Memory:
    def __init__(self):
        self.bytes = bytearray(0x1000)
        for address, data in ((0x100, _curve(*X_NORM)), (0x200, _curve(*Y_NORM)),
                              (0x300, Z_MAP.astype("<f8").tobytes()),  # COLUMN_DIR: X fastest, a row of Z_MAP each
                              (0x500, np.array([800, 1600, 3200, 0, 1, 2], "<f8").tobytes()),
                              (0x600, bytes(range(3 * 8)))):
            self.bytes[address:address + len(data)] = data

    def read(self, span: Span) -> bytes:
        return bytes(self.bytes[span.address:span.end])


@pytest.fixture(scope="module")
def model():
    return load_a2l_string(A2L, "curve_axis.a2l").model()


def test_point_k_is_where_the_rescale_curve_gives_index_k(model):
    value = read_value(model, "Z_MAP", Memory().read)
    x, y = value.axes
    assert value.shape == (7, 6)  # the map's own counts, not the curves' 5 and 4 points
    assert (x.kind, x.name, x.unit, x.input_quantity) == ("CURVE_AXIS", "X_NORM", "rpm", "N")
    assert np.allclose(x.values, [np.nan, np.nan, 0, 400, 900, np.nan, np.nan], equal_nan=True)
    assert np.allclose(y.values, [np.nan, 50, 50 + 20 / 1.4, 80, 70 + 1.6 * 30 / 1.8, np.nan], equal_nan=True)
    for axis, (inputs, indices) in ((x, X_NORM), (y, Y_NORM)):  # the ECU's normalization lands on k at point k
        reached = ~np.isnan(axis.values)
        assert np.allclose(np.interp(axis.values[reached], inputs, indices), np.flatnonzero(reached))


def test_the_worked_example_of_the_standard(model):
    """850 rpm and 60 % looked up over the axes as read give the standard's 2.194."""
    value = read_value(model, "Z_MAP", Memory().read)
    index = []
    for axis, position in zip(value.axes, (850.0, 60.0)):
        reached = ~np.isnan(axis.values)
        index.append(np.interp(position, axis.values[reached], np.flatnonzero(reached)))
    assert index == pytest.approx([3.9, 1.7])
    (i, fx), (j, fy) = ((int(k), k - int(k)) for k in index)
    grid = value.value  # indexed [x, y]
    low, high = (grid[i, k] * (1 - fx) + grid[i + 1, k] * fx for k in (j, j + 1))
    z = low * (1 - fy) + high * fy
    assert z == pytest.approx(2.194)


def test_written_points_make_the_curve_give_each_index_there(model):
    memory = Memory()
    layout = object_layout(model, "ON_N3").resolve()
    current = read_spans(layout.spans(), memory.read)
    value = layout.decode(current)
    assert list(value.axes[0].values) == [800, 1600, 3200]  # the CDF 2.0 demo's case: curve 0, 1, 2 at its points
    assert layout.encode(value, current) == []  # the same points: nothing to write
    moved = CalValue("ON_N3", "CURVE", value.value, (Axis(np.array([800.0, 2000, 3200]), "CURVE_AXIS"),))
    edits = layout.encode(moved, current)
    assert [(e.name, e.field, e.address) for e in edits] == [("N3", "AXIS_PTS_X", 0x508)]  # the curve's axis alone
    for edit in edits:
        memory.bytes[edit.address:edit.address + len(edit.data)] = edit.data
    assert list(read_value(model, "ON_N3", memory.read).axes[0].values) == [800, 2000, 3200]
    assert list(read_value(model, "N3", memory.read).value) == [0, 1, 2]


def test_a_rescale_curve_takes_the_length_memory_lets_it_have(model):
    memory = Memory()
    layout = object_layout(model, "Z_MAP")
    resolved = layout.resolve(read_spans(layout.fixed_part(), memory.read))
    value = resolved.decode(read_spans(resolved.spans(), memory.read))
    points = np.arange(7) * 100.0
    edits = resolved.encode(CalValue("Z_MAP", "MAP", value.value, (Axis(points), value.axes[1])),
                            read_spans(resolved.spans(), memory.read))
    assert {e.name for e in edits} == {"X_NORM"}  # X_NORM's count lies in memory: it grows from 5 to 7 points
    for edit in edits:
        memory.bytes[edit.address:edit.address + len(edit.data)] = edit.data
    assert list(read_value(model, "Z_MAP", memory.read).axes[0].values) == list(points)
    assert list(read_value(model, "X_NORM", memory.read).value) == list(range(7))

    wide = object_layout(model, "WIDE_ON_N3").resolve()
    current = read_spans(wide.spans(), memory.read)
    assert np.allclose(wide.decode(current).axes[0].values, [800, 1600, 3200, np.nan], equal_nan=True)
    with pytest.raises(ConversionError, match="axis X is a CURVE_AXIS; its 4 points would make the rescale curve N3 "
                                              r"\(input -> index\) 4 points long, and it has 3 that memory cannot "
                                              "change: write N3 itself"):
        wide.encode(CalValue("WIDE_ON_N3", "CURVE", np.zeros(4), (Axis(np.array([1.0, 2, 3, 4])),)), current)


def test_limits_come_from_the_rescale_curves_axis(model):
    value = read_value(model, "ON_N3", Memory().read)
    assert check_limits(model, value) == []  # 3200 rpm: beyond the AXIS_DESCR's 0..2 (index units), within N3's axis
    unreached = read_value(model, "Z_MAP", Memory().read)
    assert check_limits(model, unreached) == []  # NaN: an index the curve never reaches
    beyond = CalValue("ON_N3", "CURVE", value.value, (Axis(np.array([800.0, 1600, 12000])),))
    assert [v.message for v in check_limits(model, beyond)] == [
        "ON_N3 axis X (N3): 12000 at [2] is above the upper limit 10000"]


def test_curve_axis_points():
    assert list(curve_axis_points([10, 20, 30], [0, 1, 2], 3)) == [10, 20, 30]
    assert list(curve_axis_points([10, 20], [2, 0], 3)) == [20, 15, 10]  # a falling curve
    assert np.isnan(curve_axis_points([10, 20], [0, 1], 3)[2])
