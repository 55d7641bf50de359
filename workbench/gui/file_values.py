"""The calibrations' values as the project's flash file (s19/hex) holds them: what the calibration editors show and
edit before any ECU is connected, as CANape edits an offline dataset. Plain Python (run in the window's workers).

The file is read and written at the A2L's addresses by :class:`~workbench.sync.offline.ImageCalibration`, as
``workbench cal get|set --image`` and the cache sync read it: through the calibration segments' ADDRESS_MAPPING (a
build's s19 holds CAL ROM, the A2L names CAL RAM), or as it stands for an A2L without IF_DATA XCP. Read once, on the
first value asked for; edits change the image in memory until :meth:`FileValues.save` writes it.
"""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

from workbench.errors import InputError

__all__ = ["FileValues"]


class FileValues:
    """The calibrations of ``model`` in the flash file at ``path``, read and written by name."""

    def __init__(self, model, path: str | Path):
        self.model, self.path = model, Path(path)
        self._image: Any = None
        self._lock = threading.Lock()  # editors opened together read in several workers

    @property
    def name(self) -> str:
        return self.path.name

    def read_value(self, name: str):
        """The CalValue of calibration ``name`` as the image holds it (edits included).

        :raises InputError: the file cannot be read, or holds no value for ``name`` (why is said).
        """
        try:
            return self.image().read_value(name)
        except InputError as exc:
            raise InputError(f"{name}: not read from {self.name} ({str(exc).removeprefix(name + ': ')})") from None

    def write(self, name: str, value, *, allow_extended_limits: bool = False):
        """Write ``name`` into the image in memory, checked as online; returns the CalValue it holds now."""
        return self.image().write(name, value, allow_extended_limits=allow_extended_limits)

    @property
    def modified(self) -> bool:
        """Whether the image differs from the file (False before anything was read)."""
        return self._image is not None and self._image.modified

    def changed(self) -> list[str]:
        """The objects whose bytes differ from the file's."""
        return self._image.changed() if self._image is not None else []

    def save(self, path: str | Path) -> Path:
        """Write the image to ``path`` (only the records of changed bytes rewritten, atomically); from then on the
        values are that file's."""
        saved = self.image().save(path)
        self.path = saved
        return saved

    def reference(self):
        """The image as edited, for the cache sync's compare with the ECU (an ImageReference of its own copy)."""
        return self.image().reference()

    def image(self):
        """The :class:`~workbench.sync.offline.ImageCalibration` (loaded on the first call)."""
        with self._lock:
            if self._image is None:
                from workbench.sync.offline import ImageCalibration

                self._image = ImageCalibration.open(self.path, self.model.doc, module=self.model.name or None)
            return self._image
