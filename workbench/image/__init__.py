"""Memory images (s19/hex via bincopy), flash regions with the ranges a file fills, XCP checksums."""

from workbench.image.checksum import ChecksumType, checksum
from workbench.image.image import ERASED, AddressRange, MemoryImage, is_intel_hex, load_image, parse_image
from workbench.image.records import patched_text
from workbench.image.regions import Region, region_of, split_by_region

__all__ = [
    "ERASED",
    "AddressRange",
    "ChecksumType",
    "MemoryImage",
    "Region",
    "checksum",
    "is_intel_hex",
    "load_image",
    "parse_image",
    "patched_text",
    "region_of",
    "split_by_region",
]
