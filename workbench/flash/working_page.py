"""Flash calibrations from the working page (thesis 5.3, "flash calibrations"): CAL RAM into CAL ROM.

XCP writes change CAL RAM, which the boot fills from CAL ROM at every power-on; to keep them
the working page is read and programmed into the flash its ADDRESS_MAPPING names
(0x40000000 -> 0xFC0000 on the demo ECU). What is read is the whole mapped segment, not only
the ranges of the `.cal_ram` load image: the flash holds exactly what the ECU ran with (EPK,
padding and the calibration trailer included, none of which the A2L lists), and no ELF is
needed. Reading 128 KiB costs seconds on CAN, so a BUILD_CHECKSUM per 4 KiB block first
finds the blocks that are not all 0xFF (erased flash reads so) and only those are read.
What a sector to erase holds outside every mapping is read from the flash and kept.
"""

from __future__ import annotations

from workbench.flash.checksums import ChecksumVerifier
from workbench.flash.errors import FlashRefused
from workbench.flash.layout import DEMO_APP_KEY, AppKey, FlashLayout
from workbench.flash.plan import FlashPlan, plan_flash
from workbench.image import ERASED, AddressRange, MemoryImage
from workbench.progress import Progress, report
from workbench.session import Session
from workbench.xcp.master import XcpMaster

__all__ = ["plan_working_page"]

SCAN_BLOCK = 0x1000  # bytes per BUILD_CHECKSUM when looking for used blocks


def plan_working_page(session: Session, *, app_key: AppKey | None = DEMO_APP_KEY,
                      progress: Progress | None = None) -> FlashPlan:
    """Read the working page (what the ECU's flash must keep beside it too) and plan flashing it.

    :raises FlashRefused: the ECU runs no application, the A2L maps no RAM to flash, or the working
        page's EPK differs from the A2L's; nothing was written.
    """
    with session.lock:
        if session.in_boot:
            raise FlashRefused("the ECU is in boot (no application runs): there is no working page to flash")
        mappings = [(segment, mapping) for segment in session.config.segments for mapping in segment.address_mappings]
        if not mappings:
            raise FlashRefused("the A2L's XCP SEGMENTs have no ADDRESS_MAPPING from the working page to flash")
        layout = FlashLayout.from_a2l(session.doc, session.config, session.module)
        verifier = ChecksumVerifier(session.master)
        image = MemoryImage()
        total = sum(mapping.length for _, mapping in mappings)
        done = 0
        for segment, mapping in mappings:
            with session.on_page("working", segment.number):
                data = _used_bytes(session.master, verifier, mapping.source, mapping.length, progress, done, total)
            done += mapping.length
            for address, run in MemoryImage.from_flash_content(mapping.destination, data).segments:
                image.add(address, run)
        regions = {layout.region_at(m.destination).name for _, m in mappings if layout.region_at(m.destination)}
        if not regions:
            raise FlashRefused("the working page's ADDRESS_MAPPING points at no flash region of the A2L")
        plan = plan_flash(image, layout, sorted(regions), source="working page", app_key=app_key)
        kept = _flash_outside(session.master, verifier, plan, [AddressRange(m.destination, m.destination + m.length)
                                                               for _, m in mappings])
        if kept.size:
            for address, data in kept.segments:
                image.add(address, data)
            plan = plan_flash(image, layout, sorted(regions), source="working page", app_key=app_key)
        return plan


def _used_bytes(master: XcpMaster, verifier: ChecksumVerifier, address: int, size: int, progress: Progress | None,
                done: int, total: int) -> bytes:
    """``size`` bytes at ``address``, read only where a block is not all erased (0xFF elsewhere)."""
    data = bytearray([ERASED]) * size
    for offset in range(0, size, SCAN_BLOCK):
        report(progress, done + offset, total, f"reading the working page {address + offset:X}h")
        length = min(SCAN_BLOCK, size - offset)
        if verifier.differing(address + offset, bytes([ERASED]) * length):
            data[offset:offset + length] = master.read(address + offset, length)
    report(progress, done + size, total, "reading the working page")
    return bytes(data)


def _flash_outside(master: XcpMaster, verifier: ChecksumVerifier, plan: FlashPlan,
                   mapped: list[AddressRange]) -> MemoryImage:
    """What the sectors to erase hold outside the mapped ranges (kept by programming it again)."""
    kept = MemoryImage()
    for sector in plan.sectors:
        cursor = sector.range.start
        for window in sorted(mapped) + [AddressRange(sector.range.end, sector.range.end)]:
            if window.start > cursor:
                end = min(window.start, sector.range.end)
                data = _used_bytes(master, verifier, cursor, end - cursor, None, 0, 0)
                for address, run in MemoryImage.from_flash_content(cursor, data).segments:
                    kept.add(address, run)
            cursor = max(cursor, window.end)
            if cursor >= sector.range.end:
                break
    return kept
