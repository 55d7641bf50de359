"""The headers of an ELF file (ELF header, section and program headers) and a section's bytes.

Read with ``struct`` from a few kilobytes at the start and end of the file: pyelftools
takes about 45 ms to import and walk the headers of a large ELF, these few reads under one.
A compressed section is decompressed when read: the ELF way (SHF_COMPRESSED, zlib or zstd, as
``objcopy --compress-debug-sections`` and ``gcc -gz`` write them) and the older GNU way (``.zdebug_*``).
Every damage (a short read, a field pointing outside the file) is a ``ValueError`` the
caller turns into an error naming the file.
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path
from typing import NamedTuple

__all__ = ["ElfHeaders", "SectionHeader", "read_headers", "read_section"]

SHT_NOBITS, SHF_ALLOC, SHF_COMPRESSED = 8, 0x2, 0x800
PT_LOAD = 1
_SHN_LORESERVE, _SHN_XINDEX = 0xFF00, 0xFFFF
_ELFCOMPRESS_ZLIB, _ELFCOMPRESS_ZSTD = 1, 2
# ELF header after e_ident, section header, program header, compression header: by class
_HEADER = {32: "HHIIIIIHHHHHH", 64: "HHIQQQIHHHHHH"}
_SECTION = {32: "IIIIIIIIII", 64: "IIQQQQIIQQ"}
_SEGMENT = {32: "IIIIIIII", 64: "IIQQQQQQ"}
_CHDR = {32: "III", 64: "IIQQ"}


class SectionHeader(NamedTuple):
    name: str
    type: int
    flags: int
    address: int
    offset: int  # in the file
    size: int
    link: int


class Segment(NamedTuple):
    type: int
    vaddr: int
    paddr: int
    filesz: int
    memsz: int


class ElfHeaders(NamedTuple):
    little_endian: bool
    elfclass: int  # 32 or 64
    sections: list[SectionHeader]  # by section index
    segments: list[Segment]


def read_headers(path: Path) -> ElfHeaders:
    """The headers of the ELF at ``path``; raises ``ValueError`` for a file that is not one or is damaged
    (and ``OSError`` as ``open`` does)."""
    with open(path, "rb") as handle:
        ident = handle.read(16)
        if len(ident) < 16 or ident[:4] != b"\x7fELF" or ident[4] not in (1, 2) or ident[5] not in (1, 2):
            raise ValueError("no ELF header (magic number, class, byte order)")
        elfclass, order = 32 if ident[4] == 1 else 64, "<" if ident[5] == 1 else ">"
        fields = _unpack(order + _HEADER[elfclass], handle.read(struct.calcsize(order + _HEADER[elfclass])))
        phoff, shoff, phentsize, phnum, shentsize, shnum, shstrndx = fields[4], fields[5], *fields[8:]
        size, layout = path.stat().st_size, order + _SECTION[elfclass]
        if shoff and (shnum == 0 or shstrndx == _SHN_XINDEX):  # more sections than the header can count
            first = _table(handle, layout, shoff, shentsize, 1, size, "section")[0]
            shnum = first[5] if shnum == 0 else shnum
            shstrndx = first[6] if shstrndx == _SHN_XINDEX else shstrndx
        sections = _table(handle, layout, shoff, shentsize, shnum, size, "section")
        segments = _table(handle, order + _SEGMENT[elfclass], phoff, phentsize, phnum, size, "program")
        names = b""
        if sections and shstrndx < len(sections):
            handle.seek(sections[shstrndx][4])
            names = handle.read(sections[shstrndx][5])
    headers = []
    for name, kind, flags, address, offset, length, link, *_ in sections:
        if kind != SHT_NOBITS and offset + length > size:
            raise ValueError(f"a section of {length} bytes at offset {offset} lies outside the file of {size} bytes")
        end = names.find(b"\0", name)
        headers.append(SectionHeader(names[name : end if end >= 0 else len(names)].decode("utf-8", "replace"), kind,
                                     flags, address, offset, length, link))
    return ElfHeaders(order == "<", elfclass, headers,
                      [Segment(*(s[0], s[2], s[3], s[4], s[5]) if elfclass == 32 else (s[0], s[3], s[4], s[5], s[6]))
                       for s in segments])


def read_section(path: Path, section: SectionHeader, headers: ElfHeaders) -> bytes:
    """The bytes of ``section`` (decompressed when SHF_COMPRESSED); ValueError when they cannot be read."""
    if section.type == SHT_NOBITS:
        return b""
    with open(path, "rb") as handle:
        handle.seek(section.offset)
        data = handle.read(section.size)
    if len(data) != section.size:
        raise ValueError(f"section {section.name} lies outside the file")
    if section.name.startswith(".zdebug") and data[:4] == b"ZLIB":  # GNU's: "ZLIB", the size (8 bytes, big-endian)
        kind, expected, data = _ELFCOMPRESS_ZLIB, int.from_bytes(data[4:12], "big"), data[12:]
    elif section.flags & SHF_COMPRESSED:
        layout = ("<" if headers.little_endian else ">") + _CHDR[headers.elfclass]
        header = _unpack(layout, data[: struct.calcsize(layout)])
        kind, expected = header[0], header[1] if headers.elfclass == 32 else header[2]
        data = data[struct.calcsize(layout):]
    else:
        return data
    try:
        data = _decompress(kind, data)
    except (zlib.error, ValueError) as exc:
        raise ValueError(f"section {section.name} does not decompress ({exc})") from None
    if len(data) != expected:
        raise ValueError(f"section {section.name} decompresses to {len(data)} bytes, not {expected}")
    return data


def _decompress(kind: int, data: bytes) -> bytes:
    if kind == _ELFCOMPRESS_ZLIB:
        return zlib.decompress(data)
    if kind != _ELFCOMPRESS_ZSTD:
        raise ValueError(f"compression type {kind} is unknown to this reader")
    try:
        from compression import zstd  # Python 3.14

        return zstd.decompress(data)
    except ImportError:
        import zstandard  # a dependency below 3.14

        return zstandard.ZstdDecompressor().decompressobj().decompress(data)


def _table(handle, layout: str, offset: int, entry_size: int, count: int, file_size: int, what: str) -> list[tuple]:
    if not count:
        return []
    if entry_size < struct.calcsize(layout) or offset + entry_size * count > file_size:
        raise ValueError(f"the {what} header table lies outside the file or has entries of {entry_size} bytes")
    handle.seek(offset)
    raw = handle.read(entry_size * count)
    return [_unpack(layout, raw[i * entry_size : i * entry_size + struct.calcsize(layout)]) for i in range(count)]


def _unpack(layout: str, raw: bytes) -> tuple:
    if len(raw) < struct.calcsize(layout):
        raise ValueError("the file ends inside a header")
    return struct.unpack_from(layout, raw)
