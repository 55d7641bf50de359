"""A flash file written again with only its changed records rewritten: what offline calibration saves.

A calibration engineer who edits three values of a build's s19 expects three lines of the file to change,
not a file re-serialised with another record type, line length, header or order. :func:`patched_text` keeps
every line as it was but the data records that hold a changed byte: those are packed again by bincopy (same
record type, address and length; new data and checksum). The line endings stay the file's.
"""

from __future__ import annotations

import bincopy

from workbench.errors import InputError
from workbench.image.image import AddressRange, MemoryImage

__all__ = ["patched_text"]

_SREC_ADDRESS_DIGITS = {"1": 4, "2": 6, "3": 8}  # data records S1/S2/S3
_IHEX_DATA, _IHEX_SEGMENT, _IHEX_LINEAR = 0, 2, 4


def patched_text(text: str, image: MemoryImage, changed: list[AddressRange]) -> str:
    """``text`` (the S-record or Intel HEX file ``image`` was loaded from) with each data record that holds a byte
    of ``changed`` rewritten from ``image``; every other line stays as it was.

    :raises InputError: a changed byte lies in no record of the file (the image holds more than the file).
    """
    if not changed:
        return text
    lines = text.splitlines(keepends=True)
    covered = 0
    srec = text.lstrip().startswith("S")
    base = 0  # Intel HEX: the extended address in force
    for number, line in enumerate(lines):
        record = line.rstrip("\r\n").strip()
        if srec:
            digits = _SREC_ADDRESS_DIGITS.get(record[1:2])
            if digits is None:
                continue
            address, size = int(record[4:4 + digits], 16), int(record[2:4], 16) - digits // 2 - 1
        else:
            if len(record) < 11 or not record.startswith(":"):
                continue
            kind = int(record[7:9], 16)
            if kind == _IHEX_LINEAR:
                base = int(record[9:13], 16) << 16
            elif kind == _IHEX_SEGMENT:
                base = int(record[9:13], 16) << 4
            if kind != _IHEX_DATA:
                continue
            address, size = base + int(record[3:7], 16), int(record[1:3], 16)
        hit = sum(max(0, min(r.end, address + size) - max(r.start, address)) for r in changed)
        if not hit:
            continue
        covered += hit
        data = image.read(address, size)
        if srec:
            packed = bincopy.pack_srec(record[1], address, size, data)
        else:
            packed = bincopy.pack_ihex(_IHEX_DATA, address - base, size, data)
        lines[number] = line.replace(record, packed, 1)
    if covered < sum(r.size for r in changed):
        raise InputError(f"changed bytes in {' '.join(map(str, changed))} lie outside the file's records")
    return "".join(lines)
