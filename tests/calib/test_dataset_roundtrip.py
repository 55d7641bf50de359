"""Round trips keep every value exactly: the demo ECU's calibrations and random datasets, DCM and CDFX either way."""

from __future__ import annotations

import math
import string
from dataclasses import replace

import numpy as np
from demo_calibrations import demo_dataset
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from workbench.calib.dataset import dump_dataset, load_dataset_string
from workbench.calib.dataset.model import Dataset, ObjectInfo
from workbench.calib.values import Axis, CalValue


def trip(dataset: Dataset, *formats: str) -> Dataset:
    for fmt in formats:
        dataset = load_dataset_string(dump_dataset(dataset, fmt), fmt, f"trip.{fmt}")
    return dataset


def assert_same(a: Dataset, b: Dataset) -> None:
    """Same names in the same order, equal values (and axes, units, long names), same number types."""
    assert list(a) == list(b)
    for name in a:
        assert b[name] == a[name], name
        assert b[name].comment == a[name].comment, name
        va, vb = a[name].value, b[name].value
        if isinstance(va, np.ndarray):
            assert vb.dtype.kind == va.dtype.kind, name
            floats = va.dtype.kind == "f"
            assert not floats or np.array_equal(np.signbit(va), np.signbit(vb)), name
        else:
            assert type(vb) is type(va), name
            assert not isinstance(va, float) or math.copysign(1, va) == math.copysign(1, vb), name


def test_every_demo_calibration_survives_dcm_cdfx_and_both_ways():
    demo = demo_dataset()
    assert len(demo) == 58  # the 56 CHARACTERISTICs and 2 AXIS_PTS of assets/FLCU.a2l
    for formats in (("dcm",), ("cdfx",), ("dcm", "cdfx"), ("cdfx", "dcm"), ("dcm", "cdfx", "dcm", "cdfx")):
        back = trip(demo, *formats)
        assert_same(demo, back)
        assert [back.info[n].functions for n in back] == [demo.info[n].functions for n in demo]
        assert {n: f.version for n, f in back.functions.items()} == {n: f.version for n, f in demo.functions.items()}


def test_dcm_metadata_survives_a_dcm_trip():
    text = ('* header\nKONSERVIERUNG_FORMAT 2.0\nMODULKOPF P "x"\nVARIANTENKODIERUNG\n KRITERIUM E a b\nEND\n'
            'FUNKTIONEN\n FKT F "1" "long"\nEND\nFESTWERT v\n LANGNAME "l"\n DISPLAYNAME d\n VAR E=a\n FUNKTION F\n'
            '* c\n EINHEIT_W "u"\n WERT 1\nEND\n')
    ds = load_dataset_string(text, "dcm")
    back = trip(ds, "dcm")
    for attribute in ("comments", "module_header", "variant_criteria", "functions"):
        assert getattr(back, attribute) == getattr(ds, attribute)
    positions = {"line": 0, "value_line": 0, "value_runs": ()}  # where the values stand: not metadata
    assert replace(back.info["v"], **positions) == replace(ds.info["v"], **positions)


# ---- random datasets ----

_NAME = st.from_regex(r"[A-Za-z_][A-Za-z0-9_.]{0,12}", fullmatch=True)
# letters (umlauts, CJK ...), digits, punctuation (quotes, backslashes), symbols, spaces; no control characters
_TEXT = st.text(st.characters(categories=("L", "N", "P", "S", "Zs"), exclude_characters="\x85\u2028\u2029"), max_size=12)
_LABEL = _TEXT.map(str.strip)  # long names and units are labels: their outer spaces are not kept
_FLOAT = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, -1.7976931348623157e308,
     0.1, 1e16, 1e-7, 123456789.123456789])
_INT = st.integers(-(2**63), 2**63 - 1) | st.sampled_from([0, -1, 2**31 - 1, -(2**31), 2**63 - 1, -(2**63)])


@st.composite
def _array(draw, size: int) -> np.ndarray:
    kind = draw(st.sampled_from(["float", "int", "uint64", "text", "mixed"]))
    if kind == "float":
        return np.array(draw(st.lists(_FLOAT, min_size=size, max_size=size)), dtype=np.float64)
    if kind == "int":
        return np.array(draw(st.lists(_INT, min_size=size, max_size=size)), dtype=np.int64)
    if kind == "uint64":
        return np.array(draw(st.lists(st.integers(2**63, 2**64 - 1), min_size=size, max_size=size)), dtype=np.uint64)
    items = draw(st.lists(_TEXT if kind == "text" else st.one_of(_TEXT, st.integers(-1000, 1000)),
                          min_size=size, max_size=size))
    if kind == "mixed" and not any(isinstance(i, str) for i in items):
        items[0] = "text"
    array = np.empty(size, dtype=object)
    array[:] = items
    return array


def _numeric_axis(draw, size: int, kind: str, name: str | None) -> Axis:
    points = draw(st.lists(st.floats(-1e6, 1e6) | st.integers(-1000, 1000), min_size=size, max_size=size))
    dtype = np.int64 if all(isinstance(p, int) for p in points) else np.float64
    return Axis(np.array(points, dtype=dtype), kind, name, draw(_LABEL))


@st.composite
def calibration(draw, name: str) -> CalValue:
    kind = draw(st.sampled_from(["VALUE", "ASCII", "VAL_BLK", "CURVE", "MAP", "AXIS_PTS"]))
    unit, long_name = draw(_LABEL), draw(_LABEL)
    if kind == "VALUE":
        return CalValue(name, kind, draw(_FLOAT | _INT | _TEXT), unit=unit, comment=long_name)
    if kind == "ASCII":
        return CalValue(name, kind, draw(_TEXT), comment=long_name)
    if kind == "AXIS_PTS":
        return CalValue(name, kind, _numeric_axis(draw, draw(st.integers(1, 8)), "STD_AXIS", None).values, unit=unit,
                        comment=long_name)
    nx = draw(st.integers(1, 7))
    axis_kind = draw(st.sampled_from(["STD_AXIS", "FIX_AXIS", "COM_AXIS"]))
    axis_name = draw(_NAME) if axis_kind == "COM_AXIS" else None
    if kind == "VAL_BLK":
        shape = (nx, draw(st.integers(1, 4))) if draw(st.booleans()) else (nx,)
        return CalValue(name, kind, draw(_array(int(np.prod(shape)))).reshape(shape), unit=unit, comment=long_name)
    if kind == "CURVE":
        return CalValue(name, kind, draw(_array(nx)), axes=(_numeric_axis(draw, nx, axis_kind, axis_name),), unit=unit,
                        comment=long_name)
    ny = draw(st.integers(1, 5))
    axes = (_numeric_axis(draw, nx, axis_kind, axis_name),
            _numeric_axis(draw, ny, axis_kind, draw(_NAME) if axis_kind == "COM_AXIS" else None))
    return CalValue(name, kind, draw(_array(nx * ny)).reshape((nx, ny)), axes=axes, unit=unit, comment=long_name)


@st.composite
def datasets(draw) -> Dataset:
    dataset = Dataset()
    for name in draw(st.lists(_NAME, min_size=1, max_size=6, unique=True)):
        # XML comments cannot hold "--" (CDFX writes "- -" and reports it: tested on its own)
        comments = st.lists(_LABEL.filter(lambda text: "--" not in text and not text.endswith("-")), max_size=2)
        dataset.add(draw(calibration(name)), ObjectInfo(comments=tuple(draw(comments))))
    return dataset


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(datasets(), st.sampled_from([("dcm",), ("cdfx",), ("dcm", "cdfx"), ("cdfx", "dcm")]))
def test_random_datasets_survive_exactly(dataset, formats):
    back = trip(dataset, *formats)
    assert_same(dataset, back)
    assert [back.info[n].comments for n in back] == [dataset.info[n].comments for n in dataset]


@given(st.text(string.printable.strip() + "äöüßµ°€\"\\", max_size=20))
def test_any_text_value_survives_a_dcm_line(text):
    dataset = Dataset()
    dataset.add(CalValue("t", "VALUE", text))
    assert trip(dataset, "dcm")["t"].value == text
