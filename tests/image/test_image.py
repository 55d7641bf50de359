"""Memory images: loading s19/hex, sparse ranges, cropping, saving, located errors."""

import pytest

from workbench.errors import InputError
from workbench.image import AddressRange, MemoryImage, Region, load_image, parse_image, split_by_region

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
    with pytest.raises(InputError, match=r"bad\.s19:3:77: checksum 00, the record's bytes give 8A: the line is "
                                         "damaged"):
        load_image(path)


S1 = ["S1130000000102030405060708090A0B0C0D0E0F74", "S107001010111213A2", "S9030000FC"]  # 0x0000-0x0013
IHEX = [":020000040001F9", ":0400000001020304F2", ":020000021000EC", ":020004000506EF", ":00000001FF"]


@pytest.mark.parametrize("lines, message", [
    ([S1[0], "S107001010111213", S1[2]], "x:2: the record's count says 7 bytes follow it, the line holds 6: it is cut "
                                         "short"),
    ([S1[0], "S1070010101G1213A2", S1[2]], "x:2:12: 'G' where a hex digit belongs"),
    ([S1[0], ":0400000001020304F2"], "x:2: an Intel HEX record in an S-record file (each record starts with S)"),
    (["S4030000FC"], "x:1:2: S4 is no S-record type (S0 header, S1-S3 data, S5/S6 count, S7-S9 end)"),
    ([S1[0], S1[1], "S5030003F9", S1[2]], "x:3: S5 counts 3 data records, the file has 2 before it: records are "
                                          "missing or doubled"),
    (IHEX[:2], "x:2: the file ends without the end-of-file record (:00000001FF): it is cut short"),
    (S1[:2], "x:2: the file ends without an end record (S7/S8/S9, or the S5/S6 count before it): it is cut short"),
    ([":0300000001020304F2", IHEX[-1]], "x:1: the record's count says 3 data bytes, the line holds 4: it runs on"),
    ([":03000004000100F8", IHEX[-1]], "x:1: an extended address record (04) holds 2 bytes, this one 3"),
    ([S1[0], "S107000211223344" + "XX", S1[2]], "x:2:17: 'X' where a hex digit belongs"),
    ([S1[0], S1[1], "S1070002112233444C", S1[2]], "x:3: the record gives 11 22 33 44 at 2h, line 1 gave 02 03 04 05: "
                                                  "the file holds two contents for one address"),
    (["S1070002112233444C", S1[0], S1[2]], "x:2: the record gives 02 03 04 05 at 2h, line 1 gave 11 22 33 44"),
])
def test_a_malformed_or_cut_file_names_the_line_and_what_belongs_there(lines, message):
    """Each refusal names file:line (:column where a character is wrong) and what was expected, not bincopy's raw
    message ("expected crc '41' in record S214FC00..., but got '00'")."""
    with pytest.raises(InputError) as refused:
        parse_image("\n".join(lines) + "\n", "x")
    assert str(refused.value).startswith(message)


def test_files_from_other_toolchains_are_read_whole():
    """Records out of order, a record repeated with the same bytes, CR LF, blanks, a byte order mark, a DOS Ctrl-Z;
    Intel HEX's extended linear (04) and segment (02) addresses each set the base of the records after them."""
    expected = MemoryImage.from_bytes(0, bytes(range(16)) + bytes.fromhex("10111213"))
    for text in ("\n".join([S1[1], S1[0], S1[1], S1[2]]),
                 "\ufeff" + "\r\n".join(f"  {line}  " for line in S1) + "\r\n\r\n\x1a",
                 "\r".join(S1)):
        assert parse_image(text) == expected
    # 04 0001: base 0x10000; 02 1000: base 0x1000 * 16, the same (bincopy adds the two: 0x20004)
    assert parse_image("\n".join(IHEX)).segments == [(0x10000, bytes.fromhex("010203040506"))]


def test_missing_and_foreign_files(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_image(tmp_path / "nope.s19")
    (tmp_path / "x.s19").write_text("hello\n")
    with pytest.raises(InputError, match=r"x\.s19:1: neither"):
        load_image(tmp_path / "x.s19")
