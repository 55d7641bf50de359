"""A flash image's file names: the extensions every face reads and writes an s19/hex by (no bincopy needed).

An image file is an S-record file (``.s19``, ``.s28``, ``.s37``, ``.srec``, ``.mot``, ``.sx``) or Intel HEX
(``.hex``, ``.ihex``), told by its extension; its content is then read by its records
(:func:`workbench.image.parse_image`), and written in the format its extension names (:meth:`MemoryImage.save`).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["IMAGE_SUFFIXES", "INTEL_HEX_SUFFIXES", "S_RECORD_SUFFIXES", "image_suffixes", "is_image_file",
           "is_intel_hex"]

S_RECORD_SUFFIXES = (".s19", ".s28", ".s37", ".srec", ".mot", ".sx")
INTEL_HEX_SUFFIXES = (".hex", ".ihex")
IMAGE_SUFFIXES = S_RECORD_SUFFIXES + INTEL_HEX_SUFFIXES


def is_image_file(path: str | Path) -> bool:
    """Whether ``path`` names an S-record or Intel HEX file by its extension."""
    return Path(path).suffix.lower() in IMAGE_SUFFIXES


def is_intel_hex(path: str | Path) -> bool:
    """Whether ``path`` names an Intel HEX file (``.hex``, ``.ihex``); other image files are S-records."""
    return Path(path).suffix.lower() in INTEL_HEX_SUFFIXES


def image_suffixes(separator: str = "/", pattern: str = "{}") -> str:
    """The image extensions as a text: ``.s19/.s28/...`` for a message, ``*.s19 *.s28 ...`` for a file dialog
    (``separator=" ", pattern="*{}"``)."""
    return separator.join(pattern.format(suffix) for suffix in IMAGE_SUFFIXES)
