"""COMPU_METHODs both ways, with values computed by hand; pya2ldb as a second opinion; the formula
evaluator's operators, precedence and refusals."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from workbench.a2l import load_a2l, load_a2l_string
from workbench.a2l.formula import compile_formula
from workbench.errors import A2lParseError, ConversionError

FEATURES = Path(__file__).parent / "fixtures" / "model_features.a2l"


def module(body: str, name: str = "compu.a2l"):
    """A model of one MODULE holding ``body``."""
    text = f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n/begin MODULE M ""\n{body}\n/end MODULE\n/end PROJECT\n'
    return load_a2l_string(text, name).model()


def method(kind_and_rest: str, tables: str = ""):
    """The conversion of one COMPU_METHOD ``CM`` (its text after the format and unit)."""
    return module(f'/begin COMPU_METHOD CM "" {kind_and_rest} /end COMPU_METHOD\n{tables}').conversion("CM")


@pytest.fixture(scope="module")
def features():
    return load_a2l(FEATURES).model()


# -- numeric conversions ---------------------------------------------------------------------------------

def test_identity_keeps_integers_exact():
    identity = method('IDENTICAL "%5.0" "rpm"')
    assert identity.to_physical(7) == 7 and isinstance(identity.to_physical(7), int)
    assert identity.to_physical(2**64 - 1) == 2**64 - 1  # an A_UINT64 beyond float64's 53 bits
    assert identity.to_raw(np.array([1, 2], dtype=np.int16)).dtype == np.int16
    assert identity.to_physical(1.5) == 1.5 and identity.unit == "rpm" and identity.decimals == 0
    assert module("").conversion("NO_COMPU_METHOD").to_physical(-3) == -3
    with pytest.raises(ConversionError, match="'ON' is not a number"):
        identity.to_raw("ON")


def test_linear(features):
    linear = features.conversion("CM_lin")  # phys = 0.5 raw - 10
    assert linear.to_physical(3) == -8.5 and linear.to_raw(-8.5) == 3.0
    assert np.array_equal(linear.to_physical(np.array([[0, 2], [4, 6]])), [[-10, -9], [-8, -7]])
    assert linear.decimals == 3 and linear.unit == "bar"
    with pytest.raises(ConversionError, match="factor 0"):
        method('LINEAR "%5.0" "" COEFFS_LINEAR 0 4').to_raw(4.0)


def test_rat_func_is_raw_of_physical_and_reads_through_its_inverse(features):
    rat = features.conversion("CM_rat")  # raw = (4 phys + 8) / 2 = 2 phys + 4
    assert rat.to_raw(3.0) == 10.0 and rat.to_physical(10) == 3.0
    assert np.array_equal(rat.to_physical(np.array([4, 6, 8])), [0.0, 1.0, 2.0])
    assert method('RAT_FUNC "%5.0" "" COEFFS 0 1 0 0 0 1').to_physical(123456789) == 123456789  # exact identity
    hundredth = method('RAT_FUNC "%5.2" "" COEFFS 0 100 0 0 0 1')  # raw = 100 phys
    assert hundredth.to_physical(2550) == 25.5 and hundredth.to_raw(25.5) == 2550
    reciprocal = method('RAT_FUNC "%5.2" "" COEFFS 0 0 1000 0 1 0')  # raw = 1000 / phys
    assert reciprocal.to_raw(4.0) == 250.0 and reciprocal.to_physical(250) == 4.0


def test_rat_func_that_cannot_be_read_is_refused_clearly():
    quadratic = method('RAT_FUNC "%5.2" "" COEFFS 1 0 0 0 0 1')  # raw = phys^2
    assert quadratic.to_raw(3.0) == 9.0
    with pytest.raises(ConversionError, match="quadratic terms .* cannot be inverted"):
        quadratic.to_physical(9)
    with pytest.raises(ConversionError, match="is constant"):
        method('RAT_FUNC "%5.2" "" COEFFS 0 0 5 0 0 1').to_physical(5)


def test_tab_intp(features):
    table = features.conversion("CM_tab")  # 0 -> 0 V, 512 -> 2.5 V, 1023 -> 5 V, default -1
    assert table.to_physical(256) == 1.25 and table.to_physical(1023) == 5.0
    assert table.to_physical(2000) == -1.0 and table.to_physical(-1) == -1.0  # DEFAULT_VALUE_NUMERIC outside
    assert np.array_equal(table.to_raw(np.array([0.0, 1.25, 5.0])), [0.0, 256.0, 1023.0])
    with pytest.raises(ConversionError, match=r"outside its table's physical range \[0, 5\]"):
        table.to_raw(5.5)
    clamped = method('TAB_INTP "%5.2" "" COMPU_TAB_REF T',
                     '/begin COMPU_TAB T "" TAB_INTP 2 10 100 0 200 /end COMPU_TAB')  # decreasing, unsorted
    assert clamped.to_physical(20) == 100.0 and clamped.to_physical(-5) == 200.0  # no default: the ends
    assert clamped.to_raw(150.0) == 5.0
    folded = method('TAB_INTP "%5.2" "" COMPU_TAB_REF T', '/begin COMPU_TAB T "" TAB_INTP 3 0 0 1 1 2 0 /end COMPU_TAB')
    with pytest.raises(ConversionError, match="not strictly monotonic"):
        folded.to_raw(0.5)


def test_tab_nointp():
    table = method('TAB_NOINTP "%5.2" "" COMPU_TAB_REF T',
                   '/begin COMPU_TAB T "" TAB_NOINTP 3 1 10 2 20 4 40 DEFAULT_VALUE_NUMERIC 0 /end COMPU_TAB')
    assert table.to_physical(2) == 20.0 and table.to_physical(3) == 0.0
    assert np.array_equal(table.to_raw([40.0, 10.0]), [4.0, 1.0])
    with pytest.raises(ConversionError, match="25 is not a value of its table .*allowed: 10, 20, 40"):
        table.to_raw(25.0)
    bare = method('TAB_NOINTP "%5.2" "" COMPU_TAB_REF T', '/begin COMPU_TAB T "" TAB_NOINTP 1 1 10 /end COMPU_TAB')
    assert math.isnan(bare.to_physical(5))


# -- verbal tables -------------------------------------------------------------------------------------------

def test_tab_verb_both_ways(features):
    gear = features.conversion("CM_gear")
    assert gear.verbal and gear.allowed == ["neutral", "first", "second"]
    assert gear.to_physical(1) == "first" and gear.to_physical(7) == "invalid"  # DEFAULT_VALUE
    texts = gear.to_physical(np.array([[0, 2], [1, 1]]))
    assert texts.dtype == object and texts.tolist() == [["neutral", "second"], ["first", "first"]]
    assert gear.to_raw("second") == 2.0 and gear.to_raw(" first ") == 1.0
    assert np.array_equal(gear.to_raw(np.array(["first", 2], dtype=object)), [1.0, 2.0])  # a number is raw
    with pytest.raises(ConversionError, match=r"'third' is not one of its texts \(allowed: neutral, first, second\)"):
        gear.to_raw("third")


def test_a_text_that_differs_only_in_case_names_its_entry_when_alone():
    state = method('TAB_VERB "%3.0" "" COMPU_TAB_REF V',
                   '/begin COMPU_VTAB V "" TAB_VERB 4 0 "Low" 1 "High" 2 "OFF" 3 "off" /end COMPU_VTAB')
    assert state.to_raw("low") == 0.0 and state.to_raw(" HIGH ") == 1.0 and state.text_of("hIgH") == "High"
    assert state.to_raw("OFF") == 2.0 and state.to_raw("off") == 3.0  # exact texts first
    with pytest.raises(ConversionError, match=r"'Off' matches 'OFF', 'off', which differ only in case: write one"):
        state.to_raw("Off")
    assert state.text_of("medium") is None


def test_a_raw_value_without_text_stays_a_number():
    onoff = method('TAB_VERB "%3.0" "" COMPU_TAB_REF V', '/begin COMPU_VTAB V "" TAB_VERB 2 0 "OFF" 1 "ON" /end COMPU_VTAB')
    assert onoff.to_physical(5) == 5 and onoff.to_physical(np.array([1, 3])).tolist() == ["ON", 3]


def test_tab_verb_ranges(features):
    level = features.conversion("CM_level")  # [0, 9] low, [10, 20] high
    assert [level.to_physical(v) for v in (0, 9, 9.5, 10, 20, 21)] == ["low", "low", 9.5, "high", "high", 21]
    assert level.to_raw("high") == 10.0
    fractional = method('TAB_VERB "%3.0" "" COMPU_TAB_REF R',
                        '/begin COMPU_VTAB_RANGE R "" 2 0.5 3 "a" 3.2 3.4 "b" DEFAULT_VALUE "none" /end COMPU_VTAB_RANGE')
    assert fractional.to_raw("a") == 1.0  # the range's lowest integer: what an integer type can hold
    assert fractional.to_raw("b") == 3.2  # a range without an integer: its lower bound
    assert fractional.to_physical(0) == "none"


# -- formulas ------------------------------------------------------------------------------------------------

def test_form_with_inverse_and_system_constants(features):
    form = features.conversion("CM_form")  # X1 * 0.1 - 40, inverse (X1 + 40) * 10
    assert form.to_physical(650) == 25.0 and form.to_raw(25.0) == 650.0
    assert np.allclose(form.to_physical(np.arange(3) * 100), [-40, -30, -20])
    gain = module('/begin MOD_PAR "" SYSTEM_CONSTANT "Gain" "2.5" /end MOD_PAR\n'
                  '/begin COMPU_METHOD CM "" FORM "%5.2" "" /begin FORMULA "X1 * sysc(Gain)" /end FORMULA /end COMPU_METHOD')
    assert gain.conversion("CM").to_physical(4) == 10.0


def test_form_without_inverse_is_inverted_numerically_where_it_can_be():
    root = method('FORM "%5.2" "" /begin FORMULA "sqrt(X1) * 2" /end FORMULA')
    assert np.array_equal(root.to_raw(np.array([2.0, 6.0, 10.0]), datatype="UWORD"), [1.0, 9.0, 25.0])
    assert root.to_raw(6.1, datatype="UWORD") == 9.0  # the nearest raw value; the codec rounds nothing more
    falling = method('FORM "%5.2" "" /begin FORMULA "100 - X1 / 2" /end FORMULA')
    assert falling.to_raw(90.0, datatype="SBYTE") == 20.0
    affine = method('FORM "%5.2" "" /begin FORMULA "X1 * 0.25 + 1" /end FORMULA')
    assert affine.to_raw(2.0, datatype="FLOAT32_IEEE") == 4.0
    with pytest.raises(ConversionError, match="not linear"):
        root.to_raw(2.0, datatype="FLOAT32_IEEE")
    with pytest.raises(ConversionError, match="not monotonic"):
        method('FORM "%5.2" "" /begin FORMULA "X1 * X1" /end FORMULA').to_raw(4.0, datatype="SBYTE")
    with pytest.raises(ConversionError, match="beyond what FORM"):
        root.to_raw(1000.0, datatype="UBYTE")
    with pytest.raises(ConversionError, match="known data type"):
        root.to_raw(2.0)


@pytest.mark.parametrize("text, x, expected", [
    ("X1 * 0.1 - 40", 650, 25.0),
    ("(X1 >> 4) & 0x0F", 0xAB, 0xA),
    ("X1 & 12 | 1", 0b1110, 0b1101),  # & binds tighter than |
    ("X1 & 0x0F == 3", 0x13, 0.0),  # C: == binds tighter than &: X1 & (0x0F == 3) -> X1 & 0
    ("~X1 & 0xFF", 0x0F, 0xF0),
    ("X1 ^ 5", 6, 3),  # bitwise exclusive or
    ("!X1", 0, 1.0),
    ("!X1 == 0", 5, 1.0),  # (!X1) == 0
    ("X1 < 3 && X1 > 1", 2, 1.0),
    ("X1 < 3 || X1 > 10", 5, 0.0),
    ("1 + 2 << 1", 0, 6.0),  # + binds tighter than <<
    ("-X1 * 2", 3, -6.0),
    ("2 - -X1", 3, 5.0),
    ("X1 % 3", 7, 1.0),
    ("pow(X1, 2) + abs(-1) + min(X1, 1) + max(X1, 10)", 3, 21.0),
    ("floor(X1 / 2) + ceil(X1 / 2)", 3, 3.0),
    ("sqrt(X1) + log10(100) + log(exp(1)) + mod(7, 4)", 16, 10.0),
    ("sin(0) + cos(0) + tan(0) + asin(0) + acos(1) + atan(0) + sinh(0) + cosh(0) + tanh(0)", 0, 2.0),
    ("arcsin(0) + arccos(1) + arctan(0)", 0, 0.0),
    ("X * 2 + x1", 3, 9.0),  # X is X1; names ignore case
    ("1.5e1 + .5 + 0x10", 0, 31.5),
])
def test_formula_operators_and_precedence(text, x, expected):
    assert compile_formula(text)(x) == pytest.approx(expected)


@pytest.mark.parametrize("text, message", [
    ("__import__(X1)", "unknown name '__import__'"),
    ("__import__('os').system('true')", "unexpected \"'\""),
    ("X1.__class__", "unexpected '.'"),
    ("open(X1)", "unknown name 'open'"),
    ("lambda: 1", "unexpected ':'"),
    ("X1; X1", "unexpected ';'"),
    ("[1]", "unexpected '\\['"),
    ("X1 ? 1 : 2", "unexpected '\\?'"),
    ("sin(X1, 2)", "takes 1 argument"),
    ("(X1 + 1", "expected '\\)'"),
    ("X1 +", "unexpected end"),
    ("", "empty"),
    ("sysc(Missing)", "no SYSTEM_CONSTANT 'Missing'"),
    ("(" * 60 + "1" + ")" * 60, "nested too deeply"),
    ("sin(" * 60 + "1" + ")" * 60, "nested too deeply"),
    ("-" * 300 + "1", "nested too deeply"),
])
def test_a_formula_never_runs_code_and_says_what_is_wrong(text, message):
    with pytest.raises(ConversionError, match=message):
        compile_formula(text)


def test_a_formula_vectorizes():
    formula = compile_formula("X1 * 2 + 1")
    assert np.array_equal(formula(np.arange(4).reshape(2, 2)), [[1, 3], [5, 7]])
    assert formula(np.array([], dtype=np.float64)).shape == (0,)


# -- what a COMPU_METHOD lacks is located -------------------------------------------------------------------

def test_a_broken_compu_method_is_located():
    model = module('/begin COMPU_METHOD A "" LINEAR "%5.2" "" /end COMPU_METHOD\n'
                   '/begin COMPU_METHOD B "" TAB_VERB "%5.2" "" COMPU_TAB_REF NOPE /end COMPU_METHOD\n'
                   '/begin COMPU_METHOD C "" FORM "%5.2" "" /begin FORMULA "X1 +* 2" /end FORMULA /end COMPU_METHOD\n'
                   '/begin COMPU_METHOD D "" TAB_VERB "%5.2" "" COMPU_TAB_REF T /end COMPU_METHOD\n'
                   '/begin COMPU_TAB T "" TAB_INTP 1 0 0 /end COMPU_TAB', "broken.a2l")
    with pytest.raises(A2lParseError, match="broken.a2l:4:1: COMPU_METHOD A: LINEAR needs COEFFS_LINEAR"):
        model.conversion("A")
    with pytest.raises(A2lParseError, match="broken.a2l:5:59: COMPU_METHOD B: COMPU_TAB 'NOPE' is not defined"):
        model.conversion("B")
    with pytest.raises(A2lParseError, match=r"broken.a2l:6:1: formula 'X1 \+\* 2': unexpected '\*' at character 5"):
        model.conversion("C")
    with pytest.raises(A2lParseError, match="TAB_VERB needs a COMPU_TAB_REF to a COMPU_VTAB"):
        model.conversion("D")


def test_conversions_are_built_once(features):
    assert features.conversion("CM_lin") is features.conversion(features.characteristic("kValue"))


# -- properties -----------------------------------------------------------------------------------------------

finite = st.floats(-1e6, 1e6, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e3, 1e3).filter(lambda a: abs(a) > 1e-3), finite, finite)
def test_linear_round_trips(a, b, physical):
    linear = method(f'LINEAR "%5.2" "" COEFFS_LINEAR {a!r} {b!r}')
    assert linear.to_physical(linear.to_raw(physical)) == pytest.approx(physical, rel=1e-9, abs=1e-6)


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e3, 1e3).filter(lambda b: abs(b) > 1e-3), finite, st.floats(0.01, 1e3), finite)
def test_rat_func_round_trips(b, c, f, physical):
    rat = method(f'RAT_FUNC "%5.2" "" COEFFS 0 {b!r} {c!r} 0 0 {f!r}')
    assert rat.to_physical(rat.to_raw(physical)) == pytest.approx(physical, rel=1e-9, abs=1e-6)


# -- pya2ldb's reading of the same methods ---------------------------------------------------------------------

def test_pya2ldb_converts_the_same(features):
    from pya2l_oracle import pya2l_describe

    samples = {"CM_lin": {"raw": [0, 3, -7, 1000], "physical": [10.0, -8.5]},
               "CM_rat": {"raw": [10, 3, 4, 8000], "physical": [3.0, -0.5]},
               "CM_gear": {"raw": [0, 1, 2, 5], "physical": ["second", "neutral"]},
               "CM_level": {"raw": [0, 5, 10, 20], "physical": ["high", "low"]}}
    oracle = pya2l_describe(FEATURES, {"conversions": samples})["conversions"]
    assert set(oracle) == set(samples)  # TAB_INTP and FORM need scipy, which pya2ldb leaves out
    for name, sample in samples.items():
        ours = features.conversion(name)
        assert [ours.to_physical(raw) for raw in sample["raw"]] == oracle[name]["physical"], name
        assert [ours.to_raw(value) for value in sample["physical"]] == oracle[name]["raw"], name
