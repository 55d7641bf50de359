"""Display formats: ASAP2's "%Length.Layout" and what files in the wild write instead, read alike by every view;
``a2l check`` warns where a format is not ASAP2's form, at its string."""

from __future__ import annotations

import pytest

from workbench.a2l import check_document, load_a2l_string
from workbench.a2l.display_format import format_parts, format_problem


@pytest.mark.parametrize(("text", "parts"), [
    ("%8.3", (8, 3)), ("%.3", (None, 3)), ("%.0 ", (None, 0)),  # ASAP2's, a2ltool's and XCPlite's
    ("%8.3f", (8, 3)), ("%6.2lf", (6, 2)), ("% 8.3", (8, 3)), ("%5d", (5, 0)),  # C's, read for what they say
    ("%8", (8, None)), ("%10.3e", (10, None)), ("%0*x", (None, None)), ("8.3", (None, None)), (None, (None, None)),
    ("%8.20", (8, 17)), ("%.25lf", (None, 17)),  # beyond a FLOAT64's 17 significant digits: 17 shown
])
def test_formats_are_read_leniently(text, parts):
    assert format_parts(text) == parts


def test_asap2_form_and_the_length_left_out_are_accepted_c_conversions_are_not():
    assert [format_problem(text) for text in ("%8.3", "%.3", "%.0 ")] == [None, None, None]
    assert format_problem("%6.2lf") == ('FORMAT "%6.2lf" is not ASAP2\'s "%Length.Layout": read as "%6.2" '
                                        "(2 decimals); write it so")
    assert "as many decimals as they need" in format_problem("%8")


A2L = """/begin PROJECT P ""
/begin MODULE M ""
/begin COMPU_METHOD CM "" IDENTICAL "%6.2lf" "bar" /end COMPU_METHOD
/begin COMPU_METHOD CM_ok "" IDENTICAL "%.3" "bar" /end COMPU_METHOD
/begin MEASUREMENT m "" UBYTE CM_ok 0 0 0 255 FORMAT "%8.3f" ECU_ADDRESS 0x1000 /end MEASUREMENT
/begin CHARACTERISTIC c "" CURVE 0x2000 RL 0 CM_ok 0 255 FORMAT "%8.3"
  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY CM_ok 4 0 255 FORMAT "%d" /end AXIS_DESCR
/end CHARACTERISTIC
/begin RECORD_LAYOUT RL NO_AXIS_PTS_X 1 UBYTE AXIS_PTS_X 2 UBYTE INDEX_INCR DIRECT FNC_VALUES 3 UBYTE COLUMN_DIR DIRECT
/end RECORD_LAYOUT
/end MODULE
/end PROJECT
"""


def test_check_warns_at_each_format_that_is_not_asap2s():
    report = check_document(load_a2l_string(A2L, "wild.a2l"))
    found = [(f.kind, f.name, f.block, f.line, f.column, f.severity.name) for f in report.findings]
    lines = A2L.splitlines()
    at = [(line, lines[line - 1].index(text) + 1) for line, text in ((3, '"%6.2lf"'), (5, '"%8.3f"'), (7, '"%d"'))]
    assert found == [("format", "CM", "COMPU_METHOD", *at[0], "WARNING"),
                     ("format", "m", "MEASUREMENT", *at[1], "WARNING"),
                     ("format", "c", "AXIS_DESCR", *at[2], "WARNING")]  # an axis names its CHARACTERISTIC
    assert [f.message.partition(" is not")[0] for f in report.findings] == [  # each names its object
        'COMPU_METHOD CM: format "%6.2lf"', 'MEASUREMENT m: FORMAT "%8.3f"', 'CHARACTERISTIC c AXIS_DESCR: FORMAT "%d"']
    assert not report.ok


def test_check_warns_at_a_layout_beyond_what_a_value_holds_or_its_length():
    text = A2L.replace('FORMAT "%8.3f"', 'FORMAT "%8.20"').replace('FORMAT "%8.3"', 'FORMAT "%4.6"')
    report = check_document(load_a2l_string(text, "wide.a2l"))
    lines = text.splitlines()
    found = {f.name: (f.line, f.column, f.message) for f in report.findings if f.block != "AXIS_DESCR"}
    m_message = ('MEASUREMENT m: FORMAT "%8.20": 20 decimals are more than a FLOAT64 holds (about 17 significant '
                 "digits): shown with 17")
    c_message = 'CHARACTERISTIC c: FORMAT "%4.6": 6 decimals are more than its Length of 4 characters: write "%8.6"'
    assert found["m"] == (5, lines[4].index('"%8.20"') + 1, m_message)
    assert found["c"] == (6, lines[5].index('"%4.6"') + 1, c_message)
