"""Files in the styles of INCA, CANape and MATLAB, public third-party files and the constructs of the ASAM demos,
read correctly (tests/corpus/datasets), checked against readers that are not ours."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from demo_calibrations import demo_dataset
from lxml import etree

from workbench.calib.dataset import dataset_losses, dump_dataset, load_dataset, load_dataset_string
from workbench.findings import Severity

CORPUS = Path(__file__).parents[1] / "corpus" / "datasets"
TOOL_FILES = sorted((CORPUS / "tools").iterdir())


def as_float32(values) -> np.ndarray:
    return np.asarray(values, dtype=np.float64).astype(np.float32)


@pytest.mark.parametrize("path", TOOL_FILES, ids=lambda p: p.name)
def test_a_tool_style_file_holds_the_demo_calibrations(path):
    """What the ECU would get: the same float32 (the files round to their own digits), texts, units and axes."""
    expected, ds = demo_dataset(), load_dataset(path)
    assert list(ds) == list(expected) and ds.notes == []
    for name, want in expected.items():
        got = ds[name]
        assert (got.kind, got.unit) == (want.kind, want.unit), name
        if isinstance(want.value, str):
            assert got.value == want.value, name
        else:
            assert np.array_equal(as_float32(got.value), as_float32(want.value)), name
        assert [(a.kind, a.name, a.unit) for a in got.axes] == [(a.kind, a.name, a.unit) for a in want.axes], name
        for a, b in zip(got.axes, want.axes):
            assert np.array_equal(as_float32(a.values), as_float32(b.values)), name
        if "DCM" in path.name.upper() and "matlab" not in path.name:
            assert ds.info[name].functions == expected.info[name].functions, name


def test_tool_quirks_are_kept():
    inca = load_dataset(CORPUS / "tools" / "inca_style.dcm")
    assert inca["xsMANIFOLD_TOL"].comment == "Verteilerdruck-Toleranz gegen den offenen Tank (für IMPLAUSIBLE)"
    assert inca.info["zvTankPConv"].comments == ("Kommentar: Kennlinie am Prüfstand geprüft (Ölfilter neu), 0,5 V = 0 bar",)
    assert inca["xsPRV_PWM_PERIOD"].unit == "µs" and inca.info["zsEWMA_ALPHA"].display_name == "zsEWMA_ALPHA"
    matlab = load_dataset(CORPUS / "tools" / "matlab_style.dcm")
    assert matlab["zvTankPConv"].value.dtype == np.int64  # %g writes whole numbers without a point
    assert matlab.comments[0].startswith("DCM written by export_dcm.m")
    inca_cdfx = load_dataset(CORPUS / "tools" / "inca_style.cdfx")
    history = inca_cdfx.info["xsPRV_KP"].history[0]
    assert (history.state, history.user, history.remark) == ("prelimCalibrated", "jmüller", "Verstärkung auf Prüfstand bestätigt\n25 bar in 1 s")
    assert inca_cdfx.functions["PRVCtrl"].version == "1.0.0" and "==================== MAP" in " ".join(inca_cdfx.comments)
    canape = load_dataset(CORPUS / "tools" / "canape_style.cdfx")
    assert (canape.a2l_file, canape.data_file, canape.system) == ("FLCU.a2l", "FLCU.s19", "FLCU")


@pytest.mark.parametrize("path", TOOL_FILES, ids=lambda p: p.name)
def test_converting_a_tool_file_keeps_every_value_exactly(path):
    ds = load_dataset(path)
    for fmt in ("dcm", "cdfx"):
        back = load_dataset_string(dump_dataset(ds, fmt), fmt)
        assert back.objects == ds.objects


def test_the_dcmreader_sample():
    ds = load_dataset(CORPUS / "third_party" / "dcmReader_Sample.dcm")
    assert len(ds) == 11 and len(ds.functions) == 9
    assert ds["valueParameter"].value == 25.0 and ds["valueParameter"].unit == "°C"
    assert ds.info["valueParameter"].variants == (("VariantA", "27.5"),)
    assert ds["textParameter"].value == "ParameterA"
    assert ds["blockParameter2D"].value[:, 1].tolist() == [10.75, -10.25, 10.5, 11.5]
    fixed_map = ds["fixedCharacteristicMap"]
    assert fixed_map.axes[1].values.tolist() == [0.0, 1.0] and fixed_map.value[:, 0].tolist() == [0, 0.4, 0.8, 1, 1.4, 1.8]
    assert ds["groupCharacteristicMap"].value[:, 2].tolist() == [3, 6, 9, 7, 8, 9]
    assert ds.info["groupCharacteristicLine"].comments == ("Sample comment", "SSTX DISTRIBUTION X")
    assert ds["distrib"].value.tolist() == [1.0, 2.0, 3.0]
    for fmt in ("dcm", "cdfx"):
        assert load_dataset_string(dump_dataset(ds, fmt), fmt).objects == ds.objects



def test_the_constructs_of_the_asam_demos_are_read_and_what_needs_the_a2l_is_named():
    cdf20 = load_dataset(CORPUS / "constructs" / "cdf20_demo_style.cdfx")
    gains = cdf20["flcu.array.GAINS_N34_wS16"]
    assert (gains.kind, gains.shape, cdf20.info[gains.name].category) == ("VAL_BLK", (3, 4), "VALUE_ARRAY")
    assert gains.value[:, 1].tolist() == [0.25, 0.5, 0.75] and cdf20["flcu.bool.PUMP_EN_wU8"].value == "false"
    assert cdf20["flcu.scalar.KP_wU16"].comment == "Verstärkung des Reglers"
    assert cdf20["flcu.curve.COM_N4_wU16"].axes[0] == cdf20["flcu.curve.COM_N4_wU16"].axes[0].__class__(
        np.array([0.5, 5.0, 25.0, 50.0]), "COM_AXIS", "flcu.axis.PRESSURE_N4", "bar")
    assert cdf20["flcu.axis.RESCALE_N3"].value.tolist() == [[5.0, 15.0, 40.0], [1, 2, 3]]
    notes = {(n.kind, n.name, n.line) for n in cdf20.notes if n.kind != "not-kept"}
    assert notes == {("read-as", "flcu.dep.TWICE_wU16", 133), ("left-out", "flcu.curve.RES_N4_wS16", 291)}
    curve_axes = cdf20["flcu.map.CURAX_N3x2_wU8"].axes  # point k where the rescale curve gives index k: the labels
    assert [(a.kind, a.values.tolist()) for a in curve_axes] == [("CURVE_AXIS", [800, 1600, 3200]),
                                                                ("CURVE_AXIS", [300, 350])]

    cdf21 = load_dataset(CORPUS / "constructs" / "cdf21_style.cdfx")
    assert [v.kind for v in cdf21.values()][:5] == ["CUBOID", "AXIS_PTS", "CUBE_4", "CUBE_5", "VAL_BLK"]
    fill = cdf21["flcu.cube.FILL"]
    assert fill.shape == (2, 3, 2) and fill.value[1, 2, 1] == 12.5 and fill.value[1, 0, 0] == 2.0
    assert [a.kind for a in fill.axes] == ["STD_AXIS", "FIX_AXIS", "COM_AXIS"] and fill.axes[2].unit == "bar"
    assert cdf21.info["flcu.cube.FILL"].model_link == "FlcuModel/TankCtrl/FillTime" and cdf21.notes == []
    assert list(cdf21)[5:] == ["flcu_tank.capacity", "flcu_tank.level", "flcu_tank.valve.kp", "flcu_sensor[0].offset",
                               "flcu_sensor[0].name", "flcu_sensor[1].offset", "flcu_sensor[1].name", "flcu_limit[0]",
                               "flcu_limit[1]"]
    assert [p.name for p in cdf21.info["flcu_tank.valve.kp"].container] == ["flcu_tank", "valve"]

    dcm = load_dataset(CORPUS / "constructs" / "booleans_style.dcm")
    assert (dcm["cbTankSwitch_EN"].value, dcm["cbLowFuelLed_EN"].value) == (1, 0)
    assert dcm["xbEnables"].value.tolist() == [1, 0, 1, 0] and dcm["xbGains"].value[:, 1].tolist() == [1.25, 1.5, 1.75]
    assert [(n.line, n.column) for n in dcm.notes] == [(20, 9), (26, 9), (49, 9), (49, 14), (49, 20)]


# ---- every file of the corpus: converted both ways, checked against a reader that is not ours ----

FILES = sorted(p for folder in ("tools", "third_party", "constructs") for p in (CORPUS / folder).iterdir()
               if p.suffix.lower() in (".dcm", ".cdfx"))


@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_file_converts_both_ways_and_round_trips(path):
    """Read whole (notes are warnings, never a refusal); what a format cannot hold is left out and named."""
    ds = load_dataset(path)
    assert all(note.severity == Severity.WARNING and note.file == str(path) and note.line for note in ds.notes)
    for fmt in ("dcm", "cdfx"):
        left_out = {f.name for f in dataset_losses(ds, fmt) if f.kind == "left-out"}
        back = load_dataset_string(dump_dataset(ds, fmt), fmt, f"back.{fmt}")
        kept = _group_axes if fmt == "dcm" else lambda value: value
        assert back.objects == {name: kept(value) for name, value in ds.items() if name not in left_out}
        assert load_dataset_string(dump_dataset(back, fmt), fmt).objects == back.objects


def _group_axes(value):
    """What DCM keeps of a value: a RES_AXIS or CURVE_AXIS becomes a group axis (a loss dataset_losses names)."""
    return replace(value, axes=tuple(replace(a, kind="COM_AXIS") if a.kind in ("RES_AXIS", "CURVE_AXIS") else a
                                     for a in value.axes))


@pytest.mark.parametrize("path", [p for p in FILES if p.suffix == ".dcm"], ids=lambda p: p.name)
def test_dcm_values_agree_with_dcmreader(path, tmp_path, capsys):
    """dcmReader (PyPI, MIT) as the oracle; it knows no booleans, so WERT true/false are given to it as 1/0."""
    from dcmReader.dcm_reader import DcmReader

    ds = load_dataset(path)
    text = path.read_bytes().decode("cp1252" if "inca" in path.name else "utf-8-sig")
    plain = tmp_path / path.name
    plain.write_text(re.sub(r"(?im)^(\s*WERT\b.*)$", lambda m: re.sub(r"(?i)\btrue\b", "1", re.sub(
        r"(?i)\bfalse\b", "0", m.group(1))), text), encoding="utf-8")
    oracle = DcmReader()
    oracle.read(str(plain), "utf-8")
    capsys.readouterr()  # dcmReader prints a line for every keyword it does not know
    checked = set()
    for parameter in oracle.get_parameters():
        want = parameter.value if parameter.value is not None else parameter.text
        assert ds[parameter.name].value == want, parameter.name
        checked.add(parameter.name)
    for block in oracle.get_block_parameters():
        rows = np.asarray(block.values).T  # one row a y index
        assert np.array_equal(rows if block.y_dimension > 1 else rows.ravel(), ds[block.name].value), block.name
        checked.add(block.name)
    for line in (oracle.get_characteristic_lines() + oracle.get_fixed_characteristic_lines()
                 + oracle.get_group_characteristic_lines()):
        got = ds[line.name]
        assert list(line.values) == got.axes[0].values.tolist() and list(line.values.values()) == got.value.tolist()
        checked.add(line.name)
    for fmap in (oracle.get_characteristic_maps() + oracle.get_fixed_characteristic_maps()
                 + oracle.get_group_characteristic_maps()):
        got = ds[fmap.name]
        assert list(fmap.values) == got.axes[1].values.tolist(), fmap.name
        for j, row in enumerate(fmap.values.values()):
            assert list(row) == got.axes[0].values.tolist() and list(row.values()) == got.value[:, j].tolist()
        checked.add(fmap.name)
    for distribution in oracle.get_distributions():
        assert distribution.values == ds[distribution.name].value.tolist()
        checked.add(distribution.name)
    texts = {name for name, value in ds.items() if value.kind == "ASCII" or _has_texts(value)}
    assert checked | texts == set(ds), set(ds) - checked  # dcmReader reads no TEXTSTRING, no texts on ST_TX lines


@pytest.mark.parametrize("path", [p for p in FILES if p.suffix == ".cdfx"], ids=lambda p: p.name)
def test_cdfx_values_agree_with_an_xpath_reading(path):
    """Every instance's V/VT in document order (lxml, read here on its own) against our values x fastest."""
    ds = load_dataset(path)
    root = etree.parse(str(path), etree.XMLParser(load_dtd=False, no_network=True)).getroot()
    left_out = {note.name for note in ds.notes if note.kind == "left-out"}
    seen = set()
    for element in root.iter("{*}SW-INSTANCE"):
        values = _own(element, "SW-VALUE-CONT")
        if values is None:
            continue
        name = _xpath_name(element)
        seen.add(name)
        if name in left_out:
            continue
        got = ds[name]
        assert _flat_texts(values) == _texts_of(got.value), name
        axes = [a for a in _own_all(element, "SW-AXIS-CONT")]
        for axis_element, axis in zip(axes, got.axes):
            points = axis_element.find("{*}SW-VALUES-PHYS")
            if points is not None:
                assert _flat_texts(points) == _texts_of(axis.values), name
    assert seen == set(ds) | left_out


def _has_texts(value) -> bool:
    arrays = [value.value] + [a.values for a in value.axes]
    return any(isinstance(item, str) for array in arrays for item in np.ravel(np.asarray(array, dtype=object)))


def _own(element, tag):
    """``tag``/SW-VALUES-PHYS of this instance (directly or in its single variant), not of a nested one."""
    for found in element.iter("{*}" + tag):
        if _owner(found) is element:
            return found.find("{*}SW-VALUES-PHYS")
    return None


def _own_all(element, tag):
    return [found for found in element.iter("{*}" + tag) if _owner(found) is element]


def _owner(node):
    return next(a for a in node.iterancestors() if etree.QName(a).localname == "SW-INSTANCE")


def _xpath_name(element) -> str:
    parts = [element] + [a for a in element.iterancestors() if etree.QName(a).localname == "SW-INSTANCE"]
    name = ""
    for part in reversed(parts):
        short = part.findtext("{*}SHORT-NAME")
        name = f"{name}[{part.findtext('{*}SW-ARRAY-INDEX').strip()}]" if short is None else \
            f"{name}.{short.strip()}" if name else short.strip()
    return name


def _flat_texts(element) -> list:
    return [_number_or_text(v) for v in element.iter("{*}V", "{*}VT")]


def _number_or_text(v):
    if etree.QName(v).localname == "VT":
        return v.text or ""
    text = v.text.strip()
    return float(int(text, 16)) if text.lower().startswith("0x") else float(text)


def _texts_of(value) -> list:
    flat = np.ravel(np.asarray(value, dtype=object), order="F")
    return [item if isinstance(item, str) else float(item) for item in flat]
