"""``workbench flash`` of part of the software: what it writes must belong to what it leaves on the ECU (user
trial: a CALIB-only image of another EPK flashed onto the running application and was called a match)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from flash_images import CALIB, application_image, calib_image_with

from workbench import demo
from workbench.cli import main

OLD_EPK, NEW_EPK = b"10300020250301", b"10300020259999"
APP_HEADER_EPK = 0x840008  # AppHeader.Epk: the EPK the application was built with (docs/demo-ecu.md)


@pytest.fixture
def new_a2l(tmp_path):
    """The demo A2L of another build: EPK ...9999."""
    path = tmp_path / "new.a2l"
    path.write_bytes(demo.a2l().read_bytes().replace(OLD_EPK, NEW_EPK))
    return str(path)


def run_cli(bench, *args: str) -> int:
    return main(["flash", *args, "--interface", "virtual", "--channel", bench.channel])


@pytest.fixture
def one_epk_a2l(new_a2l, tmp_path):
    """The other build's A2L as it was before the application's ADDR_EPK: one EPK address (CALIB's)."""
    path = tmp_path / "one_epk.a2l"
    text = Path(new_a2l).read_bytes()
    assert text.count(b"ADDR_EPK 0x840008\n") == 1
    path.write_bytes(text.replace(b"      ADDR_EPK 0x840008\n", b""))
    return str(path)


def wrong_calib(tmp_path):
    path = tmp_path / "wrongepk.s19"
    image = calib_image_with("xsSWITCH_TANK_THR", 29.0)
    image.add(CALIB.start, NEW_EPK, overwrite=True)
    image.save(path)
    return path


def test_a_calib_of_another_build_is_refused_and_once_accepted_the_application_still_differs(bench, tmp_path,
                                                                                           new_a2l, capsys):
    """The demo A2L names the EPK of CALIB (FC0000h) and of the application's header (840008h): the application's
    EPK is read where it lies, so a CALIB flash accepted onto another application does not hide it."""
    path = wrong_calib(tmp_path)
    before = bench.whole_flash()
    for extra in (["--dry-run"], []):
        assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", new_a2l, *extra) == 1
        out, err = capsys.readouterr()
        assert err.count("\n") == 1 and err.startswith("error: wrongepk.s19: CALIB only, with EPK '10300020259999', "
                                                       "but the ECU reports EPK '10300020250301' (APPLICATIVE at "
                                                       "840008h) for the application that stays on it")
        assert "--accept-epk-mismatch" in err and "(nothing was erased)" in err
        assert out == ""  # the refusal alone: no plan printed as if it ran
        assert bench.whole_flash() == before
    assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", new_a2l, "--json") == 1
    out, err = capsys.readouterr()
    report = json.loads(out)  # a script reads why, and what would flash anyway
    assert (report["operation"], report["ok"], report["refused"], report["override"]) == (
        "flash", False, True, "--accept-epk-mismatch")
    assert report["error"] == err.removeprefix("error: ").rstrip("\n")
    assert report["plan"]["image_epk"] == NEW_EPK.decode()

    assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", new_a2l, "--accept-epk-mismatch") == 0
    out = capsys.readouterr().out
    assert ("the application kept: EPK '10300020250301' before the flash (APPLICATIVE at 840008h), MISMATCH accepted "
            "(--accept-epk-mismatch); the application keeps its EPK there, so the session and later flashes see the "
            "mismatch") in out
    assert bench.ecu.read(CALIB.start, 14) == NEW_EPK and bench.ecu.read(APP_HEADER_EPK, 14) == OLD_EPK
    flashed = bench.whole_flash()
    # GET_ID now reports the new EPK (CALIB's), but the next CALIB flash still sees the application's
    assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", new_a2l) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: wrongepk.s19: CALIB only, with EPK '10300020259999', but the ECU reports EPK "
                          "'10300020250301' (APPLICATIVE at 840008h)") and err.count("\n") == 1
    assert bench.whole_flash() == flashed

    assert main(["info", "--a2l", new_a2l, "--interface", "virtual", "--channel", bench.channel]) == 0
    out = capsys.readouterr().out
    assert "EPK           ECU '10300020259999', A2L '10300020259999': MISMATCH (read-only) in APPLICATIVE" in out
    assert "  in CALIB       FC0000h: ECU '10300020259999', A2L '10300020259999': match" in out
    assert "  in APPLICATIVE 840008h: ECU '10300020250301', A2L '10300020259999': MISMATCH" in out
    assert main(["info", "--json", "--interface", "virtual", "--channel", bench.channel]) == 0  # the old A2L
    parts = json.loads(capsys.readouterr().out)["epk_parts"]
    assert [(p["segment"], p["address"], p["ecu"], p["matches"]) for p in parts] == [
        ("CALIB", 0xFC0000, NEW_EPK.decode(), False), ("APPLICATIVE", APP_HEADER_EPK, OLD_EPK.decode(), True)]
    assert main(["cal", "set", "xsSWITCH_TANK_THR", "25", "--a2l", new_a2l, "--interface", "virtual",
                 "--channel", bench.channel]) == 1  # the session is read-only while a part is another build's
    assert "in APPLICATIVE (840008h); the session is read-only" in capsys.readouterr().err

    app = tmp_path / "app.s19"  # the application of that build makes them one software again: no flag
    image = application_image(100)
    image.add(APP_HEADER_EPK, NEW_EPK, overwrite=True)
    image.save(app)
    assert run_cli(bench, str(app), "-r", "APPLICATIVE", "--a2l", new_a2l) == 0
    assert "the calibration data kept: EPK '10300020259999' before the flash (CALIB at FC0000h), the same" in (
        capsys.readouterr().out)
    assert main(["info", "--a2l", new_a2l, "--interface", "virtual", "--channel", bench.channel]) == 0
    assert "A2L '10300020259999': match\n" in capsys.readouterr().out


def test_with_one_addr_epk_an_accepted_calib_hides_the_application_as_before(bench, tmp_path, one_epk_a2l, capsys):
    path = wrong_calib(tmp_path)
    assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", one_epk_a2l) == 1
    assert capsys.readouterr().err.startswith(
        "error: wrongepk.s19: CALIB only, with EPK '10300020259999', but the ECU reports EPK '10300020250301' (GET_ID) "
        "for the application that stays on it")
    assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", one_epk_a2l, "--accept-epk-mismatch") == 0
    assert ("MISMATCH accepted (--accept-epk-mismatch); after it the ECU reports EPK '10300020259999' (the flash "
            "writes ADDR_EPK), so no later check sees that the application is another build's") in capsys.readouterr().out
    # as that said (and flash --help): one EPK address, so the next CALIB flash needs no flag
    assert run_cli(bench, str(path), "-r", "CALIB", "--a2l", one_epk_a2l) == 0
    assert bench.ecu.read(APP_HEADER_EPK, 14) == OLD_EPK
    capsys.readouterr()
    assert main(["info", "--a2l", one_epk_a2l, "--json", "--interface", "virtual", "--channel", bench.channel]) == 0
    report = json.loads(capsys.readouterr().out)
    assert (report["epk_match"], report["epk_parts"]) == (True, [])


def test_a_matching_calib_flash_says_which_application_it_kept(bench, tmp_path, capsys):
    path = tmp_path / "cal.s19"
    calib_image_with("xsSWITCH_TANK_THR", 29.0).save(path)
    assert run_cli(bench, str(path), "-r", "CALIB") == 0
    assert ("the application kept: EPK '10300020250301' before the flash (APPLICATIVE at 840008h), the same"
            in capsys.readouterr().out)


def test_an_applicative_only_flash_of_another_epk_is_refused(bench, tmp_path, new_a2l, capsys):
    path = tmp_path / "app.s19"
    image = application_image(100)
    image.add(APP_HEADER_EPK, NEW_EPK, overwrite=True)
    image.save(path)
    before = bench.whole_flash()
    assert run_cli(bench, str(path), "-r", "APPLICATIVE", "--a2l", new_a2l) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: app.s19: APPLICATIVE only, with EPK '10300020259999', but the ECU reports EPK "
                          "'10300020250301' (CALIB at FC0000h) for the calibration data that stays on it")
    assert err.count("\n") == 1
    assert bench.whole_flash() == before


def test_the_whole_software_of_another_epk_flashes(bench, tmp_path, new_a2l, one_epk_a2l, capsys):
    path = tmp_path / "new.s19"
    image = application_image(100)
    image.add(APP_HEADER_EPK, NEW_EPK, overwrite=True)
    calib = calib_image_with("xsSWITCH_TANK_THR", 29.0)
    calib.add(CALIB.start, NEW_EPK, overwrite=True)
    for address, data in calib.segments:
        image.add(address, data)
    image.save(path)
    # its APPLICATIVE alone would stay with the ECU's CALIB of the other build, though the file covers ADDR_EPK
    for a2l, source in ((new_a2l, "CALIB at FC0000h"), (one_epk_a2l, "GET_ID")):
        assert run_cli(bench, str(path), "-r", "APPLICATIVE", "--a2l", a2l) == 1
        assert f"'10300020250301' ({source}) for the calibration data that stays" in capsys.readouterr().err
    assert run_cli(bench, str(path), "-r", "CALIB", "-r", "APPLICATIVE", "--a2l", new_a2l) == 0
    assert "EPK match: A2L '10300020259999', ECU '10300020259999'" in capsys.readouterr().out
