"""CDF 2.1 shapes through both formats: CUBOID, CUBE_4, CUBE_5 with every axis kind, VALUE_ARRAY, structures and
arrays of instances, model links; what DCM cannot hold is left out and named, the rest survives exactly."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from workbench.calib.dataset import dataset_losses, dump_dataset, load_dataset_string
from workbench.calib.dataset.model import Dataset, InstancePart, ObjectInfo, member_name
from workbench.calib.values import Axis, CalValue

_IDENT = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,8}", fullmatch=True)
_NUMBER = st.floats(-1e9, 1e9) | st.integers(-10**12, 10**12)
_KINDS = {"CUBOID": 3, "CUBE_4": 4, "CUBE_5": 5}
_AXIS_KINDS = ("STD_AXIS", "FIX_AXIS", "COM_AXIS", "RES_AXIS", "CURVE_AXIS")


def _numbers(draw, size: int) -> np.ndarray:
    items = draw(st.lists(_NUMBER, min_size=size, max_size=size))
    return np.array(items, dtype=np.int64 if all(isinstance(i, int) for i in items) else np.float64)


@st.composite
def grid(draw, name: str) -> CalValue:
    kind = draw(st.sampled_from(sorted(_KINDS)))
    shape = tuple(draw(st.lists(st.integers(1, 3), min_size=_KINDS[kind], max_size=_KINDS[kind])))
    axes = []
    for n in shape:
        axis_kind = draw(st.sampled_from(_AXIS_KINDS))
        ref = draw(_IDENT) if axis_kind in ("COM_AXIS", "RES_AXIS", "CURVE_AXIS") else None
        axes.append(Axis(np.sort(_numbers(draw, n)), axis_kind, ref, draw(st.sampled_from(["", "bar", "1/min"]))))
    values = _numbers(draw, int(np.prod(shape))).reshape(shape)
    return CalValue(name, kind, values, axes=tuple(axes), unit=draw(st.sampled_from(["", "%"])))


@st.composite
def block(draw, name: str) -> CalValue:
    shape = tuple(draw(st.lists(st.integers(1, 4), min_size=1, max_size=3)))
    return CalValue(name, "VAL_BLK", _numbers(draw, int(np.prod(shape))).reshape(shape))


@st.composite
def container(draw) -> tuple[InstancePart, ...]:
    parts = []
    for _ in range(draw(st.integers(0, 3))):
        if not parts or draw(st.booleans()):  # an index follows a name
            parts.append(InstancePart(draw(_IDENT), "STRUCTURE", draw(st.sampled_from(["", "a structure"]))))
        else:
            parts.append(InstancePart(str(draw(st.integers(0, 9))), "ARRAY", index=True))
    return tuple(parts)


@st.composite
def shaped_datasets(draw) -> Dataset:
    dataset = Dataset()
    for _ in range(draw(st.integers(1, 5))):
        parts = draw(container())
        leaf = InstancePart(str(draw(st.integers(0, 9))), index=True) if parts and draw(st.booleans()) else \
            InstancePart(draw(_IDENT))
        name = member_name(parts + (leaf,))
        if name in dataset:
            continue
        value = draw(st.one_of(grid(name), block(name), st.builds(lambda v: CalValue(name, "VALUE", v), _NUMBER)))
        category = "VALUE_ARRAY" if value.kind == "VAL_BLK" and draw(st.booleans()) else ""
        link = draw(st.sampled_from(["", f"model/{leaf.name}"]))
        dataset.add(value, ObjectInfo(container=parts, category=category, model_link=link))
    return dataset


def trip(dataset: Dataset, fmt: str) -> Dataset:
    return load_dataset_string(dump_dataset(dataset, fmt), fmt, f"trip.{fmt}")


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shaped_datasets())
def test_cdf21_shapes_survive_cdfx_and_dcm_keeps_what_it_can(dataset):
    back = trip(dataset, "cdfx")
    assert back.objects == dataset.objects and back.notes == []
    for name in dataset:
        got, want = back.info[name], dataset.info[name]
        assert (got.container, got.model_link) == (want.container, want.model_link), name
        assert got.category == (want.category or dataset[name].kind), name

    left_out = {f.name for f in dataset_losses(dataset, "dcm") if f.kind == "left-out"}
    assert left_out == {n for n, v in dataset.items() if v.kind in _KINDS or np.ndim(v.value) > 2}
    dcm = trip(dataset, "dcm")
    assert dcm.objects == {n: v for n, v in dataset.items() if n not in left_out}
    assert trip(dcm, "cdfx").objects == dcm.objects  # and on through CDFX: members keep their names


def test_a_cdf21_file_is_written_only_when_needed_and_nests_members():
    plain = Dataset()
    plain.add(CalValue("s.a", "VALUE", 1), ObjectInfo(container=(InstancePart("s", "STRUCTURE"),)))
    plain.add(CalValue("s.b[0]", "VALUE", 2), ObjectInfo(container=(InstancePart("s", "STRUCTURE"),
                                                                    InstancePart("b", "ARRAY"))))
    plain.add(CalValue("t", "VALUE", 3))
    text = dump_dataset(plain, "cdfx")
    assert b"<CATEGORY>CDF20</CATEGORY>" in text and b"CDF200.XSD" in text
    root = etree.fromstring(text)
    outer = root.find(".//SW-INSTANCE-TREE/SW-INSTANCE")
    assert outer.findtext("SHORT-NAME") == "s" and outer.findtext("CATEGORY") == "STRUCTURE"
    assert [i.findtext("SHORT-NAME") for i in outer.findall("SW-INSTANCE")] == ["a", "b"]
    assert outer.find("SW-INSTANCE/SW-INSTANCE").findtext("SW-ARRAY-INDEX") == "0"
    cube = Dataset()
    cube.add(CalValue("q", "CUBOID", np.zeros((1, 1, 2)), axes=(Axis(np.zeros(1)),) * 2 + (Axis(np.arange(2)),)))
    text = dump_dataset(cube, "cdfx").decode()
    assert "<CATEGORY>CDF21</CATEGORY>" in text and '"cdf_v2.1.0.sl.dtd"' in text
    assert "<VG><VG><V>0.0</V></VG></VG><VG><VG><V>0.0</V></VG></VG>" in text.replace("\n", "").replace(" ", "")
