"""What the ECU is compared with: a flash image (s19/hex of the build, or one saved from the ECU) or a dataset."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from workbench.calib.dataset import Dataset, format_of, load_dataset
from workbench.errors import InputError
from workbench.image import MemoryImage, load_image
from workbench.image.files import image_suffixes, is_image_file, refuse_elf

__all__ = ["DatasetReference", "ImageReference", "load_reference"]


@dataclass
class _FileReference:
    path: Path

    @property
    def label(self) -> str:
        return str(self.path)


@dataclass
class ImageReference(_FileReference):
    """An s19/hex: its CAL ROM bytes are compared with the ECU's working page."""

    image: MemoryImage


@dataclass
class DatasetReference(_FileReference):
    """A DCM/CDFX dataset: its objects are compared with the ECU's, one by one."""

    dataset: Dataset


Reference = ImageReference | DatasetReference


def load_reference(path: str | Path) -> Reference:
    """The image or dataset in ``path``, by its extension.

    :raises InputError: the file is missing or malformed (located), or its extension names neither.
    """
    path = Path(path)
    refuse_elf(path)
    if is_image_file(path):
        return ImageReference(path, load_image(path))
    try:
        format_of(path)
    except InputError:
        raise InputError(f"{path}: neither an image ({image_suffixes(', ')}) nor a dataset (.dcm, .cdfx) by "
                         "its extension") from None
    return DatasetReference(path, load_dataset(path))
