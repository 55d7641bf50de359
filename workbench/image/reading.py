"""The data records of an S-record or Intel HEX text, checked as a whole file and located (``file:line``).

bincopy decodes one record and checks its checksum (``unpack_srec``/``unpack_ihex``); what a whole file must be is
checked here, each refusal naming ``file:line`` and what was expected there:

* a damaged record: its checksum, its length, a character that is no hex digit (``file:line:column``), a record
  type the format does not have, an Intel HEX address record of another size than 2 bytes;
* the end: an Intel HEX file ends with its end-of-file record (01), an S-record file with its S7/S8/S9 end record
  or an S5/S6 count (linkers and srec_cat write the end record, bincopy the count and the end record only with a
  start address). A file cut short at a line's end (a copy or a download that broke off) would otherwise read as a
  whole one, and a flash of it verify against what it holds. An S5/S6 count must count the data records before it;
* the same address twice: a record that repeats bytes an earlier one gave is taken (merge tools and some linkers
  write such), one that gives other bytes is refused naming both lines.

Records may come in any order. An Intel HEX extended segment (02) or extended linear (04) address record sets the
base of the records that follow, the last one read counting (as srec_cat reads them; bincopy adds the two). Start
addresses (S7/S8/S9, 03/05) are kept. Blank lines, blanks around a record, CR LF or CR line ends, a UTF-8 byte order
mark and a DOS end-of-file character (Ctrl-Z) are accepted.
"""

from __future__ import annotations

import string
from dataclasses import dataclass
from typing import NoReturn

import bincopy

from workbench.errors import InputError

__all__ = ["ImageText", "read_image_text"]

_HEX = frozenset(string.hexdigits)
_SREC_DATA, _SREC_COUNT, _SREC_END = "123", "56", "789"
_SREC_TRAILER = _SREC_COUNT + _SREC_END  # what a file ends with: linkers write S7/S8/S9, bincopy S5/S6 without those
_IHEX_DATA, _IHEX_END, _IHEX_SEGMENT, _IHEX_LINEAR = 0, 1, 2, 4
_IHEX_START = (3, 5)
_IHEX_BASE_SHIFT = {_IHEX_SEGMENT: 4, _IHEX_LINEAR: 16}


@dataclass
class ImageText:
    """What an image file holds: contiguous pieces ``(address, data)`` in address order, its S0 header record, its
    start address."""

    pieces: list[tuple[int, bytes]]
    header: bytes | None = None  # the S0 record's data: text in any encoding, or bytes
    start_address: int | None = None


def read_image_text(text: str, path: object = "<text>") -> ImageText:
    """The pieces of the S-record or Intel HEX ``text`` (``path`` names it in errors; see the module docstring).

    :raises InputError: the text is malformed, cut short or gives two contents for one address: ``path:line``.
    """
    lines = text.lstrip("\ufeff").rstrip("\x1a \t\r\n").splitlines()
    first = next((n for n, line in enumerate(lines) if line.strip()), None)
    lead = lines[first].strip()[:1] if first is not None else ""
    if lead not in ("S", ":"):
        raise InputError(f"{path}:{(first or 0) + 1}: neither S-records (S0...S9) nor Intel HEX (:...)")
    read = _SrecReader(path) if lead == "S" else _IhexReader(path)
    last = 0
    for number, line in enumerate(lines, 1):
        record = line.strip()
        if record:
            read.record(number, record)
            last = number
    read.check_end(last)
    return ImageText(_pieces(read.data, path), read.header, read.start_address)


class _Reader:
    """One file's records; :meth:`record` takes them one by one, :meth:`check_end` after the last."""

    srec = True
    name = "S-record"
    lead = "S"

    def __init__(self, path: object):
        self.path = path
        self.data: list[tuple[int, int, bytes]] = []  # (address, line, bytes)
        self.header: bytes | None = None
        self.start_address: int | None = None
        self.ended = False  # the last record read is one a whole file ends with

    def refuse(self, number: int, record: str, error: Exception) -> NoReturn:
        """:raises InputError: what is wrong with the record bincopy refused (its message if not found here)."""
        raise InputError(f"{self.path}:{self._damage(number, record) or f'{number}: {error}'}") from None

    def _damage(self, number: int, record: str) -> str:
        """What is wrong with a record bincopy refused: ``line[:column]: reason``; "" when not found here."""
        if not record.startswith(self.lead):
            other = "an Intel HEX record" if record.startswith(":") else "an S-record" if record.startswith("S") \
                else repr(record[:16] + ("..." if len(record) > 16 else ""))
            return f"{number}: {other} in an {self.name} file (each record starts with {self.lead})"
        if self.srec and record[1:2] not in "012356789":
            return f"{number}:2: S{record[1:2]} is no S-record type (S0 header, S1-S3 data, S5/S6 count, S7-S9 end)"
        body = record[2:] if self.srec else record[1:]
        offset = len(record) - len(body)
        bad = next((i for i, char in enumerate(body) if char not in _HEX), None)
        if bad is not None:
            return f"{number}:{offset + bad + 1}: {body[bad]!r} where a hex digit belongs"
        if len(body) < (4 if self.srec else 10):
            return f"{number}: the record is too short to be one ({record!r})"
        count = int(body[:2], 16)
        expected = 2 + 2 * count if self.srec else 10 + 2 * count  # digits: count, (address, type,) data, checksum
        if len(body) != expected:
            holds = (len(body) - 2) // 2 if self.srec else (len(body) - 10) // 2
            what = "bytes follow it" if self.srec else "data bytes"
            cut = "it is cut short" if len(body) < expected else "it runs on"
            return f"{number}: the record's count says {count} {what}, the line holds {holds}: {cut}"
        given = int(body[-2:], 16)
        computed = (bincopy.crc_srec if self.srec else bincopy.crc_ihex)(body[:-2])
        if given != computed:
            return (f"{number}:{len(record) - 1}: checksum {given:02X}, the record's bytes give {computed:02X}: the "
                    "line is damaged")
        return ""

    def check_end(self, last: int) -> None:
        """:raises InputError: the file does not end as its format requires (cut short)."""
        if not self.ended:
            raise InputError(f"{self.path}:{last}: the file ends without {self.trailer}: it is cut short (a whole "
                             "file ends with one)")


class _SrecReader(_Reader):
    trailer = "an end record (S7/S8/S9, or the S5/S6 count before it)"

    def record(self, number: int, record: str) -> None:
        try:
            kind, address, _size, data = bincopy.unpack_srec(record)
        except (bincopy.Error, ValueError) as error:
            self.refuse(number, record, error)
        self.ended = kind in _SREC_TRAILER
        if kind in _SREC_DATA:
            self.data.append((address, number, data))
            return
        if kind == "0":
            self.header = bytes(data)
        elif kind in _SREC_COUNT:
            counted, bits = len(self.data), 16 if kind == "5" else 24
            if address != counted % (1 << bits):
                raise InputError(f"{self.path}:{number}: S{kind} counts {address} data records, the file has "
                                 f"{counted} before it: records are missing or doubled")
        elif kind in _SREC_END:
            self.start_address = address


class _IhexReader(_Reader):
    srec = False
    name = "Intel HEX"
    lead = ":"
    trailer = "the end-of-file record (:00000001FF)"

    def __init__(self, path: object):
        super().__init__(path)
        self.base = 0  # the extended segment (02) or linear (04) address in force

    def record(self, number: int, record: str) -> None:
        try:
            kind, address, size, data = bincopy.unpack_ihex(record)
        except (bincopy.Error, ValueError) as error:
            self.refuse(number, record, error)
        self.ended = kind == _IHEX_END
        if kind == _IHEX_DATA:
            self.data.append((self.base + address, number, data))
            return
        if kind in _IHEX_BASE_SHIFT:
            if size != 2:
                raise InputError(f"{self.path}:{number}: an extended address record ({kind:02d}) holds 2 bytes, "
                                 f"this one {size}")
            self.base = int.from_bytes(data, "big") << _IHEX_BASE_SHIFT[kind]
        elif kind in _IHEX_START:
            self.start_address = int.from_bytes(data, "big")
        elif not self.ended:
            raise InputError(f"{self.path}:{number}: record type {kind:02X} is none of Intel HEX's (00 data, 01 end, "
                             "02/04 extended address, 03/05 start address)")



def _pieces(records: list[tuple[int, int, bytes]], path: object) -> list[tuple[int, bytes]]:
    """The records joined into contiguous pieces in address order; bytes two records give alike are taken once.

    :raises InputError: two records give different bytes for one address (both lines named).
    """
    pieces: list[tuple[int, bytes]] = []
    start, joined = 0, bytearray()
    for address, _, data in records:  # a linker's order: ascending, no byte twice
        if address == start + len(joined):
            joined += data
        elif address > start + len(joined):
            if joined:
                pieces.append((start, bytes(joined)))
            start, joined = address, bytearray(data)
        else:
            return _sorted_pieces(records, path)
    if joined:
        pieces.append((start, bytes(joined)))
    return pieces


def _sorted_pieces(records: list[tuple[int, int, bytes]], path: object) -> list[tuple[int, bytes]]:
    """:func:`_pieces` of records out of order or overlapping."""
    records.sort(key=lambda record: (record[0], record[1]))
    pieces: list[tuple[int, bytes]] = []
    start, joined, spans = 0, bytearray(), []  # the piece being joined, its records' (start, end, line)
    for address, number, data in records:
        end = start + len(joined)
        if address == end and spans:  # the common case: the next record
            joined += data
            spans.append((address, address + len(data), number))
            continue
        if address > end or not spans:
            if spans:
                pieces.append((start, bytes(joined)))
            start, joined, spans = address, bytearray(data), [(address, address + len(data), number)]
            continue
        held = joined[address - start:address - start + len(data)]
        if held != data[:len(held)]:
            _two_contents(path, address, number, data, held, spans)
        joined += data[len(held):]
        spans.append((address, address + len(data), number))
    if spans:
        pieces.append((start, bytes(joined)))
    return pieces


def _two_contents(path: object, address: int, number: int, data: bytes, held: bytes, spans: list) -> None:
    at = next(i for i, (mine, theirs) in enumerate(zip(data, held)) if mine != theirs)
    other = next(line for first, end, line in reversed(spans) if first <= address + at < end)
    ours, theirs = data[at:at + 4].hex(" ").upper(), held[at:at + 4].hex(" ").upper()
    (early, said), (late, says) = sorted([(other, theirs), (number, ours)])
    raise InputError(f"{path}:{late}: the record gives {says} at {address + at:X}h, line {early} gave {said}: the file "
                     "holds two contents for one address (two builds merged?)")
