"""Parameter sets in the window, as CANape keeps them: open a DCM/CDFX and compare it with the ECU (or,
offline, with the project's s19 as edited), save the ECU's working page as one, compare the working page with
the reference page or two files, and apply one to the ECU (offline: to the project's s19, in memory, as the
editors edit it; File > Save image writes it). Where the set holds values beyond their limits
and within their EXTENDED_LIMITS (the report's ``extended_limits``), the question offers that choice
explicitly, as ``cal load --extended-limits`` does; ticking it checks the set again with them.

Everything is the library's: :func:`workbench.sync.read_dataset`, :func:`~workbench.sync.sync_compare`,
:func:`~workbench.calib.dataset.diff_datasets`, :func:`~workbench.calib.dataset.save_dataset` and
:func:`~workbench.sync.apply_dataset` - the same checks as ``workbench cal load``: a dry run first
lists what would change and what is refused; one refusal and nothing is written.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from PySide6.QtCore import QObject, Qt, Signal
from PySide6.QtWidgets import QCheckBox, QFileDialog, QMessageBox, QProgressDialog

from workbench.gui.worker import Task

__all__ = ["ParameterSets"]

FILES = "Parameter sets (*.dcm *.cdfx *.cdf);;All files (*)"
PAGES = ("reference page (CAL ROM)", "working page (CAL RAM)")


def compare_pages(session, progress=None):
    """The reference page (A) against the working page (B), every calibration."""
    from workbench.calib.dataset import diff_datasets
    from workbench.sync import read_dataset

    reference = read_dataset(session, page="reference", progress=progress)
    working = read_dataset(session, page="working", progress=progress)
    return diff_datasets(reference, working, a_label=PAGES[0], b_label=PAGES[1])


def compare_with_ecu(session, path: Path, progress=None):
    """The ECU's working page (A: the page the cache sync reads, whichever XCP uses) against the file (B), the
    file's values as the ECU would hold them."""
    from workbench.sync import load_reference, sync_compare

    diff = sync_compare(session, load_reference(path), progress=progress).diff.reversed()
    return dataclasses.replace(diff, a_label=f"ECU {PAGES[1]}")


def compare_files(a: Path, b: Path, model=None):
    """Two files: parameter sets, or a flash image decoded by name with the A2L ``model`` (with a model, as
    ``cal diff`` compares them: the sets' floats as the A2L's types hold them)."""
    from workbench.calib.dataset import diff_datasets, load_dataset
    from workbench.sync import file_dataset

    def values(path: Path):
        return load_dataset(path) if model is None else file_dataset(model, path)

    return diff_datasets(values(a), values(b), a_label=str(a), b_label=str(b))


def compare_with_image(values, path: Path, progress=None):
    """The project's image as edited offline (A, a :class:`~workbench.gui.file_values.FileValues`) against the file
    (B), object by object as the ECU is compared with it: the objects the file holds."""
    from workbench.calib.dataset import diff_datasets
    from workbench.sync import file_dataset

    image = values.image()
    file, held = file_dataset(image.model, path), image.dataset()
    for name in [name for name in held if name not in file]:
        del held[name]
    return diff_datasets(held, file, a_label=values.name, b_label=str(path))


def apply_to_image(values, path: Path, dry_run: bool, extended_limits: bool = False, progress=None):
    """``workbench cal load --image`` in the window: the file applied to the project's image in memory."""
    return apply_file(values.image(), path, dry_run, extended_limits, progress)


def save_working_page(session, path: Path, progress=None) -> str:
    """The working page's calibrations into ``path`` (DCM or CDFX by its extension); what was written."""
    from workbench.calib.dataset import save_dataset
    from workbench.sync import read_dataset

    dataset = read_dataset(session, page="working", progress=progress)
    losses = save_dataset(dataset, path)
    return f"{len(dataset)} calibrations saved to {path}" + (f" ({len(losses)} notes)" if losses else "")


def apply_file(session, path: Path, dry_run: bool, extended_limits: bool = False, progress=None):
    """``workbench cal load [--extended-limits]`` in the window: :func:`~workbench.sync.apply_dataset` of the file."""
    from workbench.calib.dataset import load_dataset
    from workbench.sync import apply_dataset

    return apply_dataset(session, load_dataset(path), dry_run=dry_run, allow_extended_limits=extended_limits,
                         progress=progress, source=str(path))


class ParameterSets(QObject):
    """The window's parameter-set commands; results go to ``view`` (a :class:`CompareView`)."""

    compared = Signal(object)  # the DatasetDiff shown
    applied = Signal(object)  # the ApplyReport of a written parameter set
    message = Signal(str)  # a line for the status bar

    def __init__(self, window, view):
        super().__init__(window)
        self.window = window
        self.view = view
        self.file: Path | None = None  # the parameter set B of the view, when it is one
        self.extended_limits = False  # the user chose to apply values up to the EXTENDED_LIMITS (per file)
        self.last = None  # how to compare again: (function, args, can_apply)
        self.confirm: QMessageBox | None = None  # the apply's question (tests answer it)
        self.progress: QProgressDialog | None = None
        view.refresh_requested.connect(self.compare_again)
        view.apply_requested.connect(self.ask_apply)
        window.controller.written.connect(lambda name: self.ecu_changed(f"{name} written since"))
        window.controller.page_changed.connect(self._page_switched)
        # a restarted or another ECU may hold other values
        window.controller.connected.connect(lambda _: self.ecu_changed("ECU reconnected since"))

    @property
    def session(self):
        return self.window.controller.session

    @property
    def image(self):
        """The project's image a parameter set is compared with and applied to offline (None: connected, being
        reconnected, or no image)."""
        workspace, controller = self.window.workspace, self.window.controller
        if controller.session is not None or controller.lost_error is not None or workspace is None:
            return None
        return workspace.file_values

    def _target(self) -> tuple:
        """``(apply function, its first argument or None, what it writes into)``: what the set was compared with, the
        ECU or (offline) the project's image, while it is there."""
        if self.last is not None and self.last[0] is compare_with_image:
            image = self.image
            return apply_to_image, image, image.name if image is not None else "the image"
        return apply_file, self.session, "the ECU"

    # --- commands -------------------------------------------------------------------------------

    def open_dialog(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self.window, "Open parameter set", "", FILES)
        if path:
            self.open(Path(path))

    def open(self, path: Path) -> Task:
        """Compare the parameter set with the ECU (offline: with the project's s19)."""
        self.file = Path(path)
        self.extended_limits = False
        if self.session is not None:
            return self._compare(compare_with_ecu, (self.session, self.file), can_apply=True, progress=True)
        if self.image is not None:
            return self._compare(compare_with_image, (self.image, self.file), can_apply=True)
        s19 = self.window.project.s19
        if s19 is None:
            return self._compare(compare_files, (self.file, self.file, None))
        return self._compare(compare_files, (Path(s19), self.file, self.window.workspace.model))

    def compare_pages(self) -> Task | None:
        if self.session is None:
            return None
        self.file = None
        return self._compare(compare_pages, (self.session,), progress=True)

    def compare_files_dialog(self) -> None:
        a, _ = QFileDialog.getOpenFileName(self.window, "Compare: parameter set A", "", FILES)
        b, _ = QFileDialog.getOpenFileName(self.window, "Compare with parameter set B", "", FILES) if a else ("", "")
        if a and b:
            self.compare_files(Path(a), Path(b))

    def compare_files(self, a: Path, b: Path) -> Task:
        self.file = None
        model = self.window.workspace.model if self.window.workspace is not None else None
        return self._compare(compare_files, (a, b, model))

    def save_dialog(self) -> None:
        if self.session is None:
            return
        path, _ = QFileDialog.getSaveFileName(self.window, "Save the ECU's calibrations as", "parameters.dcm", FILES)
        if path:
            self.save(Path(path))

    def save(self, path: Path) -> Task | None:
        if self.session is None:
            return None
        return self._run(save_working_page, (self.session, path), "saving the working page", self.message.emit)

    def ecu_changed(self, reason: str) -> None:
        """The ECU's values changed (a write, a flash, a page switch, a reconnect): a comparison that read them
        says it is outdated."""
        if self.last is not None and self.last[0] in _READ_THE_ECU:
            self.view.mark_outdated(reason)

    def forget(self) -> None:
        """Another project opens: what was compared (and the question of applying it) goes with the one before;
        a comparison still running is not shown."""
        self.file, self.last, self.extended_limits = None, None, False
        if self.confirm is not None:
            self.confirm.close()
            self.confirm = None
        self.view.clear()

    def _page_switched(self, page: str) -> None:
        """The ECU against a file read the page XCP used (a pages' comparison reads both by name)."""
        if self.last is not None and self.last[0] is compare_with_ecu:
            self.view.mark_outdated(f"{page} page active since")

    def compare_again(self) -> None:
        if self.last is None:
            return
        function, args, can_apply = self.last
        if function in _READ_THE_ECU:  # with the session there is now (a reconnect opens a new one)
            if self.session is None:
                self.message.emit("not compared: not connected")
                return
            args = (self.session, *args[1:])
        self._compare(function, args, can_apply=can_apply, progress=self.session is not None)

    # --- applying -------------------------------------------------------------------------------

    def ask_apply(self) -> Task | None:
        """A dry run of the parameter set, then the question (what would change, what is refused)."""
        if self.file is None:
            return None
        function, target, _ = self._target()
        if target is None:  # said, not ignored: the button stays where the user pressed it
            why = self.window.controller.offline_reason or "compared with the image before connecting: open it again"
            self.message.emit(f"{self.file.name} not applied: {why}")
            return None
        return self._run(function, (target, self.file, True, self.extended_limits), "checking", self._confirm)

    def _confirm(self, report) -> None:
        if self.confirm is not None:
            self.confirm.close()
        box = QMessageBox(self.window)
        box.setWindowTitle("Apply parameter set")
        changing = report.named("would change")
        refused = report.named("refused")
        if report.extended_limits:  # the explicit choice, offered only where it decides something
            names = ", ".join(report.extended_limits[:3]) + (" …" if len(report.extended_limits) > 3 else "")
            choice = QCheckBox(f"allow values up to the EXTENDED_LIMITS ({len(report.extended_limits)}: {names})",
                               box)  # owned by the box: PySide6's setCheckBox leaves the Python object the owner
            choice.setChecked(self.extended_limits)
            choice.toggled.connect(self._choose_extended_limits)
            box.setCheckBox(choice)
        if refused:
            box.setIcon(QMessageBox.Warning)
            box.setText(f"{len(refused)} object(s) of {self.file.name} are refused; nothing is written.")
            box.setStandardButtons(QMessageBox.Close)
        else:
            box.setIcon(QMessageBox.Question)
            where = self._target()[2]
            box.setText(f"Write {len(changing)} changed object(s) of {self.file.name} into {where}?" if changing
                        else f"{where[0].upper()}{where[1:]} already holds every value of {self.file.name}.")
            box.setStandardButtons(QMessageBox.Ok | QMessageBox.Cancel if changing else QMessageBox.Close)
        # the warnings where they are read before Ok (a shared axis the set moves, the page the ECU runs), not only
        # under Details
        box.setInformativeText("\n".join([report.summary()] + [f"warning: {text}" for text in report.warnings]))
        box.setDetailedText(report.to_text())
        box.setModal(False)
        if changing and not refused:
            box.button(QMessageBox.Ok).clicked.connect(self._apply)
        self.confirm = box
        box.show()

    def _apply(self) -> Task | None:
        function, target, _ = self._target()
        if target is None or self.file is None:
            return None

        def done(report) -> None:
            self.message.emit(report.summary())
            self.applied.emit(report)
            self.compare_again()

        return self._run(function, (target, self.file, False, self.extended_limits), "writing the parameter set", done)

    def _choose_extended_limits(self, allowed: bool) -> None:
        """Check the set again with (or without) its EXTENDED_LIMITS: a new question follows."""
        self.extended_limits = allowed
        self.ask_apply()

    # --- workers --------------------------------------------------------------------------------

    def _compare(self, function, args, *, can_apply: bool = False, progress: bool = False) -> Task:
        last = self.last = (function, args, can_apply)

        def show(diff) -> None:
            if self.last is not last:  # forgotten, or compared again meanwhile
                return
            self.view.show_diff(diff, can_apply=can_apply)
            self.compared.emit(diff)

        return self._run(function, args, "comparing" if progress else None, show)

    def _run(self, function, args, label: str | None, on_done, on_error=None) -> Task:
        on_error = on_error or self.window.show_error
        if args and args[0] is not None and args[0] is self.session:  # the ECU's: not a failure once the user closed it
            task = self.window.controller.task(function, *args[1:], on_done=on_done, on_error=on_error,
                                               progress=label is not None)
        else:
            task = Task(function, *args, progress=label is not None)
            task.succeeded.connect(on_done)
            task.failed.connect(on_error)
        if label is not None:
            self.progress = _progress_dialog(self.window, task, label)
        return task.start()


_READ_THE_ECU = (compare_with_ecu, compare_pages)  # comparisons whose first argument is the session


def _progress_dialog(parent, task: Task, label: str) -> QProgressDialog:
    """A progress dialog that follows ``task`` (shown after half a second) and cancels it."""
    dialog = QProgressDialog(label, "Cancel", 0, 0, parent)
    dialog.setWindowModality(Qt.NonModal)
    dialog.setMinimumDuration(500)
    dialog.canceled.connect(task.cancel)

    def progressed(done: int, total: int, text: str) -> None:
        dialog.setMaximum(max(total, 1))
        dialog.setValue(done)
        dialog.setLabelText(text or label)

    task.progress.changed.connect(progressed)
    task.finished.connect(dialog.reset)
    return dialog
