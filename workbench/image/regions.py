"""Flash regions and the parts of a region an image fills.

A region is a named address window of the ECU's flash (BOOT, APPLICATIVE, CALIB ...)
erased and programmed in sectors. Flashing programs only the ranges the image holds
inside the region (:meth:`Region.partial_ranges`), never the whole window.
"""

from __future__ import annotations

from dataclasses import dataclass

from workbench.image.image import AddressRange, MemoryImage

__all__ = ["Region", "region_of", "split_by_region"]


@dataclass(frozen=True)
class Region:
    """A flash window ``[start, start + size)`` made of equal sectors of ``sector_size`` bytes."""

    name: str
    start: int
    size: int
    sector_size: int = 0  # 0: one sector spanning the region

    def __post_init__(self) -> None:
        if self.sector_size and self.size % self.sector_size:
            raise ValueError(f"region {self.name}: size 0x{self.size:X} is not a multiple of its sectors")

    @property
    def end(self) -> int:
        return self.start + self.size

    @property
    def sectors(self) -> list[AddressRange]:
        step = self.sector_size or self.size
        return [AddressRange(a, a + step) for a in range(self.start, self.end, step)]

    def contains(self, address: int, size: int = 1) -> bool:
        return self.start <= address and address + size <= self.end

    def partial_ranges(self, image: MemoryImage) -> list[AddressRange]:
        """The ranges of this region that ``image`` fills, in address order."""
        return image.crop(self.start, self.end).ranges

    def describe(self, image: MemoryImage) -> str:
        """``"Partial: FC0000h-FC000Dh FC0010h-FC0C22h"`` as the thesis's flash dialog shows it."""
        ranges = self.partial_ranges(image)
        if not ranges:
            return "empty"
        if ranges == [AddressRange(self.start, self.end)]:
            return "Full"
        return "Partial: " + " ".join(map(str, ranges))

    def __str__(self) -> str:
        return f"{self.name} {self.start:X}h-{self.end - 1:X}h ({self.size:X}h)"


def region_of(regions: list[Region], address: int, size: int = 1) -> Region | None:
    """The region that holds all of ``[address, address + size)``, or None."""
    return next((r for r in regions if r.contains(address, size)), None)


def split_by_region(image: MemoryImage, regions: list[Region]) -> tuple[dict[str, MemoryImage], list[AddressRange]]:
    """The image cut into one piece per region it touches, and the ranges no region holds."""
    pieces = {}
    for region in regions:
        piece = image.crop(region.start, region.end)
        if piece.size:
            pieces[region.name] = piece
    outside = [part for held in image.ranges for part in held.outside(regions)]
    return pieces, outside
