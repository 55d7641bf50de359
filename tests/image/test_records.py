"""patched_text: a flash file written again with only the records of changed bytes rewritten, every other line (and
the line endings, the record types, an Intel HEX file's extended segment addresses) as it was."""

from __future__ import annotations

import bincopy
import pytest

from workbench.errors import InputError
from workbench.image import AddressRange, parse_image, patched_text


def test_an_s_record_file_keeps_its_lines_and_endings():
    records = [bincopy.pack_srec("0", 0, 4, b"demo"), bincopy.pack_srec("2", 0xFC0000, 8, bytes(range(8))),
               bincopy.pack_srec("2", 0xFC0008, 4, b"\xff" * 4), bincopy.pack_srec("8", 0xFC0000, 0, b"")]
    text = "\r\n".join(records) + "\r\n"
    image = parse_image(text)
    image.add(0xFC0009, b"\x42", overwrite=True)
    out = patched_text(text, image, [AddressRange(0xFC0009, 0xFC000A)])
    lines = out.split("\r\n")
    assert lines[:2] == records[:2] and lines[3:] == [records[3], ""]
    assert lines[2] == bincopy.pack_srec("2", 0xFC0008, 4, b"\xff\x42\xff\xff")
    assert parse_image(out) == image


def test_intel_hex_with_segment_addresses_is_patched_where_the_record_lies():
    records = [bincopy.pack_ihex(2, 0, 2, b"\x10\x00"),  # extended segment address 0x1000 -> base 0x10000
               bincopy.pack_ihex(0, 0x0010, 4, b"\x01\x02\x03\x04"), bincopy.pack_ihex(1, 0, 0, b"")]
    text = "\n".join(records) + "\n"
    image = parse_image(text)
    assert image.read(0x10010, 4) == b"\x01\x02\x03\x04"
    image.add(0x10012, b"\x33", overwrite=True)
    out = patched_text(text, image, [AddressRange(0x10012, 0x10013)])
    assert out.splitlines() == [records[0], bincopy.pack_ihex(0, 0x0010, 4, b"\x01\x02\x33\x04"), records[2]]


def test_a_change_no_record_holds_is_refused():
    text = bincopy.pack_srec("1", 0x100, 2, b"ab") + "\nS9030000FC\n"
    image = parse_image(text)
    image.add(0x200, b"x")
    with pytest.raises(InputError, match="outside the file's records"):
        patched_text(text, image, [AddressRange(0x200, 0x201)])
