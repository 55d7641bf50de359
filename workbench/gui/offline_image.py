"""The project's s19/hex edited offline in the window, as CANape edits a HEX file: what the editors wrote into it,
the window's modified mark, File > Save image (as), and what a connection then compares with the ECU.

The editors write into the image (:class:`~workbench.gui.file_values.FileValues`, the library's
:class:`~workbench.sync.offline.ImageCalibration`) while no ECU is connected; this object tells the window. Saving
rewrites only the records of changed bytes, atomically, in a worker; the built-in demo's s19 and a read-only file
are never written in place (Save image asks for a name then). Once an ECU connects, the cache sync compares it with
the image as edited (saved or not), so its dialog lists the offline changes and offers to download them. Closing the
window or opening another project with unsaved edits asks first: save, discard or cancel.
"""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QObject, Signal
from PySide6.QtWidgets import QFileDialog, QMessageBox

from workbench.gui.worker import run_task
from workbench.image.files import image_suffixes

__all__ = ["IMAGE_FILES", "OfflineImage"]

IMAGE_FILES = f"Flash images ({image_suffixes(' ', '*{}')});;All files (*)"  # the file dialogs' filter


class OfflineImage(QObject):
    """The image side of ``window`` (a MainWindow): its ``workspace.file_values``, saved through its project."""

    changed = Signal()  # edited or saved: the window's title and actions follow
    saved = Signal(object)  # the Path written

    def __init__(self, window):
        super().__init__(window)
        self.window = window
        self._opening = None  # the FileValues of the image being read by open()
        window.loaded.connect(self._offer_to_fix_panel)
        window.fix_panel.offline_written.connect(self._fixes_written)

    def _offer_to_fix_panel(self) -> None:
        """The fix panel lists and edits the image's _EN/_VALUE pairs before a connection, as the editors do."""
        workspace = self.window.workspace
        self.window.fix_panel.set_offline(self.values, workspace.model if workspace is not None else None)

    def _fixes_written(self) -> None:
        for editor in self.window.editors.values():  # an editor of an _EN or _VALUE shows it
            editor.reload()
        self.changed.emit()

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

    def enable_actions(self) -> None:
        """File > Open image once the A2L is read; Save image (as) while there is an image."""
        window = self.window
        window.open_image_action.setEnabled(window.workspace is not None)
        for action in (window.save_image_action, window.save_image_as_action):
            action.setEnabled(self.values is not None)

    def edited(self, _name: str = "") -> None:
        """An editor wrote into the image: the title follows, the fix panel shows a pair it changed."""
        self.window.fix_panel.refresh()
        self.changed.emit()

    def reference(self):
        """What the cache sync compares a connected ECU with: the image as edited, or the project's file."""
        return self.values.reference() if self.modified else self.window.project.s19

    def open_dialog(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self.window, "Open image", "", IMAGE_FILES)
        if path:
            self.open(Path(path))

    def open(self, path: Path) -> None:
        """Take ``path`` as the project's s19/hex (unsaved edits of the one before asked about first): the editors
        show and edit its values until an ECU is connected, and a connection compares the ECU with it. The file is
        read first (in a worker): one that cannot be read, or does not fit the A2L, is said in an error dialog and
        the project keeps the image it had."""
        from workbench.gui.file_values import FileValues

        workspace = self.window.workspace
        if workspace is None or not self.may_close():
            return
        values = self._opening = FileValues(workspace.model, path)
        run_task(values.image, on_done=lambda _: self._read(workspace, values),
                 on_error=lambda exc: self._refused(values, exc))

    def _refused(self, values, exc: BaseException) -> None:
        """Why ``values``' file was not taken (file:line), and which image stays."""
        from workbench.errors import WorkbenchError
        from workbench.gui.widgets.errors import show_error

        if values is not self._opening:
            return
        self._opening = None
        box = show_error(self.window, exc, "Open image")
        if isinstance(exc, WorkbenchError):  # else the box says "unexpected ..." with the traceback
            kept = self.values
            box.setInformativeText(f"{values.name} not opened: the editors keep the values of {kept.name}"
                                   if kept is not None else f"{values.name} not opened")
        self.window.errors.append(box)

    def _read(self, workspace, values) -> None:
        """``values``' file read: the project's image now (unless another project or image was opened meanwhile)."""
        if values is not self._opening or workspace is not self.window.workspace:
            return
        self._opening = None
        self.window.project.s19 = values.path
        workspace.file_values = values
        for editor in self.window.editors.values():
            editor.offline = workspace.file_values
            editor.reload()
        self._offer_to_fix_panel()
        self.changed.emit()

    def may_close(self) -> bool:
        """Whether the project may close now: no unsaved edits, or the user saved (here, at once) or discarded them."""
        if not self.modified:
            return True
        changed = self.values.changed()
        shown = ", ".join(changed[:5]) + (f" and {len(changed) - 5} more" if len(changed) > 5 else "")
        answer = QMessageBox.question(
            self.window, "Calibrations edited offline",
            f"{self.values.name} holds calibrations edited offline that are not saved: {shown}.\nSave the image?",
            QMessageBox.Save | QMessageBox.Discard | QMessageBox.Cancel, QMessageBox.Save)
        if answer == QMessageBox.Discard:
            return True
        if answer != QMessageBox.Save:
            return False
        path = self._target()
        if path is None:
            return False
        try:
            self._saved(self.values.save(path))
        except Exception as exc:  # noqa: BLE001 - the window stays open and says why
            self.window.show_error(exc)
            return False
        return True

    def save(self) -> None:
        """Write the image over its file; the demo's built-in s19 or a read-only file: asks for a name instead."""
        path = self._target()
        if path is not None:
            self.save_to(path)

    def save_as(self) -> None:
        path = self._target(ask=True)
        if path is not None:
            self.save_to(path)

    def _target(self, ask: bool = False) -> Path | None:
        """Where the image is saved: its file, or (``ask``, the demo's built-in s19, a read-only file) the name the
        user chooses; None: no image, or no name chosen."""
        from workbench import demo

        values = self.values
        if values is None:
            return None
        path = values.path
        read_only = path.is_file() and not path.stat().st_mode & 0o200
        if not ask and path.resolve() != demo.s19().resolve() and not read_only:
            return path
        suggested = path.with_name(f"{path.stem}-offline{path.suffix}")
        chosen, _ = QFileDialog.getSaveFileName(self.window, "Save image as", str(suggested), IMAGE_FILES)
        return Path(chosen) if chosen else None

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
