"""The sync's bookkeeping without an ECU: bytes known and patched, an image seen at the ECU's addresses, the
checksum search over a fake master."""

from __future__ import annotations

import zlib

import pytest

from workbench import WorkbenchError, demo
from workbench.a2l import load_a2l, read_xcp_config
from workbench.a2l.xcp import XcpAddressMapping
from workbench.calib.memory import ByteEdit, Span
from workbench.image import MemoryImage
from workbench.sync.areas import CalibrationArea, ImageView, calibration_areas
from workbench.sync.scan import LEAF_BYTES, scan_ranges
from workbench.sync.store import ByteStore


def test_pieces_join_and_later_bytes_win():
    store = ByteStore({Span(0x10, 4): b"abcd", Span(0x20, 2): b"xy"})
    store.put(0x14, b"EFGH")  # touches the first piece: one piece now
    store.put(0x1C, b"12345")  # overlaps the second: joined, its own bytes win
    assert store.spans() == [Span(0x10, 8), Span(0x1C, 6)]
    assert store.read(Span(0x12, 4)) == b"cdEF" and store.read(Span(0x1C, 6)) == b"12345y"
    store.apply([ByteEdit(0x11, b"ZZ")])
    assert store.read(Span(0x10, 4)) == b"aZZd"
    with pytest.raises(WorkbenchError, match="no bytes known at 0x17..0x1C"):
        store.read(Span(0x17, 6))


def test_a_copy_is_patched_alone_and_the_fallback_fills_only_what_is_missing():
    asked = []

    def fallback(spans):
        asked.extend(spans)
        return {span: bytes(range(span.address, span.end)) for span in spans}

    store = ByteStore({Span(4, 4): b"\xAA" * 4}, fallback)
    twin = store.copy()
    twin.put(4, b"\xBB")
    assert store.read(Span(4, 1)) == b"\xAA" and twin.read(Span(4, 1)) == b"\xBB"
    assert store.read(Span(2, 8)) == bytes([2, 3, 0xAA, 0xAA, 0xAA, 0xAA, 8, 9])  # held bytes stay
    assert asked == [Span(2, 8)]
    assert store.read(Span(3, 3)) == bytes([3, 0xAA, 0xAA]) and asked == [Span(2, 8)]  # kept, not asked again
    assert store.read(Span(4, 2, extension=1)) == bytes([4, 5])  # another address space


def test_the_demo_area_maps_the_working_page_onto_cal_rom():
    doc = load_a2l(demo.a2l())
    (area,) = calibration_areas(doc, read_xcp_config(doc))
    assert (area.name, area.span, area.segment, area.max_checksum_block) == ("CALRAM", Span(0x40000000, 0x20000), 0,
                                                                             0x20000)
    assert area.flash_address(0x40000010) == 0xFC0010


def test_an_image_is_read_through_the_mapping_or_as_it_stands():
    area = CalibrationArea("CAL", Span(0x1000, 0x100), 0, (XcpAddressMapping(0x1000, 0x9000, 0x80),))
    rom = MemoryImage.from_bytes(0x9000, b"\x01\x02\x03\x04")
    rom.add(0x9070, b"\x07" * 0x10)
    view = ImageView(rom, [area])
    assert view.held(area) == [Span(0x1000, 4), Span(0x1070, 0x10)]
    assert view.read(Span(0x1002, 4)) == b"\x03\x04\xff\xff"  # erased flash where the image holds nothing
    assert view.read(Span(0x107E, 4)) == b"\x07\x07\xff\xff"  # 0x1080.. is not mapped: read as it stands
    dump = ImageView(MemoryImage.from_bytes(0x1000, b"\x05\x06"), [area])
    assert dump.read(Span(0x1000, 2)) == b"\x05\x06" and dump.held(area) == [Span(0x1000, 2)]
    assert dump.image_address(0x1000) == 0x1000 and view.image_address(0x1000) == 0x9000


class FakeMaster:
    """BUILD_CHECKSUM (CRC-32) over bytes in a dict; counts the commands; refuses blocks beyond ``limit``."""

    order = "<"
    granularity = 1  # bytes per address (BYTE)

    def __init__(self, memory: bytes, base: int, limit: int = 1 << 20):
        self.memory, self.base, self.limit = bytearray(memory), base, limit
        self.sizes: list[int] = []

    def build_checksum(self, address: int, size: int, extension: int = 0):
        from workbench.errors import XcpCommandError
        from workbench.xcp_protocol import Err

        if size > self.limit:
            raise XcpCommandError("BUILD_CHECKSUM", Err.OUT_OF_RANGE)
        self.sizes.append(size)
        start = address - self.base
        return 0x09, zlib.crc32(bytes(self.memory[start:start + size]))

    def resynchronize(self):
        pass


def test_the_search_halves_down_to_the_leaves_and_spares_the_second_half_when_it_can():
    reference = bytes(4096)
    master = FakeMaster(reference, 0x1000)
    master.memory[3000] = 1
    scan = scan_ranges(master, [(Span(0x1000, 4096), reference)])
    assert scan.differing == [Span(0x1000 + 2944, LEAF_BYTES)]
    # the whole; then per halving the first half, and the second only when the first differs too (2048..3071
    # differs, so 3072..4095 is asked): 4096 -> 2048 (1) -> 1024 (2) -> 512 (1) -> 256 (1) -> 128 (1)
    assert scan.checksums == len(master.sizes) == 7 and scan.checksum_type == "CRC_32"
    master.memory[3000], master.memory[10], master.memory[4000] = 0, 1, 1
    scan = scan_ranges(master, [(Span(0x1000, 4096), reference)])
    assert scan.differing == [Span(0x1000, LEAF_BYTES), Span(0x1000 + 3968, LEAF_BYTES)]


def test_a_block_the_ecu_refuses_is_halved_and_remembered():
    reference = bytes(1024)
    master = FakeMaster(reference, 0, limit=256)
    scan = scan_ranges(master, [(Span(0, 1024), reference)], max_block=1024)
    assert scan.equal and master.sizes == [256, 256, 256, 256]
