"""Memory images (s19/hex via bincopy), flash regions with the ranges a file fills, XCP checksums.

The names are imported on first use (but the checksums: a lazy ``checksum`` would lose to its module of the same
name), so that naming the image files (:mod:`workbench.image.files`, e.g. in a command's help) does not load bincopy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from workbench.image.checksum import ChecksumType, checksum  # eager: the function shares its module's name
from workbench.lazy_exports import lazy_exports

_EXPORTS = {
    "workbench.image.files": ("IMAGE_SUFFIXES", "image_suffixes", "is_image_file", "is_intel_hex"),
    "workbench.image.image": ("ERASED", "AddressRange", "MemoryImage", "load_image", "parse_image"),
    "workbench.image.records": ("patched_text",),
    "workbench.image.regions": ("Region", "region_of", "split_by_region"),
}
_lazy, __getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = sorted([*_lazy, "ChecksumType", "checksum"])

if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from workbench.image.files import IMAGE_SUFFIXES, image_suffixes, is_image_file, is_intel_hex
    from workbench.image.image import ERASED, AddressRange, MemoryImage, load_image, parse_image
    from workbench.image.records import patched_text
    from workbench.image.regions import Region, region_of, split_by_region
