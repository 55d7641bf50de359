"""What a flash will do, decided and checked before the ECU is touched (:func:`plan_flash`).

A plan holds, per chosen region, the ranges the image fills there ("Partial: FC0000h-FC000Dh
FC0010h-FC0C22h FDFFF0h-FDFFFFh", thesis figure 38), the sectors to erase for them, and the
application-valid key that is cleared first and set last. Everything that would make the
flash unsafe is refused here, with nothing erased: an image whose EPK differs from the A2L's,
data outside the flash regions, regions or sectors that overlap, a sector that reaches
beyond the chosen regions, the boot loader without an explicit permission.
"""

from __future__ import annotations

import math
from pathlib import Path
from dataclasses import dataclass, replace
from typing import Any

from workbench.a2l import XcpConfig
from workbench.errors import InputError, epk_text
from workbench.flash.errors import FlashRefused
from workbench.flash.layout import DEMO_APP_KEY, AppKey, FlashLayout, FlashRegion, Sector
from workbench.image import ERASED, AddressRange, MemoryImage, load_image
from workbench.xcp.info import data_per_frame, program_block_size

__all__ = ["FlashPlan", "RegionPlan", "plan_file", "plan_flash", "programming_frames", "with_sectors"]

STANDARD_FRAME_BITS = (111, 135)  # an 8-byte classic CAN frame, 11-bit id: no stuff bits / the most there can be


@dataclass(frozen=True)
class RegionPlan:
    region: FlashRegion
    image: MemoryImage  # the bytes to program, all inside the region
    sectors: tuple[Sector, ...]  # erased for them, in clear order

    @property
    def ranges(self) -> list[AddressRange]:
        return self.image.ranges

    @property
    def size(self) -> int:
        return self.image.size

    def describe(self) -> str:
        return self.region.as_region.describe(self.image)


@dataclass(frozen=True)
class FlashPlan:
    source: str  # the file, or "working page"
    layout: FlashLayout
    regions: tuple[RegionPlan, ...]
    skipped: tuple[tuple[str, str], ...]  # (region, its data file info) of file data in regions not chosen
    app_key: AppKey | None
    key_sector: Sector | None
    image_epk: str | None  # the EPK the image holds at ADDR_EPK (any); None: the image covers none
    unchosen: tuple[tuple[str, MemoryImage], ...] = ()  # (region, its data) of file data in regions not chosen

    @property
    def size(self) -> int:
        """Bytes to program (the key not counted)."""
        return sum(r.size for r in self.regions)

    @property
    def image(self) -> MemoryImage:
        """Everything to program, all regions in one image."""
        whole = MemoryImage()
        for plan in self.regions:
            for start, data in plan.image.segments:
                whole.add(start, data)
        return whole

    @property
    def sectors(self) -> list[Sector]:
        """The sectors to erase (the key's excepted), in clear order."""
        unique = {s for r in self.regions for s in r.sectors}
        return sorted(unique, key=lambda s: (s.clear_sequence, s.range.start))

    def sectors_holding(self, ranges: list[AddressRange]) -> list[Sector]:
        """The sectors to erase that hold a byte of ``ranges``."""
        return [s for s in self.sectors if any(s.range.start < r.end and r.start < s.range.end for r in ranges)]

    def sector_content(self, sector: Sector) -> bytes:
        """What ``sector`` holds after the flash: the image's bytes, erased flash elsewhere."""
        return self.image.read(sector.range.start, sector.range.size, ERASED)

    def frames(self, block_size: int, per_frame: int) -> int:
        """CAN frames the PROGRAM commands take: ``per_frame`` data bytes a frame, one response a block."""
        frames = 0
        for held in self.image.ranges:
            frames += math.ceil(held.size / per_frame) + math.ceil(held.size / block_size) + 4  # + SET_MTA, PROGRAM 0
        return frames

    def bus_time_s(self, bitrate: int, block_size: int = 252, per_frame: int = 6) -> tuple[float, float]:
        """The programming's time on a CAN bus of ``bitrate`` bit/s, (fewest, most stuff bits); erasing and
        checksums, which the ECU's flash speed decides, are not in it."""
        frames = self.frames(block_size, per_frame)
        return tuple(frames * bits / bitrate for bits in STANDARD_FRAME_BITS)  # type: ignore[return-value]

    def describe(self) -> str:
        """The plan as the thesis's flash dialog shows it, one region a line, then what is erased and how."""
        lines = [f"{self.source}:"]
        rows = [(r.region, r.describe()) for r in self.regions]
        rows += [(self.layout.region(name), f"{info} (in the file, not selected)") for name, info in self.skipped]
        width = max(len(region.name) for region, _ in rows + [(FlashRegion("name", 0, 0), "")])
        lines.append(f"  {'name':<{width}}  start    end      size     data file info")
        for region, info in rows:
            lines.append(f"  {region.name:<{width}}  {region.start:06X}h  {region.end - 1:06X}h  {region.size:06X}h  {info}")
        for sector in self.sectors:
            lines.append(f"  erase {sector}")
        if self.app_key is not None and self.key_sector is not None:
            lines.append(f"  application key {self.app_key}: cleared first (erase {self.key_sector}), set last")
        ranges = sum(len(r.ranges) for r in self.regions)
        lines.append(f"  program {self.size} bytes in {ranges} range{'s' if ranges != 1 else ''}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        return {
            "source": self.source,
            "regions": [{"name": r.region.name, "start": r.region.start, "size": r.region.size,
                         "info": r.describe(), "bytes": r.size,
                         "ranges": [[x.start, x.end] for x in r.ranges],
                         "sectors": [s.name or s.number for s in r.sectors]} for r in self.regions],
            "skipped": [{"name": name, "info": info} for name, info in self.skipped],
            "app_key": None if self.app_key is None else {"address": self.app_key.address,
                                                          "value": self.app_key.value.hex()},
            "bytes": self.size,
            "image_epk": self.image_epk,
            "sectors_from": self.layout.sectors_from,
        }


def plan_flash(image: MemoryImage, layout: FlashLayout, regions: list[str] | tuple[str, ...], *, source: str = "image",
               allow_boot: bool = False, app_key: AppKey | None = DEMO_APP_KEY) -> FlashPlan:
    """Plan flashing ``regions`` of ``layout`` with what ``image`` holds there.

    :param app_key: the application-valid key to clear first and set last (default: the demo ECU's);
        None for an ECU whose boot has none. A key no sector holds is refused, never skipped.
    :raises InputError: no region named, an unknown one, or one that is no flash target (RESERVED).
    :raises FlashRefused: the flash would be unsafe (the message says why); nothing was touched.
    """
    if not regions:
        raise InputError("name the region to flash (e.g. CALIB or APPLICATIVE)")
    chosen = _chosen_regions(layout, regions, allow_boot)
    image_epk = _check_epk(image, layout, source)
    outside, skipped = _outside(image, layout, chosen)
    if outside:
        regions = ", ".join(f"{region.name} {region.range}" for region in layout.regions)
        raise FlashRefused(f"{source}: data outside the flash regions {'/'.join(r.name for r in chosen)}: "
                           + "; ".join(outside) + f" (the A2L's flash regions: {regions or 'none'}; nothing was "
                           "erased)")
    plans = []
    for region in chosen:
        piece = image.crop(region.start, region.end)
        if not piece.size:
            raise FlashRefused(f"{source} holds nothing in {region.name} ({region.start:X}h-{region.end - 1:X}h)")
        plans.append(RegionPlan(region, piece, tuple(_sectors_for(layout, piece, region, chosen, source))))
    key_sector = _key_sector(layout, app_key, plans) if app_key is not None else None
    unchosen = tuple((name, image.crop(layout.region(name).start, layout.region(name).end)) for name, _ in skipped)
    return FlashPlan(source, layout, tuple(plans), tuple(skipped), app_key, key_sector, image_epk, unchosen)


def plan_file(path: str | Path, layout: FlashLayout, regions: list[str] | tuple[str, ...], *,
              allow_boot: bool = False, app_key: AppKey | None = DEMO_APP_KEY) -> FlashPlan:
    """:func:`plan_flash` of an S-record or Intel HEX file.

    :raises InputError: the file is missing or malformed (overlapping records included: ``path:line``).
    """
    return plan_flash(load_image(path), layout, regions, source=Path(path).name, allow_boot=allow_boot,
                      app_key=app_key)


def programming_frames(config: XcpConfig) -> tuple[int, int]:
    """(bytes a block, bytes a frame) of the programming as the A2L states it (PROGRAM_START may say otherwise at
    run time): frames of MAX_CTO_PGM, blocks of 1 + MAX_BS_PGM of them where PGM's COMMUNICATION_MODE_SUPPORTED
    has master block mode (the protocol layer's when there is no PGM block), else one PROGRAM (PROGRAM_MAX where the
    ECU has it) a response."""
    pgm, ag = config.pgm, config.address_granularity
    max_cto = min(pgm.max_cto_pgm or config.max_cto, config.max_cto) if pgm is not None else config.max_cto
    mode = pgm.communication_mode if pgm is not None else config.communication_mode
    blocks = mode is not None and mode.master_block_mode and mode.max_bs
    block = program_block_size(max_cto, ag, max_bs=mode.max_bs if blocks else None,
                               use_max="PROGRAM_MAX" in config.optional_commands)
    return block, data_per_frame(max_cto, ag) if blocks else block


def with_sectors(plan: FlashPlan, layout: FlashLayout) -> FlashPlan:
    """``plan`` erased in the sectors of ``layout`` (the ECU's own), checked again as :func:`plan_flash` does.

    :raises FlashRefused: with these sectors the flash would be unsafe.
    """
    chosen = [r.region for r in plan.regions]
    regions = tuple(replace(r, sectors=tuple(_sectors_for(layout, r.image, r.region, chosen, plan.source)))
                    for r in plan.regions)
    key_sector = _key_sector(layout, plan.app_key, list(regions)) if plan.app_key is not None else None
    return replace(plan, layout=layout, regions=regions, key_sector=key_sector)


def _chosen_regions(layout: FlashLayout, names, allow_boot: bool) -> list[FlashRegion]:
    chosen = []
    for name in dict.fromkeys(n.upper() for n in names):
        region = layout.region(name)
        if not region.selectable:
            raise InputError(f"{region.name} is no region to flash (it is reserved: {region.description or 'RESERVED'})")
        if region.is_boot and not allow_boot:
            raise FlashRefused(f"{region.name} holds the boot loader: a flash that fails there cannot be repaired over "
                               f"XCP; allow it explicitly (--allow-boot) to flash it anyway", override="allow_boot")
        chosen.append(region)
    chosen.sort(key=lambda r: r.start)
    for a, b in zip(chosen, chosen[1:]):
        if b.start < a.end:
            raise FlashRefused(f"the A2L's flash regions {a.name} and {b.name} overlap: the memory map is wrong")
    return chosen


def _check_epk(image: MemoryImage, layout: FlashLayout, source: str) -> str | None:
    """The image's EPK at the ADDR_EPK(s) it covers (None: none); refused where it differs from the A2L's."""
    if layout.epk is None or layout.addr_epk is None:
        return None
    expected = layout.epk.encode("latin-1")
    text = None
    for address in layout.epk_addresses or (layout.addr_epk,):
        held = image.crop(address, address + len(expected))
        if not held.size:
            continue
        found = image.read(address, len(expected))
        if held.size != len(expected) or found != expected:
            region = layout.region_at(address)
            where = f"{address:X}h" + (f" ({region.name})" if region is not None and len(layout.epk_addresses) > 1
                                       else "")
            raise FlashRefused(f"{source}: the image's EPK {epk_text(found.decode('latin-1'))} at {where} differs "
                               f"from the A2L's {epk_text(layout.epk)}: the A2L does not describe this software "
                               f"(nothing was erased)")
        text = text or found.decode("latin-1").rstrip("\0\xff")
    return text


def _outside(image: MemoryImage, layout: FlashLayout, chosen: list[FlashRegion]) -> tuple[list[str], list[tuple[str, str]]]:
    """Data outside the chosen regions: refused (in no flash target region) or skipped (in another one)."""
    refused, skipped = [], []
    chosen_ranges = [r.range for r in chosen]
    for held in image.ranges:
        for piece in _minus(held, chosen_ranges):
            region = layout.region_at(piece.start)
            if region is None or not region.selectable or piece.end > region.end:
                where = f"in {region.name}, {region.description or 'not a flash target'}" if region else "in no flash region"
                refused.append(f"{piece} ({where})")
    for region in layout.regions:
        if region in chosen or not region.selectable:
            continue
        piece = image.crop(region.start, region.end)
        if piece.size:
            skipped.append((region.name, region.as_region.describe(image)))
    return refused, skipped


def _minus(held: AddressRange, cut: list[AddressRange]) -> list[AddressRange]:
    pieces = [held]
    for c in cut:
        pieces = [p for q in pieces for p in (AddressRange(q.start, min(q.end, c.start)),
                                              AddressRange(max(q.start, c.end), q.end)) if p.size > 0]
    return pieces


def _sectors_for(layout: FlashLayout, piece: MemoryImage, region: FlashRegion, chosen: list[FlashRegion],
                 source: str) -> list[Sector]:
    uncovered = layout.uncovered(piece)
    if uncovered:
        raise FlashRefused(f"{source}: no PGM sector covers {' '.join(map(str, uncovered))} in {region.name}: the ECU "
                           f"cannot erase it, so not program it (nothing was erased)")
    sectors = layout.sectors_touching(piece.ranges)
    for sector in sectors:
        beyond = _minus(sector.range, [r.range for r in chosen])
        if beyond:
            raise FlashRefused(f"erasing {sector} would also erase {' '.join(map(str, beyond))} outside "
                               f"{'/'.join(r.name for r in chosen)} (nothing was erased)")
    for a in sectors:
        for b in layout.erase_units():
            if a != b and a.range.start < b.range.end and b.range.start < a.range.end:
                raise FlashRefused(f"{a} and {b} overlap: the sector map is wrong (nothing was erased)")
    return sectors


def _key_sector(layout: FlashLayout, key: AppKey, plans: list[RegionPlan]) -> Sector:
    sector = layout.sector_of(key.address)
    if sector is None or key.range.end > sector.range.end:
        raise FlashRefused(f"no PGM sector holds the application-valid key {key}: name the ECU's key, or flash "
                           f"without one (--no-app-key) if its boot has none")
    for plan in plans:
        if sector in plan.sectors or (plan.region.start < key.range.end and key.address < plan.region.end):
            raise FlashRefused(f"the application-valid key {key} lies in {plan.region.name}, the region to flash: "
                               f"it must have a sector of its own")
    return sector
