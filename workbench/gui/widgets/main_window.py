"""The workbench window: variable browser, measurement windows, calibration editors, fix panel,
numeric view and CAN trace around one ECU connection, as CANape's main window arranges them.

The window holds no protocol logic: files are read by :mod:`workbench.gui.workspace` in a
worker, the ECU is reached through the :class:`~workbench.gui.ecu.EcuController`, live samples
flow through the :class:`~workbench.gui.signal_hub.SignalHub`. Its actions, toolbar and menus (and their keys)
are built by :mod:`workbench.gui.widgets.menus`; the slots they call are here, those around the ECU connection
(connecting, the page, DAQ, recording, flashing, the cache sync) in :mod:`workbench.gui.widgets.ecu_actions`.
"""

from __future__ import annotations

import base64
from pathlib import Path

from PySide6.QtCore import QByteArray, Qt, Signal
from PySide6.QtGui import QKeySequence, QUndoGroup
from PySide6.QtWidgets import (
    QDockWidget,
    QFileDialog,
    QLabel,
    QMainWindow,
    QMessageBox,
    QSplitter,
    QStyle,
    QTabBar,
    QTabWidget,
    QVBoxLayout,
    QWidget,
)

from workbench.errors import ConnectionLostError, InputError
from workbench.gui import theme
from workbench.gui.a2l_info import calibration_info, measurement_info
from workbench.gui.ecu import EcuController
from workbench.gui.mime import names_from_mime
from workbench.gui.offline_image import OfflineImage
from workbench.gui.parameter_sets import ParameterSets
from workbench.gui.project import PlotSpec, Project, remember_project, save_project
from workbench.gui.models.variables import variables_of_file
from workbench.gui.signal_hub import SignalHub, SignalInfo
from workbench.gui.widgets.a2l_tools_dialog import A2lToolsDialog
from workbench.gui.widgets.calibration_editor import CalibrationEditor
from workbench.gui.widgets.columns import column_widths, set_column_widths
from workbench.gui.widgets.compare_view import CompareView
from workbench.gui.widgets.can_trace import CanTrace
from workbench.gui.widgets.ecu_actions import EcuWindowActions
from workbench.gui.widgets.epk_dialog import EpkDialog
from workbench.gui.widgets.errors import seed_and_key_failure, seed_and_key_text, show_error
from workbench.gui.widgets.fix_panel import FixPanel
from workbench.gui.widgets.flash_dialog import FlashDialog
from workbench.gui.widgets.lost_banner import LostBanner
from workbench.gui.widgets.menus import KEYS, build_menus
from workbench.gui.widgets.numeric_view import NumericView
from workbench.gui.widgets.plot_hint import PlotHint
from workbench.gui.widgets.plot_window import PlotWindow
from workbench.gui.widgets.status_bar import EcuStatusBar
from workbench.gui.widgets.tests_dialog import RequirementTestsDialog
from workbench.gui.widgets.sync_dialog import SyncDialog
from workbench.gui.widgets.variable_browser import VariableBrowser
from workbench.gui.worker import Task, run_task
from workbench.gui.workspace import Workspace, load_workspace
from workbench.logs import logger

log = logger(__name__)

__all__ = ["MainWindow"]


class MainWindow(EcuWindowActions, QMainWindow):
    loaded = Signal()  # the project's files are read and its windows open
    live = Signal()  # every measurement window shows samples
    measurement_opened = Signal(object)  # the plot of a measurement file opened for analysis

    def __init__(self, project: Project | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.project = project or Project()
        self.workspace: Workspace | None = None
        self.hub = SignalHub(self)
        self.controller = EcuController(self, before_close=self.hub.detach)
        self.plots: list[PlotWindow] = []
        self.editors: dict[str, CalibrationEditor] = {}
        self.epk_dialog: EpkDialog | None = None
        self._connecting: Task | None = None  # the connection attempt under way
        self._closing = False  # the window waits for the ECU to be let go of before it closes
        self._seed_and_key: tuple = (None, None)  # (session, dialog) of the seed & key failure said
        self.flash_dialog: FlashDialog | None = None
        self.sync_dialog: SyncDialog | None = None
        self.a2l_tools: A2lToolsDialog | None = None
        self.tests_dialog: RequirementTestsDialog | None = None
        self.copy_confirm: QMessageBox | None = None  # the page copy's question (tests answer it)
        self.sync_report = None  # the last cache sync's workbench.sync.SyncReport
        self.last_recording = None  # the last recording's workbench.record.RecordingStats
        self.errors: list = []  # the error dialogs shown (tests look at them)
        self._build()
        self.fit_to_screen()
        self.controller.connected.connect(self._connected)
        self.controller.disconnected.connect(self._disconnected)
        self.controller.released.connect(self._released)
        self.controller.failed.connect(self.show_error)
        self.controller.page_changed.connect(self._show_page)
        self.controller.written.connect(self.refresh_sharing_editors)
        self.controller.lost.connect(self._lost)
        self.controller.reconnecting.connect(
            lambda attempt: self.status.set_pause(f"reconnecting (attempt {attempt})", self.status.pause[1]
                                                  if self.status.pause else None))
        self.hub.failed.connect(self.show_error)
        self._update_title()

    # --- building -------------------------------------------------------------------------------

    def _build(self) -> None:
        self.setDockOptions(QMainWindow.AnimatedDocks | QMainWindow.AllowTabbedDocks)
        self.setCorner(Qt.BottomLeftCorner, Qt.LeftDockWidgetArea)
        self.setCorner(Qt.BottomRightCorner, Qt.RightDockWidgetArea)
        self.plot_area = QSplitter(Qt.Vertical)
        self.plot_area.setChildrenCollapsible(False)
        central = QWidget()
        column = QVBoxLayout(central)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(0)
        self.lost_banner = LostBanner(self.controller)
        column.addWidget(self.lost_banner)
        column.addWidget(self.plot_area, 1)
        self.plot_hint = PlotHint(self.hub, lambda names: self.add_plot(PlotSpec("Measurement", names)),
                                  QKeySequence(KEYS["new plot"]))
        column.addWidget(self.plot_hint, 1)
        self.setCentralWidget(central)
        self.browser = VariableBrowser()
        self.browser.open_requested.connect(self.open_variable)
        self.browser_dock = self._dock("Variables", self.browser, Qt.LeftDockWidgetArea)
        self.editor_tabs = _EditorTabs(self)
        self.editor_tabs.setTabsClosable(True)
        self.editor_tabs.tabCloseRequested.connect(self._close_editor)
        self.editor_tabs.setDocumentMode(True)
        self.undo_group = QUndoGroup(self)  # Edit > Undo/Redo act on the editor shown (the one typed in)
        self.editor_tabs.currentChanged.connect(self._editor_shown)
        placeholder = QLabel("Double-click a calibration in the variable browser to edit it.")
        placeholder.setAlignment(Qt.AlignCenter)
        placeholder.setStyleSheet(f"color: {theme.MUTED};")
        self.editor_placeholder = placeholder
        self._show_placeholder()
        self.editor_dock = self._dock("Calibration", self.editor_tabs, Qt.RightDockWidgetArea)
        self.fix_panel = FixPanel(self.controller, self.hub)
        self.fix_panel.error.connect(self.show_error)
        self.fix_dock = self._dock("Fix calibrations", self.fix_panel, Qt.RightDockWidgetArea)
        self.numeric = NumericView(self.hub)
        self.numeric.not_current = self._not_measuring
        self.numeric_dock = self._dock("Numeric", self.numeric, Qt.BottomDockWidgetArea)
        self.trace = CanTrace(self.hub)
        self.trace_dock = self._dock("CAN trace", self.trace, Qt.BottomDockWidgetArea)
        self.compare = CompareView()
        self.compare.open_requested.connect(self.open_editor)
        self.compare_dock = self._dock("Compare", self.compare, Qt.BottomDockWidgetArea)
        self.tabifyDockWidget(self.numeric_dock, self.trace_dock)
        self.tabifyDockWidget(self.trace_dock, self.compare_dock)
        self.numeric_dock.raise_()
        self.parameter_sets = ParameterSets(self, self.compare)
        self.parameter_sets.compared.connect(lambda _: self.compare_dock.raise_())
        self.parameter_sets.message.connect(lambda text: self.statusBar().showMessage(text, 15000))
        self.parameter_sets.applied.connect(lambda _: [editor.reload() for editor in self.editors.values()])
        self.parameter_sets.applied.connect(lambda _: self._update_title())  # offline: the image is modified
        self.offline_image = OfflineImage(self)  # the project's s19/hex as the editors change it offline
        self.offline_image.changed.connect(self._update_title)
        self.status = EcuStatusBar(self.hub)
        self.setStatusBar(self.status)
        build_menus(self)
        self._show_plot_hint()

    def fit_to_screen(self) -> None:
        """The screen the window opens on, all of it up to 1600 x 1000 and 92 % of a larger one, never more;
        the docks share the space in proportion (on 1366 x 768 as on 1920 x 1080)."""
        space = self.screen().availableGeometry()
        width = min(space.width(), max(1600, int(space.width() * 0.92)))
        height = min(space.height(), max(1000, int(space.height() * 0.92)))
        self.resize(width, height)
        self.resizeDocks([self.browser_dock, self.editor_dock], [int(width * 0.22), int(width * 0.3)], Qt.Horizontal)
        self.resizeDocks([self.editor_dock, self.fix_dock], [int(height * 0.36), int(height * 0.5)], Qt.Vertical)
        self.resizeDocks([self.numeric_dock], [int(height * 0.22)], Qt.Vertical)

    def showEvent(self, event) -> None:
        super().showEvent(event)
        if not event.spontaneous():
            self._frame_within_screen()

    def _frame_within_screen(self) -> None:
        """The window's frame (title bar, borders) inside the screen too: the window gives them room."""
        space = self.screen().availableGeometry()
        frame = self.frameGeometry()
        extra_w, extra_h = frame.width() - self.width(), frame.height() - self.height()
        if frame.width() > space.width() or frame.height() > space.height():
            self.resize(min(self.width(), space.width() - extra_w), min(self.height(), space.height() - extra_h))
        frame = self.frameGeometry()
        if not space.contains(frame):
            self.move(max(space.left(), min(frame.left(), space.right() + 1 - frame.width())),
                      max(space.top(), min(frame.top(), space.bottom() + 1 - frame.height())))

    def _not_measuring(self) -> str:
        """Why the samples are not live now ("" while DAQ runs): the status bar's pause, or no measurement."""
        if self.status.pause is not None:
            return self.status.pause[0]
        return "" if self.hub.acquisition is not None else self.controller.offline_reason or "not measuring"

    def _dock(self, title: str, widget: QWidget, area) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(title.replace(" ", "_").lower())
        dock.setWidget(widget)
        dock.setFeatures(QDockWidget.DockWidgetMovable | QDockWidget.DockWidgetFloatable
                         | QDockWidget.DockWidgetClosable)
        self.addDockWidget(area, dock)
        return dock

    def find_variable(self) -> None:
        """The variable browser shown and its search field focused, its text selected to be typed over."""
        self.browser_dock.show()
        self.browser_dock.raise_()
        self.browser.search.setFocus(Qt.ShortcutFocusReason)
        self.browser.search.selectAll()

    def _editor_shown(self, _index: int) -> None:
        editor = self.editor_tabs.currentWidget()
        self.undo_group.setActiveStack(editor.undo_stack if isinstance(editor, CalibrationEditor) else None)

    def _update_title(self) -> None:
        ecu = self.controller.info.identification if self.controller.info else "offline"
        self.setWindowTitle(f"{self.project.name} — {ecu}{self.offline_image.title()} — workbench")
        self.offline_image.enable_actions()

    # --- project --------------------------------------------------------------------------------

    def load(self, project: Project | None = None):
        """Read the project's files (in a worker), then open its windows; ``loaded`` follows."""
        if project is not None:
            self.project = project
        self.browser.reading(self.project.a2l.name if self.project.a2l else "the demo ECU's A2L")
        return run_task(load_workspace, self.project, on_done=self._workspace_loaded, on_error=self._not_loaded)

    def _not_loaded(self, exc: BaseException) -> None:
        self.browser.reading(None)
        self.show_error(exc)

    def _workspace_loaded(self, workspace: Workspace) -> None:
        self.workspace = workspace
        model = workspace.model
        self.hub.set_resolver(lambda name: measurement_info(model, name))
        self.hub.add_signals(workspace.can2_infos())
        left_out = model.instance_errors() + model.instance_limits()
        self.browser.set_variables(workspace.variables, left_out=[str(error) for error in left_out])
        self.compare.set_a2l(model)
        self.status.show_offline_only(workspace.no_xcp)
        if workspace.left_out:  # said, not refused: an A2ML include sent without its file holds no object
            self.show_error(InputError("\n".join(workspace.left_out) + "\nthe rest of the A2L is open; what the "
                                       "missing files hold is not (put them beside the A2L and open it again)"))
        if self.a2l_tools is not None:  # its reload offer is for the files read now (another project's, its includes)
            self.a2l_tools.set_in_use(self.a2l_in_use())
        self._open_windows()
        self._update_title()
        self.loaded.emit()

    def _open_windows(self) -> None:
        for plot in list(self.plots):
            self._remove_plot(plot)
        for spec in self.project.plots:
            self.add_plot(spec)
        self.numeric.remove_signals(self.numeric.signals)
        for signals in self.project.tables[:1]:
            self.numeric.add_signals([n for n in signals if self.hub.known(n)])
        for name in self.project.editors:
            self.open_editor(name)
        if self.project.editors and self.project.editors[0] in self.editors:
            self.editor_tabs.setCurrentWidget(self.editors[self.project.editors[0]])
        if self.project.layout:
            self.restoreState(QByteArray(base64.b64decode(self.project.layout)))
        tables = self.column_tables()
        for name, widths in self.project.columns.items():
            if name in tables:
                set_column_widths(tables[name], widths)

    def open_project_dialog(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Open project", "", "Projects (*.toml *.json);;All files (*)")
        if path:
            self.open_project_file(Path(path))

    def open_project_file(self, path: Path) -> None:
        from workbench.gui.project import load_project

        try:
            project = load_project(path)
        except Exception as exc:  # noqa: BLE001 - every failure is a dialog
            self.show_error(exc)
            return
        if not self.offline_image.may_close():
            return
        remember_project(path)
        self._close_project()
        self.load(project)
        self._update_title()

    def _close_project(self) -> None:
        """Another project opens, as CANape opens another configuration: nothing stays bound to the A2L (or the ECU)
        of the one before. The connection closes; its editors, plots, numeric view, CAN trace, fixes and comparison go,
        and a question about them; the new project's windows open once its files are read. The A2L tools stay (they
        work on files): their reload offer follows the new project's A2L."""
        self.controller.close()
        if self._connecting is not None:  # an attempt under way is the project before's (closed if it connects):
            self._connecting = None      # Connect is offered for the new one (it stayed greyed, 'connecting …')
            self.connect_action.setEnabled(not self.controller.closing)
            self.status.show_disconnected(self.controller.closing)
        self.workspace = None  # connecting before the new files are read reads the new project's A2L
        for index in reversed(range(self.editor_tabs.count())):
            self._close_editor(index)
        for plot in list(self.plots):
            self._remove_plot(plot)
        self.numeric.remove_signals(self.numeric.signals)
        self.fix_panel.clear()
        self.parameter_sets.forget()
        self.compare.set_a2l(None)  # its decimals held the A2L model until the next project's was read
        self.trace.clear()
        self.browser.set_variables([])
        self.hub.clear()
        self.sync_report = None
        for dialog in (self.epk_dialog, self.sync_dialog, self.copy_confirm):
            if dialog is not None:
                dialog.blockSignals(True)  # not answered: its question was about the project before
                dialog.close()
                dialog.deleteLater()
        self.epk_dialog = self.sync_dialog = self.copy_confirm = None
        if self.flash_dialog is not None and self.flash_dialog.task is None:  # (modal: no project opens while flashing)
            self.flash_dialog.close()
            self.flash_dialog.deleteLater()
            self.flash_dialog = None

    def current_project(self) -> Project:
        """The project as the window shows it now (windows, signals, layout)."""
        project = self.project
        project.plots = [PlotSpec(p.title, p.signals, p.span_s) for p in self.plots]
        project.tables = [self.numeric.signals] if self.numeric.signals else []
        project.editors = list(self.editors)
        widths = {name: column_widths(view) for name, view in self.column_tables().items()}
        project.columns = {name: sizes for name, sizes in widths.items() if sizes}  # the user's, where given
        project.layout = base64.b64encode(bytes(self.saveState())).decode("ascii")
        return project

    def column_tables(self) -> dict:
        """The tables whose column widths the project file keeps, by name."""
        tables = {"variables": self.browser.table, "fixes": self.fix_panel.table, "numeric": self.numeric,
                  "trace": self.trace.table, "compare": self.compare.table}
        tables.update({f"plot {number}": plot.legend for number, plot in enumerate(self.plots, 1)})
        return tables

    def save(self) -> None:
        if self.project.path is None:
            self.save_as()
            return
        self.save_to(self.project.path)

    def save_as(self) -> None:
        path, _ = QFileDialog.getSaveFileName(self, "Save project", f"{self.project.name}.toml",
                                              "TOML project (*.toml);;JSON project (*.json)")
        if path:
            self.save_to(Path(path))

    def save_to(self, path: Path) -> None:
        try:
            save_project(self.current_project(), path)
        except Exception as exc:  # noqa: BLE001
            self.show_error(exc)
            return
        remember_project(path)
        self._update_title()

    # --- windows --------------------------------------------------------------------------------

    def add_plot(self, spec: PlotSpec) -> PlotWindow:
        plot = PlotWindow(self.hub, spec.title, spec.span_s)
        plot.not_current = self._not_measuring
        plot.add_signals([n for n in spec.signals if self.hub.known(n)])
        plot.samples_arrived.connect(self._check_live)
        plot.close_requested.connect(lambda: self._remove_plot(plot))
        self.plot_area.addWidget(plot)
        self.plots.append(plot)
        self._show_plot_hint()
        return plot

    def _remove_plot(self, plot: PlotWindow) -> None:
        self.plots.remove(plot)
        self.hub.hide(plot)  # its signals are no longer measured for it
        plot.timer.stop()
        plot.setParent(None)
        plot.deleteLater()
        self._show_plot_hint()

    def _show_plot_hint(self) -> None:
        """The hint (and drop place) in place of plots while there are none."""
        self.plot_area.setVisible(bool(self.plots))
        self.plot_hint.setVisible(not self.plots)

    def _check_live(self) -> None:
        if all(p.samples_shown() or not p.signals for p in self.plots):
            self.live.emit()

    def open_variable(self, variable) -> None:
        """A double-click in the browser: an editor for a calibration, the first plot for a signal."""
        if variable is None:
            return
        if variable.editable:
            self.open_editor(variable.name)
        elif variable.plottable:
            plot = self.plots[0] if self.plots else self.add_plot(PlotSpec("Measurement"))
            plot.add_signals([variable.name])

    def open_editor(self, name: str) -> CalibrationEditor | None:
        if name in self.editors:
            self.editor_tabs.setCurrentWidget(self.editors[name])
            return self.editors[name]
        if self.workspace is None:
            return None
        try:
            info = calibration_info(self.workspace.model, name)
        except Exception as exc:  # noqa: BLE001
            self.show_error(exc)
            return None
        editor = CalibrationEditor(self.controller, info, hub=self.hub, offline=self.workspace.file_values)
        editor.error.connect(self.show_error)
        editor.offline_written.connect(self.offline_image.edited)
        editor.offline_written.connect(self.refresh_sharing_editors)
        self.undo_group.addStack(editor.undo_stack)
        self.editors[name] = editor
        if self.editor_tabs.indexOf(self.editor_placeholder) >= 0:
            self.editor_tabs.removeTab(self.editor_tabs.indexOf(self.editor_placeholder))
        self.editor_tabs.addTab(editor, name)
        self.editor_tabs.setCurrentWidget(editor)
        editor.reload()  # from the ECU, or offline from the project's s19
        return editor

    def refresh_sharing_editors(self, name: str) -> None:
        """``name`` was written: the open editors whose value shares its bytes (a map and the AXIS_PTS of its axis)
        read theirs again (the writer's own editor shows what it wrote)."""
        writer = self.editors.get(name)
        for editor in self.editors.values():
            if editor is not writer and (name in editor.info.shares or (writer and editor.info.name in writer.info.shares)):
                editor.reload()

    def _close_editor(self, index: int) -> None:
        widget = self.editor_tabs.widget(index)
        if isinstance(widget, CalibrationEditor):
            widget.release()
            self.editors.pop(widget.info.name, None)
            self.editor_tabs.removeTab(index)
            widget.deleteLater()
        if not self.editors and self.editor_tabs.indexOf(self.editor_placeholder) < 0:
            self._show_placeholder()  # what to do, not an empty dock

    def _show_placeholder(self) -> None:
        """The hint in place of editors, as a tab without a close button (closing it did nothing)."""
        index = self.editor_tabs.addTab(self.editor_placeholder, "Calibration")
        bar = self.editor_tabs.tabBar()
        side = QTabBar.ButtonPosition(bar.style().styleHint(QStyle.SH_TabBar_CloseButtonPosition, None, bar))
        bar.setTabButton(index, side, None)

    def open_measurement_dialog(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Open measurement file", "",
                                              "MDF (*.mf4 *.mdf *.dat);;All files (*)")
        if path:
            self.open_measurement(Path(path))

    def open_measurement(self, path: Path) -> Task:
        """Read an MDF file (in a worker) and show it in a plot of its own, with cursors; ``measurement_opened``
        follows with that plot. Its channels join the variable browser (kind "recorded") to be dragged."""
        from workbench.gui.offline import read_measurement_file

        return run_task(read_measurement_file, path, on_done=lambda channels: self._measurement_read(path, channels),
                        on_error=self.show_error)

    def _measurement_read(self, path: Path, channels) -> None:
        names = [f"{path.name}:{channel.name}" for channel in channels]
        self.hub.add_signals(SignalInfo(name, "MDF", channel.unit, channel.comment, states=channel.states,
                                        decimals=channel.decimals, label=channel.name)
                             for name, channel in zip(names, channels))
        for name, channel in zip(names, channels):
            self.hub.load(name, channel.times, channel.values)
        self.browser.add_variables(variables_of_file(path.name, channels))
        shown = [n for n, c in zip(names, channels) if not c.name.startswith("HostTime")][:6]
        plot = self.add_plot(PlotSpec(f"{path.name} (offline)", shown))
        plot.show_all()
        plot.cursor_button.setChecked(True)
        self.measurement_opened.emit(plot)

    # --- the A2L tools ---------------------------------------------------------------------------

    def project_a2l(self) -> Path:
        """The A2L the window reads (the demo's when the project names none)."""
        from workbench import demo

        return self.project.a2l or demo.a2l()

    def a2l_in_use(self) -> list[Path]:
        """The files of the A2L the window holds: the project's, then those it includes (as they were read)."""
        doc = self.workspace.doc if self.workspace is not None else None
        included = [s.source.path for s in doc.source_map.segments if s.source.path is not None] if doc else []
        return [self.project_a2l(), *included]

    def open_a2l_tools(self, operation: str) -> A2lToolsDialog:
        """The A2L tools (Tools menu), non-modal, on the tab of ``operation``; a new dialog starts with the project's
        A2L and ELF, an open one keeps what the user chose."""
        if self.a2l_tools is not None and self.a2l_tools.isVisible():
            if self.a2l_tools.task is None:
                self.a2l_tools.set_operation(operation)
        else:
            if self.a2l_tools is not None:
                self.a2l_tools.deleteLater()
            self.a2l_tools = A2lToolsDialog(operation, self.project_a2l(), self.project.elf, self.a2l_in_use(), self)
            self.a2l_tools.reload_requested.connect(self.reload_a2l)
        self.a2l_tools.show()
        self.a2l_tools.raise_()
        return self.a2l_tools

    def open_requirement_tests(self) -> RequirementTestsDialog:
        """The requirement tests (Tools menu), non-modal; one dialog, which keeps its choices and its last run."""
        if self.tests_dialog is None:
            self.tests_dialog = RequirementTestsDialog(self)
        self.tests_dialog.show()
        self.tests_dialog.raise_()
        return self.tests_dialog

    def reload_a2l(self) -> Task:
        """Read the project's files again (its A2L was rewritten), the windows kept; the editors are opened again
        (theirs was the A2L as it was), and a connection, which holds it too, is closed and made again."""
        reconnect = self.controller.session is not None
        project = self.current_project()
        self.controller.close()
        for index in reversed(range(self.editor_tabs.count())):
            self._close_editor(index)
        task = self.load(project)
        if reconnect:
            task.succeeded.connect(lambda _: self.connect_ecu())
        return task

    # --- errors and closing ---------------------------------------------------------------------

    def show_error(self, exc: BaseException) -> None:
        if isinstance(exc, ConnectionLostError):  # not a dialog: the banner and the status bar say it
            self.controller.connection_lost(exc)
            return
        if seed_and_key_failure(exc):
            self._seed_and_key_failed(exc)
            return
        self.errors.append(show_error(self, exc))

    def _seed_and_key_failed(self, exc: BaseException) -> None:
        """One dialog a connection for seed & key, whichever calls found it (the cache check, an editor, DAQ: a
        dialog each before): the resources that stay locked and what to do; a later failure adds its line there."""
        session, box = self._seed_and_key
        if box is not None and session is self.controller.session:
            lines = box.informativeText().split("\n")
            if str(exc) not in lines:
                box.setInformativeText("\n".join([*lines, str(exc)]))
                box.setText(seed_and_key_text(box.informativeText()))
            return
        box = show_error(self, exc)
        box.setText(seed_and_key_text(str(exc)))
        box.setInformativeText(str(exc))
        self._seed_and_key = (self.controller.session, box)
        self.errors.append(box)

    def closeEvent(self, event) -> None:
        if self.flash_dialog is not None and self.flash_dialog.task is not None:  # as the flash dialog itself:
            event.ignore()  # closing blocked the window while the session closed under the erase, and cut the flash
            self.show_error(InputError("a flash is under way: closing now would cut it off and leave the ECU in its "
                                       "boot loader; wait for it to end, or press Cancel flash first"))
            self.flash_dialog.raise_()
            return
        if self._closing:  # closed again while the ECU is let go of: the first close ends it
            event.ignore()
            return
        if not self.offline_image.may_close():
            event.ignore()
            return
        if self.tests_dialog is not None:  # the window goes: a requirement test run goes with it
            self.tests_dialog.stop()
        self._closing = True
        self._connecting = None  # an attempt under way is closed when it connects, and says nothing to the window
        self.controller.close()
        if self.controller.closing:  # the ECU let go of (DAQ stopped, DISCONNECT, the bus freed) before the window
            self.setEnabled(False)   # goes, painting meanwhile; nothing more to click
            self.controller.wait_released()
            self.setEnabled(True)
        self._closing = False
        super().closeEvent(event)


class _EditorTabs(QTabWidget):
    """The calibration editors' tabs: a calibration dropped on them opens its editor."""

    def __init__(self, window: MainWindow):
        super().__init__()
        self.window_ = window
        self.setAcceptDrops(True)

    def dragEnterEvent(self, event) -> None:
        if self._calibrations(event.mimeData()):
            event.acceptProposedAction()

    def dropEvent(self, event) -> None:
        for name in self._calibrations(event.mimeData()):
            self.window_.open_editor(name)
        event.acceptProposedAction()

    def _calibrations(self, mime) -> list[str]:
        browser = self.window_.browser
        return [n for n in names_from_mime(mime) if (v := browser.variable(n)) is not None and v.editable]

