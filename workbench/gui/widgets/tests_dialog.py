"""Requirement tests in the window (Tools ▸ Requirement tests…): ``workbench test`` with its options, run in a process
of its own (:class:`~workbench.testbench.run.RequirementRun`: pytest never runs in the window's process), each test's
verdict in a table as it ends (PASSED, FAILED, NOT JUDGED, ERROR, with its requirement ids and the failure's one line),
Cancel as Ctrl-C, and at the end the totals and the report.

The tests run on a simulated demo ECU each (in parallel with -n), or on the ECU the window is connected to: the
window lets go of it while they run (XCP takes one master at a time), waits meanwhile (the dialog is modal), and
connects again after them through its own Connect.
"""

from __future__ import annotations

import os
import re
import time
from pathlib import Path

from PySide6.QtCore import Qt, QTimer, QUrl, Signal
from PySide6.QtGui import QDesktopServices, QStandardItem, QStandardItemModel
from PySide6.QtWidgets import (
    QButtonGroup,
    QCompleter,
    QDialog,
    QFileDialog,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QProgressBar,
    QPushButton,
    QRadioButton,
    QSpinBox,
    QStyledItemDelegate,
    QTableView,
    QTabWidget,
    QVBoxLayout,
)

from workbench.errors import InputError
from workbench.gui import theme
from workbench.gui.models.verdicts import VerdictsModel
from workbench.gui.widgets.job_buttons import JobButtons
from workbench.testbench.run import FLCU_SUITE, RequirementRun, RunOptions
from workbench.testbench.verdicts import report_anchor, requirement_verdicts

__all__ = ["RequirementTestsDialog", "connected_ecu_options"]

POLL_MS = 200  # how often the run's verdicts and output are read
_REPETITION = re.compile(r"\[\d+-\d+\]$|-\d+-\d+(?=\]$)")  # pytest-repeat's test_x[2-5], test_x[param-2-5]
_WORDS = re.compile(r"[,;\s]+")  # between the requirement ids typed
_EXCEPTION_PREFIX = re.compile(r"^(?:[\w.]+\.)?(ExpectationFailed|NotJudged|Failed): ")  # the verdict says it
_DOTTED_EXCEPTION = re.compile(r"^[a-z_][\w]*(?:\.[\w]+)*\.(\w+): ")  # workbench.errors.X: -> X:


def connected_ecu_options(window) -> tuple[list[str], str]:
    """``workbench test``'s options for the ECU ``window`` is connected to, and how to name it.
    :raises InputError: not connected, or on a bus no other process reaches."""
    session = window.controller.session
    if session is None:
        raise InputError("the window is not connected: connect it first (F9), the tests then run on its ECU")
    settings = session.link.settings
    options = ["--a2l", str(window.project_a2l())]
    if settings.transport == "CAN":
        bus = dict(settings.bus.kwargs()) if settings.bus is not None else {}
        if bus.get("interface") == "virtual":
            raise InputError(f"the window's ECU is on a python-can virtual bus ({bus.get('channel')}), which only "
                             "this process reaches (the demo's simulated ECU): choose a simulated ECU per test, or "
                             "serve one with workbench sim --interface udp_multicast and connect the window to it")
        bus.pop("receive_own_messages", None)
        for key in ("interface", "channel", "bitrate"):
            value = bus.pop(key, None)
            if value is not None:
                options += [f"--{key}", str(value)]
        if bus:
            options += ["--bus-kwargs", *(f"{key}={value}" for key, value in bus.items())]
    else:
        options += ["--host", str(settings.host), "--port", str(settings.port),
                    "--protocol", settings.transport.lower()]
    connection = window.project.connection
    if connection.key_function:
        options += ["--key-function", connection.key_function]
    if window.project.dbcs:
        options += ["--dbc", str(window.project.dbcs[0])]
    return options, settings.describe()


class _IdCompleter(QCompleter):
    """Completes the id being typed after the others in the requirement ids' field (the catalogue's, its name in the
    tooltip)."""

    def __init__(self, field: QLineEdit):
        super().__init__(field)
        self.setModel(QStandardItemModel(self))
        self.setCaseSensitivity(Qt.CaseInsensitive)
        self.setFilterMode(Qt.MatchContains)
        field.setCompleter(self)

    def set_catalogue(self, requirements) -> None:
        model = self.model()
        model.clear()
        for requirement in requirements:
            item = QStandardItem(requirement.id)
            item.setToolTip(requirement.name or requirement.description)
            model.appendRow(item)

    def splitPath(self, path: str) -> list[str]:
        return [_WORDS.split(path)[-1]]

    def pathFromIndex(self, index) -> str:
        before = self.widget().text()
        kept = before[:len(before) - len(_WORDS.split(before)[-1])]
        return kept + index.data() + " "


class _ElideMiddle(QStyledItemDelegate):
    def initStyleOption(self, option, index) -> None:
        super().initStyleOption(option, index)
        option.textElideMode = Qt.ElideMiddle


def _reason(message: str) -> str:
    """The failure's line as the table shows it: no exception class where the verdict says it, no module path."""
    return _DOTTED_EXCEPTION.sub(r"\1: ", _EXCEPTION_PREFIX.sub("", message))


class RequirementTestsDialog(QDialog):
    """Choose, run and follow requirement tests (see the module's docstring); ``window``: the MainWindow."""

    finished_run = Signal(object)  # the RequirementRun, once it ended and its verdicts are shown

    def __init__(self, window):
        super().__init__(window)
        self.window_ = window
        self.setWindowTitle("Requirement tests")
        self.run: RequirementRun | None = None
        self.last_report: Path | None = None  # the folder of the last run's report
        self._root: Path | None = None  # the folder the last run's node ids are relative to
        self._repeated = False  # the last run repeated each test (its node ids end in [2-5])
        self.on_ecu = False  # the run uses the window's ECU (released while it runs)
        self.ecu_lost = False
        self._ecu_wanted = False  # the window's ECU was chosen, and the window disconnected since
        self._started = 0.0
        self._proposed = ""  # the report folder proposed: a new one each run, unless the user chose another
        self._timer = QTimer(self)
        self._timer.setInterval(POLL_MS)
        self._timer.timeout.connect(self._poll)
        self._build()
        self.refresh_target()
        window.controller.connected.connect(self.refresh_target)
        window.controller.disconnected.connect(self.refresh_target)

    # --- building ---------------------------------------------------------------------------------

    def _build(self) -> None:
        layout = QVBoxLayout(self)
        layout.addWidget(self._tests_box())
        layout.addWidget(self._target_box())
        report = QHBoxLayout()
        report.addWidget(QLabel("Report folder"))
        self.folder = QLineEdit()
        self.folder.setToolTip("report.html, junit.xml and each test's MDF4 evidence go here (--report)")
        report.addWidget(self.folder, 1)
        report.addWidget(self._button("Browse…", self._browse_folder))
        layout.addLayout(report)
        self._propose_folder()

        self.status = QLabel("Choose the tests and the ECU, then Run.")
        self.progress = QProgressBar()
        self.progress.setTextVisible(True)
        self.progress.setFormat("%v of %m tests")
        self.progress.setVisible(False)
        status_row = QHBoxLayout()
        status_row.addWidget(self.status, 1)
        status_row.addWidget(self.progress)
        layout.addLayout(status_row)

        self.model = VerdictsModel(self)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.setSelectionBehavior(QTableView.SelectRows)
        self.table.setAlternatingRowColors(True)
        self.table.verticalHeader().setVisible(False)
        self.table.setWordWrap(False)
        self.table.setItemDelegateForColumn(2, _ElideMiddle(self.table))  # a test's module and its name's end
        self.table.setToolTip("double-click a test: its steps and plots in the report (once the run ended)")
        self.table.doubleClicked.connect(lambda index: self.open_report(self.model.rows[index.row()]["nodeid"]))
        header = self.table.horizontalHeader()
        for column, mode in enumerate((QHeaderView.ResizeToContents, QHeaderView.Interactive, QHeaderView.Interactive,
                                       QHeaderView.ResizeToContents, QHeaderView.Stretch)):
            header.setSectionResizeMode(column, mode)
        header.resizeSection(1, 130)
        header.resizeSection(2, 330)
        self.output = QPlainTextEdit()
        self.output.setReadOnly(True)
        self.output.setLineWrapMode(QPlainTextEdit.NoWrap)
        self.tabs = QTabWidget()
        self.tabs.addTab(self.table, "Verdicts")
        self.tabs.addTab(self.output, "Output")
        layout.addWidget(self.tabs, 1)

        self.message = QLabel("")
        self.message.setWordWrap(True)
        self.message.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.message.setVisible(False)
        layout.addWidget(self.message)

        self.buttons = JobButtons(self, "Run", "Cancel", self.start, self.cancel,
                                  guarded=[self.tests_box, self.target_box, self.folder])
        self.run_button, self.cancel_button = self.buttons.run_button, self.buttons.cancel_button
        self.open_report_button = self._button("Open report", lambda: self.open_report(), enabled=False)
        self.open_folder_button = self._button("Open folder", self.open_folder, enabled=False)
        self.rerun_button = self._button("Run failed again", lambda: self.start(self._to_rerun()), enabled=False)
        self.rerun_button.setToolTip("the tests that failed, were not judged or could not start, on the same ECU, "
                                     "each once")
        self.buttons.insertWidget(0, self.open_report_button)
        self.buttons.insertWidget(1, self.open_folder_button)
        self.buttons.insertWidget(3, self.rerun_button)  # beside Run, after the stretch
        layout.addLayout(self.buttons)
        screen = self.window_.screen().availableGeometry() if self.window_.screen() else None
        width, height = 1000, 680  # a big screen gives the table more room
        if screen is not None:
            width = min(max(width, screen.width() * 3 // 5), screen.width() - 40)
            height = min(max(height, screen.height() * 7 // 10), screen.height() - 60)
        self.resize(width, height)

    def _button(self, text: str, slot, enabled: bool = True) -> QPushButton:
        button = QPushButton(text)
        button.setAutoDefault(False)
        button.setEnabled(enabled)
        button.clicked.connect(slot)
        return button

    def _tests_box(self) -> QGroupBox:
        box = self.tests_box = QGroupBox("Tests")
        form = QFormLayout(box)
        self.suite_radio = QRadioButton("The FLCU requirement suite (SW_REQ_ID_001-008, built in)")
        self.suite_radio.setChecked(True)
        self.own_radio = QRadioButton("My tests")
        group = QButtonGroup(box)
        group.addButton(self.suite_radio)
        group.addButton(self.own_radio)
        form.addRow(self.suite_radio)
        own = QHBoxLayout()
        own.addWidget(self.own_radio)
        self.paths = QLineEdit()
        self.paths.setPlaceholderText("test files or folders; several separated by ;")
        self.paths.textEdited.connect(lambda text: self.own_radio.setChecked(True) if text.strip() else None)
        own.addWidget(self.paths, 1)
        own.addWidget(self._button("Folder…", self._browse_tests_folder))
        own.addWidget(self._button("Files…", self._browse_test_files))
        form.addRow(own)
        self.catalogue = QLineEdit()
        self.catalogue.setPlaceholderText("optional: id,name,description (the FLCU suite's own without one)")
        self.catalogue.setToolTip("the requirements the report traces, those no test covers listed as NOT TESTED "
                                  "(--requirements)")
        form.addRow("Requirements CSV", self.catalogue)
        chosen = QHBoxLayout()
        self.req = QLineEdit()
        self.req.setPlaceholderText("all, or e.g. SW_REQ_ID_001 SW_REQ_ID_002.2")
        self.req.setToolTip("the tests that verify these requirements or ones below them (--req; SW_REQ_ID_001 takes "
                            "SW_REQ_ID_001.1 …)")
        self.req_completer = _IdCompleter(self.req)
        self.suite_radio.toggled.connect(self._read_catalogue)
        self.catalogue.editingFinished.connect(self._read_catalogue)
        self._read_catalogue()
        chosen.addWidget(self.req, 3)
        chosen.addWidget(QLabel("Test names (-k)"))
        self.keyword = QLineEdit()
        self.keyword.setPlaceholderText("e.g. tank_ctrl and not low_fuel")
        self.keyword.setToolTip("pytest's -k: the tests whose names match")
        chosen.addWidget(self.keyword, 2)
        chosen.addWidget(QLabel("Repeat"))
        self.repeat = QSpinBox()
        self.repeat.setRange(1, 1000)
        self.repeat.setSuffix(" ×")
        self.repeat.setToolTip("run each test this many times (--repeat)")
        self.repeat.setMaximumWidth(self.repeat.sizeHint().width() + 20)
        chosen.addWidget(self.repeat)
        form.addRow("Requirement ids", chosen)
        return box

    def _target_box(self) -> QGroupBox:
        box = self.target_box = QGroupBox("ECU")
        form = QFormLayout(box)
        simulated = QHBoxLayout()
        self.sim_radio = QRadioButton("A simulated demo ECU per test")
        self.sim_radio.setChecked(True)
        simulated.addWidget(self.sim_radio)
        simulated.addSpacing(20)
        simulated.addWidget(QLabel("Processes"))
        self.workers = QSpinBox()
        self.workers.setRange(1, max(1, os.cpu_count() or 1))
        self.workers.setToolTip("run the tests in this many processes at once (-n), each test with its own ECU")
        simulated.addWidget(self.workers)
        simulated.addStretch(1)
        form.addRow(simulated)
        self.ecu_radio = QRadioButton("The ECU this window is connected to")
        group = QButtonGroup(box)
        group.addButton(self.sim_radio)
        group.addButton(self.ecu_radio)
        self.ecu_radio.toggled.connect(lambda on: self.workers.setEnabled(not on))
        form.addRow(self.ecu_radio)
        self.ecu_note = QLabel("")
        self.ecu_note.setWordWrap(True)
        self.ecu_note.setStyleSheet(f"color: {theme.MUTED}; margin-left: 22px;")
        form.addRow(self.ecu_note)
        return box

    # --- choices ------------------------------------------------------------------------------------

    def refresh_target(self, *_args) -> None:
        """What the connected-ECU choice would do now (or why it cannot be chosen)."""
        if self.run is not None and self.on_ecu:
            return  # the window let go of the ECU for this run: it says so in the status line
        try:
            _, describe = connected_ecu_options(self.window_)
        except InputError as exc:
            self.ecu_radio.setEnabled(False)
            if self.ecu_radio.isChecked():  # chosen again when the window is connected again
                self._ecu_wanted = True
                self.sim_radio.setChecked(True)
            self.ecu_note.setText(f"Not available: {exc}.")
            return
        self.ecu_radio.setEnabled(True)
        if self._ecu_wanted:
            self.ecu_radio.setChecked(True)
            self._ecu_wanted = False
        self.ecu_note.setText(f"{describe}. The window disconnects while the tests run (an ECU takes one XCP master "
                              "at a time), waits, and connects again after them.")

    def _read_catalogue(self, *_args) -> None:
        """The requirement ids the field completes: the CSV's given, else the FLCU suite's (when it runs)."""
        from workbench.testbench.report import read_requirements

        path = self.catalogue.text().strip() or (str(FLCU_SUITE / "requirements.csv") if self.suite_radio.isChecked()
                                                 else "")
        try:
            self.req_completer.set_catalogue(read_requirements(path) if path else [])
        except InputError:  # said by the run, which reads it too
            self.req_completer.set_catalogue([])

    def _propose_folder(self) -> None:
        project = self.window_.project
        base = project.path.parent if project.path is not None else Path.cwd()
        self._proposed = str(base / f"test-report-{time.strftime('%Y%m%d-%H%M%S')}")
        self.folder.setText(self._proposed)

    def _browse_folder(self) -> None:
        chosen = QFileDialog.getExistingDirectory(self, "Report folder", str(Path(self.folder.text()).parent))
        if chosen:
            self.folder.setText(chosen)

    def _browse_tests_folder(self) -> None:
        chosen = QFileDialog.getExistingDirectory(self, "Folder of requirement tests", self._first_path())
        if chosen:
            self._set_paths([chosen])

    def _browse_test_files(self) -> None:
        chosen, _ = QFileDialog.getOpenFileNames(self, "Requirement tests", self._first_path(),
                                                 "Python tests (test_*.py *_test.py);;All files (*)")
        if chosen:
            self._set_paths(chosen)

    def _first_path(self) -> str:
        paths = self._paths()
        return paths[0] if paths else str(Path.cwd())

    def _set_paths(self, paths: list[str]) -> None:
        self.paths.setText("; ".join(paths))
        self.own_radio.setChecked(True)

    def _paths(self) -> list[str]:
        return [part.strip() for part in self.paths.text().split(";") if part.strip()]

    def options(self) -> RunOptions:
        """The run the fields describe. :raises InputError: the connected ECU chosen where there is none."""
        ecu = connected_ecu_options(self.window_)[0] if self.ecu_radio.isChecked() else []
        return RunOptions(report=self.folder.text().strip(), paths=self._paths() if self.own_radio.isChecked() else [],
                          req=[part for part in _WORDS.split(self.req.text()) if part],
                          keyword=self.keyword.text().strip(), repeat=self.repeat.value() if self.repeat.value() > 1
                          else 0, workers=self.workers.value() if not ecu and self.workers.value() > 1 else 0,
                          requirements=self.catalogue.text().strip(), ecu=ecu)

    # --- running ------------------------------------------------------------------------------------

    def _to_rerun(self) -> list[str]:
        """The last run's tests that failed, were not judged or could not start, as test paths (each once: a
        repetition's suffix dropped)."""
        if self._root is None:
            return []
        nodeids = [_REPETITION.sub("", row["nodeid"]) if self._repeated else row["nodeid"] for row in self.model.rows
                   if row["state"] in ("failed", "not judged", "error")]
        return [str(self._root / nodeid) for nodeid in dict.fromkeys(nodeids)]

    def start(self, tests: list[str] | None = None) -> None:
        """Run the tests chosen (``tests``: these test paths instead, each once); the window's ECU released first
        when they run on it."""
        if self.run is not None:
            return
        if self.folder.text() == self._proposed:
            self._propose_folder()
        try:
            options = self.options()
            if not options.report:
                raise InputError("choose a report folder")
            if self.own_radio.isChecked() and not options.paths:
                raise InputError("name the test files or folders to run (Folder…, Files…), or choose the FLCU suite")
        except InputError as exc:
            self._say(str(exc), theme.BAD)
            return
        if tests:
            options.paths, options.req, options.keyword, options.repeat = tests, [], "", 0
        self._root, self._repeated = None, options.repeat > 1
        self.rerun_button.setEnabled(False)
        self.model.clear()
        self.output.clear()
        self._say("", None)
        self.ecu_lost = False
        self.on_ecu = bool(options.ecu)
        self.run = RequirementRun(options)
        self._set_busy(True)
        if self.on_ecu:
            self._hold_window(True)
            self.status.setText("The window lets go of the ECU …")
            self._release_ecu(lambda: self._launch())
        else:
            self._launch()

    def _release_ecu(self, then) -> None:
        """Disconnect the window (its public path: Disconnect's); ``then`` once the session let go of the bus."""
        controller = self.window_.controller
        controller.close()
        if not getattr(controller, "closing", False):  # closed at once
            then()
            return

        def released() -> None:
            controller.released.disconnect(released)
            then()

        controller.released.connect(released)

    def _launch(self) -> None:
        if self.run is None or self.run.process is not None:  # cancelled while the window let go of the ECU (and
            return  # maybe another run started since: the release of the cancelled one comes late)
        self.run.start()
        self._started = time.monotonic()
        if self.on_ecu:  # the window says why it is not connected
            self.window_.status.set_pause("the requirement tests use the ECU")
        where = "the window's ECU" if self.on_ecu else "a simulated ECU per test"
        self.status.setText(f"Starting the tests on {where} …")
        self._timer.start()

    def cancel(self) -> None:
        """Stop the run as Ctrl-C does: the test under way ends (its ECU's values restored), the report is written."""
        if self.run is None:
            return
        if self.run.process is None:  # still releasing the ECU: nothing started
            self.run = None
            self._ended(cancelled=True)
            return
        self.run.cancel()
        self.cancel_button.setEnabled(False)
        self.status.setText("Cancelling: the test under way stops and restores what it changed …")

    def _poll(self) -> None:
        run = self.run
        if run is None:
            return
        for event in run.events():
            self._event(event)
        self._append_output(run)
        if run.poll() is not None:
            for event in run.events():  # what came between the last read and the end
                self._event(event)
            self._append_output(run)
            self._timer.stop()
            self._finish(run)

    def _append_output(self, run: RequirementRun) -> None:
        text = run.read_output()
        if text:
            cursor = self.output.textCursor()
            cursor.movePosition(cursor.MoveOperation.End)
            cursor.insertText(text)

    def _event(self, event: dict) -> None:
        kind = event.get("event")
        if kind == "collected":
            self._root = Path(event["root"])
            for test in event["tests"]:
                self.model.row_of(test["nodeid"])["requirements"] = list(test["requirements"])
            self.progress.setRange(0, len(self.model.rows))
            self.progress.setValue(0)
            self.progress.setVisible(True)
        elif kind == "started":
            self.model.row_of(event["nodeid"])["state"] = "running"
            self.model.changed(event["nodeid"])
        elif kind == "verdict":
            row = self.model.row_of(event["nodeid"])
            row.update(state=event["verdict"], requirements=event["requirements"] or row["requirements"],
                       message=_reason(event["message"]), duration=event["duration"], ecu=event.get("ecu"),
                       ecu_error=event.get("ecu_error"))
            self.model.changed(event["nodeid"])
            self.progress.setMaximum(max(self.progress.maximum(), len(self.model.rows)))
            self.progress.setValue(sum(1 for r in self.model.rows if r["state"] not in ("pending", "running")))
            if event.get("ecu") == "lost":
                self.ecu_lost = True
        if kind in ("collected", "started", "verdict"):
            self.status.setText(self._counts(running=True))
        if kind == "collected":
            self._fit_test_column()

    def _fit_test_column(self) -> None:
        """The tests' names whole where they fit in half the table (the reasons take the rest)."""
        metrics = self.table.fontMetrics()
        widest = max((metrics.horizontalAdvance(row["nodeid"]) for row in self.model.rows), default=0) + 24
        self.table.horizontalHeader().resizeSection(2, max(200, min(widest, self.table.viewport().width() // 2)))

    def _counts(self, running: bool) -> str:
        states = [row["state"] for row in self.model.rows]
        parts = [f"{states.count(state)} {state}" + ("s" if state == "error" and states.count(state) > 1 else "")
                 for state in ("passed", "failed", "not judged", "error", "skipped")
                 if states.count(state) or state in ("passed", "failed")]
        if running:
            return f"Running: {', '.join(parts)}; {states.count('running')} running, {states.count('pending')} to come"
        return ", ".join(parts)

    def _finish(self, run: RequirementRun) -> None:
        """The run ended: its totals, what went wrong in one message, the report."""
        cancelled = run.cancelled_at is not None
        report = run.report.is_file()
        code = run.exit_code
        self.model.end(cancelled)
        elapsed = time.monotonic() - self._started
        if code == 2 and not cancelled and not any(r["state"] not in ("cancelled", "pending") for r in self.model.rows):
            self.model.clear()  # nothing ran: the command's own line says why
            self.status.setText("Not run.")
            self._say(f"Not run: {run.error().removeprefix('ERROR: ')}", theme.BAD)
        else:
            judged = requirement_verdicts((r["nodeid"], r["state"], r["requirements"]) for r in self.model.rows)
            verdicts = [verdict for verdict, _ in judged.values()]
            requirements = ", ".join(f"{verdicts.count(v)} {v}" for v in ("verified", "failed", "not judged")
                                     if verdicts.count(v) or v != "not judged")
            done = "Cancelled" if cancelled else "Finished"
            self.status.setText(f"{done} in {elapsed:.0f} s: {self._counts(running=False)}"
                                + (f" — requirements: {requirements}" if judged else ""))
            problem = self._problem(run, cancelled)
            self._say(problem[0], problem[1]) if problem else self._say("", None)
        self.last_report = Path(run.options.report)
        self.open_report_button.setEnabled(report)
        self.open_folder_button.setEnabled(self.last_report.is_dir())
        self.rerun_button.setEnabled(bool(self._to_rerun()))
        run.close()
        self._ended(cancelled)
        self.finished_run.emit(run)

    def _problem(self, run: RequirementRun, cancelled: bool) -> tuple[str, str] | None:
        """What a person must know beyond the table: the ECU lost, a run that stopped by itself."""
        rows = self.model.rows
        if self.ecu_lost:
            at = next(number for number, row in enumerate(rows) if row.get("ecu") == "lost")
            after = sum(1 for row in rows[at + 1:] if row["state"] == "error")
            text = f"The ECU stopped answering during {rows[at]['nodeid']} ({rows[at]['ecu_error']})"
            if after:
                text += f". The {after} test{'s' if after > 1 else ''} after it could not reach it"
            if self.on_ecu:
                text += ". The window stays disconnected: Connect (F9) once the ECU answers again"
            return text + ".", theme.BAD
        if cancelled:
            return "Cancelled: the report holds the tests that ended (the one cut short: INTERRUPTED).", theme.WARN
        if run.exit_code not in (0, 1):
            return f"The test run stopped (exit {run.exit_code}): {run.error() or 'see Output'}", theme.BAD
        if run.exit_code == 1 and not rows:
            return run.error() or "The test run failed before any test ran: see Output.", theme.BAD
        return None

    def _ended(self, cancelled: bool) -> None:
        on_ecu, lost = self.on_ecu, self.ecu_lost
        self.run = None
        self._set_busy(False)
        if cancelled and not self.model.rows:
            self.status.setText("Cancelled before the tests started.")
        if on_ecu:
            self._hold_window(False)
            self.window_.status.set_pause(None)
            if not lost:
                self.window_.connect_ecu()  # the window's own Connect: EPK check, cache sync, measuring
        self.on_ecu = False
        self.refresh_target()

    def _set_busy(self, busy: bool) -> None:
        self.buttons.set_busy(busy)
        if busy:
            self.open_report_button.setEnabled(False)
            self.open_folder_button.setEnabled(False)
            self.progress.setVisible(False)

    def _hold_window(self, hold: bool) -> None:
        """Modal while the tests use the window's ECU: nothing in the window connects to it meanwhile."""
        if self.isVisible():
            self.hide()
            self.setWindowModality(Qt.WindowModal if hold else Qt.NonModal)
            self.show()
        else:
            self.setWindowModality(Qt.WindowModal if hold else Qt.NonModal)

    def _say(self, text: str, colour: str | None) -> None:
        self.message.setText(text)
        self.message.setStyleSheet(f"color: {colour}; font-weight: 600;" if colour else "")
        self.message.setVisible(bool(text))

    # --- the report ---------------------------------------------------------------------------------

    def open_report(self, nodeid: str | None = None) -> None:
        """The last run's report.html in the browser (at the section of the test ``nodeid``)."""
        if self.run is not None or self.last_report is None or not (self.last_report / "report.html").is_file():
            return
        url = QUrl.fromLocalFile(str(self.last_report / "report.html"))
        if nodeid:
            url.setFragment(report_anchor(nodeid))
        QDesktopServices.openUrl(url)

    def open_folder(self) -> None:
        if self.last_report is not None:
            QDesktopServices.openUrl(QUrl.fromLocalFile(str(self.last_report)))

    # --- closing ------------------------------------------------------------------------------------

    def reject(self) -> None:
        if self.run is None:  # Close (and Escape) wait for the run's end: Cancel stops it
            super().reject()

    def stop(self) -> None:
        """End a run at once (the window closes: its closeEvent, once nothing keeps it open): its processes are
        stopped, nothing is reconnected."""
        self._timer.stop()
        run, self.run = self.run, None
        if run is not None:
            run.close()
            self.model.end(cancelled=True)
            self.on_ecu = False
            self._set_busy(False)

