"""The calibrations' values as the project's flash file (s19/hex) holds them: what the calibration editors show
before any ECU is connected, as CANape shows an offline dataset. Plain Python (run in the window's workers).

The file is read at the A2L's addresses as ``workbench cal diff`` and the cache sync read it: through the calibration
segments' ADDRESS_MAPPING (a build's s19 holds CAL ROM, the A2L names CAL RAM), or as it stands for an A2L without
IF_DATA XCP. Read once, on the first value asked for.
"""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

from workbench.errors import InputError

__all__ = ["FileValues"]


class FileValues:
    """``read_value(name)`` of the calibrations of ``model`` from the flash file at ``path`` (``config``: the A2L's
    XcpConfig, None when it has none)."""

    def __init__(self, model, config, path: str | Path):
        self.model, self.config, self.path = model, config, Path(path)
        self._view: Any = None
        self._lock = threading.Lock()  # editors opened together read in several workers

    @property
    def name(self) -> str:
        return self.path.name

    def read_value(self, name: str):
        """The CalValue of calibration ``name`` as the file holds it.

        :raises InputError: the file cannot be read, or holds no value for ``name`` (why is said).
        """
        from workbench.sync.values import decode_values, object_layouts

        layouts, problems = object_layouts(self.model, [name])
        values, failed = decode_values(layouts, self._image_view().fetch)
        if name not in values:
            raise InputError(f"{name}: not read from {self.name} ({failed.get(name) or problems.get(name)})")
        return values[name]

    def _image_view(self):
        with self._lock:
            if self._view is None:
                from workbench.image import load_image
                from workbench.sync.areas import ImageView, calibration_areas

                areas = calibration_areas(self.model.doc, self.config) if self.config is not None else []
                self._view = ImageView(load_image(self.path), areas)
            return self._view
