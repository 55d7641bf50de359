"""The cache sync against the simulated ECU: BUILD_CHECKSUM first (no upload for an unchanged ECU, counted in the
simulator's frames), the changed objects exactly, upload (ECU -> file) and download (file -> ECU) both ending in
a clean sync."""

from __future__ import annotations

import shutil
import struct
from dataclasses import replace
from pathlib import Path

import pytest

from workbench import Cancelled, EpkMismatchError, InputError, Session, WorkbenchError, XcpCommandError, demo
from workbench.calib.dataset import load_dataset, save_dataset
from workbench.image import ChecksumType, MemoryImage, checksum, load_image
from workbench.sim import serve_demo
from workbench.sync import read_dataset, sync_compare, sync_download, sync_upload
from workbench.sync.scan import LEAF_BYTES
from workbench.xcp_protocol import Cmd, Err

from sync_helpers import FAST, downloads, edited_a2l, uploads

CAL_RAM, CAL_ROM = 0x40000000, 0xFC0000
CAL_IMAGE_END = 0x1C4  # the .cal_ram load image ends at FC01C3h (EPK, calibrations)


def checksums(sim) -> int:
    return sim.ecu.faults.commands_seen(Cmd.BUILD_CHECKSUM)


def test_an_unchanged_ecu_is_confirmed_by_checksums_alone(sim, ecu):
    before_uploads, before_checksums, before_frames = uploads(sim), checksums(sim), sim.ecu.faults.frames_seen("rx")
    report = sync_compare(ecu, demo.s19())
    assert report.equal and report.changed == [] and report.outside == []
    assert uploads(sim) == before_uploads  # not one byte of calibration memory read
    assert sim.ecu.faults.frames_seen("rx") - before_frames == 7  # GET_SEED, UNLOCK (CAL/PAG) the first time
    before_frames = sim.ecu.faults.frames_seen("rx")
    assert sync_compare(ecu, demo.s19()).equal and uploads(sim) == before_uploads
    # every frame the master sent: GET_CAL_PAGE (XCP on the working page already), 2 x (SET_MTA, BUILD_CHECKSUM)
    assert sim.ecu.faults.frames_seen("rx") - before_frames == 5
    assert checksums(sim) - before_checksums == 2 * report.checksums == 4  # FC0000h-FC01C3h, trailer FDFFF0h-
    (area,) = report.areas
    assert [(s.address, s.size) for s in area.scan.compared] == [(CAL_RAM, CAL_IMAGE_END), (CAL_RAM + 0x1FFF0, 16)]
    assert report.bytes_uploaded == 0 and len(report.diff.objects) == 58
    assert 'the data in the ECU equals "FLCU.s19" (58 objects)' in report.to_text()


def test_a_changed_ecu_lists_exactly_the_changed_objects_and_uploads_only_their_blocks(sim, ecu):
    ecu.write("xsSWITCH_TANK_THR", 25.0)
    ecu.write("zvTankPConv", ecu.read("zvTankPConv") * 0.5)
    ecu.write("cfENABLEFLCU_EN", 1)
    before = uploads(sim)
    report = sync_compare(ecu, demo.s19())
    assert not report.equal and report.outside == []
    assert sorted(report.changed) == ["cfENABLEFLCU_EN", "xsSWITCH_TANK_THR", "zvTankPConv"]
    (area,) = report.areas
    assert all(leaf.size <= LEAF_BYTES for leaf in area.scan.differing)
    assert report.bytes_uploaded == sum(leaf.size for leaf in area.scan.differing) < CAL_IMAGE_END
    assert uploads(sim) > before
    threshold = next(o for o in report.diff.objects if o.name == "xsSWITCH_TANK_THR")
    assert [(d.a, d.b, d.delta) for d in threshold.differences] == [(20.0, 25.0, 5.0)]
    assert report.ecu_values["cfENABLEFLCU_EN"].value == "ON"


def test_upload_writes_a_reference_that_then_syncs_clean(sim, ecu, tmp_path):
    reference = tmp_path / "FLCU.s19"
    shutil.copy(demo.s19(), reference)
    ecu.write("xsPRV_KP", 6.5)
    report = sync_compare(ecu, reference)
    assert report.changed == ["xsPRV_KP"]
    assert sync_upload(report) == reference
    assert sync_compare(ecu, reference).equal
    old, new = load_image(demo.s19()), load_image(reference)
    assert new.ranges == old.ranges  # the application and every range the file held are still there
    assert new.header == old.header == b"FLCU.s19" and reference.read_text().startswith("S00B0000464C43552E733139")
    assert new.crop(0x840000, 0xFC0000) == old.crop(0x840000, 0xFC0000)
    address = ecu.model.object("xsPRV_KP").address - CAL_RAM + CAL_ROM
    assert struct.unpack("<f", new.read(address, 4)) == (6.5,)
    assert [path.name for path in tmp_path.iterdir()] == ["FLCU.s19"]  # written through a temporary file, renamed


def test_download_makes_the_ecu_match_and_build_checksum_agrees(sim, ecu):
    ecu.write("xsPRV_KP", 6.5)
    ecu.write("xvPRV_DC_FF", ecu.read("xvPRV_DC_FF") * 0.5)
    report = sync_compare(ecu, demo.s19())
    before = downloads(sim)
    result = sync_download(ecu, report)
    assert sorted(result.objects) == ["xsPRV_KP", "xvPRV_DC_FF"] and "verified" in result.verified
    assert 0 < result.bytes <= 4 + 30 * 4 and downloads(sim) - before <= 3
    assert sync_compare(ecu, demo.s19()).equal
    image = load_image(demo.s19())
    with ecu.on_page("working"):
        kind, value = ecu.master.build_checksum(CAL_RAM, CAL_IMAGE_END)
    assert (kind, value) == (ChecksumType.CRC_32, checksum(image.read(CAL_ROM, CAL_IMAGE_END), ChecksumType.CRC_32))
    assert (ecu.read("xsPRV_KP"), ecu.read("xvPRV_DC_FF")[1, 0]) == (5.0, 100.0)


def test_a_download_that_breaks_off_names_what_reached_the_ecu(sim, ecu):
    ecu.write("xsPRV_PWM_PERIOD", 500)
    ecu.write("zfRAILPRESSURE_VALUE", 12.0)
    report = sync_compare(ecu, demo.s19())
    sim.ecu.faults.reject_command(2, Err.WRITE_PROTECTED, Cmd.DOWNLOAD)
    with pytest.raises(WorkbenchError, match="2 of 4 bytes were downloaded before .*: objects that reached the ECU: "
                                             "zfRAILPRESSURE_VALUE$"):
        sync_download(ecu, report)  # in address order: zfRAILPRESSURE_VALUE lies before xsPRV_PWM_PERIOD
    assert ecu.read("zfRAILPRESSURE_VALUE") == 0.0 and ecu.read("xsPRV_PWM_PERIOD") == 500


def test_bytes_outside_every_object_are_listed_apart(sim, ecu, tmp_path):
    image = load_image(demo.s19())
    image.add(0xFDFFFC, b"\x00\x00\x00\x00", overwrite=True)  # the CalTrailer's ValidKey: no A2L object
    reference = tmp_path / "trailer.s19"
    image.save(reference)
    report = sync_compare(ecu, reference)
    assert report.changed == [] and not report.equal
    (outside,) = report.outside
    assert (outside.span.address, outside.reference, outside.ecu) == (CAL_RAM + 0x1FFFC, bytes(4),
                                                                      bytes.fromhex("A55A3CC3"))
    assert "4 bytes outside the objects" in report.summary()
    sync_upload(report)
    assert sync_compare(ecu, reference).equal


def test_a_dataset_reference_reads_exactly_its_objects(sim, ecu, tmp_path):
    path = tmp_path / "two.cdfx"
    save_dataset(read_dataset(ecu, ["xsPRV_KP", "xsPRV_KI"]), path)
    before = uploads(sim)
    report = sync_compare(ecu, path)
    assert report.equal and report.bytes_uploaded == 8 and uploads(sim) - before == 1  # two floats side by side
    ecu.write("xsPRV_KI", 2.5)
    report = sync_compare(ecu, path)
    assert report.changed == ["xsPRV_KI"]
    sync_upload(report)
    assert load_dataset(path)["xsPRV_KI"].value == 2.5 and sync_compare(ecu, path).equal
    ecu.write("xsPRV_KI", 3.5)
    sync_download(ecu, sync_compare(ecu, path))
    assert ecu.read("xsPRV_KI") == 2.5


def test_a_dataset_keeps_its_labels_and_unknown_objects_when_uploaded(ecu, tmp_path):
    dataset = read_dataset(ecu, ["xsPRV_KP"])
    dataset["xsPRV_KP"] = replace(dataset["xsPRV_KP"], unit="%/bar (gain)")
    dataset.add(replace(dataset["xsPRV_KP"], name="xsOLD_GAIN"))
    path = tmp_path / "old.dcm"
    save_dataset(dataset, path)
    ecu.write("xsPRV_KP", 4.0)
    report = sync_compare(ecu, path)
    assert report.changed == ["xsPRV_KP"]
    assert "xsOLD_GAIN: not compared (not in the A2L)" in report.notes
    assert any("unit '%/bar (gain)' in the file" in note for note in report.notes)
    sync_upload(report)
    again = load_dataset(path)
    assert (again["xsPRV_KP"].value, again["xsPRV_KP"].unit, list(again)) == (4.0, "%/bar (gain)",
                                                                               ["xsPRV_KP", "xsOLD_GAIN"])


def test_an_image_of_other_software_is_refused(ecu, tmp_path):
    image = load_image(demo.s19())
    image.add(CAL_ROM, b"09000020250301", overwrite=True)
    image.save(tmp_path / "other.s19")
    with pytest.raises(InputError, match=r"holds EPK '09000020250301' in CALIB \(FC0000h\), the A2L '10300020250301'"):
        sync_compare(ecu, tmp_path / "other.s19")


def test_calibration_data_of_other_software_is_refused_whichever_addr_epk_comes_first(sim, tmp_path, channel):
    a2l = edited_a2l(tmp_path, "ADDR_EPK 0xFC0000\n      ADDR_EPK 0x840008",
                     "ADDR_EPK 0x840008\n      ADDR_EPK 0xFC0000")
    calib = load_image(demo.s19()).crop(CAL_ROM, CAL_ROM + 0x20000)  # CAL ROM only: no application header
    calib.add(CAL_ROM, b"09000020250301", overwrite=True)
    calib.save(tmp_path / "calib.s19")
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        with pytest.raises(InputError, match=r"holds EPK '09000020250301' in CALIB \(FC0000h\), the A2L"):
            sync_compare(ecu, tmp_path / "calib.s19")


def test_a_dump_of_the_working_page_is_compared_as_it_stands(ecu):
    rom = load_image(demo.s19()).crop(CAL_ROM, CAL_ROM + 0x20000)
    dump = MemoryImage()
    for address, data in rom.segments:
        dump.add(address - CAL_ROM + CAL_RAM, data)
    from workbench.sync import ImageReference

    ecu.write("xsPRV_KD", 0.5)
    report = sync_compare(ecu, ImageReference(demo.path("ram.hex"), dump))
    assert report.changed == ["xsPRV_KD"]


def test_the_checksum_blocks_respect_max_block_size(tmp_path, channel):
    a2l = edited_a2l(tmp_path, "MAX_BLOCK_SIZE 0x20000", "MAX_BLOCK_SIZE 0x40")
    from workbench.sim.demo_ecu import DemoFiles

    files = replace(DemoFiles.defaults(), a2l=a2l)
    with serve_demo({"interface": "virtual", "channel": channel}, files=files) as sim:
        with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
            before = uploads(sim)
            report = sync_compare(ecu, demo.s19())
            assert report.equal and report.checksums == -(-CAL_IMAGE_END // 0x40) + 1 and uploads(sim) == before
            ecu.write("xsPRV_DC_MAX", 90.0)
            report = sync_compare(ecu, demo.s19())
            assert report.changed == ["xsPRV_DC_MAX"] and report.areas[0].scan.differing[0].size <= 0x40
            with ecu.on_page("working"), pytest.raises(XcpCommandError, match="ERR_OUT_OF_RANGE"):
                ecu.master.build_checksum(CAL_RAM, 0x80)  # the simulator takes MAX_BLOCK_SIZE from the A2L too


def test_an_ecu_in_its_boot_loader_has_nothing_to_compare(channel):
    with serve_demo({"interface": "virtual", "channel": channel}, valid_key=False):
        with Session.open(interface="virtual", channel=channel, timeouts=FAST) as ecu:
            with pytest.raises(WorkbenchError, match="boot loader"):
                sync_compare(ecu, demo.s19())


def test_a_read_only_session_compares_but_downloads_nothing(tmp_path, channel):
    a2l = edited_a2l(tmp_path, 'EPK "10300020250301"', 'EPK "99999920250301"')
    with serve_demo({"interface": "virtual", "channel": channel}):
        with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
            path = tmp_path / "kp.dcm"
            save_dataset(read_dataset(ecu, ["xsPRV_KP"]), path)
            report = sync_compare(ecu, path)
            assert report.equal
            with pytest.raises(EpkMismatchError):
                sync_download(ecu, report)


class _Recorder:
    def __init__(self, cancel_after: int | None = None):
        self.calls: list[tuple[int, int, str]] = []
        self.cancel_after = cancel_after

    @property
    def cancelled(self) -> bool:
        return self.cancel_after is not None and len(self.calls) >= self.cancel_after

    def update(self, done: int, total: int, label: str = "") -> None:
        self.calls.append((done, total, label))


def test_progress_is_reported_and_a_cancel_stops_the_upload(ecu):
    ecu.write("xsPRV_KP", 6.5)
    progress = _Recorder()
    sync_compare(ecu, demo.s19(), progress=progress)
    labels = {label.split(" 0x")[0] for _, _, label in progress.calls}
    assert {"checksums", "checksums compared", "uploading the blocks that differ"} <= labels
    with pytest.raises(Cancelled):
        sync_compare(ecu, demo.s19(), progress=_Recorder(cancel_after=1))


def test_without_calibration_pages_the_segments_are_compared_where_the_image_holds_them(sim, channel, tmp_path):
    text = Path(demo.a2l()).read_text(encoding="utf-8")
    start, end = text.index("/begin IF_DATA XCP\n          /begin SEGMENT"), text.index("/end SEGMENT")
    a2l = tmp_path / "no_pages.a2l"
    a2l.write_text(text[:start] + text[text.index("/end IF_DATA", end) + len("/end IF_DATA"):])
    with Session.open(a2l, interface="virtual", channel=channel, timeouts=FAST) as ecu:
        assert ecu.config.segments == ()
        assert read_dataset(ecu, ["xsPRV_KP"])["xsPRV_KP"].value == 5.0  # no page to switch: the one there is
        with pytest.raises(InputError, match="no calibration pages"):
            read_dataset(ecu, ["xsPRV_KP"], page="reference")
        report = sync_compare(ecu, demo.s19())  # CALIB compared as it stands (flash), CAL RAM's objects not at all
        assert report.equal and [check.area.name for check in report.areas] == ["CALIB"]
        assert "xsPRV_KP: not compared (FLCU.s19 holds nothing for CALRAM)" in report.notes
