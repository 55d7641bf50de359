"""Compare ECU memory with expected bytes by BUILD_CHECKSUM, computed locally with the ECU's checksum type.

The ECU names its checksum type in every response; the largest block it accepts starts as the
caller says (cache sync: the segment's CHECKSUM MAX_BLOCK_SIZE) and is learnt from ERR_OUT_OF_RANGE:
the size the ECU returns there (ASAM: in the checksum field), or half the block when it returns none.
ADD_22/24/44 sum words in the ECU's byte order (its CPU's, which BYTE_ORDER states). A response that
names no checksum type is a stale one (a late answer to an earlier command): SYNCH, then ask again. A mismatch is asked once more
before it counts, so a stale answer can fail a block only when it repeats. When the ECU
computes a checksum the workbench does not know (user-defined), or has no BUILD_CHECKSUM at all
(ERR_CMD_UNKNOWN: BUILD_CHECKSUM is optional, small boot loaders leave it out), the bytes are read back.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from workbench.errors import WorkbenchError, XcpCommandError
from workbench.image import AddressRange, ChecksumType, checksum
from workbench.logs import logger
from workbench.xcp.master import XcpMaster
from workbench.xcp_protocol import Err

log = logger(__name__)

__all__ = ["ChecksumVerifier"]

_SMALLEST_BLOCK = 0x100


@dataclass
class ChecksumVerifier:
    master: XcpMaster
    max_block: int = 0x20000  # bytes of one BUILD_CHECKSUM until the ECU refuses a larger one
    kind: ChecksumType | None = None  # the ECU's, once it answered; None before (or user-defined)
    commands: int = 0
    confirm_mismatch: bool = True  # ask a mismatch again (a search that narrows mismatches down confirms by itself)
    unsupported: bool = False  # the ECU has no BUILD_CHECKSUM (ERR_CMD_UNKNOWN): every block is read back

    def differing(self, address: int, expected: bytes) -> list[AddressRange]:
        """The blocks of ``[address, address + len(expected))`` whose content differs from ``expected``.

        BUILD_CHECKSUM covers whole elements of the address granularity (from an aligned address) and of
        the checksum type (ADD_x2/x4 sum words): bytes before the first and after the last are read back.
        """
        bad = []
        offset = min(-address % self.master.granularity, len(expected))  # before the first element: read back
        if offset and self.master.read(address, offset) != expected[:offset]:
            bad.append(AddressRange(address, address + offset))
        while offset < len(expected):
            size = min(self.max_block, len(expected) - offset)
            unit = max(self.kind.element_size if self.kind is not None else 1, self.master.granularity)
            if size % unit:  # an ADD_x2/x4 sum, or a granularity, of an odd tail
                size -= size % unit
                if not size:
                    tail = expected[offset:]
                    if self.master.read(address + offset, len(tail)) != tail:
                        bad.append(AddressRange(address + offset, address + len(expected)))
                    break
            try:
                same = self._same(address + offset, expected[offset:offset + size])
            except XcpCommandError as exc:
                allowed = self._allowed(exc)
                if exc.code != Err.OUT_OF_RANGE or (size <= _SMALLEST_BLOCK and not unit <= allowed < size):
                    raise
                self.max_block = allowed if unit <= allowed < size else max(_SMALLEST_BLOCK, size // 2)
                log.debug("BUILD_CHECKSUM: %d bytes refused, trying %d", size, self.max_block)
                continue
            if not same:
                bad.append(AddressRange(address + offset, address + offset + size))
            offset += size
        return bad

    def _allowed(self, refusal: XcpCommandError) -> int:
        """Bytes of the largest block an ERR_OUT_OF_RANGE of BUILD_CHECKSUM says the ECU takes (elements in its
        checksum field, after the alignment word); 0 when it says none."""
        if len(refusal.payload) < 6:
            return 0
        return struct.unpack_from(f"{self.master.order}I", refusal.payload, 2)[0] * self.master.granularity

    def _same(self, address: int, expected: bytes) -> bool:
        value = self._checksum(address, len(expected))
        if value is None:  # a checksum this side cannot compute: compare the bytes themselves
            return self.master.read(address, len(expected)) == expected
        if value == checksum(expected, self.kind, self.master.order == "<"):
            return True
        if not self.confirm_mismatch:
            return False
        self.master.resynchronize()
        return self._checksum(address, len(expected)) == checksum(expected, self.kind, self.master.order == "<")

    def _checksum(self, address: int, size: int) -> int | None:
        """The ECU's checksum of the block; None when its type is one this side cannot compute, or it has none."""
        for attempt in range(2):
            if self.unsupported:
                return None
            try:
                code, value = self.master.build_checksum(address, size)
            except XcpCommandError as exc:
                if exc.code != Err.CMD_UNKNOWN:
                    raise
                log.info("the ECU has no BUILD_CHECKSUM: comparing by reading back")
                self.unsupported = True
                return None
            self.commands += 1
            kind = _checksum_type(code)
            if kind is not None:
                if self.kind is not None and kind != self.kind:
                    raise WorkbenchError(f"the ECU changed its checksum type from {self.kind.name} to {kind.name}")
                self.kind = kind
                return value
            if attempt == 0:  # most likely a late response to another command taken for this one
                self.master.resynchronize()
        log.info("BUILD_CHECKSUM type 0x%02X is not one of XCP's: comparing by reading back", code)
        return None


def _checksum_type(code: int) -> ChecksumType | None:
    try:
        return ChecksumType(code)
    except ValueError:
        return None
