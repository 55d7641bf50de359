"""Plans: the regions and partial ranges of a file, and every refusal before the ECU is touched."""

from __future__ import annotations

import dataclasses

import pytest
from flash_images import calib_image_with

from workbench import demo
from workbench.a2l import load_a2l, read_xcp_config
from workbench.errors import InputError
from workbench.flash import DEMO_APP_KEY, AppKey, FlashLayout, FlashRefused, Sector, plan_file, plan_flash
from workbench.flash.plan import programming_frames, with_sectors
from workbench.image import AddressRange, MemoryImage, load_image
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.sim.memory_map import HDS9

EPK = b"10300020250301\0\0"


@pytest.fixture(scope="module")
def layout() -> FlashLayout:
    doc = load_a2l(demo.a2l())
    return FlashLayout.from_a2l(doc, read_xcp_config(doc))


def image(*pieces: tuple[int, bytes]) -> MemoryImage:
    result = MemoryImage()
    for address, data in pieces:
        result.add(address, data)
    return result


def test_the_layout_is_the_a2ls_memory_segments_and_pgm_sectors(layout):
    assert [(r.name, r.start, r.size, r.selectable) for r in layout.regions] == [
        ("BOOT", 0x800000, 0x40000, True), ("APPLICATIVE", 0x840000, 0x780000, True),
        ("CALIB", 0xFC0000, 0x20000, True), ("SHARED", 0xFE0000, 0x4000, False)]
    assert [(s.name, s.range, s.clear_sequence, s.program_sequence) for s in layout.sectors] == [
        ("APPLICATIVE", AddressRange(0x840000, 0xFC0000), 1, 0), ("CALIB", AddressRange(0xFC0000, 0xFE0000), 2, 1),
        ("SHARED", AddressRange(0xFE0000, 0xFE4000), 0, 2)]
    assert (layout.epk, layout.addr_epk, layout.epk_addresses) == ("10300020250301", 0xFC0000, (0xFC0000, 0x840008))
    assert [(address, region.name) for address, region in layout.epk_parts] == [
        (0xFC0000, "CALIB"), (0x840008, "APPLICATIVE")]


def test_the_demo_key_is_the_one_the_simulated_boot_checks():
    assert (DEMO_APP_KEY.address, DEMO_APP_KEY.value) == (HDS9.app_key_address, HDS9.app_key)


def test_a_plan_shows_the_partial_ranges_as_the_thesis_dialog_does(layout):
    thesis = image((0xFC0000, EPK[:14]), (0xFC0010, bytes(0xC13)), (0xFDFFF0, bytes(16)))
    plan = plan_flash(thesis, layout, ["CALIB"], source="eAxle.s19")
    assert plan.regions[0].describe() == "Partial: FC0000h-FC000Dh FC0010h-FC0C22h FDFFF0h-FDFFFFh"
    assert plan.size == 14 + 0xC13 + 16
    assert [s.name for s in plan.sectors] == ["CALIB"] and plan.key_sector.name == "SHARED"
    text = plan.describe()
    assert "CALIB  FC0000h  FDFFFFh  020000h  Partial: FC0000h-FC000Dh FC0010h-FC0C22h FDFFF0h-FDFFFFh" in text
    assert "application key 3C C3 A5 5A at FE0000h: cleared first" in text


def test_the_demo_s19_fills_two_regions_and_the_one_not_chosen_is_listed_not_flashed(layout):
    plan = plan_file(demo.s19(), layout, ["CALIB"])
    assert [r.region.name for r in plan.regions] == ["CALIB"]
    assert plan.regions[0].ranges[0].start == 0xFC0000 and plan.regions[0].ranges[-1] == AddressRange(0xFDFFF0, 0xFE0000)
    assert plan.skipped[0][0] == "APPLICATIVE" and plan.skipped[0][1].startswith("Partial: 840000h-84003Bh")
    assert "(in the file, not selected)" in plan.describe()
    assert plan.image_epk == "10300020250301"
    both = plan_file(demo.s19(), layout, ["APPLICATIVE", "calib"])
    assert [r.region.name for r in both.regions] == ["APPLICATIVE", "CALIB"] and not both.skipped


def test_an_image_with_another_epk_is_refused(layout):
    wrong = image((0xFC0000, b"09000020240101\0\0"), (0xFC0010, bytes(16)))
    with pytest.raises(FlashRefused, match=r"EPK '09000020240101' at FC0000h \(CALIB\) differs from the A2L's "
                                           r"'10300020250301'"):
        plan_flash(wrong, layout, ["CALIB"])
    header = image((0x840000, b"HDS9\1\0\0\0" + b"09000020240101\0\0"))  # the application's own EPK (ADDR_EPK 2)
    with pytest.raises(FlashRefused, match=r"EPK '09000020240101' at 840008h \(APPLICATIVE\) differs"):
        plan_flash(header, layout, ["APPLICATIVE"])
    with pytest.raises(FlashRefused, match="EPK"):  # the EPK is checked for any region the file is flashed into
        plan_flash(image((0xFC0000, b"0900"), (0x840000, bytes(8))), layout, ["APPLICATIVE"])


def test_an_image_without_the_epk_is_not_checked(layout):
    plan = plan_flash(image((0x840000, bytes(8)), (0x840020, bytes(64))), layout, ["APPLICATIVE"])
    assert plan.image_epk is None


@pytest.mark.parametrize("address, where", [
    (0xFE0000, "in SHARED"),  # the key's own sector: the flash sets the key, a file must not
    (0x40000010, "in no flash region"),  # CAL RAM
    (0xFDFFF8, "FE0000h-FE0007h"),  # across the end of CALIB
])
def test_data_outside_the_flash_regions_is_refused(layout, address, where):
    with pytest.raises(FlashRefused, match=f"data outside the flash regions CALIB: .*{where}.*nothing was erased"):
        plan_flash(image((0xFC0000, EPK), (address, bytes(16))), layout, ["CALIB"])


def test_boot_needs_an_explicit_flag_and_then_a_sector_the_ecu_programs(layout):
    boot = image((0x800000, bytes(32)))
    with pytest.raises(FlashRefused, match="boot loader.*--allow-boot"):
        plan_flash(boot, layout, ["BOOT"])
    with pytest.raises(FlashRefused, match="no PGM sector covers 800000h-80001Fh in BOOT"):
        plan_flash(boot, layout, ["BOOT"], allow_boot=True)


def test_region_names_are_checked(layout):
    with pytest.raises(InputError, match="no flash region 'CALRAM'.*BOOT, APPLICATIVE, CALIB"):
        plan_flash(image((0xFC0000, EPK)), layout, ["CALRAM"])
    with pytest.raises(InputError, match="SHARED is no region to flash"):
        plan_flash(image((0xFE0000, bytes(4))), layout, ["SHARED"])
    with pytest.raises(InputError, match="name the region"):
        plan_flash(image((0xFC0000, EPK)), layout, [])
    with pytest.raises(FlashRefused, match="holds nothing in APPLICATIVE"):
        plan_flash(image((0xFC0000, EPK)), layout, ["APPLICATIVE"])


def test_overlapping_records_are_refused_with_their_line(tmp_path, layout):
    path = tmp_path / "overlap.s19"
    first = MemoryImage.from_bytes(0xFC0000, EPK).to_srec().splitlines()[0]
    second = MemoryImage.from_bytes(0xFC0008, bytes(16)).to_srec().splitlines()[0]
    path.write_text(f"{first}\n{second}\nS9030000FC\n")
    with pytest.raises(InputError, match=r"overlap.s19:2: the record gives 00 00 00 00 at FC0008h, line 1 gave "
                                         r"32 35 30 33: the file holds two contents for one address"):
        plan_file(path, layout, ["CALIB"])


def test_the_key_needs_a_sector_of_its_own(layout):
    calib = calib_image_with("xsSWITCH_TANK_THR", 25.0)
    with pytest.raises(FlashRefused, match="no PGM sector holds the application-valid key 01 at 7FF000h"):
        plan_flash(calib, layout, ["CALIB"], app_key=AppKey(0x7FF000, b"\x01"))
    with pytest.raises(FlashRefused, match="lies in CALIB, the region to flash"):
        plan_flash(calib, layout, ["CALIB"], app_key=AppKey(0xFDFFF0, b"\x01"))
    assert plan_flash(calib, layout, ["CALIB"], app_key=None).key_sector is None


def test_a_sector_reaching_beyond_the_chosen_regions_is_refused(layout):
    wide = dataclasses.replace(layout, sectors=(Sector("BIG", 0, AddressRange(0xFC0000, 0xFE4000)),))
    with pytest.raises(FlashRefused, match="erasing sector BIG FC0000h-FE3FFFh would also erase FE0000h-FE3FFFh"):
        plan_flash(calib_image_with("xsSWITCH_TANK_THR", 25.0), wide, ["CALIB"], app_key=None)


def test_the_ecus_finer_sectors_erase_only_those_the_ranges_touch(layout):
    plan = plan_file(demo.s19(), layout, ["CALIB"])
    fine = tuple(Sector("", n, AddressRange(a, a + 0x4000), 1, 1) for n, a in enumerate(range(0xFC0000, 0xFE0000, 0x4000)))
    fine += (Sector("", 8, AddressRange(0xFE0000, 0xFE4000), 0, 2),)
    replanned = with_sectors(plan, layout.with_sectors(fine, "ECU"))
    assert [s.range for s in replanned.sectors] == [AddressRange(0xFC0000, 0xFC4000), AddressRange(0xFDC000, 0xFE0000)]
    assert replanned.key_sector.range == AddressRange(0xFE0000, 0xFE4000)
    assert replanned.layout.sectors_from == "ECU"


def test_the_estimate_counts_the_frames_of_block_mode(layout):
    full = image((0xFC0000, EPK), (0xFC0010, bytes(0x20000 - 0x10)))  # one range of 128 KiB
    plan = plan_flash(full, layout, ["CALIB"])
    frames = -(-0x20000 // 6) + -(-0x20000 // 252) + 4  # data frames, one response a block, SET_MTA, PROGRAM 0
    assert plan.frames(252, 6) == frames
    fastest, slowest = plan.bus_time_s(1_000_000)
    assert fastest == frames * 111 / 1e6 and slowest == frames * 135 / 1e6


@pytest.mark.parametrize(("profile", "frames"), [("demo", (252, 6)), ("boot-minimal", (6, 6)), ("slow-flash", (54, 6)),
                                                 ("no-block-mode", (7, 7)), ("granularity-dword", (172, 4))])
def test_the_estimate_takes_the_blocks_and_frames_of_the_a2ls_pgm(profile, frames):
    """PGM's COMMUNICATION_MODE_SUPPORTED (MAX_BS_PGM) and MAX_CTO_PGM, not the protocol layer's; one PROGRAM a
    response without master block mode (PROGRAM_MAX where the ECU has it); whole elements of the granularity."""
    doc = build_demo_ecu(slave_profile=profile).a2l
    assert programming_frames(read_xcp_config(doc).for_transport("CAN")) == frames


def test_the_demo_s19_loads_as_the_simulated_ecu_holds_it():
    assert load_image(demo.s19()).crop(0xFC0000, 0xFC0000 + 14).segments[0][1] == EPK[:14]
