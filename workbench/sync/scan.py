"""Which blocks of the ECU's calibration memory differ from the reference, found with BUILD_CHECKSUM alone.

Each range is checksummed in blocks of at most the segment's CHECKSUM MAX_BLOCK_SIZE (fewer when the
ECU refuses a size with ERR_OUT_OF_RANGE: :class:`~workbench.flash.checksums.ChecksumVerifier` learns
it). A block that differs is halved and the first half checksummed: when it matches, the difference
lies in the second half, which needs no checksum of its own; when not, the second half is
checksummed too. Halving stops at :data:`LEAF_BYTES`, what the sync then uploads.

Why 128 bytes: on CAN a BUILD_CHECKSUM costs two exchanges (SET_MTA, BUILD_CHECKSUM: 4 frames),
an UPLOAD of n bytes about 3 + n/7 frames; halving 128 bytes saves ~9 frames of upload for at most
8 of checksums, below that it no longer pays.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from workbench.calib.memory import Span
from workbench.flash.checksums import ChecksumVerifier
from workbench.progress import Progress, report
from workbench.xcp.master import XcpMaster

__all__ = ["LEAF_BYTES", "ChecksumScan", "scan_ranges"]

LEAF_BYTES = 128
DEFAULT_MAX_BLOCK = 0x20000  # when the A2L states no MAX_BLOCK_SIZE: the verifier halves it on a refusal
_ALIGN = 4  # halves stay multiples of the largest ADD checksum element


@dataclass
class ChecksumScan:
    """The outcome of :func:`scan_ranges`: the blocks that differ (at most LEAF_BYTES each, in address order)."""

    compared: list[Span] = field(default_factory=list)
    differing: list[Span] = field(default_factory=list)
    checksums: int = 0  # BUILD_CHECKSUM commands sent
    checksum_type: str = ""  # the ECU's (CRC_32 ...), "" when it answered none

    @property
    def equal(self) -> bool:
        return not self.differing


def scan_ranges(master: XcpMaster, ranges: list[tuple[Span, bytes]], *, max_block: int | None = None,
                narrow: bool = True, progress: Progress | None = None) -> ChecksumScan:
    """Compare each ``(span, expected bytes)`` with the ECU by BUILD_CHECKSUM (on the page XCP is on).

    :param narrow: halve differing blocks down to LEAF_BYTES (False: report the checksum blocks as they are).
    :raises XcpCommandError, XcpTimeoutError: the ECU refused (other than a too large block) or did not answer.
    """
    verifier = ChecksumVerifier(master, max_block=max_block or DEFAULT_MAX_BLOCK, confirm_mismatch=False)
    scan = ChecksumScan(compared=[span for span, _ in ranges])
    total = sum(span.size for span, _ in ranges)
    done = 0
    for span, expected in ranges:
        report(progress, done, total, f"checksums {span}")
        for block in verifier.differing(span.address, expected):
            offset = block.start - span.address
            scan.differing += _narrow(verifier, block.start, expected[offset:offset + block.size], span.extension,
                                      narrow)
        done += span.size
    report(progress, total, total, "checksums compared")
    scan.checksums = verifier.commands
    scan.checksum_type = verifier.kind.name if verifier.kind is not None else ""
    return scan


def _narrow(verifier: ChecksumVerifier, address: int, expected: bytes, extension: int, narrow: bool) -> list[Span]:
    """The leaves of a block known to differ."""
    size = len(expected)
    if not narrow or size <= LEAF_BYTES:
        return [Span(address, size, extension)]
    middle = size // 2 // _ALIGN * _ALIGN
    first, second = expected[:middle], expected[middle:]
    found: list[Span] = []
    first_differs = verifier.differing(address, first)
    for block in first_differs:
        found += _narrow(verifier, block.start, first[block.start - address:block.end - address], extension, narrow)
    if not first_differs:  # the block differs, its first half does not: the second half does
        return _narrow(verifier, address + middle, second, extension, narrow)
    for block in verifier.differing(address + middle, second):
        start = block.start - address - middle
        found += _narrow(verifier, block.start, second[start:start + block.size], extension, narrow)
    return found
