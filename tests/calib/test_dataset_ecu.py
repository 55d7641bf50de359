"""The new shapes between files and the simulated ECU: DCM <-> CDFX <-> ECU where the A2L has the object.

The demo A2L is given a VAL_BLK 3 x 4, a CUBOID, a CUBE_4, a CUBE_5 (each with its own axes) and two members
of a structure (``tsCal.gain``, ``tsCal.limit[1]``) laid over the demo's CAL RAM (the only memory the
simulated ECU lets XCP write); values drawn by hypothesis go from a file to the ECU and back into both formats.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from workbench import Session, demo
from workbench.calib.dataset import Dataset, dataset_losses, dump_dataset, load_dataset_string
from workbench.calib.dataset.model import InstancePart, ObjectInfo
from workbench.calib.values import Axis, CalValue
from workbench.sim import serve_demo
from workbench.sync import ApplyRefused, apply_dataset, read_dataset, sync_compare, sync_download
from workbench.sync.values import as_typed_value

_GRIDS = {"tqCUBE": ("CUBOID", (2, 3, 2), 0x40000040), "tqCUBE4": ("CUBE_4", (2, 2, 2, 2), 0x4000008C),
          "tqCUBE5": ("CUBE_5", (2, 2, 2, 2, 2), 0x400000EC)}
_STRUCT = (InstancePart("tsCal", "STRUCTURE"),)
_NAMES = ["tbBLOCK", *_GRIDS, "tsCal.gain", "tsCal.limit[1]"]


def _layout(dimensions: int) -> str:
    axes = " ".join(f"AXIS_PTS_{letter} {i + 1} FLOAT32_IEEE INDEX_INCR DIRECT"
                    for i, letter in enumerate("XYZ45"[:dimensions]))
    return (f"/begin RECORD_LAYOUT RL_{dimensions}D {axes} FNC_VALUES {dimensions + 1} FLOAT32_IEEE COLUMN_DIR DIRECT "
            f"/end RECORD_LAYOUT\n")


def _grid(name: str) -> str:
    kind, counts, address = _GRIDS[name]
    axes = "".join(f"  /begin AXIS_DESCR STD_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD {n} -1000 1000 /end AXIS_DESCR\n"
                   for n in counts)
    return (f'/begin CHARACTERISTIC {name} "a {kind}" {kind} {address:#x} RL_{len(counts)}D 0 NO_COMPU_METHOD '
            f"-1000 1000\n{axes}/end CHARACTERISTIC\n")


def _scalar(name: str, address: int) -> str:
    return (f'/begin CHARACTERISTIC {name} "a member" VALUE {address:#x} Scalar_FLOAT32_IEEE 0 NO_COMPU_METHOD '
            f"-1000 1000 /end CHARACTERISTIC\n")


@pytest.fixture(scope="module")
def ecu(tmp_path_factory):
    extra = ("/begin RECORD_LAYOUT RL_Block FNC_VALUES 1 FLOAT32_IEEE COLUMN_DIR DIRECT /end RECORD_LAYOUT\n"
             + "".join(_layout(n) for n in (3, 4, 5))
             + '/begin CHARACTERISTIC tbBLOCK "a block" VAL_BLK 0x40000010 RL_Block 0 NO_COMPU_METHOD -1000 1000 '
               "MATRIX_DIM 3 4 /end CHARACTERISTIC\n"
             + "".join(_grid(name) for name in _GRIDS) + _scalar("tsCal.gain", 0x40000194)
             + _scalar("tsCal.limit[1]", 0x40000198))
    text = Path(demo.a2l()).read_text(encoding="utf-8")
    end = text.rindex("/end MODULE")
    a2l = tmp_path_factory.mktemp("a2l") / "shapes.a2l"
    a2l.write_text(text[:end] + extra + text[end:], encoding="utf-8")
    channel = "dataset-shapes-ecu"
    with serve_demo({"interface": "virtual", "channel": channel}), \
            Session.open(a2l, interface="virtual", channel=channel) as session:
        yield session


_FLOAT32 = st.floats(-1000, 1000, width=32)


def _values(draw, shape: tuple[int, ...]) -> np.ndarray:
    return np.array(draw(st.lists(_FLOAT32, min_size=int(np.prod(shape)), max_size=int(np.prod(shape)))),
                    dtype=np.float64).reshape(shape)


def _points(draw, n: int) -> np.ndarray:
    return np.sort(_values(draw, (n,)))  # a STD_AXIS without MONOTONY must not decrease


@st.composite
def ecu_datasets(draw) -> Dataset:
    dataset = Dataset()
    dataset.add(CalValue("tbBLOCK", "VAL_BLK", _values(draw, (3, 4))), ObjectInfo(category="VALUE_ARRAY"))
    for name, (kind, counts, _) in _GRIDS.items():
        axes = tuple(Axis(_points(draw, n)) for n in counts)
        dataset.add(CalValue(name, kind, _values(draw, counts), axes=axes))
    for name in ("tsCal.gain", "tsCal.limit[1]"):
        dataset.add(CalValue(name, "VALUE", float(draw(_FLOAT32))), ObjectInfo(container=_STRUCT))
    return dataset


def _file(dataset: Dataset, fmt: str) -> Dataset:
    return load_dataset_string(dump_dataset(dataset, fmt), fmt, f"shapes.{fmt}")


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                 HealthCheck.too_slow])
@given(ecu_datasets())
def test_cdf21_shapes_go_from_a_file_to_the_ecu_and_back_into_both_formats(ecu, dataset):
    from_file = _file(dataset, "cdfx")
    report = apply_dataset(ecu, from_file)
    assert report.ok and report.dry_run is False
    back = read_dataset(ecu, ["tbBLOCK", "tqCUBE*", "tsCal.*"])
    assert list(back) == _NAMES
    assert all(back[name].same_values(as_typed_value(ecu.model, dataset[name])) for name in _NAMES)  # floats as typed
    assert _file(back, "cdfx").objects == back.objects
    dcm = _file(back, "dcm")  # what DCM cannot hold is left out, each named
    assert {f.name for f in dataset_losses(back, "dcm") if f.kind == "left-out"} == set(_GRIDS)
    assert list(dcm) == ["tbBLOCK", "tsCal.gain", "tsCal.limit[1]"]
    assert apply_dataset(ecu, _file(dcm, "cdfx")).counts()["unchanged"] == 3  # DCM -> CDFX -> ECU: the same values


def test_a_value_beyond_its_limit_is_refused_with_the_file_and_line_of_the_value(ecu, tmp_path):
    text = ("KONSERVIERUNG_FORMAT 2.0\n\nFESTWERTEBLOCK tbBLOCK 3 @ 4\n  WERT 1 2 3\n  WERT 4 5 6\n  WERT 7 8 9\n"
            "  WERT 10 11 12\nEND\n\nFESTWERT tsCal.gain\n  LANGNAME \"a member\"\n  WERT 5000\nEND\n")
    dataset = load_dataset_string(text, "dcm", "limits.dcm")
    with pytest.raises(ApplyRefused) as refused:
        apply_dataset(ecu, dataset)
    message = str(refused.value)
    assert "tsCal.gain: limits.dcm:12: " in message and "5000" in message, message
    assert "\n" not in message
    cdfx = load_dataset_string(dump_dataset(dataset, "cdfx"), "cdfx", "limits.cdfx")
    line = next(n for n, text in enumerate(dump_dataset(dataset, "cdfx").decode().splitlines(), 1)
                if "<V>5000</V>" in text)
    with pytest.raises(ApplyRefused, match=rf"tsCal.gain: limits.cdfx:{line}: "):  # its first <V>, as DCM its WERT
        apply_dataset(ecu, cdfx)
    path = tmp_path / "limits.dcm"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ApplyRefused, match=rf"tsCal.gain: {path}:12: "):  # the cache sync's download alike
        sync_download(ecu, sync_compare(ecu, path))
