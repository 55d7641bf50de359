"""What the views read from the A2L: the decimals of values and axis points (one rule for every view)."""

from __future__ import annotations

import pytest

from workbench import demo
from workbench.a2l import load_a2l_string
from workbench.gui.a2l_info import calibration_info, measurement_info, value_decimals

AXIS_PTS = "      /* Name                   */ xaPRV_FF_TARGET\n"
END_OF_AXIS_PTS = "      /* Upper Limit            */ 50\n    /end AXIS_PTS"
MANIFOLD_AXIS = "        AXIS_PTS_REF xaPRV_FF_MANIFOLD\n"


@pytest.fixture(scope="module")
def model():
    """The demo A2L with FORMATs of its own on a map's axes: the AXIS_PTS of X "%5.1", the AXIS_DESCR of Y "%4.0"
    (its AXIS_PTS has none: CM_bar's "%8.2" would be next)."""
    text = demo.a2l().read_text(encoding="utf-8")
    at = text.index(END_OF_AXIS_PTS, text.index(AXIS_PTS))
    text = text[:at] + "      /* Upper Limit            */ 50\n      FORMAT \"%5.1\"\n    /end AXIS_PTS" + \
        text[at + len(END_OF_AXIS_PTS):]
    text = text.replace(MANIFOLD_AXIS, MANIFOLD_AXIS + "        FORMAT \"%4.0\"\n", 1)
    return load_a2l_string(text, "formats.a2l").model()


def test_an_axis_reads_its_own_format_then_its_axis_pts_format_then_its_conversions(model):
    info = calibration_info(model, "xvPRV_DC_FF")
    assert info.axis_decimals == (1, 0) and info.decimals == 2
    # the compare view's elements by the same rule
    assert [value_decimals(model, "xvPRV_DC_FF", where) for where in ("x[2]", "y", "value[1, 2]")] == [1, 0, 2]
    assert calibration_info(model, "zvRailPConv").axis_decimals == (3,)  # a STD_AXIS: its conversion's "%6.3"
    assert calibration_info(model, "xsSWITCH_TANK_THR").axis_decimals == ()


FLAGS = """
    /begin MEASUREMENT tFlag "a flag without texts" UBYTE CM_Identity 0 0 0 1 ECU_ADDRESS 0x1000 /end MEASUREMENT
    /begin MEASUREMENT tBit "bit 3 of a status byte" UBYTE CM_Identity 0 0 0 255 ECU_ADDRESS 0x1001
      BIT_MASK 0x08 /end MEASUREMENT
    /begin MEASUREMENT tSignedBit "a signed one-bit field" SBYTE CM_Identity 0 0 -1 0 ECU_ADDRESS 0x1002
      BIT_MASK 0x01 /end MEASUREMENT
    /begin MEASUREMENT tTwoBits "a two-bit field" UBYTE CM_Identity 0 0 0 3 ECU_ADDRESS 0x1003
      BIT_MASK 0x06 /end MEASUREMENT
    /begin MEASUREMENT tScaled "0 .. 1 in steps of 0.01" UBYTE CM_CAN_0p01_Percent 0 0 0 1 ECU_ADDRESS 0x1004
      /end MEASUREMENT
    /begin MEASUREMENT tRatio "a float 0 .. 1" FLOAT32_IEEE CM_Identity 0 0 0 1 ECU_ADDRESS 0x1008 /end MEASUREMENT
    /begin MEASUREMENT tCount "a count" UWORD CM_Identity 0 0 0 1000 ECU_ADDRESS 0x100C /end MEASUREMENT
    /begin MEASUREMENT tFlags "four flags" UBYTE CM_Identity 0 0 0 1 ECU_ADDRESS 0x1010
      MATRIX_DIM 4 1 1 /end MEASUREMENT
"""


def test_two_state_signals_are_integer_flags_of_limits_0_1_and_one_bit_fields_nothing_else():
    text = demo.a2l().read_text(encoding="utf-8")
    at = text.index("/begin MEASUREMENT")
    flags = load_a2l_string(text[:at] + FLAGS.strip() + "\n    " + text[at:], "flags.a2l").model()
    zero_one = ((0.0, "0"), (1.0, "1"))
    found = {name: measurement_info(flags, name).two_states for name in
             ("tFlag", "tBit", "tSignedBit", "tTwoBits", "tScaled", "tRatio", "tCount", "tFlags")}
    assert found == {"tFlag": zero_one, "tBit": zero_one, "tSignedBit": ((-1.0, "-1"), (0.0, "0")), "tTwoBits": (),
                     "tScaled": (), "tRatio": (), "tCount": (), "tFlags": ()}
    valve = measurement_info(flags, "xsValve1State")  # texts of its own: those label its lane
    assert valve.two_states == () and valve.lane_states == valve.states == ((0.0, "OFF"), (1.0, "ON"))
    assert measurement_info(flags, "CANRX_PCM_TO_FLCU_001_Pdu.TimeOut").lane_states == zero_one
    assert measurement_info(flags, "zsRailPressure").lane_states == ()


def test_objects_of_more_than_two_dimensions_are_refused_with_what_to_use_instead():
    """A VAL_BLK of MATRIX_DIM 2 3 4 crashed its editor (pyqtgraph: shape (2, 3, 4)), a CUBOID showed as a scalar."""
    from pathlib import Path

    from workbench.a2l import load_a2l
    from workbench.errors import InputError

    model = load_a2l(Path(__file__).parents[1] / "a2l" / "fixtures" / "model_features.a2l").model()
    with pytest.raises(InputError, match=r"^kBlock is a VAL_BLK of MATRIX_DIM 2 3 4: .*`workbench cal get kBlock`"):
        calibration_info(model, "kBlock")
    with pytest.raises(InputError, match=r"^kCube is a CUBOID: the window's editors show values, curves, maps"):
        calibration_info(model, "kCube")
    assert calibration_info(model, "kMap").type == "MAP"
