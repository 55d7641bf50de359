"""Memory images: loading s19/hex, sparse ranges, cropping, saving, located errors."""

import pytest

from workbench.errors import InputError
from workbench.image import AddressRange, MemoryImage, Region, load_image, split_by_region

CALIB = Region("CALIB", 0xFC0000, 0x20000, 0x4000)


def thesis_like_image() -> MemoryImage:
    """The CALIB part of the thesis's s19: EPK, the cal data, the trailer (thesis 5.4)."""
    image = MemoryImage()
    image.add(0xFC0000, b"08493820231002")
    image.add(0xFC0010, bytes(range(256)) * 12 + bytes(0xC23 - 0x10 - 256 * 12))
    image.add(0xFDFFF0, b"\xA5" * 16)
    return image


def test_partial_ranges_as_the_flash_dialog_prints_them():
    image = thesis_like_image()
    assert CALIB.describe(image) == "Partial: FC0000h-FC000Dh FC0010h-FC0C22h FDFFF0h-FDFFFFh"
    assert CALIB.partial_ranges(image)[0] == AddressRange(0xFC0000, 0xFC000E)


def test_full_and_empty_regions():
    full = MemoryImage.from_bytes(CALIB.start, b"\0" * CALIB.size)
    assert CALIB.describe(full) == "Full"
    assert CALIB.describe(MemoryImage()) == "empty"


def test_read_fills_gaps_with_erased_bytes():
    image = thesis_like_image()
    assert image.read(0xFC000C, 6) == b"02\xff\xff\x00\x01"


def test_srec_and_ihex_round_trip(tmp_path):
    image = thesis_like_image()
    for name in ("calib.s19", "calib.hex"):
        image.save(tmp_path / name)
        assert load_image(tmp_path / name) == image


def test_split_by_region_reports_what_no_region_holds():
    image = thesis_like_image()
    image.add(0xFE0000, b"\x3c\xc3\xa5\x5a")
    pieces, outside = split_by_region(image, [CALIB])
    assert list(pieces) == ["CALIB"] and pieces["CALIB"].size == image.size - 4
    assert outside == [AddressRange(0xFE0000, 0xFE0004)]


def test_overlapping_data_is_refused():
    image = MemoryImage.from_bytes(0x100, b"abc")
    with pytest.raises(InputError, match="overlaps"):
        image.add(0x101, b"x")


def test_bad_record_names_file_and_line(tmp_path):
    good = MemoryImage.from_bytes(0x1000, bytes(100)).to_srec().splitlines()
    good[2] = good[2][:-2] + ("00" if good[2][-2:] != "00" else "01")  # break one checksum
    path = tmp_path / "bad.s19"
    path.write_text("\n".join(good) + "\n")
    with pytest.raises(InputError, match=r"bad\.s19:3: .*crc"):
        load_image(path)


def test_missing_and_foreign_files(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_image(tmp_path / "nope.s19")
    (tmp_path / "x.s19").write_text("hello\n")
    with pytest.raises(InputError, match=r"x\.s19:1: neither"):
        load_image(tmp_path / "x.s19")
