"""diff_datasets: only in A/B, changed element by element with both values and the difference, shapes, tolerance."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from demo_calibrations import demo_dataset

from workbench.calib.dataset import diff_datasets
from workbench.calib.dataset.diff import ElementDiff
from workbench.calib.dataset.model import Dataset
from workbench.calib.values import Axis, CalValue
from workbench.errors import InputError


def changed_demo() -> Dataset:
    ds = demo_dataset()
    ds["xsPRV_KP"] = CalValue("xsPRV_KP", "VALUE", 5.5, unit="%/bar")
    ff = ds["xvPRV_DC_FF"]
    value = ff.value.copy()
    value[1, 2] = 72.5
    axes = (ff.axes[0], Axis(np.array([50.0, 100, 250, 400, 700]), "COM_AXIS", "xaPRV_FF_MANIFOLD", "bar"))
    ds["xvPRV_DC_FF"] = CalValue("xvPRV_DC_FF", "MAP", value, axes=axes, unit="%")
    ds["zvRailPConv"] = CalValue("zvRailPConv", "CURVE", np.zeros(8), axes=(Axis(np.arange(8.0), unit="V"),), unit="bar")
    ds["cfENABLEFLCU_EN"] = CalValue("cfENABLEFLCU_EN", "VALUE", "ON")
    del ds["xsPRV_KD"]
    ds.add(CalValue("xsNEW", "VALUE", 1))
    return ds


def test_the_differences_by_object():
    result = diff_datasets(demo_dataset(), changed_demo(), a_label="base.dcm", b_label="tuned.cdfx")
    by_name = {o.name: o for o in result.objects}
    assert not result.equal
    assert result.counts() == {"only-in-a": 1, "only-in-b": 1, "shape-changed": 1, "changed": 3, "equal": 53}
    assert by_name["xsPRV_KP"].differences == (ElementDiff("value", 5.0, 5.5, 0.5),)
    assert by_name["xvPRV_DC_FF"].differences == (
        ElementDiff("y[2]", 200.0, 250.0, 50.0), ElementDiff("value[1, 2]", 70.0, 72.5, 2.5, (10.0, 200.0)))
    assert by_name["cfENABLEFLCU_EN"].differences == (ElementDiff("value", "OFF", "ON"),)
    assert by_name["zvRailPConv"].status == "shape-changed"
    assert by_name["zvRailPConv"].differences == (ElementDiff("shape", (9,), (8,)), ElementDiff("x points", 9, 8))
    assert by_name["xsPRV_KD"].status == "only-in-a" and by_name["xsNEW"].status == "only-in-b"
    assert [o.name for o in result.objects][-1] == "xsNEW"


def test_text_table_and_json():
    result = diff_datasets(demo_dataset(), changed_demo(), a_label="base.dcm", b_label="tuned.cdfx")
    text = result.to_text()
    lines = text.splitlines()
    assert lines[:2] == ["A: base.dcm", "B: tuned.cdfx"]
    assert lines[2].split() == ["name", "status", "where", "A", "B", "B", "-", "A"]
    assert any(line.split() == ["xvPRV_DC_FF", "changed", "value[1,", "2]", "(x", "10", "bar,", "y", "200", "bar)",
                                "70", "%", "72.5", "%", "+2.5", "%"] for line in lines)  # with units, as cal get
    assert any(line.split()[:2] == ["xsPRV_KD", "only-in-a"] for line in lines)
    assert lines[-1] == "59 objects: 53 equal, 3 changed, 1 shape changed, 1 only in A, 1 only in B"
    assert "zsEWMA_ALPHA" not in text and "zsEWMA_ALPHA" in result.to_text(show_equal=True)
    data = json.loads(json.dumps(result.to_dict()))
    kp = next(o for o in data["objects"] if o["name"] == "xsPRV_KP")
    assert kp == {"name": "xsPRV_KP", "status": "changed", "kind": {"a": "VALUE", "b": "VALUE"},
                  "unit": {"a": "%/bar", "b": "%/bar"},
                  "differences": [{"where": "value", "a": 5.0, "b": 5.5, "delta": 0.5, "at": [],
                                   "unit": {"a": "%/bar", "b": "%/bar"}}]}
    assert data["counts"]["equal"] == 53 and data["equal"] is False


def test_tolerance_nan_integers_and_kinds():
    a, b = Dataset(), Dataset()
    a.add(CalValue("v", "VAL_BLK", np.array([1.0, 100.0, math.nan, 3.0])))
    b.add(CalValue("v", "VAL_BLK", np.array([1.05, 101.0, math.nan, 3.0])))
    a.add(CalValue("i", "VALUE", 1))
    b.add(CalValue("i", "VALUE", 1.0))
    a.add(CalValue("k", "VALUE", 1))
    b.add(CalValue("k", "VAL_BLK", np.array([1])))
    exact = diff_datasets(a, b)
    assert [d.where for d in exact.objects[0].differences] == ["value[0]", "value[1]"]
    assert exact.objects[1].status == "equal"  # 1 and 1.0 are the same value
    assert exact.objects[2].differences == (ElementDiff("kind", "VALUE", "VAL_BLK"),)
    assert [d.where for d in diff_datasets(a, b, abs_tol=0.1).objects[0].differences] == ["value[1]"]
    assert diff_datasets(a, b, abs_tol=0.1, rel_tol=0.01).objects[0].status == "equal"
    inf = Dataset()
    inf.add(CalValue("x", "VALUE", math.inf))
    other = Dataset()
    other.add(CalValue("x", "VALUE", -math.inf))
    assert diff_datasets(inf, other, abs_tol=1e300).to_dict()["objects"][0]["differences"][0]["a"] == "Inf"


def test_seen_from_the_other_side():
    a, b = demo_dataset(), changed_demo()
    forward, backward = diff_datasets(a, b), diff_datasets(b, a)
    flipped = forward.reversed()
    assert (flipped.a_label, flipped.b_label) == (forward.b_label, forward.a_label)
    assert flipped.counts() == backward.counts()
    by_name = {o.name: o for o in backward.objects}
    for mine in flipped.objects:
        theirs = by_name[mine.name]
        assert mine.status == theirs.status and [(d.where, d.a, d.b, d.delta) for d in mine.differences] == \
            [(d.where, d.a, d.b, d.delta) for d in theirs.differences]


def test_equal_datasets():
    result = diff_datasets(demo_dataset(), demo_dataset())
    assert result.equal and result.to_text().splitlines()[-1] == "58 objects: 58 equal, 0 changed, 0 shape changed, 0 only in A, 0 only in B"


def test_a_dataset_is_edited_like_a_dict_and_keeps_its_metadata():
    ds = demo_dataset()
    ds["xsPRV_KP"] = CalValue("xsPRV_KP", "VALUE", 6.0, unit="%/bar")
    assert ds.info["xsPRV_KP"].functions == ("PRVCtrl",) and list(ds).index("xsPRV_KP") == 19  # in place
    del ds["xsPRV_KI"]
    assert "xsPRV_KI" not in ds and "xsPRV_KI" not in ds.info and len(ds) == 57
    with pytest.raises(InputError, match="xsPRV_KD: stored under the name 'other'"):
        ds["other"] = ds["xsPRV_KD"]


def test_the_table_shows_float32_values_as_typed_and_keeps_what_the_short_text_would_hide():
    """A FLOAT32 calibration typed as 25.123 holds 25.12299919128418: the table shows 25.123 and the
    difference of what it shows (+20.123; 12.5 - 25.12 is -12.62, not -12.620000000000001); values
    that differ below a float32's digits show every digit. JSON keeps the exact values."""
    typed = float(np.float32(25.123))
    a, b = Dataset(), Dataset()
    for name, before, after in (("f32", 5.0, typed), ("word", 25.12, 12.5), ("close", typed, 25.123)):
        a.add(CalValue(name, "VALUE", before))
        b.add(CalValue(name, "VALUE", after))
    result = diff_datasets(a, b)
    rows = {line.split()[0]: line.split()[3:] for line in result.to_text().splitlines()[3:-1]}
    assert rows == {"f32": ["5", "25.123", "+20.123"], "word": ["25.12", "12.5", "-12.62"],
                    "close": ["25.12299919128418", "25.123", "+8.087158214209467e-07"]}
    assert result.to_dict()["objects"][0]["differences"][0]["b"] == typed


def test_texts_are_bare_unless_that_hides_the_difference():
    a, b = Dataset(), Dataset()
    for name, left, right in (("mode", "Low", "High"), ("empty", "", "x"), ("blank", "abc", "abc "), ("raw", 7, "7")):
        a.add(CalValue(name, "ASCII" if name in ("empty", "blank") else "VALUE", left))
        b.add(CalValue(name, "ASCII" if name in ("empty", "blank") else "VALUE", right))
    rows = {line.split("changed")[0].strip(): line.split("value", 1)[1].split() for line in
            diff_datasets(a, b).to_text().splitlines()[3:-1]}
    assert rows == {"mode": ["Low", "High"], "empty": ["''", "x"], "blank": ["abc", "'abc", "'"],
                    "raw": ["7", "'7'"]}
