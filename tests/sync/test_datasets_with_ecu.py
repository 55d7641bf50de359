"""Datasets with the ECU: save a page, change values, diff, apply, diff again; refusals that write nothing; a
failure halfway that names what reached the ECU."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from workbench import EpkMismatchError, Session, demo
from workbench.a2l import load_a2l
from workbench.calib.dataset import Dataset, diff_datasets, load_dataset, load_dataset_string, save_dataset
from workbench.image import load_image
from workbench.sim import serve_demo
from workbench.sync.values import as_typed_value
from workbench.sync import ApplyFailed, ApplyRefused, apply_dataset, image_dataset, read_dataset, sync_compare
from workbench.xcp_protocol import Cmd, Err

from demo_calibrations import demo_dataset
from session_helpers import extended_limits_a2l
from sync_helpers import FAST, downloads, edited_a2l
from xcp_commands import CommandLog


def ecu_diff(ecu, dataset):
    """The file's objects against the ECU's, by value (the dataset path of the cache sync)."""
    return sync_compare(ecu, _reference(dataset)).diff


def _reference(dataset: Dataset):
    from workbench.sync import DatasetReference

    return DatasetReference(Path(dataset.source or "dataset"), dataset)


def test_the_working_page_as_a_dataset_holds_every_demo_calibration(ecu, tmp_path):
    dataset = read_dataset(ecu)
    expected = {name: as_typed_value(ecu.model, value) for name, value in demo_dataset().items()}  # 0.2, not 0.2F
    assert list(dataset) == [name for name in ecu.model.names("CHARACTERISTIC") + ecu.model.names("AXIS_PTS")]
    assert sorted(dataset) == sorted(expected)
    assert all(dataset[name].same_values(expected[name]) for name in expected), \
        [name for name in expected if not dataset[name].same_values(expected[name])]
    assert dataset["zsEWMA_ALPHA"].value == 0.2  # a FLOAT32 as typed: the file says 0.2, as CANape writes it
    for suffix in ("dcm", "cdfx"):
        save_dataset(dataset, tmp_path / f"base.{suffix}")
        assert diff_datasets(load_dataset(tmp_path / f"base.{suffix}"), dataset).equal
    assert dataset.info["xsPRV_KP"].functions == ("PRVCtrl",)


def test_the_s19_decodes_to_the_same_values_without_an_ecu():
    model = load_a2l(demo.a2l()).model()
    from_image = image_dataset(model, load_image(demo.s19()), source="FLCU.s19")
    expected = {name: as_typed_value(model, value) for name, value in demo_dataset().items()}
    assert sorted(from_image) == sorted(expected)
    assert all(from_image[name].same_values(expected[name]) for name in expected)


def test_names_and_globs_and_the_reference_page(ecu):
    ecu.write("xsPRV_KP", 6.0)
    working = read_dataset(ecu, ["xsPRV_K*", "xsSWITCH_TANK_THR"])
    assert list(working) == ["xsPRV_KP", "xsPRV_KI", "xsPRV_KD", "xsSWITCH_TANK_THR"]
    assert working["xsPRV_KP"].value == 6.0
    assert read_dataset(ecu, ["xsPRV_KP"], page="reference")["xsPRV_KP"].value == 5.0
    with pytest.raises(Exception, match="did you mean 'xsPRV_KP'"):
        read_dataset(ecu, ["xsPRV_KPX"])
    with pytest.raises(Exception, match="no calibration matches 'nothing\\*'"):
        read_dataset(ecu, ["nothing*"])


def test_save_change_diff_apply_and_diff_again_empty(sim, ecu):
    saved = read_dataset(ecu)
    ecu.write("xsSWITCH_TANK_THR", 25.0)
    ecu.write("zvRailPConv", ecu.read("zvRailPConv") * 0.5)
    ecu.write("xaPRV_FF_TARGET", [0, 10, 20, 30, 45, 50])
    diff = ecu_diff(ecu, saved)
    changed = ["xvPRV_DC_FF", "zvRailPConv", "xsSWITCH_TANK_THR", "xaPRV_FF_TARGET"]  # the MAP uses the axis
    assert [o.name for o in diff.objects if o.status != "equal"] == changed
    assert {(o.name, d.where, d.a, d.b) for o in diff.objects for d in o.differences if o.name != "zvRailPConv"} == {
        ("xsSWITCH_TANK_THR", "value", 20.0, 25.0), ("xaPRV_FF_TARGET", "value[4]", 40.0, 45.0),
        ("xvPRV_DC_FF", "x[4]", 40.0, 45.0)}

    before = downloads(sim)
    report = apply_dataset(ecu, saved)
    assert report.named("applied") == changed
    assert report.counts()["unchanged"] == len(saved) - 4 and report.ok
    assert downloads(sim) - before == 3  # the shared axis once (with the MAP), each changed object's bytes once
    assert ecu_diff(ecu, saved).equal
    assert sync_compare(ecu, demo.s19()).equal


def test_a_dry_run_shows_what_would_change_and_writes_nothing(sim, ecu):
    saved = read_dataset(ecu)
    ecu.write("xsPRV_KI", 3.0)
    before = downloads(sim)
    report = apply_dataset(ecu, saved, dry_run=True)
    assert downloads(sim) == before
    assert report.named("would change") == ["xsPRV_KI"]
    (changed,) = report.diff.objects
    assert (changed.name, changed.differences[0].a, changed.differences[0].b) == ("xsPRV_KI", 3.0, 2.0)
    assert "xsPRV_KI  would change" in report.to_text()


@pytest.mark.parametrize("spoil, reason", [
    (lambda ds: ds.__setitem__("xsSWITCH_TANK_THR", replace(ds["xsSWITCH_TANK_THR"], value=900.0)),
     "900.00 is above the upper limit 800.00"),
    (lambda ds: ds.add(replace(ds["xsPRV_KP"], name="xsPRV_KQ")), "not in the A2L; did you mean xsPRV_KP"),
    (lambda ds: ds.__setitem__("zvRailPConv", replace(ds["zvRailPConv"], value=np.zeros(3))), "shape"),
    (lambda ds: ds.__setitem__("xaPRV_FF_TARGET", replace(ds["xaPRV_FF_TARGET"],
                                                          value=np.array([0, 10, 5, 30, 40, 50.0]))), "MON_INCREASE"),
])
def test_one_bad_object_and_nothing_is_written(sim, ecu, spoil, reason):
    dataset = read_dataset(ecu)
    dataset["xsPRV_KP"] = replace(dataset["xsPRV_KP"], value=7.0)  # a good change that must not be written either
    spoil(dataset)
    before = downloads(sim)
    with pytest.raises(ApplyRefused) as refused:
        apply_dataset(ecu, dataset)
    assert downloads(sim) == before and ecu.read("xsPRV_KP") == 5.0
    report = refused.value.report
    (bad,) = [o for o in report.outcomes if o.status == "refused"]
    assert reason in bad.reason and reason in str(refused.value)
    assert report.named("not written") == ["xsPRV_KP"]
    assert report.reached_ecu == []


def test_the_report_names_what_extended_limits_decide_and_writes_it_only_when_allowed(sim, channel, tmp_path):
    a2l = extended_limits_a2l(tmp_path)
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        dataset = read_dataset(ecu, ["xsSWITCH_TANK_THR", "xsPRV_KP", "zfRAILPRESSURE_VALUE"])
        dataset["xsSWITCH_TANK_THR"] = replace(dataset["xsSWITCH_TANK_THR"], value=900.0)
        dry = apply_dataset(ecu, dataset, dry_run=True)
        assert dry.extended_limits == ["xsSWITCH_TANK_THR"] and dry.named("refused") == ["xsSWITCH_TANK_THR"]
        assert dry.to_dict()["extended_limits"] == ["xsSWITCH_TANK_THR"]
        allowed = apply_dataset(ecu, dataset, dry_run=True, allow_extended_limits=True)
        assert allowed.extended_limits == allowed.named("would change") == ["xsSWITCH_TANK_THR"]
        dataset["zfRAILPRESSURE_VALUE"] = replace(dataset["zfRAILPRESSURE_VALUE"], value=900.0)  # no EXTENDED_LIMITS
        dataset["xsSWITCH_TANK_THR"] = replace(dataset["xsSWITCH_TANK_THR"], value=1500.0)  # beyond them too
        assert apply_dataset(ecu, dataset, dry_run=True, allow_extended_limits=True).extended_limits == []
        assert apply_dataset(ecu, read_dataset(ecu), dry_run=True).extended_limits == []  # nothing beyond a limit
        dataset = read_dataset(ecu, ["xsSWITCH_TANK_THR"])
        dataset["xsSWITCH_TANK_THR"] = replace(dataset["xsSWITCH_TANK_THR"], value=900.0)
        assert apply_dataset(ecu, dataset, allow_extended_limits=True).named("applied") == ["xsSWITCH_TANK_THR"]
        assert ecu.read("xsSWITCH_TANK_THR") == 900.0


def test_every_problem_is_listed_before_anything_is_written(sim, ecu):
    dataset = read_dataset(ecu)
    dataset.add(replace(dataset["xsPRV_KP"], name="zsRailPressure"))  # a MEASUREMENT
    dataset["xsPRV_DC_MAX"] = replace(dataset["xsPRV_DC_MAX"], value=-1.0)
    dataset["xsPRV_PWM_PERIOD"] = replace(dataset["xsPRV_PWM_PERIOD"], value="fast")
    with pytest.raises(ApplyRefused) as refused:
        apply_dataset(ecu, dataset)
    assert refused.value.report.named("refused") == ["xsPRV_PWM_PERIOD", "xsPRV_DC_MAX", "zsRailPressure"]
    assert "3 of 59 objects refused, nothing written" in str(refused.value)


def test_a_shared_axis_given_twice_with_other_points_is_refused(ecu):
    dataset = read_dataset(ecu, ["xvPRV_DC_FF", "xaPRV_FF_TARGET"])
    curve = dataset["xvPRV_DC_FF"]
    axes = (replace(curve.axes[0], values=np.array([0, 10, 20, 30, 45, 50.0])), curve.axes[1])
    dataset["xvPRV_DC_FF"] = replace(curve, axes=axes)
    with pytest.raises(ApplyRefused) as refused:
        apply_dataset(ecu, dataset)
    (bad,) = [o for o in refused.value.report.outcomes if o.status == "refused"]
    address = ecu.model.object("xaPRV_FF_TARGET").address + 4 * 4  # its fifth point (float32) is the one both give
    assert (bad.name, bad.reason) == ("xaPRV_FF_TARGET", f"xvPRV_DC_FF writes other bytes at 0x{address:X}.."
                                      f"0x{address + 3:X} (the dataset gives both other values there, as a shared "
                                      "axis edited in one place only): make them agree or leave one out")
    dataset["xaPRV_FF_TARGET"] = replace(dataset["xaPRV_FF_TARGET"], value=np.array([0, 10, 20, 30, 45, 50.0]))
    assert apply_dataset(ecu, dataset).named("applied") == ["xvPRV_DC_FF", "xaPRV_FF_TARGET"]
    assert ecu.read("xaPRV_FF_TARGET")[4] == 45.0


def test_a_failure_halfway_names_what_reached_the_ecu(sim, ecu):
    dataset = read_dataset(ecu)
    for name, value in (("xsPRV_KP", 6.0), ("xsPRV_KI", 3.0), ("xsPRV_KD", 0.5)):
        dataset[name] = replace(dataset[name], value=value)
    sim.ecu.faults.reject_command(2, Err.WRITE_PROTECTED, Cmd.DOWNLOAD)
    with pytest.raises(ApplyFailed) as failed:
        apply_dataset(ecu, dataset)
    report = failed.value.report
    assert report.named("applied") == ["xsPRV_KP"] and report.named("failed") == ["xsPRV_KI"]
    assert report.named("not written") == ["xsPRV_KD"] and report.reached_ecu == ["xsPRV_KP"]
    assert "ERR_WRITE_PROTECTED" in str(failed.value) and "objects that reached the ECU: xsPRV_KP" in str(failed.value)
    assert (ecu.read("xsPRV_KP"), ecu.read("xsPRV_KI"), ecu.read("xsPRV_KD")) == (6.0, 2.0, pytest.approx(0.02))


def test_a_cancel_between_objects_names_what_reached_the_ecu(ecu):
    """Ctrl-C in `cal load` (its first one cancels) or a Cancel button: the objects written stay listed."""

    class CancelAfterFirst:
        cancelled = False

        def update(self, done, total, label=""):
            self.cancelled = label.startswith("writing") and done >= 1

    dataset = read_dataset(ecu)
    for name, value in (("xsPRV_KP", 6.5), ("xsPRV_KI", 3.5), ("xsPRV_KD", 0.25)):
        dataset[name] = replace(dataset[name], value=value)
    with pytest.raises(ApplyFailed) as failed:
        apply_dataset(ecu, dataset, progress=CancelAfterFirst())
    report = failed.value.report
    assert report.reached_ecu == ["xsPRV_KP"] and report.named("not written") == ["xsPRV_KI", "xsPRV_KD"]
    assert str(failed.value).startswith("cancelled: writing xsPRV_KI at 1/3; objects that reached the ECU: xsPRV_KP")
    assert failed.value.exit_code == 130 and ecu.read("xsPRV_KI") == 2.0


def test_a_file_value_compares_as_the_ecu_holds_it(ecu):
    text = "KONSERVIERUNG_FORMAT 2.0\nFESTWERT zsEWMA_ALPHA\n  WERT 0.2\nEND\nFESTWERT xsPRV_KD\n  WERT 0.03\nEND\n"
    dataset = load_dataset_string(text, "dcm", "tuned.dcm")
    assert [o.name for o in ecu_diff(ecu, dataset).objects if o.status != "equal"] == ["xsPRV_KD"]
    assert apply_dataset(ecu, dataset).named("applied") == ["xsPRV_KD"]
    assert ecu_diff(ecu, dataset).equal  # 0.03 in the file is float32's 0.03 in the ECU


def test_a_read_only_session_applies_nothing_but_may_dry_run(channel, tmp_path):
    a2l = edited_a2l(tmp_path, 'EPK "10300020250301"', 'EPK "99999920250301"')
    with serve_demo({"interface": "virtual", "channel": channel}):
        with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
            assert ecu.read_only
            dataset = read_dataset(ecu, ["xsPRV_KP"])
            dataset["xsPRV_KP"] = replace(dataset["xsPRV_KP"], value=7.0)
            assert apply_dataset(ecu, dataset, dry_run=True).named("would change") == ["xsPRV_KP"]
            with pytest.raises(EpkMismatchError):
                apply_dataset(ecu, dataset)


def test_each_object_is_read_once_and_only_what_changes_is_written(sim, channel, tmp_path):
    """Counted on the bus: the checks read the objects (merged UPLOADs, no address twice), the writes after them
    read nothing again: per changed object SET_MTA, DOWNLOAD of the changed bytes, their SHORT_UPLOAD read-back."""
    model = load_a2l(demo.a2l()).model()
    dataset = image_dataset(model, load_image(demo.s19()), ["xvPRV_DC_FF", "xsSWITCH_TANK_THR", "xsPRV_K*"])
    ff = dataset["xvPRV_DC_FF"].value.copy()
    ff[2, 3] = 42.0
    dataset["xvPRV_DC_FF"] = replace(dataset["xvPRV_DC_FF"], value=ff)
    dataset["xsSWITCH_TANK_THR"] = replace(dataset["xsSWITCH_TANK_THR"], value=25.0)
    with Session.open(interface="virtual", channel=channel, timeouts=FAST) as ecu, CommandLog(channel) as log:
        log.take()
        assert apply_dataset(ecu, dataset).named("applied") == ["xvPRV_DC_FF", "xsSWITCH_TANK_THR"]
        commands = log.take()
        mta = [int.from_bytes(bytes(f.data[4:8]), "little") for f in log.frames if f.data[0] == Cmd.SET_MTA]
    # first XCP onto the working page (asked: it is on it), last which page the ECU runs (it runs the working page)
    assert commands[:3] == ["GET_SEED", "UNLOCK", "GET_CAL_PAGE"] and commands[-2:] == ["GET_CAL_PAGE"] * 2
    write = ["SET_MTA", "DOWNLOAD", "SHORT_UPLOAD"]
    reads = len(commands) - 3 - 2 * len(write) - 2
    assert commands[3:3 + reads] == ["SET_MTA", "UPLOAD"] * (reads // 2) and len(set(mta[:reads // 2])) == reads // 2
    assert commands[3 + reads:-2] == write + write
    assert mta[reads // 2] == model.characteristic("xvPRV_DC_FF").address + 4 * (3 * 6 + 2)  # the one cell

    moved = edited_a2l(tmp_path, "0x400000E4 /* @ECU_Address@xsPRV_KP@ */", "0xFC00E4")  # into CAL ROM (flash)
    dataset["xsPRV_KP"] = replace(dataset["xsPRV_KP"], value=7.0)
    with Session.open(a2l=moved, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        with pytest.raises(ApplyRefused) as refused:
            apply_dataset(ecu, dataset)
    assert [(o.name, o.reason) for o in refused.value.report.outcomes if o.status == "refused"] == [
        ("xsPRV_KP", "FNC_VALUES at 0xFC00E4..0xFC00E7 lie outside the A2L's writable memory (MEMORY_SEGMENTs of "
                     "calibration RAM); not written")]


def test_a_fix_switch_turned_on_is_written_after_its_value_and_one_turned_off_before(ecu, monkeypatch):
    """As Session.override and release write them: in the file's order (_EN first) the ECU ran the signal on the
    old override value between the two writes (user trial 10)."""
    written = []
    write = ecu.write
    monkeypatch.setattr(ecu, "write", lambda name, value, **kw: (written.append(name), write(name, value, **kw))[1])
    dataset = read_dataset(ecu, ["zfRAILPRESSURE_EN", "zfRAILPRESSURE_VALUE", "cfFUELLEVEL_EN", "cfFUELLEVEL_VALUE"])
    for name, value in (("zfRAILPRESSURE_EN", "ON"), ("zfRAILPRESSURE_VALUE", 30.0), ("cfFUELLEVEL_EN", "ON"),
                        ("cfFUELLEVEL_VALUE", 40.0)):
        dataset[name] = replace(dataset[name], value=value)
    apply_dataset(ecu, dataset)
    assert written == ["zfRAILPRESSURE_VALUE", "zfRAILPRESSURE_EN", "cfFUELLEVEL_VALUE", "cfFUELLEVEL_EN"]
    written.clear()
    for name, value in (("zfRAILPRESSURE_EN", "OFF"), ("zfRAILPRESSURE_VALUE", 0.0)):
        dataset[name] = replace(dataset[name], value=value)
    apply_dataset(ecu, dataset)
    assert written == ["zfRAILPRESSURE_EN", "zfRAILPRESSURE_VALUE"]
