"""The flash dialog (thesis figure 38): pick an s19/hex, see per region the partial ranges the file
fills, choose CALIB and/or APPLICATIVE (or the working page into CAL ROM), flash with progress,
rate and time left, cancel, and read the verify result. The flash runs in a worker
(``workbench.flash.flash_ecu``); cancelling makes the library stop at its next block.

A refusal the CLI lets the user override (``--erase-beyond-file``, ``--accept-epk-mismatch``) shows its
text and a check box, unticked, for that option: only ticking it and pressing Flash again flashes with it
(until the file or the regions change). A refusal that wants more regions flashed offers to select them."""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QDialog,
    QFileDialog,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QProgressBar,
    QPushButton,
    QStyle,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
)

from workbench.errors import Cancelled, WorkbenchError
from workbench.gui import theme
from workbench.gui.offline_image import IMAGE_FILES
from workbench.gui.widgets.job_buttons import JobButtons
from workbench.gui.worker import Task

__all__ = ["FlashDialog"]

WORKING_PAGE = "working page"  # the source that flashes CAL RAM into CAL ROM
_MEASURING_STOPS_S = 10.0  # how long a flash waits for the window's DAQ to stop (one read, or a command's timeouts)


def _layout(session):
    from workbench.flash import FlashLayout

    return FlashLayout.from_a2l(session.doc, session.config)


def _plan_file(session, path: str, regions: list[str]):
    from workbench.flash import plan_file

    return plan_file(path, _layout(session), regions)


def _flash(session, source: str, regions: list[str], overrides: frozenset[str] = frozenset(),
           measuring_stopped: threading.Event | None = None, progress=None):
    """Flash as ``workbench flash`` does; ``overrides``: the FlashOptions the user ticked (``erase_beyond_file``...);
    ``measuring_stopped``: waited for first (the flash refuses an ECU whose DAQ runs)."""
    from workbench.flash import FlashOptions, flash_ecu, plan_working_page

    if measuring_stopped is not None:
        measuring_stopped.wait(_MEASURING_STOPS_S)
    plan = (plan_working_page(session, progress=progress) if source == WORKING_PAGE
            else _plan_file(session, source, regions))
    return flash_ecu(session, plan, progress=progress, options=FlashOptions(**dict.fromkeys(overrides, True)))


class FlashDialog(QDialog):
    """Flash through ``session``; ``flashed(result)`` after a successful flash. ``stop_measuring()`` runs in the GUI
    thread as a flash starts: what measures on the session stops (the flash waits in its worker for the
    ``threading.Event`` it returns)."""

    flashed = Signal(object)  # workbench.flash.FlashResult
    flash_failed = Signal(object)
    flash_started = Signal(object)  # the Task, before it runs (to follow its progress)

    def __init__(self, session, s19: Path | None = None, parent=None,
                 stop_measuring: Callable[[], threading.Event] | None = None):
        super().__init__(parent)
        self.session = session
        self.stop_measuring = stop_measuring
        self.task: Task | None = None
        self.plan = None
        self.setWindowTitle("Flash")
        self.resize(820, 460)
        layout = QVBoxLayout(self)
        row = QHBoxLayout()
        row.addWidget(QLabel("file"))
        self.path = QLineEdit(str(s19) if s19 else "")
        self.path.setPlaceholderText("an s19 or Intel HEX file, or the working page")
        self.path.editingFinished.connect(self.replan)
        row.addWidget(self.path, 1)
        browse = QPushButton("Browse…")
        browse.clicked.connect(self._browse)
        row.addWidget(browse)
        working = QPushButton("Working page → CAL ROM")
        working.setToolTip("flash the calibrations of the working page (CAL RAM) into CAL ROM, so they survive "
                           "power-off")
        working.clicked.connect(self._working_page)
        row.addWidget(working)
        layout.addLayout(row)
        self.table = QTableWidget(0, 5)
        self.table.setHorizontalHeaderLabels(["name", "start", "end", "size", "data file info"])
        self.table.verticalHeader().hide()
        self.table.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.table.setSelectionMode(QAbstractItemView.NoSelection)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeToContents)
        self.table.horizontalHeader().setStretchLastSection(True)
        self.table.itemChanged.connect(self._region_toggled)
        layout.addWidget(self.table, 1)
        self.progress = QProgressBar()
        self.progress.setFormat("%p %")
        layout.addWidget(self.progress)
        self.progress_label = QLabel()
        self.progress_label.setStyleSheet(f"color: {theme.MUTED};")
        layout.addWidget(self.progress_label)
        self.result = QPlainTextEdit()
        self.result.setReadOnly(True)
        self.result.setFont(theme.mono_font(9))
        self.result.setMaximumHeight(110)
        layout.addWidget(self.result)
        # the CLI's overrides of a refusal, shown when one refuses the flash; unticked: nothing is erased without them
        self.overrides = {
            "erase_beyond_file": QCheckBox("Erase the bytes listed above although the file does not give them back "
                                           "(--erase-beyond-file)"),
            "accept_epk_mismatch": QCheckBox("Flash although the EPK differs from the part that stays on the ECU "
                                             "(--accept-epk-mismatch)"),
        }
        for box in self.overrides.values():
            box.toggled.connect(self._override_toggled)
            layout.addWidget(box)
        self.add_regions_button = QPushButton()
        self.add_regions_button.clicked.connect(self._add_regions)
        self.regions_to_add: tuple[str, ...] = ()
        self.offered_for: tuple | None = None  # (file, regions) of the refusal the overrides answer
        self.flashing: tuple | None = None  # (file, regions) of the flash under way
        row = QHBoxLayout()
        row.addWidget(self.add_regions_button)
        row.addStretch(1)
        layout.addLayout(row)
        self.buttons = JobButtons(self, "Flash", "Cancel flash", self.start, self.cancel,
                                  guarded=(self.table, *self.overrides.values(), self.add_regions_button))
        self.flash_button, self.cancel_button, self.close_button = (self.buttons.run_button, self.buttons.cancel_button,
                                                                    self.buttons.close_button)
        layout.addLayout(self.buttons)
        self._reset_overrides()
        self._fill_regions()
        if s19:
            self.replan()

    # --- the plan -------------------------------------------------------------------------------

    def _fill_regions(self) -> None:
        self.table.blockSignals(True)
        regions = [r for r in _layout(self.session).regions]
        self.table.setRowCount(len(regions))
        for row, region in enumerate(regions):
            name = QTableWidgetItem(region.name)
            if region.selectable and not region.is_boot:
                name.setFlags(name.flags() | Qt.ItemIsUserCheckable)
                name.setCheckState(Qt.Checked if region.name.upper().startswith("CAL") else Qt.Unchecked)
            else:
                # not ticked by select_regions() either (a table item is user-checkable unless told)
                name.setFlags(name.flags() & ~(Qt.ItemIsEnabled | Qt.ItemIsUserCheckable))
                name.setToolTip("the boot loader is not flashed from here" if region.is_boot else "not a flash target")
            self.table.setItem(row, 0, name)
            for column, text in ((1, f"{region.start:06X}h"), (2, f"{region.end - 1:06X}h"), (3, f"{region.size:X}h"),
                                 (4, "")):
                item = QTableWidgetItem(text)
                item.setFont(theme.mono_font(9))
                self.table.setItem(row, column, item)
        self.table.blockSignals(False)
        # the names whole beside their check boxes (the contents' size left APPLICATIVE cut to "APPLICATI…")
        indicator = self.table.style().pixelMetric(QStyle.PM_IndicatorWidth, None, self.table)
        widest = max((self.table.fontMetrics().horizontalAdvance(region.name) for region in regions), default=0)
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(0, QHeaderView.Fixed)
        header.resizeSection(0, max(header.sectionSizeHint(0), widest + indicator + 28))

    def selected_regions(self) -> list[str]:
        return [self.table.item(row, 0).text() for row in range(self.table.rowCount())
                if self.table.item(row, 0).checkState() == Qt.Checked]

    def software_regions(self) -> list[str]:
        """The regions a flash of the whole software selects: every one that can be ticked (the boot loader cannot)."""
        return [self.table.item(row, 0).text() for row in range(self.table.rowCount())
                if self.table.item(row, 0).flags() & Qt.ItemIsUserCheckable]

    def select_regions(self, names) -> None:
        wanted = {n.upper() for n in names}
        self.table.blockSignals(True)
        for row in range(self.table.rowCount()):
            item = self.table.item(row, 0)
            if item.flags() & Qt.ItemIsUserCheckable:
                item.setCheckState(Qt.Checked if item.text().upper() in wanted else Qt.Unchecked)
        self.table.blockSignals(False)
        self.replan()

    def _region_toggled(self, item) -> None:
        if item.column() == 0:
            self.replan()

    def _browse(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Flash image", self.path.text(),
                                              IMAGE_FILES)
        if path:
            self.path.setText(path)
            self.replan()

    def _working_page(self) -> None:
        self.path.setText(WORKING_PAGE)
        self.replan()

    def replan(self) -> None:
        """Show what the chosen file holds per region (read in a worker: a big image takes a moment)."""
        source = self.path.text().strip()
        if (source, tuple(self.selected_regions())) == self.offered_for:
            return  # the file and regions refused: the refusal stays shown beside its choice
        self._reset_overrides()  # a choice made for one file and its regions is not one for another
        for row in range(self.table.rowCount()):
            self.table.item(row, 4).setText("")
        self.plan = None
        if not source or source == WORKING_PAGE:
            self.result.setPlainText("flashes the working page (CAL RAM) into CAL ROM" if source else "")
            return
        regions = self.selected_regions()
        if not regions:
            self.result.setPlainText("choose a region")
            return
        task = Task(_plan_file, self.session, source, regions)
        task.succeeded.connect(self._show_plan)
        task.failed.connect(lambda exc: self.result.setPlainText(f"⚠ {exc}"))
        task.start()

    def _show_plan(self, plan) -> None:
        self.plan = plan
        infos = {r.region.name: r.describe() for r in plan.regions}
        infos.update({name: f"{info} (not selected)" for name, info in plan.skipped})
        for row in range(self.table.rowCount()):
            self.table.item(row, 4).setText(infos.get(self.table.item(row, 0).text(), ""))
        self.result.setPlainText(plan.describe())

    # --- flashing -------------------------------------------------------------------------------

    def start(self) -> Task | None:
        source = self.path.text().strip()
        if not source:
            self.result.setPlainText("choose a file first")
            return None
        self.flashing = (source, tuple(self.selected_regions()))
        stopped = self.stop_measuring() if self.stop_measuring is not None else None
        self.task = Task(_flash, self.session, *self.flashing, self.chosen_overrides(), stopped, progress=True)
        self.buttons.follow(self.task, self._progressed, self._done, self._failed, self._finished)
        self.result.setPlainText("flashing …")
        self.flash_started.emit(self.task)
        return self.task.start()

    def chosen_overrides(self) -> frozenset[str]:
        """The overrides ticked (shown after a refusal): the FlashOptions fields the flash sets True."""
        return frozenset(name for name, box in self.overrides.items() if not box.isHidden() and box.isChecked())

    def _reset_overrides(self) -> None:
        for box in self.overrides.values():
            box.setChecked(False)
            box.hide()
        self.regions_to_add = ()
        self.add_regions_button.hide()
        self.offered_for = None

    def _override_toggled(self) -> None:
        self.flash_button.setText("Flash anyway" if self.chosen_overrides() else "Flash")

    def _offer(self, exc: WorkbenchError) -> None:
        """What the user may do about a refusal: tick its override (unticked), or select the regions it names."""
        self.offered_for = self.flashing
        box = self.overrides.get(getattr(exc, "override", None))
        if box is not None:
            box.show()
        self.regions_to_add = tuple(r for r in getattr(exc, "regions", ()) if r not in self.selected_regions())
        if self.regions_to_add:
            self.add_regions_button.setText(f"Select {' and '.join(self.regions_to_add)} too")
            self.add_regions_button.show()

    def _add_regions(self) -> None:
        self.select_regions(self.selected_regions() + list(self.regions_to_add))

    def cancel(self) -> None:
        if self.task is not None:
            self.task.cancel()
            self.progress_label.setText("cancelling at the next block …")

    def _progressed(self, done: int, total: int, label: str) -> None:
        self.progress_label.setStyleSheet(f"color: {theme.MUTED};")
        self.progress.setMaximum(max(total, 1))
        self.progress.setValue(done)
        self.progress_label.setText(label)

    def _done(self, result) -> None:
        self.progress.setValue(self.progress.maximum())
        self._reset_overrides()  # the next flash asks again
        self.result.setPlainText(result.describe())
        self._final("done: " + ("verified, the application runs" if result.application_running
                                else "verified, the ECU is in its boot loader"), theme.GOOD)
        self.flashed.emit(result)

    def _failed(self, exc) -> None:
        from workbench.flash import FlashRefused

        self.result.setPlainText(f"⚠ {exc}")
        if isinstance(exc, FlashRefused):
            self._offer(exc)
            self._final("refused, nothing was flashed: see below", theme.BAD)
        else:
            self._final("cancelled" if isinstance(exc, Cancelled) else "failed: see below", theme.BAD)
        self.flash_failed.emit(exc)

    def _final(self, text: str, colour: str) -> None:
        """The flash is over: the progress line says how it ended (not the last phase it reported)."""
        self.progress_label.setText(text)
        self.progress_label.setStyleSheet(f"color: {colour};")

    def _finished(self) -> None:
        self.task = None

    def reject(self) -> None:
        if self.task is None:  # never close while the ECU is half flashed
            super().reject()
