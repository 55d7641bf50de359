"""What the views read from the A2L: the decimals of values and axis points (one rule for every view)."""

from __future__ import annotations

import pytest

from workbench import demo
from workbench.a2l import load_a2l_string
from workbench.gui.a2l_info import calibration_info, value_decimals

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
