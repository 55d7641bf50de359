"""The button row of a dialog that runs one job in a worker (flash, the A2L tools): Run (the default), Cancel and
Close, right-aligned. While the job runs, Cancel alone is enabled: the dialog's fields do not change under it, and
it is not closed behind it (Close waits for the end)."""

from __future__ import annotations

from collections.abc import Callable, Iterable

from PySide6.QtWidgets import QDialog, QHBoxLayout, QPushButton, QWidget

from workbench.gui.worker import Task

__all__ = ["JobButtons"]


class JobButtons(QHBoxLayout):
    """Run/Cancel/Close of ``dialog``; ``guarded``: its fields, disabled while a job runs."""

    def __init__(self, dialog: QDialog, run: str, cancel: str, on_run: Callable[[], object],
                 on_cancel: Callable[[], None], guarded: Iterable[QWidget] = ()):
        super().__init__()
        self.guarded = list(guarded)
        self.addStretch(1)
        self.run_button = QPushButton(run)
        self.run_button.setDefault(True)
        self.run_button.clicked.connect(on_run)
        self.cancel_button = QPushButton(cancel)
        self.cancel_button.setEnabled(False)
        self.cancel_button.clicked.connect(on_cancel)
        self.close_button = QPushButton("Close")
        self.close_button.clicked.connect(dialog.reject)
        for button in (self.run_button, self.cancel_button, self.close_button):
            self.addWidget(button)

    def follow(self, task: Task, progressed, succeeded, failed, finished) -> None:
        """The row busy while ``task`` runs; its progress, result, failure and end go to the dialog's slots (the
        end after the row is ready again)."""
        task.progress.changed.connect(progressed)
        task.succeeded.connect(succeeded)
        task.failed.connect(failed)
        # one slot, not two: the worker posts an event a slot, and the window ran between the two (Run enabled while
        # the dialog still held the job, a click on it ignored: CI, test_a_refused_update_says_one_line...)
        task.finished.connect(lambda: (self.set_busy(False), finished()))
        self.set_busy(True)

    def set_busy(self, busy: bool) -> None:
        self.run_button.setEnabled(not busy)
        self.cancel_button.setEnabled(busy)
        self.close_button.setEnabled(not busy)
        for widget in self.guarded:
            widget.setEnabled(not busy)
