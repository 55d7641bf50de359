"""The project's s19/hex edited offline in the window, as CANape edits a HEX file: what the editors wrote into it,
the window's modified mark, File > Save image (as), and what a connection then compares with the ECU.

The editors write into the image (:class:`~workbench.gui.file_values.FileValues`, the library's
:class:`~workbench.sync.offline.ImageCalibration`) while no ECU is connected; this object tells the window. Saving
rewrites only the records of changed bytes, atomically, in a worker; the built-in demo's s19 and a read-only file
are never written in place (Save image asks for a name then). Once an ECU connects, the cache sync compares it with
the image as edited (saved or not), so its dialog lists the offline changes and offers to download them.
"""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QObject, Signal
from PySide6.QtWidgets import QFileDialog

from workbench.gui.worker import run_task

__all__ = ["OfflineImage"]

FILES = "Flash images (*.s19 *.s28 *.s37 *.srec *.mot *.hex *.ihex);;All files (*)"


class OfflineImage(QObject):
    """The image side of ``window`` (a MainWindow): its ``workspace.file_values``, saved through its project."""

    changed = Signal()  # edited or saved: the window's title and actions follow
    saved = Signal(object)  # the Path written

    def __init__(self, window):
        super().__init__(window)
        self.window = window

    @property
    def values(self):
        """The FileValues of the project's image (None: the project names none, or it is not read yet)."""
        workspace = self.window.workspace
        return workspace.file_values if workspace is not None else None

    @property
    def modified(self) -> bool:
        return self.values is not None and self.values.modified

    def title(self) -> str:
        """What the window's title adds: the image's name while it holds unsaved edits."""
        return f" — {self.values.name} modified" if self.modified else ""

    def edited(self, _name: str = "") -> None:
        self.changed.emit()

    def reference(self):
        """What the cache sync compares a connected ECU with: the image as edited, or the project's file."""
        return self.values.reference() if self.modified else self.window.project.s19

    def save(self) -> None:
        """Write the image over its file; the demo's built-in s19 or a read-only file: asks for a name instead."""
        from workbench import demo

        values = self.values
        if values is None:
            return
        path = values.path
        if path.resolve() == demo.s19().resolve() or (path.is_file() and not path.stat().st_mode & 0o200):
            self.save_as()
            return
        self.save_to(path)

    def save_as(self) -> None:
        values = self.values
        if values is None:
            return
        suggested = values.path.with_name(f"{values.path.stem}-offline{values.path.suffix}")
        path, _ = QFileDialog.getSaveFileName(self.window, "Save image as", str(suggested), FILES)
        if path:
            self.save_to(Path(path))

    def save_to(self, path: Path) -> None:
        """Write the image to ``path`` (in a worker); the project's s19 is that file from then on."""
        run_task(self.values.save, path, on_done=self._saved, on_error=self.window.show_error)

    def _saved(self, path: Path) -> None:
        self.window.project.s19 = path
        for editor in self.window.editors.values():
            editor.file_saved(path.name)
        self.window.statusBar().showMessage(f"wrote {path} (only the records of changed bytes rewritten)", 15000)
        self.saved.emit(path)
        self.changed.emit()
