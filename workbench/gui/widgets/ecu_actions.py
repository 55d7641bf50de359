"""The main window's actions around the ECU connection: connecting (the EPK question), the page, measuring by
DAQ, copying the reference page, recording, flashing and the cache sync after a connection.

:class:`EcuWindowActions` is a part of :class:`~workbench.gui.widgets.main_window.MainWindow` (its first base):
the slots the menus and the :class:`~workbench.gui.ecu.EcuController`'s signals call, on the window's state.
"""

from __future__ import annotations

import time
from pathlib import Path

from PySide6.QtWidgets import QFileDialog, QMessageBox

from workbench.errors import InputError, XcpCommandError
from workbench.gui.acquisition import DaqAcquisition, RecordRequest
from workbench.gui.ecu import Connected, NotWrittenError
from workbench.gui.widgets.connection_dialog import ConnectionDialog
from workbench.gui.widgets.epk_dialog import EpkChoice, EpkDialog
from workbench.gui.widgets.flash_dialog import FlashDialog
from workbench.gui.widgets.menus import enable_ecu_actions
from workbench.gui.widgets.sync_dialog import SyncChoice, SyncDialog, sync_differences
from workbench.gui.worker import Task, run_task

__all__ = ["EcuWindowActions"]


def _can_monitor(session, databases, sink, origin):
    """A CAN monitor on the session's XCP bus (in a worker), at the bus's bit rate as the A2L completed it."""
    from workbench.gui.can_monitor import CanMonitor

    spec = session.bus_spec
    bitrate = (spec.bitrate if spec else None) or (session.config.can.baudrate if session.config.can else None)
    return CanMonitor(session, databases, sink, origin, bitrate)


class EcuWindowActions:
    """The ECU's part of the main window (see the module docstring)."""

    # --- connection -----------------------------------------------------------------------------

    def edit_connection(self) -> None:
        dialog = ConnectionDialog(self.project.connection, self.workspace.config if self.workspace else None, self)
        if dialog.exec():
            self.project.connection = dialog.connection()

    def connect_ecu(self, accept_epk_mismatch: bool = False):
        if self.workspace is not None and self.workspace.no_xcp:
            self.show_error(InputError(f"cannot connect: {self.workspace.no_xcp}; the A2L describes no XCP "
                                       "connection (add the ECU's IF_DATA XCP, e.g. Tools > Merge A2L fragments, "
                                       "or open the A2L the ECU's supplier delivers for XCP)"))
            return None
        self.connect_action.setEnabled(False)
        self.status.link.setText("connecting …")
        a2l = self.workspace.doc if self.workspace is not None else self.project.a2l  # read once, not again
        task = self._connecting = self.controller.open(a2l, self.project.connection, accept_epk_mismatch,
                                                       on_failed=lambda: self._not_connected(task))
        return task

    def _not_connected(self, task: Task) -> None:
        """A connection attempt failed (the controller says why, unless another project opened meanwhile): offline
        again, unless a later attempt is under way."""
        if task is self._connecting:
            self._connecting = None
            self.connect_action.setEnabled(not self.controller.closing)
            self.status.show_disconnected(self.controller.closing)

    def set_page(self, page: str) -> None:
        """Switch the ECU to ``page`` (the toolbar's page buttons); refused, the buttons show the page the ECU uses."""
        def refused(exc: BaseException) -> None:
            now = self.controller.page
            self._show_page(now)
            if isinstance(exc, XcpCommandError):
                exc = exc.about(f"switching the ECU to the {page} page (it stays on the {now} page)")
            self.show_error(exc)

        if self.controller.set_page(page, on_error=refused) is None:
            self._show_page(self.controller.page)

    def _show_page(self, page: str) -> None:
        """The page the ECU uses, in the status bar and on the page buttons (a button's click checks it at once)."""
        self.status.show_page(page)
        (self.working_action if page == "working" else self.reference_action).setChecked(True)

    def _connected(self, result: Connected) -> None:
        self._connecting = None
        session, info = result.session, result.info
        self.status.show_connected(session, info)
        self._show_page(self.controller.page)
        enable_ecu_actions(self, session, info)
        self._update_title()
        if session.epk.matches is False and session.read_only:
            self.epk_dialog = EpkDialog(self.workspace.doc.name if self.workspace else "A2L",
                                        info.identification, session.epk.a2l or "", session.epk.ecu or "", self,
                                        session.epks())
            self.epk_dialog.finished.connect(self._epk_chosen)
            self.epk_dialog.open()
            return
        self._start_measuring()

    def _epk_chosen(self, _result: int) -> None:
        choice = self.epk_dialog.choice
        if choice is EpkChoice.DISCONNECT:
            self.controller.close()
        elif choice is EpkChoice.FLASH:
            dialog = self.open_flash_dialog()
            if dialog is not None:  # the parts of another build, else the whole software
                dialog.select_regions(self.epk_dialog.differing_parts or dialog.software_regions())
        else:
            self._start_measuring()

    def _start_measuring(self, check_cache: bool = True) -> None:
        session = self.controller.session
        if session is None:
            return
        if self.controller.info.boot:  # no application: nothing to measure, no calibrations
            self.status.set_pause("the ECU is in its boot loader (flash the application)")
            return
        if check_cache and self.project.s19 is not None:
            self.check_cache()
        acquisition = DaqAcquisition(session, self.hub.sink, self.hub.origin, self, gap=self.hub.mark_gap)
        acquisition.recording_stopped.connect(self._recording_stopped)
        acquisition.refused.connect(self._not_measurable)
        self.hub.attach(acquisition)
        if session.link.is_can and self.workspace is not None and self.workspace.dbcs:
            self._listen_to_can2(acquisition)
        self.status.set_pause(None)
        self.record_action.setEnabled(True)
        self._check_live()  # no plot to fill (a project of one A2L): live now, a screenshot need not wait for samples

    def _listen_to_can2(self, acquisition: DaqAcquisition) -> None:
        """The CAN monitor on the bus, made in a worker (it waits for the link's lock, which a command in flight
        holds, and may open a bus); taken while ``acquisition`` is still the one measuring, else closed again.
        A failure is said; XCP goes on without the CAN2 view."""
        def listening(monitor) -> None:
            if self.hub.acquisition is acquisition:
                self.hub.listen(monitor)
            else:
                run_task(monitor.close)

        self.controller.call(_can_monitor, [d.database for d in self.workspace.dbcs], self.hub.sink, self.hub.origin,
                             on_done=listening, on_error=self.show_error)

    def _not_measurable(self, refused: dict) -> None:
        """Signals the ECU refused to sample: said once, the others are measured (the status bar keeps the count)."""
        lines = [f"{name}: {why}" for name, why in refused.items()]
        self.show_error(InputError("not measured by DAQ (the ECU refuses to sample it; the other signals are "
                                   "measured):\n" + "\n".join(lines)))

    def _disconnected(self) -> None:
        """No session any more (the controller stopped the measurement, ``before_close``); it closes in a worker:
        Connect waits for its release."""
        self.status.show_disconnected(self.controller.closing)
        self.status.set_pause(None)
        enable_ecu_actions(self)
        self._update_title()

    def _released(self) -> None:
        """The session closed has let go of the ECU: Connect again (unless connected or connecting meanwhile)."""
        if self.controller.session is not None or self._connecting is not None:
            return
        self.connect_action.setEnabled(True)
        if self.controller.lost_error is None:
            self.status.show_disconnected()

    def _lost(self, exc) -> None:
        """The ECU stopped answering: say what and when; the controller reconnects when it answers again."""
        self.status.show_lost(exc)
        self.status.set_pause("connection lost", exc.when)
        self.connect_action.setEnabled(not self.controller.closing)

    def copy_reference(self) -> None:
        """Say first what the copy overwrites (read in the pool: the ECU may be asked), then ask."""
        self.controller.call("page_copies", on_done=self._ask_copy)

    def _ask_copy(self, copies) -> None:
        """The question of ``cal page copy``, non-modal as the parameter sets' (No by default); only Yes copies."""
        if self.copy_confirm is not None:
            self.copy_confirm.close()
        box = QMessageBox(self)
        box.setWindowTitle("Copy reference → working")
        box.setIcon(QMessageBox.Question)
        box.setText("Copy the reference page onto the working page, losing every change since start-up?")
        box.setInformativeText("\n".join(f"Overwrites {copy} with the reference page {copy.reference}."
                                          for copy in copies))
        box.setStandardButtons(QMessageBox.Yes | QMessageBox.No)
        box.setDefaultButton(QMessageBox.No)
        box.setModal(False)
        box.finished.connect(lambda _: self._copy_answered(box.clickedButton() is box.button(QMessageBox.Yes)))
        self.copy_confirm = box
        box.show()

    def _copy_answered(self, yes: bool) -> None:
        if not yes:  # No, Escape or the window closed
            self.statusBar().showMessage("not confirmed: nothing copied", 15000)
            return

        def copied(_) -> None:
            self.statusBar().showMessage("copied the reference page onto the working page", 15000)
            self.parameter_sets.ecu_changed("reference page copied since")
            for editor in self.editors.values():
                editor.reload()

        self.controller.call("copy_reference_to_working", on_done=copied)

    # --- recording ------------------------------------------------------------------------------

    def record_toggled(self, checked: bool) -> None:
        if not checked:
            self.stop_recording()
            return
        folder = self.project.path.parent if self.project.path else Path.cwd()
        suggestion = folder / f"recording-{time.strftime('%Y%m%d-%H%M%S')}.mf4"
        path, _ = QFileDialog.getSaveFileName(self, "Record to", str(suggestion), "MDF4 (*.mf4)")
        if not path:
            self.record_action.setChecked(False)
            return
        path = Path(path)  # a name typed without a suffix gets the filter's, as native dialogs add it
        self.start_recording(path if path.suffix else path.with_name(path.name + ".mf4"))

    def start_recording(self, path: Path) -> None:
        """Record what the windows measure, and the CAN2 bus decoded with the project's first DBC (XCP on
        CAN), to ``path`` (replaced when the recording ends; the file dialog asked)."""
        acquisition = self.hub.acquisition
        if acquisition is None:
            self.record_action.setChecked(False)
            return
        dbcs = self.workspace.dbcs if self.workspace is not None else []
        on_can = self.controller.session.link.settings.transport == "CAN"
        acquisition.record(RecordRequest(Path(path), dbcs[0] if dbcs and on_can else None,
                                         on_can and self.raw_can_action.isChecked()))
        self.record_action.setChecked(True)

    def stop_recording(self) -> None:
        if self.hub.acquisition is not None:
            self.hub.acquisition.stop_recording()

    def _recording_stopped(self, stats) -> None:
        self.record_action.setChecked(False)
        self.last_recording = stats
        if stats is not None:
            self.statusBar().showMessage(f"recorded {stats.describe()}", 15000)

    # --- flash and cache sync -------------------------------------------------------------------

    def open_flash_dialog(self, regions=None) -> FlashDialog | None:
        session = self.controller.session
        if session is None:
            return None
        self.flash_dialog = FlashDialog(session, self.project.s19, self, stop_measuring=self.hub.detach)
        if regions:
            self.flash_dialog.select_regions(regions)
        self.flash_dialog.flash_started.connect(self._flash_started)
        self.flash_dialog.open()
        return self.flash_dialog

    def _flash_started(self, task) -> None:
        """The ECU flashes with no DAQ running (the dialog stopped it: ``stop_measuring``); measuring resumes by
        itself when the flash is over."""
        self.status.set_pause("flashing")
        task.finished.connect(self._flash_over)

    def _flash_over(self) -> None:
        """Read what the ECU is now (the application again, or the boot loader after a failed flash)."""
        self.parameter_sets.ecu_changed("flashed since")
        self.status.set_pause("reading the ECU after the flash")
        self.controller.call("info", on_done=self._ecu_after_flash)

    def _ecu_after_flash(self, info) -> None:
        session = self.controller.session
        if session is None:
            return
        if self.flash_dialog is not None and self.flash_dialog.task is not None:
            return  # flashing again (a refusal's override): no DAQ under it; its own end reads the ECU
        self.controller.info = info
        self.status.show_connected(session, info)
        for editor in self.editors.values():
            editor.reload()
        self._start_measuring(check_cache=False)

    def check_cache(self) -> Task | None:
        """Compare the ECU with the project's s19 as edited offline (thesis figure 39: checksums first, objects after);
        when they differ, ask whether to download the file's values or upload the ECU's (not when the session closed
        meanwhile: nothing to ask of it)."""
        from workbench.sync import sync_compare

        session = self.controller.session

        def compared(report) -> None:
            if self.controller.session is session:
                self._cache_compared(report)

        return self.controller.call(sync_compare, self.offline_image.reference(),  # offline edits too
                                    on_done=compared, on_error=self.show_error)

    def _cache_compared(self, report) -> None:
        self.sync_report = report
        if report.equal:
            self.statusBar().showMessage(report.summary(), 8000)
            return
        differences = sync_differences(report, self.workspace.model if self.workspace is not None else None)
        ecu = self.controller.info.identification if self.controller.info else "ECU"
        self.sync_dialog = SyncDialog(ecu, Path(report.reference.label).name, differences, self)
        self.sync_dialog.accepted.connect(lambda: self._synchronise(report, self.sync_dialog.choice))
        self.sync_dialog.rejected.connect(lambda: self._synchronise(report, SyncChoice.KEEP))
        self.sync_dialog.open()

    def _synchronise(self, report, choice: SyncChoice) -> None:
        from workbench.sync import sync_download, sync_upload

        if choice is SyncChoice.KEEP:
            self.statusBar().showMessage(f"{report.summary()}: kept the ECU's values, nothing written", 15000)
            return
        if choice is SyncChoice.DOWNLOAD:
            if self.controller.call(sync_download, report, progress=True, on_error=self.show_error,
                                    on_done=lambda _: [editor.reload() for editor in self.editors.values()]) is None:
                self.show_error(NotWrittenError(f"nothing downloaded: {self.controller.offline_reason}"))
            return
        reference = Path(report.reference.label)
        path, _ = QFileDialog.getSaveFileName(self, "Upload: the ECU's calibrations into",
                                              str(reference.with_name(f"{reference.stem}-ecu{reference.suffix}")))
        if path:
            try:
                self.project.s19 = sync_upload(report, path)
            except Exception as exc:  # noqa: BLE001
                self.show_error(exc)
