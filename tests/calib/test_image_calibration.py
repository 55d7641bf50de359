"""Offline calibration in the library: ImageCalibration reads and writes the demo's s19 by name as a session does
the ECU (no ECU here), keeps the file's format and lines, and refuses what online would refuse and what the file
lacks."""

from __future__ import annotations

import os

import numpy as np
import pytest

from workbench import EpkMismatchError, ImageCalibration, InputError, LimitsError, UnknownSymbolError, demo
from workbench.calib.layout import object_layout
from workbench.image import load_image
from workbench.sync import apply_dataset, image_dataset


@pytest.fixture
def cal() -> ImageCalibration:
    return ImageCalibration.open(demo.s19())


def _image_address(cal: ImageCalibration, name: str) -> int:
    return cal.view.pieces(object_layout(cal.model, name).resolve().span())[0][0]


def test_reads_what_the_sync_and_the_window_read(cal):
    ours = cal.dataset()
    theirs = image_dataset(cal.model, load_image(demo.s19()))
    assert len(ours) == len(theirs) == 58 and not ours.notes
    for name in theirs:
        assert np.array_equal(np.asarray(ours[name].value, dtype=object), np.asarray(theirs[name].value, dtype=object))
    assert cal.read("xsSWITCH_TANK_THR") == 20.0 and cal.read("xsSWITCH_TANK_THR", raw=True) == 20.0
    assert cal.read("cfENABLEFLCU_EN") == "OFF" and cal.read("cfENABLEFLCU_EN", raw=True) == 0
    assert cal.epk == "10300020250301" and not cal.modified


def test_writes_by_name_and_saves_only_the_changed_records(cal, tmp_path):
    assert cal.write("xsSWITCH_TANK_THR", 22.5).value == 22.5
    assert cal.write("cfENABLEFLCU_EN", "ON").value == "ON"  # an enum's text
    assert cal.write_cells("zvRailPConv", {(3,): 41.0}) == {(3,): 41.0}
    assert cal.read("zvRailPConv")[3] == 41.0 and cal.read("zvRailPConv")[2] == 12.5
    assert cal.changed() == ["xsSWITCH_TANK_THR", "cfENABLEFLCU_EN", "zvRailPConv"]
    cal.save(tmp_path / "new.s19")
    before, after = demo.s19().read_text().splitlines(), (tmp_path / "new.s19").read_text().splitlines()
    assert len(before) == len(after) and before[0] == after[0]  # the S0 header, record types, lengths kept
    changed = [i for i, (a, b) in enumerate(zip(before, after)) if a != b]
    assert 1 <= len(changed) <= 3 and all(len(before[i]) == len(after[i]) for i in changed)
    again = ImageCalibration.open(tmp_path / "new.s19")
    assert (again.read("xsSWITCH_TANK_THR"), again.read("cfENABLEFLCU_EN")) == (22.5, "ON")
    assert not cal.modified and cal.path == tmp_path / "new.s19"  # saved: the image is that file's now


def test_intel_hex_stays_intel_hex_and_a_value_written_back_is_no_change(cal, tmp_path):
    load_image(demo.s19()).save(tmp_path / "app.hex")
    cal = ImageCalibration.open(tmp_path / "app.hex")
    cal.write("xsPRV_KP", 6.5)
    assert cal.modified and cal.changed() == ["xsPRV_KP"] and "--region CALIB" in cal.notes()[0]
    cal.write("xsPRV_KP", 5.0)  # back to the file's value
    assert not cal.modified and cal.changed() == [] and cal.notes() == []
    cal.write("xsPRV_KP", 6.5)
    cal.save(tmp_path / "new.hex")
    before = (tmp_path / "app.hex").read_text().splitlines()
    after = (tmp_path / "new.hex").read_text().splitlines()
    assert len(before) == len(after) and sum(a != b for a, b in zip(before, after)) == 1
    assert ImageCalibration.open(tmp_path / "new.hex").read("xsPRV_KP") == 6.5


def test_refuses_as_online(cal):
    with pytest.raises(LimitsError, match="xsSWITCH_TANK_THR: 9999.00 is above the upper limit 800.00 bar"):
        cal.write("xsSWITCH_TANK_THR", 9999)
    with pytest.raises(UnknownSymbolError):
        cal.write("xsSWITCH_TANK", 1)
    with pytest.raises(InputError, match="zsRailPressure is a MEASUREMENT"):
        cal.read("zsRailPressure")
    with pytest.raises(InputError, match=r"zvRailPConv has 9 values: index 9 is beyond \(0-8\)"):
        cal.write_cells("zvRailPConv", {(9,): 1.0})
    with pytest.raises(LimitsError, match="xaPRV_FF_TARGET"):  # an axis' points keep their order
        cal.write_cells("xaPRV_FF_TARGET", {(0,): 45.0})
    assert not cal.modified


def test_an_object_the_file_lacks_is_refused_naming_it_and_where(tmp_path):
    cal = ImageCalibration.open(demo.s19())
    address = _image_address(cal, "xsSWITCH_TANK_THR")
    kept = []
    for line in demo.s19().read_text().splitlines():
        start, size = (int(line[4:10], 16), int(line[2:4], 16) - 4) if line.startswith("S2") else (0, 0)
        if not start <= address < start + size:
            kept.append(line)
    (tmp_path / "partial.s19").write_text("\n".join(kept) + "\n")
    partial = ImageCalibration.open(tmp_path / "partial.s19")
    with pytest.raises(InputError, match=r"xsSWITCH_TANK_THR: partial.s19 holds no bytes at 0x4000[0-9A-F]{4}\.\..*"
                                         r"\(at [0-9A-F]+h-[0-9A-F]+h in the file\); not written"):
        partial.write("xsSWITCH_TANK_THR", 25)
    with pytest.raises(InputError, match="xsSWITCH_TANK_THR: partial.s19 holds no bytes at"):
        partial.read("xsSWITCH_TANK_THR")
    dataset = partial.dataset()
    assert "xsSWITCH_TANK_THR" not in dataset and any("xsSWITCH_TANK_THR" in str(n) for n in dataset.notes)


def test_another_software_s_image_is_read_only(tmp_path):
    image = load_image(demo.s19())
    epk_address = 0xFC0000
    assert image.read(epk_address, 14) == b"10300020250301"
    image.add(epk_address, b"99999999999999", overwrite=True)
    image.save(tmp_path / "other.s19")
    other = ImageCalibration.open(tmp_path / "other.s19")
    assert other.read("xsSWITCH_TANK_THR") == 20.0
    with pytest.raises(EpkMismatchError, match="'99999999999999'"):
        other.write("xsSWITCH_TANK_THR", 25)
    other.accept_epk_mismatch = True
    assert other.write("xsSWITCH_TANK_THR", 25).value == 25.0


def test_a_dataset_applies_as_online_and_a_read_only_file_is_not_overwritten(cal, tmp_path):
    dataset = cal.dataset(["xsPRV_K*", "xsSWITCH_TANK_THR"])
    dataset["xsSWITCH_TANK_THR"] = dataset["xsSWITCH_TANK_THR"].__class__(
        "xsSWITCH_TANK_THR", "VALUE", 30.0, unit="bar")
    report = apply_dataset(cal, dataset)
    assert report.named("applied") == ["xsSWITCH_TANK_THR"] and cal.read("xsSWITCH_TANK_THR") == 30.0
    target = tmp_path / "locked.s19"
    target.write_text(demo.s19().read_text())
    os.chmod(target, 0o444)
    with pytest.raises(InputError, match="locked.s19: the file is read-only; not overwritten"):
        cal.save(target)
    assert target.read_text() == demo.s19().read_text()


def test_no_write_touches_an_epk(cal, tmp_path):
    """An A2L whose further ADDR_EPK lies on a calibration, the image holding the EPK there too."""
    span = object_layout(cal.model, "xsPRV_KP").resolve().span()
    text = demo.a2l().read_text(encoding="utf-8")
    more = text.replace("ADDR_EPK 0x840008", f"ADDR_EPK 0x840008 ADDR_EPK 0x{span.address:X}")
    (tmp_path / "kp.a2l").write_text(more, encoding="utf-8")
    image = load_image(demo.s19())
    image.add(_image_address(cal, "xsPRV_KP"), b"10300020250301", overwrite=True)
    image.save(tmp_path / "kp.s19")
    on_kp = ImageCalibration.open(tmp_path / "kp.s19", tmp_path / "kp.a2l")
    assert on_kp.epk == "10300020250301"
    with pytest.raises(InputError, match=r"xsPRV_KP: its bytes at 0x4000[0-9A-F]+\.\.0x4000[0-9A-F]+ hold the EPK "
                                         rf"\(ADDR_EPK 0x{span.address:X}\)"):
        on_kp.write("xsPRV_KP", 6.0)
    assert not on_kp.modified


def test_calibration_data_of_another_build_is_read_only_whichever_addr_epk_comes_first(tmp_path):
    text = demo.a2l().read_text(encoding="utf-8")
    assert "ADDR_EPK 0xFC0000\n      ADDR_EPK 0x840008" in text
    swapped = text.replace("ADDR_EPK 0xFC0000\n      ADDR_EPK 0x840008", "ADDR_EPK 0x840008\n      ADDR_EPK 0xFC0000")
    (tmp_path / "app_first.a2l").write_text(swapped, encoding="utf-8")
    calib = load_image(demo.s19()).crop(0xFC0000, 0xFE0000)  # CAL ROM only: no application header
    calib.add(0xFC0000, b"99999999999999", overwrite=True)
    calib.save(tmp_path / "calib.s19")
    other = ImageCalibration.open(tmp_path / "calib.s19", tmp_path / "app_first.a2l")
    assert other.epk == "99999999999999"
    with pytest.raises(EpkMismatchError, match="'99999999999999'"):
        other.write("xsSWITCH_TANK_THR", 25)


def test_an_epk_padded_otherwise_is_the_same_epk_offline_as_online(tmp_path):
    """The A2L pads its EPK with blanks, the build with NULs (a C string in a 16-byte array): the session, the cache
    sync and the flash take them for one EPK, so the offline calibration writes as well."""
    text = demo.a2l().read_text(encoding="utf-8").replace('EPK "10300020250301"', 'EPK "10300020250301  "')
    (tmp_path / "padded.a2l").write_text(text, encoding="utf-8")
    image = load_image(demo.s19())
    for address in (0xFC0000, 0x840008):
        image.add(address, b"10300020250301\0\0", overwrite=True)
    image.save(tmp_path / "padded.s19")
    padded = ImageCalibration.open(tmp_path / "padded.s19", tmp_path / "padded.a2l")
    assert padded.write("xsSWITCH_TANK_THR", 25).value == 25.0
