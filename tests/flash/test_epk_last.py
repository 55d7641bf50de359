"""Each part's EPK is programmed last within the part, and the application key is set only over parts that all hold
their EPK (user trial: after a power cut half-way through APPLICATIVE, a CALIB-only flash set the key over the
half-written application and said "the application runs")."""

from __future__ import annotations

import pytest
from flash_images import APPLICATIVE, CALIB

from workbench import demo
from workbench.cli import main
from workbench.flash import FlashError, flash_ecu, plan_flash, read_part_epks
from workbench.image import MemoryImage, load_image
from workbench.sim.ecu import EcuState
from workbench.sim.memory_map import HDS9
from workbench.xcp_protocol import Cmd, Err

EPK = b"10300020250301"
CALIB_EPK, APPLICATIVE_EPK = 0xFC0000, 0x840008  # the demo A2L's two ADDR_EPKs


def cli(bench, *args: str) -> int:
    return main(["flash", *args, "--interface", "virtual", "--channel", bench.channel])


def calib_file(tmp_path):
    path = tmp_path / "calib.s19"
    load_image(demo.s19()).crop(CALIB.start, CALIB.end).save(path)  # EPK, calibrations, CALT trailer
    return path


@pytest.fixture
def cut_applicative(bench):
    """The power cut half-way through flashing the demo's APPLICATIVE (its ~1,200 PROGRAM frames)."""
    plan = plan_flash(load_image(demo.s19()).crop(APPLICATIVE.start, APPLICATIVE.end), bench.layout, ["APPLICATIVE"])
    bench.ecu.faults.power_loss_at_program(600)
    with pytest.raises(FlashError):
        flash_ecu(bench.session, plan)
    assert bench.ecu.faults.fired == ["power loss at PROGRAM frame 600"]
    assert bench.simulator.power_on() is EcuState.BOOT
    bench.session.connect()
    return bench


def test_a_calib_flash_after_a_power_cut_in_applicative_does_not_set_the_key(cut_applicative, tmp_path, capsys):
    bench = cut_applicative
    assert bench.ecu.read(APPLICATIVE_EPK, len(EPK)) == b"\xff" * len(EPK)  # held back: the cut came first
    before = bench.whole_flash()
    assert cli(bench, str(calib_file(tmp_path)), "-r", "CALIB") == 1
    out, err = capsys.readouterr()
    assert err == ("error: calib.s19: APPLICATIVE's EPK at 840008h reads erased (14 bytes FF): a flash of APPLICATIVE "
                   "probably broke off, so the application key is not set and the ECU stays in its boot loader: flash "
                   "the whole software (-r CALIB -r APPLICATIVE), or APPLICATIVE again from a file with its EPK "
                   "(nothing was erased)\n")
    assert "the application runs" not in out
    assert bench.whole_flash() == before
    bench.power_cycle()
    assert bench.ecu.state is EcuState.BOOT
    assert cli(bench, str(demo.s19()), "-r", "APPLICATIVE", "-r", "CALIB") == 0  # the whole software
    assert "the application runs" in capsys.readouterr().out
    assert bench.ecu.read(APPLICATIVE_EPK, len(EPK)) == bench.ecu.read(CALIB_EPK, len(EPK)) == EPK


def test_the_key_is_not_set_when_a_part_ends_without_its_epk(bench, tmp_path, capsys):
    """Checked again right before the key: a CALIB file without the EPK leaves CALIB's erased (its erasure allowed)."""
    path = tmp_path / "no_epk.s19"
    load_image(demo.s19()).crop(CALIB_EPK + len(EPK), CALIB.end).save(path)
    assert cli(bench, str(path), "-r", "CALIB", "--erase-beyond-file") == 1
    out, err = capsys.readouterr()
    assert err == ("error: no_epk.s19: CALIB's EPK at FC0000h reads erased (14 bytes FF): the file holds no EPK there, "
                   "so the application key is not set and the ECU stays in its boot loader: flash the whole software "
                   "(-r CALIB), or CALIB again from a file with its EPK\n")
    assert "the application runs" not in out
    assert bench.ecu.read(HDS9.app_key_address, len(HDS9.app_key)) == b"\xff" * len(HDS9.app_key)
    assert bench.ecu.state is EcuState.BOOT  # reset after the refusal: the boot finds no key
    assert cli(bench, str(calib_file(tmp_path)), "-r", "CALIB") == 0
    out = capsys.readouterr().out
    assert "the application runs" in out
    assert ("the application key was cleared before this flash: an earlier flash did not finish; the parts this one "
            "leaves hold their EPK (none of them broke off)") in out


def test_a_calib_flash_of_an_intact_ecu_sets_the_key(bench, tmp_path, capsys):
    assert cli(bench, str(calib_file(tmp_path)), "-r", "CALIB") == 0
    assert "the application runs" in capsys.readouterr().out
    assert bench.ecu.state is EcuState.APPLICATION


def test_each_part_s_epk_is_programmed_after_every_other_byte_of_it(bench, monkeypatch):
    memory = bench.ecu.memory
    programmed = []
    real = memory.program
    monkeypatch.setattr(memory, "program", lambda address, data: (programmed.append(address), real(address, data)))
    plan = plan_flash(load_image(demo.s19()), bench.layout, ["APPLICATIVE", "CALIB"])
    assert flash_ecu(bench.session, plan).application_running
    for region, epk in ((APPLICATIVE, APPLICATIVE_EPK), (CALIB, CALIB_EPK)):
        inside = [a for a in programmed if region.start <= a < region.end]  # one call a PROGRAM frame
        first = next(i for i, a in enumerate(inside) if epk <= a < epk + len(EPK))
        assert 0 < first and all(epk <= a < epk + len(EPK) for a in inside[first:])
    assert programmed[-1] == HDS9.app_key_address


def test_a_boot_loader_that_refuses_upload_has_its_epks_compared_by_checksum(bench):
    bench.ecu.memory.load_flash(MemoryImage.from_bytes(APPLICATIVE_EPK, b"\xff" * len(EPK)))
    for n in (1, 2):
        bench.ecu.faults.reject_command(n, Err.CMD_UNKNOWN, Cmd.UPLOAD)
    calib, application = read_part_epks(bench.session.master, bench.layout)
    assert bench.ecu.faults.fired == ["reject command 0xF5 with CMD_UNKNOWN"] * 2
    assert (calib.held, calib.same, calib.complete) == (None, True, True)
    assert (application.held, application.same, application.complete) == (None, False, False)
    assert application.found == "not the A2L's EPK (BUILD_CHECKSUM; UPLOAD refused)"


def test_the_key_is_not_set_over_a_part_of_another_build_the_session_did_not_see(bench):
    """Read again before the key: the session read the EPKs at CONNECT, another tool flashed APPLICATIVE since."""
    bench.ecu.memory.load_flash(MemoryImage.from_bytes(APPLICATIVE_EPK, b"10300020259999"))
    plan = plan_flash(load_image(demo.s19()).crop(CALIB.start, CALIB.end), bench.layout, ["CALIB"], source="cal.s19")
    with pytest.raises(FlashError) as refused:
        flash_ecu(bench.session, plan)
    assert str(refused.value) == (
        "cal.s19: APPLICATIVE's EPK at 840008h reads '10300020259999', not the A2L's '10300020250301': another "
        "build's, so the application key is not set and the ECU stays in its boot loader: flash the whole software, or "
        "pass --accept-epk-mismatch to set it anyway")
    assert bench.ecu.state is EcuState.BOOT
