"""What erasing a plan's sectors would lose: bytes the ECU holds in them that the file does not give back.

A file that fills only part of a sector ("Partial: FC0000h-FC01C3h") still has the whole sector
erased: whatever the ECU held beyond the file's ranges (a calibration trailer, data of an older
build) is gone afterwards. The flash refuses that unless the user says so, so it is found first, by
BUILD_CHECKSUM of the gaps against erased flash (0xFF): a gap that reads erased costs one command per
128 KiB; one that does not is narrowed down in sixteenths to blocks of at most 256 bytes, which are
read to name the exact range.
"""

from __future__ import annotations

from workbench.flash.checksums import ChecksumVerifier
from workbench.flash.plan import FlashPlan
from workbench.image import ERASED, AddressRange
from workbench.xcp.master import XcpMaster

__all__ = ["unlisted_data"]

_READ_BLOCK = 0x100  # narrowed down to this, then read
_MAX_READS = 32  # blocks read to name ranges exactly; beyond it ranges are named by their blocks


def unlisted_data(master: XcpMaster, plan: FlashPlan) -> list[AddressRange]:
    """The ranges of the plan's sectors (the key's excepted) outside the file's ranges that do not read erased."""
    verifier = ChecksumVerifier(master, confirm_mismatch=False)
    held = plan.image.ranges
    found: list[AddressRange] = []
    budget = [_MAX_READS]
    for sector in plan.sectors:
        if sector == plan.key_sector:
            continue
        for gap in sector.range.outside(held):
            for block in verifier.differing(gap.start, bytes([ERASED]) * gap.size):
                found += _narrowed(master, verifier, block, budget)
    return _joined(found)  # ranges less than a block apart are named as one


def _narrowed(master: XcpMaster, verifier: ChecksumVerifier, block: AddressRange, budget: list[int]
              ) -> list[AddressRange]:
    """``block`` (not erased) narrowed down to the bytes that are not erased."""
    if block.size <= _READ_BLOCK:
        if budget[0] <= 0:
            return [block]
        budget[0] -= 1
        data = master.read(block.start, block.size)
        used = [i for i, byte in enumerate(data) if byte != ERASED]
        return [AddressRange(block.start + used[0], block.start + used[-1] + 1)] if used else []
    step = max(_READ_BLOCK, -(-block.size // 16))
    found = []
    for start in range(block.start, block.end, step):
        part = AddressRange(start, min(start + step, block.end))
        for bad in verifier.differing(part.start, bytes([ERASED]) * part.size):
            found += _narrowed(master, verifier, bad, budget)
    return found


def _joined(ranges: list[AddressRange]) -> list[AddressRange]:
    joined: list[AddressRange] = []
    for r in sorted(ranges):
        if joined and r.start <= joined[-1].end + _READ_BLOCK:  # erased bytes between are no loss: one range
            joined[-1] = AddressRange(joined[-1].start, max(joined[-1].end, r.end))
        else:
            joined.append(r)
    return joined
