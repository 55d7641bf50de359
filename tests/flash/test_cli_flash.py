"""``workbench flash`` end to end: against a ``workbench sim`` process on udp_multicast, and in-process for the
refusals and usage errors (which must leave the ECU's flash as it was)."""

from __future__ import annotations

import json
import random
import struct

import bincopy
import pytest
from cli_helpers import run
from flash_images import CALIB, application_image, calib_image_with, calibration_rom_address
from sim_process import start_sim_process

from workbench import demo
from workbench.cli import main
from workbench.elf import ElfSymbols
from workbench.image import MemoryImage, load_image
from workbench.session import Session
from workbench.sim import serve_demo
from workbench.sim.memory_map import HDS9
from workbench.sim.profiles import SlaveProfile


THRESHOLD = "xsSWITCH_TANK_THR"


@pytest.fixture
def sim_process(free_udp_port):
    """``workbench sim`` on a multicast group and a UDP port of its own; yields the CLI's bus options."""
    group = f"239.74.{random.randint(164, 250)}.{random.randint(1, 250)}"
    process, banner = start_sim_process("--interface", "udp_multicast", "--channel", group,
                                        "--bus-kwargs", f"port={free_udp_port}", "--duration", "120")
    yield ["--interface", "udp_multicast", "--channel", group, "--bus-kwargs", f"port={free_udp_port}"]
    if process.poll() is None:
        process.kill()
        process.wait()


def threshold_of(bus: list[str]) -> float:
    options = dict(zip(bus[0::2], bus[1::2]))
    with Session.open(demo.a2l(), interface="udp_multicast", channel=options["--channel"],
                      bus_kwargs={"port": int(options["--bus-kwargs"].split("=")[1])}) as session:
        return struct.unpack("<f", session.read_memory(ElfSymbols(demo.elf()).symbol(THRESHOLD).address, 4))[0]


@pytest.mark.slow
def test_flash_calib_and_applicative_into_a_simulator_process(tmp_path, sim_process, capsys):
    bus = sim_process
    calib = tmp_path / "cal.s19"
    calib_image_with(THRESHOLD, 26.5).save(calib)
    assert main(["flash", str(calib), "--region", "CALIB", "--dry-run", *bus]) == 0
    out = capsys.readouterr().out
    assert "CALIB  FC0000h  FDFFFFh  020000h  Partial: FC0000h-FC01C3h FDFFF0h-FDFFFFh" in out
    assert "programming on the bus at 1000 kbit/s" in out and "dry run: nothing was flashed" in out
    assert threshold_of(bus) == 20.0  # the dry run changed nothing

    assert main(["flash", str(calib), "--region", "CALIB", *bus]) == 0
    out = capsys.readouterr().out
    assert "verified: CRC_32 of 1 sector; EPK match" in out and "the application runs" in out
    assert threshold_of(bus) == 26.5  # PROGRAM_RESET restarted the ECU: the boot copied CAL ROM into CAL RAM
    assert main(["flash", str(calib), "--region", "CALIB", "--verify-only", *bus]) == 0
    assert capsys.readouterr().out == "CALIB FC0000h-FC01C3h matches\nCALIB FDFFF0h-FDFFFFh matches\n"

    app = tmp_path / "app.hex"
    application_image(4000).save(app)
    assert main(["flash", str(app), "--region", "APPLICATIVE", "--json", *bus]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["application_running"] and result["verified"] == "CRC_32 of 1 sector"
    assert result["plan"]["regions"][0]["name"] == "APPLICATIVE"


@pytest.mark.slow
def test_flash_the_working_page_in_a_simulator_process(sim_process, capsys):
    bus = sim_process
    options = dict(zip(bus[0::2], bus[1::2]))
    with Session.open(demo.a2l(), interface="udp_multicast", channel=options["--channel"],
                      bus_kwargs={"port": int(options["--bus-kwargs"].split("=")[1])}) as session:
        session.write_memory(ElfSymbols(demo.elf()).symbol(THRESHOLD).address, struct.pack("<f", 31.0))
    assert main(["flash", "--from-working-page", *bus]) == 0
    assert "working page:" in capsys.readouterr().out
    assert threshold_of(bus) == 31.0


def run_cli(bench, *args: str) -> int:
    return main(["flash", *args, "--interface", "virtual", "--channel", bench.channel])


@pytest.mark.parametrize("case, message, override", [
    ("wrong-epk", "EPK '09000020240101' at FC0000h (CALIB) differs from the A2L's", None),
    ("outside", "data outside the flash regions CALIB: FE0000h-FE0003h (in SHARED", None),
    ("nowhere", "data outside the flash regions CALIB: 700000h-700002h (in no flash region) (the A2L's flash regions: "
                "BOOT 800000h-83FFFFh, APPLICATIVE 840000h-FBFFFFh, CALIB FC0000h-FDFFFFh, SHARED FE0000h-FE3FFFh; "
                "nothing was erased)", None),
    ("boot", "BOOT holds the boot loader", "--allow-boot"),
])
def test_refusals_leave_the_ecus_flash_untouched(bench, tmp_path, capsys, case, message, override):
    path = tmp_path / f"{case}.s19"
    image = calib_image_with(THRESHOLD, 29.0)
    region = "CALIB"
    if case == "wrong-epk":
        image.add(CALIB.start, b"09000020240101", overwrite=True)
    elif case == "outside":
        image.add(HDS9.app_key_address, HDS9.app_key)
    elif case == "nowhere":  # a file of another ECU, or an A2L that lacks a MEMORY_SEGMENT: the list says which
        image.add(0x700000, b"\x01\x02\x03")
    else:
        image = MemoryImage.from_bytes(0x800000, bytes(64))
        region = "BOOT"
    image.save(path)
    before = bench.whole_flash()
    assert run_cli(bench, str(path), "--region", region) == 1
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and err.startswith("error: ")
    assert bench.whole_flash() == before
    assert run_cli(bench, str(path), "--region", region, "--dry-run", "--json") == 1
    report = json.loads(capsys.readouterr().out)  # the option the error names is the one the report names
    assert (report["refused"], report["override"]) == (True, override)


@pytest.mark.parametrize("args, message", [
    (["--region", "CALIB"], "give FILE and --region NAME"),
    (["FILE"], "give FILE and --region NAME"),
    (["FILE", "--region", "NOPE"], "no flash region 'NOPE'"),
    (["--from-working-page", "FILE"], "give no FILE and no --region"),
    (["FILE", "--region", "CALIB", "--app-key", "0xFE0000=xyz"], "expected ADDRESS=HEXBYTES"),
    (["missing.s19", "--region", "CALIB"], "missing.s19"),
])
def test_bad_input_is_exit_code_2(bench, tmp_path, capsys, args, message):
    good = tmp_path / "good.s19"
    calib_image_with(THRESHOLD, 20.0).save(good)
    args = [str(good) if a == "FILE" else str(tmp_path / a) if a == "missing.s19" else a for a in args]
    assert run_cli(bench, *args) == 2
    assert message in capsys.readouterr().err


def test_verify_only_exits_1_on_a_difference(bench, tmp_path, capsys):
    path = tmp_path / "changed.s19"
    calib_image_with(THRESHOLD, 28.0).save(path)
    assert run_cli(bench, str(path), "--region", "CALIB", "--verify-only") == 1
    captured = capsys.readouterr()
    assert "CALIB FC0000h-FC01C3h DIFFERS" in captured.out and "1 of 2 ranges match the file" in captured.err
    assert bench.ecu.read(calibration_rom_address(THRESHOLD), 4) == struct.pack("<f", 20.0)


def test_the_demo_s19_flashes_with_the_cli_in_process(bench, capsys):
    assert run_cli(bench, str(demo.s19()), "--region", "CALIB", "--region", "APPLICATIVE", "--verify", "readback") == 0
    out = capsys.readouterr().out
    assert "read back" in out
    assert bench.flash_content(CALIB)[:14] == load_image(demo.s19()).read(CALIB.start, 14)


def test_a_dry_run_refuses_what_the_flash_refuses(bench, tmp_path, capsys):
    """The dry run asks the ECU what the flash asks first (programming offered, no DAQ running, its sectors):
    a flash that would be refused is a dry run refused, exit 1, as the flash itself."""
    path = tmp_path / "calib.s19"
    calib_image_with(THRESHOLD, 29.0).save(path)
    with bench.session.measure(["zsRailPressure"]):  # another master's DAQ runs on the ECU
        assert run_cli(bench, str(path), "--region", "CALIB", "--dry-run") == 1
    assert capsys.readouterr().err == ("error: a DAQ measurement runs on the ECU: stop it before flashing; nothing "
                                       "was touched\n")
    bench.session.connect()
    assert run_cli(bench, str(path), "--region", "CALIB", "--dry-run") == 0
    assert "dry run: nothing was flashed" in capsys.readouterr().out


def test_verify_only_without_a_region_compares_every_region_the_file_fills(bench, capsys):
    assert run_cli(bench, str(demo.s19()), "--verify-only") == 0
    out = capsys.readouterr().out
    assert "APPLICATIVE 840000h-84003Bh matches" in out and "CALIB FDFFF0h-FDFFFFh matches" in out


def test_json_says_the_operation_and_ok_as_the_a2l_reports_do(bench, tmp_path, capsys):
    path = tmp_path / "changed.s19"
    calib_image_with(THRESHOLD, 28.0).save(path)
    for extra, operation, code in ((["--dry-run"], "dry-run", 0), (["--verify-only"], "verify-only", 1), ([], "flash", 0),
                                   (["--verify-only"], "verify-only", 0)):
        assert run_cli(bench, str(path), "--region", "CALIB", "--json", *extra) == code
        report = json.loads(capsys.readouterr().out)
        assert report["operation"] == operation and report["ok"] is (code == 0)
        assert "plan" in report or "ranges" in report  # the fields there were stay


def test_a_file_that_gives_back_only_part_of_a_sector_is_refused_unless_told(bench, tmp_path, capsys):
    """The CALT trailer at FDFFF0h is in the sector the file's FC0000h-FC01C3h needs erased, not in the file."""
    path = tmp_path / "calib_noepk.s19"
    calib_image_with(THRESHOLD, 29.0).crop(CALIB.start, 0xFDFF00).save(path)
    before = bench.whole_flash()
    for extra in (["--dry-run"], []):
        assert run_cli(bench, str(path), "--region", "CALIB", *extra) == 1
        assert capsys.readouterr().err == (
            "error: calib_noepk.s19: erasing sector CALIB FC0000h-FDFFFFh would also erase FDFFF0h-FDFFFFh, which hold "
            "data the file does not give back: put them in the file, or pass --erase-beyond-file to lose them "
            "(nothing was erased)\n")
        assert bench.whole_flash() == before
    assert run_cli(bench, str(path), "--region", "CALIB", "--erase-beyond-file", "--dry-run") == 0
    assert "note: erased and not written again (--erase-beyond-file): FDFFF0h-FDFFFFh" in capsys.readouterr().out
    assert run_cli(bench, str(path), "--region", "CALIB", "--erase-beyond-file") == 0
    assert "erased and not written again (--erase-beyond-file): FDFFF0h-FDFFFFh" in capsys.readouterr().out
    assert bench.ecu.read(0xFDFFF0, 16) == b"\xff" * 16


def test_the_cli_flashes_a_boot_loader_of_another_kind_with_the_a2l_it_publishes(tmp_path, capsys):
    """``workbench sim --profile boot-minimal --write-a2l`` gives the A2L a master needs; ``workbench flash --a2l``
    with it programs the demo s19 as that boot loader wants (the A2L's small sectors, one PROGRAM a frame, pages
    ended by PROGRAM 0) and verifies it by UPLOAD (the profile matrix flashes every profile through the library)."""
    profile = "boot-minimal"
    where = {"interface": "virtual", "channel": f"cli-flash-{profile}"}
    with serve_demo(dict(where), profile=profile, time_scale=None) as simulator:
        a2l = tmp_path / f"{profile}.a2l"
        a2l.write_bytes(simulator.a2l.source.file_bytes(simulator.a2l.data))
        code = main(["flash", str(demo.s19()), "-r", "CALIB", "-r", "APPLICATIVE", "--a2l", str(a2l),
                     "--interface", "virtual", "--channel", where["channel"]])
        out = capsys.readouterr().out
        assert code == 0, out
        assert "verified: read-back of 3 sectors" in out and "the application runs" in out
        image = load_image(demo.s19())
        assert all(simulator.ecu.read(address, len(data)) == data for address, data in image.segments)


def test_reconnect_waits_as_long_as_told_for_an_ecu_that_boots_slowly(tmp_path, capsys):
    """An ECU that boots 1 s after PROGRAM_RESET, its A2L's T6 100 ms (three CONNECTs a try): --reconnect 0.2 gives up
    (the flash is complete, exit 1, said so), the default 5 s waits for it."""
    booting = SlaveProfile("slow-boot", "boots 1 s", "reconnect", pgm={"boot_s": 1.0}, timeouts_ms={"t6": 100})
    where = {"interface": "virtual", "channel": "cli-flash-slow-boot"}
    with serve_demo(dict(where), profile=booting, time_scale=None) as simulator:
        a2l = tmp_path / "slow-boot.a2l"
        a2l.write_bytes(simulator.a2l.source.file_bytes(simulator.a2l.data))
        bus = ["--a2l", str(a2l), "--interface", "virtual", "--channel", where["channel"]]
        assert main(["flash", str(demo.s19()), "-r", "CALIB", "--reconnect", "0.2", *bus]) == 1
        error = capsys.readouterr().err
        assert "complete and verified, but the ECU does not answer CONNECT after PROGRAM_RESET" in error
        assert main(["flash", str(demo.s19()), "-r", "CALIB", *bus]) == 0


def test_another_toolchain_s_file_flashes_and_a_damaged_one_is_refused_by_every_command(bench, tmp_path, capsys):
    """S2 records out of order, one twice (same bytes), CR LF and trailing blanks: flashed as the file says. A
    damaged record: flash, cal --image and a2l check --image each refuse it in one line naming file:line:column."""
    records = calib_image_with(THRESHOLD, 27.0).to_srec().splitlines()
    records = [bincopy.pack_srec("2", *bincopy.unpack_srec(line)[1:]) for line in records if line.startswith("S3")]
    random.Random(7).shuffle(records)
    foreign = tmp_path / "foreign.s28"
    foreign.write_bytes("".join(f"{line}  \r\n" for line in [*records, records[0], "S804000000FB"]).encode())
    assert run_cli(bench, str(foreign), "--region", "CALIB") == 0, capsys.readouterr().err
    assert bench.ecu.read(calibration_rom_address(THRESHOLD), 4) == struct.pack("<f", 27.0)
    lines = foreign.read_text().splitlines()
    lines[3] = lines[3].rstrip()[:-2] + ("00" if not lines[3].rstrip().endswith("00") else "01")
    damaged = tmp_path / "damaged.s28"
    damaged.write_text("\n".join(lines) + "\n")
    capsys.readouterr()
    column = len(lines[3]) - 1
    for argv in (["flash", damaged, "--region", "CALIB", "--interface", "virtual", "--channel", bench.channel],
                 ["cal", "get", THRESHOLD, "--image", damaged], ["a2l", "check", demo.a2l(), "--image", damaged]):
        code, out, err = run(capsys, *argv)
        assert (code, out) == (2, ""), argv
        assert err.startswith(f"error: {damaged}:4:{column}: checksum 00, the record's bytes give ") and \
            err.endswith(": the line is damaged\n"), err
