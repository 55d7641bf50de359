"""A flash image's file names: the extensions every face reads and writes an s19/hex by (no bincopy needed).

An image file is an S-record file (``.s19``, ``.s28``, ``.s37``, ``.srec``, ``.mot``, ``.sx``) or Intel HEX
(``.hex``, ``.ihex``), told by its extension; its content is then read by its records
(:func:`workbench.image.parse_image`), and written in the format its extension names (:meth:`MemoryImage.save`).
"""

from __future__ import annotations

from pathlib import Path

from workbench.errors import InputError

__all__ = ["ELF_MAGIC", "IMAGE_SUFFIXES", "INTEL_HEX_SUFFIXES", "S_RECORD_SUFFIXES", "elf_given", "image_suffixes",
           "is_image_file", "is_intel_hex", "refuse_elf"]

S_RECORD_SUFFIXES = (".s19", ".s28", ".s37", ".srec", ".mot", ".sx")
INTEL_HEX_SUFFIXES = (".hex", ".ihex")
IMAGE_SUFFIXES = S_RECORD_SUFFIXES + INTEL_HEX_SUFFIXES
ELF_MAGIC = b"\x7fELF"  # the first bytes of an ELF file, whatever its name


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


def elf_given(path: str | Path) -> InputError:
    """The error for the ELF file ``path`` named where a flash image is expected (the build's two outputs are easily
    swapped): it says so and names the build's s19/hex beside it when there is one."""
    path = Path(path)
    beside = next((image for image in map(path.with_suffix, IMAGE_SUFFIXES) if image != path and image.is_file()),
                  None)
    hint = f" ({beside} is beside it)" if beside is not None else ""
    return InputError(f"{path}: is an ELF file, not a flash image: give the build's s19/hex{hint}")


def refuse_elf(path: str | Path) -> None:
    """:raises InputError: ``path`` is an ELF file by its first bytes (:func:`elf_given`); a file that cannot be
    read passes, for the reader that follows to say why."""
    try:
        with open(path, "rb") as file:
            head = file.read(len(ELF_MAGIC))
    except OSError:
        return
    if head == ELF_MAGIC:
        raise elf_given(path)
