"""The checksums of XCP's BUILD_CHECKSUM, computed the way the ASAM XCP standard defines them.

``ADD_xy`` sums elements of ``x`` bytes into a ``y``-byte result (modulo ``2**(8*y)``);
multi-byte elements use the ECU's byte order. ``CRC_16`` is CRC-16/ARC, ``CRC_16_CITT``
CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF), ``CRC_32`` the zlib CRC-32.
"""

from __future__ import annotations

import binascii
import zlib
from enum import IntEnum

import numpy as np
from crccheck.crc import Crc16Arc

__all__ = ["ChecksumType", "checksum"]


class ChecksumType(IntEnum):
    """XCP checksum types (BUILD_CHECKSUM response byte 1)."""

    ADD_11 = 0x01
    ADD_12 = 0x02
    ADD_14 = 0x03
    ADD_22 = 0x04
    ADD_24 = 0x05
    ADD_44 = 0x06
    CRC_16 = 0x07
    CRC_16_CITT = 0x08
    CRC_32 = 0x09

    @property
    def element_size(self) -> int:
        """Bytes per summed element; a checksummed block must be a multiple of it."""
        return {ChecksumType.ADD_22: 2, ChecksumType.ADD_24: 2, ChecksumType.ADD_44: 4}.get(self, 1)


_ADD_LAYOUT = {  # element dtype, result bits
    ChecksumType.ADD_11: ("u1", 8),
    ChecksumType.ADD_12: ("u1", 16),
    ChecksumType.ADD_14: ("u1", 32),
    ChecksumType.ADD_22: ("u2", 16),
    ChecksumType.ADD_24: ("u2", 32),
    ChecksumType.ADD_44: ("u4", 32),
}


def checksum(data: bytes, kind: ChecksumType, little_endian: bool = True) -> int:
    """The ``kind`` checksum of ``data``.

    :raises ValueError: ``len(data)`` is not a multiple of the element size of an ``ADD_x2``/``ADD_x4`` sum.
    """
    kind = ChecksumType(kind)
    if kind in _ADD_LAYOUT:
        element, bits = _ADD_LAYOUT[kind]
        if len(data) % kind.element_size:
            raise ValueError(f"{kind.name}: {len(data)} bytes is not a multiple of {kind.element_size}")
        dtype = np.dtype(element).newbyteorder("<" if little_endian else ">")
        total = int(np.frombuffer(data, dtype=dtype).sum(dtype=np.uint64))
        return total % (1 << bits)
    if kind is ChecksumType.CRC_16:
        return Crc16Arc.calc(data)
    if kind is ChecksumType.CRC_16_CITT:
        return binascii.crc_hqx(data, 0xFFFF)
    return zlib.crc32(data) & 0xFFFFFFFF
