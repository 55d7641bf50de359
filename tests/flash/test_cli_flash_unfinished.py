"""A flash that was killed half-way (user trial: ``timeout -s KILL 6 workbench flash calib_full.s19 -r CALIB``):
``info`` says so, and a flash of another region does not set the application key over the unfinished one (its EPK,
programmed last, is still erased)."""

from __future__ import annotations

import json
import random
import re

import pytest
from flash_images import CALIB, calib_image_with

from workbench import demo
from workbench.cli import main
from workbench.flash import flash_ecu, plan_flash
from workbench.sim.memory_map import HDS9


class Killed(BaseException):
    """What a SIGKILL leaves: no handler of the flash runs (no PROGRAM_RESET)."""


class KillAt:
    def __init__(self, at: int):
        self.at = at
        self.cancelled = False

    def update(self, done: int, total: int, label: str = "") -> None:
        if done >= self.at:
            raise Killed


@pytest.fixture
def killed_calib_flash(bench):
    image = calib_image_with("xsSWITCH_TANK_THR", 29.0)
    image.add(0xFC0200, random.Random(3).randbytes(0x2000))
    plan = plan_flash(image, bench.layout, ["CALIB"], source="calib_full.s19")
    with pytest.raises(Killed):
        flash_ecu(bench.session, plan, progress=KillAt(0x1000))
    bench.session.connect()  # the next command's own connection
    return bench


def cli(bench, *args: str) -> int:
    return main([*args, "--interface", "virtual", "--channel", bench.channel])


def test_info_says_the_flash_did_not_finish(killed_calib_flash, capsys):
    bench = killed_calib_flash
    assert cli(bench, "info") == 0
    state = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("state"))
    assert state == ("state         programming, the application stopped; application key at FE0000h cleared: a flash "
                     "did not finish (the application does not start at the next reset); flash again what was flashed")
    assert cli(bench, "info", "--json") == 0
    assert json.loads(capsys.readouterr().out)["app_key"] == "cleared"
    bench.power_cycle()
    assert cli(bench, "info") == 0
    assert "state         boot loader (programming only); application key at FE0000h cleared" in capsys.readouterr().out


def test_the_key_is_not_set_over_the_unfinished_region(killed_calib_flash, capsys):
    bench = killed_calib_flash
    before = bench.whole_flash()
    assert cli(bench, "flash", str(demo.s19()), "-r", "APPLICATIVE") == 1
    assert capsys.readouterr().err == (  # CALIB's EPK is programmed last: the killed flash left it erased
        "error: FLCU.s19: CALIB's EPK at FC0000h reads erased (14 bytes FF): a flash of CALIB probably broke off, so "
        "the application key is not set and the ECU stays in its boot loader: flash the whole software (-r "
        "APPLICATIVE -r CALIB), or CALIB again from a file with its EPK (nothing was erased)\n")
    assert bench.whole_flash() == before
    assert cli(bench, "flash", str(demo.s19()), "-r", "APPLICATIVE", "-r", "CALIB", "--erase-beyond-file") == 0
    out = capsys.readouterr().out
    assert "the application key was cleared before this flash: an earlier flash did not finish\n" in out
    assert "the application runs" in out and bench.ecu.read(HDS9.app_key_address, 4) == HDS9.app_key
    assert bench.flash_content(CALIB)[0x200:0x210] == b"\xff" * 16  # the unfinished flash's bytes are gone
    assert cli(bench, "info") == 0
    assert "state         application running" in capsys.readouterr().out


def test_info_of_a_healthy_ecu_reads_the_key_as_set(bench, capsys):
    assert cli(bench, "info", "--json") == 0
    report = json.loads(capsys.readouterr().out)
    assert report["app_key"] == "set" and report["state"] == "application running"


def test_info_claims_nothing_of_a_key_the_a2ls_flash_has_no_sector_for(killed_calib_flash, capsys, tmp_path):
    """The demo's key is the default: on another ECU (its A2L without a sector at FE0000h) the bytes there are not
    read as an unfinished flash."""
    other = tmp_path / "other.a2l"
    other.write_text(re.sub(r'/begin SECTOR\s+"SHARED".*?/end SECTOR', "", demo.a2l().read_text(), flags=re.S))
    assert cli(killed_calib_flash, "info", "--json", "--a2l", str(other)) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["app_key"] is None and "cleared" not in report["state"]
    assert cli(killed_calib_flash, "info", "--json", "--a2l", str(other), "--app-key", "0xFE0000=3CC3A55A") == 0
    assert json.loads(capsys.readouterr().out)["app_key"] == "cleared"  # named by the user: read wherever it is
