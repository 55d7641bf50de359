"""Files in the styles of INCA, CANape and MATLAB, and public third-party files, read correctly (tests/corpus/datasets)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from demo_calibrations import demo_dataset

from workbench.calib.dataset import dump_dataset, load_dataset, load_dataset_string

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
