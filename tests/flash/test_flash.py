"""The flash sequence against the simulated ECU: CALIB, APPLICATIVE, the working page, progress, cancel,
refusals that leave the flash untouched, verification, the key sector's other bytes."""

from __future__ import annotations

import struct
from dataclasses import replace

import pytest
from flash_images import (
    APPLICATIVE,
    CALIB,
    PATIENT,
    application_image,
    calib_image_with,
    calibration_rom_address,
    open_bench,
)

from workbench import demo
from workbench.elf import ElfSymbols
from workbench.errors import Cancelled
from workbench.flash import (
    FlashError,
    FlashLayout,
    FlashOptions,
    FlashRefused,
    Verify,
    check_flash,
    flash_ecu,
    plan_flash,
    plan_working_page,
    verify_ecu,
)
from workbench.image import MemoryImage
from workbench.session import Session
from workbench.sim import EthernetEndpoint, serve_demo
from workbench.sim.ecu import EcuState
from workbench.sim.memory_map import HDS9
from workbench.sim.profiles import SlaveProfile
from workbench.xcp_protocol import Cmd, Err, Resource

THRESHOLD = "xsSWITCH_TANK_THR"  # real32, 20.0 in the demo s19


class Recorder:
    """A Progress that remembers every report and cancels once ``cancel_at`` bytes are done."""

    def __init__(self, cancel_at: int | None = None):
        self.reports: list[tuple[int, int, str]] = []
        self.cancel_at = cancel_at

    def update(self, done: int, total: int, label: str = "") -> None:
        self.reports.append((done, total, label))

    @property
    def cancelled(self) -> bool:
        return self.cancel_at is not None and bool(self.reports) and self.reports[-1][0] >= self.cancel_at


@pytest.fixture
def bench():
    """On the lockstep wire: a loaded machine makes no answer late for FAST's T1 of 100 ms (conftest's bench, on a
    virtual bus, is for the CLI's tests, which reach the ECU by its channel)."""
    with open_bench(lockstep=True) as bench:
        yield bench


def threshold_in_ram(bench) -> float:
    address = ElfSymbols(demo.elf()).symbol(THRESHOLD).address
    return struct.unpack("<f", bench.session.read_memory(address, 4))[0]


def test_a_changed_calibration_flashed_into_calib_survives_a_power_cycle(bench):
    assert threshold_in_ram(bench) == 20.0
    plan = plan_flash(calib_image_with(THRESHOLD, 27.5), bench.layout, ["CALIB"], source="cal.s19")
    result = flash_ecu(bench.session, plan)
    assert result.application_running and result.verified == "CRC_32 of 1 sector"
    assert bench.ecu.read(calibration_rom_address(THRESHOLD), 4) == struct.pack("<f", 27.5)
    bench.power_cycle()
    assert threshold_in_ram(bench) == 27.5  # the boot copied CAL ROM into CAL RAM
    assert bench.flash_content(CALIB) == plan.sector_content(plan.sectors[0])  # gaps erased, nothing else


def test_an_applicative_flash_verifies_sets_the_key_and_starts_the_application(bench):
    plan = plan_flash(application_image(20_000), bench.layout, ["APPLICATIVE"], source="app.s19")
    calib_before = bench.flash_content(CALIB)
    result = flash_ecu(bench.session, plan)
    assert bench.flash_content(APPLICATIVE) == plan.sector_content(plan.sectors[0])
    assert bench.flash_content(CALIB) == calib_before
    assert bench.ecu.read(HDS9.app_key_address, 4) == HDS9.app_key
    assert bench.ecu.state is EcuState.APPLICATION
    assert bench.session.master.connect_info.resources & (Resource.CAL_PAG | Resource.DAQ) == Resource.CAL_PAG | Resource.DAQ
    assert result.epk.startswith("EPK match") and result.recoveries == result.rewrites == 0
    assert result.bytes_sent == plan.size + len(HDS9.app_key) and result.rate > 0


def test_an_ecu_in_boot_is_flashed_into_running_its_application(bench):
    bench.ecu.faults.power_loss_at_program(1)
    plan = plan_flash(application_image(2_000), bench.layout, ["APPLICATIVE"])
    with pytest.raises(FlashError):
        flash_ecu(bench.session, plan)
    bench.simulator.power_on()
    bench.session.connect()
    assert bench.session.in_boot
    assert flash_ecu(bench.session, plan).application_running


def test_progress_reports_bytes_rate_and_time_left(bench):
    plan = plan_flash(application_image(30_000), bench.layout, ["APPLICATIVE"])
    progress = Recorder()
    flash_ecu(bench.session, plan, progress=progress)
    programming = [r for r in progress.reports if r[2].startswith("programming")]
    assert {total for _, total, _ in progress.reports} == {plan.size}
    assert [done for done, _, _ in programming] == sorted(done for done, _, _ in programming)
    assert programming[-1][0] == plan.size
    assert "KiB/s" in programming[-1][2] and programming[-1][2].endswith("0:00 left")
    labels = [label for _, _, label in progress.reports]
    assert labels.index("PROGRAM_START") < labels.index("erasing sector SHARED FE0000h-FE3FFFh") < \
        labels.index("erasing sector APPLICATIVE 840000h-FBFFFFh") < labels.index(programming[0][2]) < \
        labels.index("verifying sector APPLICATIVE 840000h-FBFFFFh") < labels.index("PROGRAM_RESET")


def test_a_cancel_stops_at_a_block_leaves_the_ecu_in_boot_and_a_new_flash_finishes(bench):
    plan = plan_flash(application_image(30_000), bench.layout, ["APPLICATIVE"])
    with pytest.raises(Cancelled, match="application key is cleared: the ECU was reset and stays in boot"):
        flash_ecu(bench.session, plan, progress=Recorder(cancel_at=10_000))
    assert bench.ecu.state is EcuState.BOOT
    assert bench.ecu.read(HDS9.app_key_address, 4) == b"\xff" * 4
    bench.session.connect()
    assert bench.session.in_boot
    flash_ecu(bench.session, plan)
    assert bench.ecu.state is EcuState.APPLICATION


def test_a_cancel_before_anything_was_erased_leaves_the_application_running(bench):
    plan = plan_flash(application_image(3_000), bench.layout, ["APPLICATIVE"])
    before = bench.whole_flash()

    class CancelAt(Recorder):
        def __init__(self, label: str):
            super().__init__()
            self.label = label

        @property
        def cancelled(self) -> bool:
            return self.reports[-1][2].startswith(self.label)

    with pytest.raises(Cancelled, match=r"cancelled: PROGRAM_START at 0/\d+; nothing was written to the ECU"):
        flash_ecu(bench.session, plan, progress=CancelAt("PROGRAM_START"))
    with pytest.raises(Cancelled, match="nothing was erased; the ECU was reset"):  # after PROGRAM_START halted it
        flash_ecu(bench.session, plan, progress=CancelAt("erasing"))
    assert bench.whole_flash() == before and bench.ecu.state is EcuState.APPLICATION


def test_a_running_daq_measurement_is_refused(bench):
    master = bench.session.master
    master.free_daq()
    master.alloc_daq(1)
    master.alloc_odt(0, 1)
    master.alloc_odt_entry(0, 0, 1)
    master.set_daq_ptr(0, 0, 0)
    master.write_daq(4, 0x40020000)
    master.set_daq_list_mode(0, 0, timestamp=False)
    master.start_stop_daq_list(0, 1)
    before = bench.whole_flash()
    with pytest.raises(FlashRefused, match="DAQ measurement runs"):
        flash_ecu(bench.session, plan_flash(application_image(100), bench.layout, ["APPLICATIVE"]))
    assert bench.whole_flash() == before


def test_a_refusal_names_the_flash_option_that_overrides_it_and_a_script_passes_it(bench, monkeypatch):
    """What the dialog offers and the CLI's --erase-beyond-file / --accept-epk-mismatch set: FlashOptions fields."""
    image = calib_image_with("xsSWITCH_TANK_THR", 29.0).crop(CALIB.start, 0xFDFF00)  # not the CALT trailer
    plan = plan_flash(image, bench.layout, ["CALIB"], source="part.s19")
    with pytest.raises(FlashRefused, match="would also erase FDFFF0h-FDFFFFh") as refused:
        check_flash(bench.session, plan)
    assert refused.value.override == "erase_beyond_file" and refused.value.regions == ()
    other = tuple(replace(part, ecu="10300020259999") for part in bench.session.epk.parts)
    monkeypatch.setattr(bench.session, "epk", replace(bench.session.epk, ecu="10300020259999", parts=other))  # another build runs
    with pytest.raises(FlashRefused, match="for the application that stays on it") as refused:
        check_flash(bench.session, plan)
    assert refused.value.override == "accept_epk_mismatch"
    _, notes = check_flash(bench.session, plan, FlashOptions(erase_beyond_file=True, accept_epk_mismatch=True))
    assert "erased and not written again (--erase-beyond-file): FDFFF0h-FDFFFFh" in notes
    assert any("MISMATCH accepted" in note for note in notes)


def test_the_working_page_goes_into_cal_rom_and_survives_a_power_cycle(bench):
    address = ElfSymbols(demo.elf()).symbol(THRESHOLD).address
    bench.session.write_memory(address, struct.pack("<f", 33.0))
    rom_before = bench.flash_content(CALIB)
    progress = Recorder()
    plan = plan_working_page(bench.session, progress=progress)
    assert plan.source == "working page" and plan.image_epk == "10300020250301"
    assert plan.regions[0].ranges == MemoryImage.from_flash_content(CALIB.start, rom_before).ranges
    assert any(label.startswith("reading the working page") for _, _, label in progress.reports)
    flash_ecu(bench.session, plan)
    bench.power_cycle()
    assert threshold_in_ram(bench) == 33.0
    rom = bench.flash_content(CALIB)
    changed = [i for i in range(len(rom)) if rom[i] != rom_before[i]]
    offset = calibration_rom_address(THRESHOLD) - CALIB.start
    assert changed and all(offset <= i < offset + 4 for i in changed)  # the EPK, the trailer, all else as it was


def test_no_working_page_in_boot(bench):
    bench.ecu.faults.power_loss_at_program(1)
    with pytest.raises(FlashError):
        flash_ecu(bench.session, plan_flash(application_image(100), bench.layout, ["APPLICATIVE"]))
    bench.simulator.power_on()
    bench.session.connect()
    with pytest.raises(FlashRefused, match="in boot"):
        plan_working_page(bench.session)


def test_verify_only_compares_without_writing(bench):
    plan = plan_flash(calib_image_with(THRESHOLD, 20.0), bench.layout, ["CALIB"])
    before = bench.whole_flash()
    assert all(check.matches for check in verify_ecu(bench.session, plan))
    changed = plan_flash(calib_image_with(THRESHOLD, 21.0), bench.layout, ["CALIB"])
    checks = verify_ecu(bench.session, changed)
    assert [check.matches for check in checks] == [False, True]
    assert "DIFFERS" in str(checks[0])
    assert bench.whole_flash() == before


def test_readback_verification_and_none_on_request(bench):
    plan = plan_flash(calib_image_with(THRESHOLD, 22.0), bench.layout, ["CALIB"])
    assert flash_ecu(bench.session, plan, options=FlashOptions(verify=Verify.READBACK)).verified == \
        f"CRC_32 of 1 sector, {plan.size} bytes read back"
    result = flash_ecu(bench.session, plan, options=FlashOptions(verify=Verify.NONE))
    assert result.verified == "not verified" and "not verified (the user chose so)" in result.notes


def test_what_the_key_sector_holds_besides_the_key_is_kept(bench):
    bench.ecu.memory.program(0xFE0100, b"boot's own data")  # e.g. a counter the boot keeps there
    plan = plan_flash(calib_image_with(THRESHOLD, 23.0), bench.layout, ["CALIB"])
    result = flash_ecu(bench.session, plan)
    assert bench.ecu.read(0xFE0100, 15) == b"boot's own data"
    assert bench.ecu.read(HDS9.app_key_address, 4) == HDS9.app_key
    assert "kept what sector SHARED FE0000h-FE3FFFh holds besides the key" in result.notes


def test_a_wrong_write_is_found_by_verification_and_the_sector_written_again(bench):
    plan = plan_flash(calib_image_with(THRESHOLD, 24.0), bench.layout, ["CALIB"])
    original = bench.ecu.memory.program

    def program_one_byte_wrong(address, data):  # a flash cell that takes a wrong value, once
        bench.ecu.memory.program = original
        original(address, bytes([data[0] ^ 0x01]) + data[1:])

    bench.ecu.memory.program = program_one_byte_wrong
    result = flash_ecu(bench.session, plan)
    assert result.rewrites == 1
    assert bench.flash_content(CALIB) == plan.sector_content(plan.sectors[0])


@pytest.mark.parametrize("protocol", ["tcp", "udp"])
def test_flash_over_xcp_on_ethernet_in_packets_of_its_max_cto(request, protocol):
    port = request.getfixturevalue(f"free_{protocol}_port")
    with serve_demo(ethernet=EthernetEndpoint("127.0.0.1", port, protocol), time_scale=None) as simulator, \
            Session.open(demo.a2l(), host="127.0.0.1", port=port, protocol=protocol, timeouts=PATIENT) as session:
        assert session.master.max_cto == 255  # one PROGRAM of 253 bytes a command: no block mode needed
        plan = plan_flash(application_image(50_000), FlashLayout.from_a2l(session.doc, session.config),
                          ["APPLICATIVE"])
        result = flash_ecu(session, plan)
        assert result.application_running
        assert simulator.ecu.read(APPLICATIVE.start, APPLICATIVE.size) == plan.sector_content(plan.sectors[0])


def test_an_ecu_that_refuses_to_go_on_where_a_block_broke_gets_the_sector_erased_and_written_again(bench):
    plan = plan_flash(calib_image_with(THRESHOLD, 25.5), bench.layout, ["CALIB"])
    bench.ecu.faults.reject_command(2, Err.ACCESS_DENIED, Cmd.PROGRAM)  # the second block: repaired by going on
    bench.ecu.faults.reject_command(3, Err.ACCESS_DENIED, Cmd.PROGRAM)  # and there again: as a real page refuses
    result = flash_ecu(bench.session, plan)
    assert (result.recoveries, result.rewrites) == (2, 1)
    assert bench.flash_content(CALIB) == plan.sector_content(plan.sectors[0])


def test_an_ecu_that_programs_in_functional_mode_only_is_refused_before_anything_is_erased(bench):
    """GET_PGM_PROCESSOR_INFO without absolute access mode: PROGRAM_CLEAR by address would be refused after the key
    was cleared; the flash is refused before."""
    slave = bench.ecu.slave
    slave.params = replace(slave.params, pgm=replace(slave.params.pgm, functional_only=True))
    before = bench.whole_flash()
    with pytest.raises(FlashRefused, match="functional mode only"):
        flash_ecu(bench.session, plan_flash(calib_image_with(THRESHOLD, 25.5), bench.layout, ["CALIB"]))
    assert bench.whole_flash() == before and bench.ecu.state is EcuState.APPLICATION


def test_an_ecu_that_counts_no_sectors_is_erased_in_the_a2ls():
    """GET_PGM_PROCESSOR_INFO's MAX_SECTOR 0 tells nothing (it is no flash without sectors): the A2L's 16 KiB sectors
    are erased, not all CALIB as one."""
    untold = SlaveProfile("sectors-untold", "MAX_SECTOR 0", "the A2L's sectors", pgm={"counts_sectors": False},
                          sector_sizes={"APPLICATIVE": 0x10000, "CALIB": 0x4000, "SHARED": 0x4000})
    where = {"interface": "virtual", "channel": "flash-sectors-untold"}
    with serve_demo(dict(where), profile=untold, time_scale=None) as simulator, \
            Session.open(simulator.a2l, **where, timeouts=PATIENT) as session:
        plan = plan_flash(calib_image_with(THRESHOLD, 25.5), FlashLayout.from_a2l(session.doc, session.config),
                          ["CALIB"])
        result = flash_ecu(session, plan)
        assert [(s.range.start, s.range.size) for s in result.plan.sectors] == [(0xFC0000, 0x4000), (0xFDC000, 0x4000)]
        assert result.application_running and not result.notes
