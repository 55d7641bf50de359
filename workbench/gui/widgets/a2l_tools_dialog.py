"""The A2L tool chain in the window (Tools menu), as CANape users update the A2L after every build: update an
A2L from an ELF, check it, merge module fragments into a master, insert objects for the ELF's variables (into a
new A2L made from the ELF alone too, struct variables as INSTANCEs), remove objects with the references to them,
clean up what nothing uses, write /include'd text inline — what ``workbench a2l
update|check|merge|insert|remove|cleanup|flatten`` do (:mod:`workbench.gui.a2l_jobs`), with the CLI's options
(--dry-run where it has one), its summary line and its exit codes' meaning (an update with errors, a check with
warnings, a refused removal: failed).

The job runs in a worker with a progress bar and Cancel (the library stops at its next check point and writes
nothing); a refusal (a malformed A2L, a missing ELF: one line with file:line:column) is said in the dialog,
never as a traceback; the findings are listed problems first, the infos (every address updated ...) on
"show all" (a dry run shows them: what would change). A file written over the A2L the window holds says so and
offers to read it again."""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QComboBox,
    QDialog,
    QFileDialog,
    QFormLayout,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QListWidget,
    QProgressBar,
    QPushButton,
    QStyledItemDelegate,
    QTabBar,
    QTableView,
    QVBoxLayout,
    QWidget,
)

from workbench.errors import Cancelled, WorkbenchError
from workbench.findings import Severity
from workbench.gui import theme
from workbench.gui.a2l_jobs import (A2lOutcome, check_a2l, cleanup_a2l, flatten_a2l, insert_a2l, merge_a2l, remove_a2l,
                                    update_a2l)
from workbench.gui.models.rows import RowsModel
from workbench.gui.widgets.errors import show_error
from workbench.gui.widgets.job_buttons import JobButtons
from workbench.gui.widgets.names import NameDelegate
from workbench.gui.worker import Task

__all__ = ["A2lToolsDialog", "CHECK", "CLEANUP", "FLATTEN", "FindingsModel", "INSERT", "MERGE", "REMOVE", "UPDATE"]

UPDATE, CHECK, MERGE, INSERT = "update", "check", "merge", "insert"
REMOVE, CLEANUP, FLATTEN = "remove", "cleanup", "flatten"
_OPERATIONS = (UPDATE, CHECK, MERGE, INSERT, REMOVE, CLEANUP, FLATTEN)  # the tabs, in order
_TITLES = {UPDATE: "Update from ELF", CHECK: "Check", MERGE: "Merge fragments", INSERT: "Insert from ELF",
           REMOVE: "Remove objects", CLEANUP: "Clean up", FLATTEN: "Flatten includes"}
_RUN = {UPDATE: "Update", CHECK: "Check", MERGE: "Merge", INSERT: "Insert", REMOVE: "Remove", CLEANUP: "Clean up",
        FLATTEN: "Flatten"}  # the Run button's text
_DRY_RUN = (INSERT, REMOVE, CLEANUP)  # the operations with --dry-run
_FLATTEN_OUTPUT = "the file to write the flattened A2L to (not the A2L itself: its /include lines would be lost)"
_A2L_FILES = "A2L files (*.a2l *.A2L);;All files (*)"
_ELF_FILES = "ELF files (*.elf *.out *.axf);;All files (*)"
_SEVERITY_COLOUR = {Severity.ERROR: theme.BAD, Severity.WARNING: theme.WARN, Severity.INFO: theme.MUTED}


# --- the findings table -----------------------------------------------------------------------------------

class FindingsModel(RowsModel):
    """A report's findings, problems first (errors, then warnings, each in the report's order); the infos
    only when ``show_all``."""

    COLUMNS = ("severity", "file:line:column", "object", "message")

    def __init__(self, parent=None):
        super().__init__(parent)
        self.findings: list = []
        self.show_all = False

    def set_findings(self, findings, show_all: bool | None = None) -> None:
        self.findings = sorted(findings, key=lambda f: -f.severity)  # stable: the report's order within each
        if show_all is not None:
            self.show_all = show_all
        self.set_rows(f for f in self.findings if self.show_all or f.severity > Severity.INFO)

    def data(self, index, role=Qt.DisplayRole):
        if role not in (Qt.DisplayRole, Qt.ToolTipRole, Qt.ForegroundRole) or not index.isValid():
            return None
        finding, column = self.rows[index.row()], index.column()
        if role == Qt.ForegroundRole:
            return QColor(_SEVERITY_COLOUR[finding.severity]) if column == 0 else None
        if column == 0:
            return finding.severity.name.lower() if role == Qt.DisplayRole else finding.kind
        if column == 1:
            return finding.location
        if column == 2:
            return finding.name if role == Qt.DisplayRole else f"{finding.block} {finding.name}".strip()
        return finding.message


class _KeepEnd(QStyledItemDelegate):
    """A long ``file:line:column`` cut at its start: the file's name and the line stay."""

    def initStyleOption(self, option, index) -> None:
        super().initStyleOption(option, index)
        option.textElideMode = Qt.ElideLeft


# --- the dialog -------------------------------------------------------------------------------------------

class _PathField(QWidget):
    """A file name to type, or to pick with Browse…"""

    def __init__(self, title: str, filters: str, save: bool = False, placeholder: str = ""):
        super().__init__()
        self.title, self.filters, self.save = title, filters, save
        row = QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        self.edit = QLineEdit()
        self.edit.setPlaceholderText(placeholder)
        self.edit.textChanged.connect(self.edit.setToolTip)  # a long path whole, where the field shows part of it
        row.addWidget(self.edit, 1)
        browse = QPushButton("Browse…")
        browse.clicked.connect(self._browse)
        row.addWidget(browse)

    def text(self) -> str:
        return self.edit.text().strip()

    def setText(self, text) -> None:
        self.edit.setText(str(text) if text else "")

    def _browse(self) -> None:
        pick = QFileDialog.getSaveFileName if self.save else QFileDialog.getOpenFileName
        path, _ = pick(self, self.title, self.text(), self.filters)
        if path:
            self.setText(path)


def _boxes(*boxes: QCheckBox) -> QWidget:
    """Check boxes one below the other, as one row of the form (side by side, the Remove tab's two long ones made
    the dialog 1,168 px wide at least: more than a 1366 x 768 screen has beside the window's edge)."""
    row = QWidget()
    layout = QVBoxLayout(row)
    layout.setContentsMargins(0, 0, 0, 0)
    for box in boxes:
        layout.addWidget(box)
    return row


def _ranges(text: str) -> list[tuple[int, int]] | str:
    """``MIN MAX`` address pairs (0x hex allowed), ``;`` between pairs; a text: what is wrong."""
    ranges = []
    for pair in filter(None, (part.strip() for part in text.split(";"))):
        try:
            low, high = (int(value, 0) for value in pair.split())
        except ValueError:
            return f"address range {pair!r}: give MIN MAX, e.g. 0xFC0000 0xFE0000 (; between ranges)"
        if low < 0 or high < 0:
            return f"address range {pair!r}: an address is 0 or more"
        ranges.append((low, high))
    return ranges


def _choice(items: list[tuple[str, object]], tip: str) -> QComboBox:
    box = QComboBox()
    for text, value in items:
        box.addItem(text, value)
    box.setToolTip(tip)
    return box


class A2lToolsDialog(QDialog):
    """Update, check, merge, insert into, remove from, clean up or flatten A2L files; ``operation`` (UPDATE, CHECK,
    MERGE, INSERT, REMOVE, CLEANUP, FLATTEN) is the tab shown first.

    ``a2l``/``elf``: the files the fields start with (the project's); ``in_use``: the files of the A2L the window
    holds (its main file first, then those it includes), whose rewriting the dialog offers to read again
    (``reload_requested``)."""

    started = Signal(object)  # the Task, before it runs (to follow its progress)
    done = Signal(object)  # A2lOutcome
    refused = Signal(object)  # the exception: a refusal, a cancel, or a failure
    reload_requested = Signal()

    def __init__(self, operation: str = UPDATE, a2l: Path | None = None, elf: Path | None = None,
                 in_use=(), parent: QWidget | None = None):
        super().__init__(parent)
        self.in_use: list[Path] = []
        self.set_in_use(in_use)
        self.task: Task | None = None
        self.outcome: A2lOutcome | None = None
        self.setWindowTitle("A2L tools")
        self.resize(1080, 620)  # within a 1366 x 768 screen, beside the window's edge
        layout = QVBoxLayout(self)
        self.tabs = QTabBar()
        for operation_ in _OPERATIONS:
            self.tabs.addTab(_TITLES[operation_])
        self.tabs.currentChanged.connect(self._show_fields)
        layout.addWidget(self.tabs)
        layout.addLayout(self._fields(a2l, elf))
        self._result_area(layout)
        self.buttons = JobButtons(self, "Run", "Cancel", self.run, self.cancel,
                                  guarded=(self.tabs, *(widget for widget, _ in self.rows.values())))
        self.run_button, self.cancel_button, self.close_button = (self.buttons.run_button, self.buttons.cancel_button,
                                                                  self.buttons.close_button)
        layout.addLayout(self.buttons)
        self.set_operation(operation)
        self._show_result(None)

    def _fields(self, a2l: Path | None, elf: Path | None) -> QFormLayout:
        """The files and options, each row shown for the operations it serves."""
        from workbench.a2l.reports import ConflictPolicy, IncludeMode, UpdateMode

        self.form = QFormLayout()
        self.a2l = _PathField("A2L", _A2L_FILES)
        self.a2l.setText(a2l)
        self.elf = _PathField("ELF", _ELF_FILES)
        self.elf.setText(elf)
        self.output = _PathField("Write the A2L to", _A2L_FILES, save=True,
                                 placeholder="the A2L itself (replaced atomically)")
        self.master = _PathField("Master A2L", _A2L_FILES)
        self.fragments = QListWidget()
        self.fragments.setSelectionMode(QAbstractItemView.ExtendedSelection)
        self.fragments.setMaximumHeight(90)
        fragment_buttons = QVBoxLayout()
        add, remove = QPushButton("Add…"), QPushButton("Remove")
        add.clicked.connect(self._add_fragments)
        remove.clicked.connect(lambda: [self.fragments.takeItem(self.fragments.row(item))
                                        for item in self.fragments.selectedItems()])
        for button in (add, remove):
            fragment_buttons.addWidget(button)
        fragment_buttons.addStretch(1)
        fragments = QWidget()
        fragment_row = QHBoxLayout(fragments)
        fragment_row.setContentsMargins(0, 0, 0, 0)
        fragment_row.addWidget(self.fragments, 1)
        fragment_row.addLayout(fragment_buttons)
        self.types = QCheckBox("data types, sizes and limits (--types)")
        self.epk = QCheckBox("EPK (MOD_PAR EPK and ADDR_EPK)")
        self.epk.setChecked(True)
        self.missing = _choice([("keep (a warning)", UpdateMode.DEFAULT), ("remove (--remove-missing)",
                                UpdateMode.REMOVE_MISSING), ("refuse: write nothing (--strict)", UpdateMode.STRICT)],
                               "objects whose symbol is not in the ELF")
        self.missing.currentIndexChanged.connect(self._show_fields)
        self.update_drop_optional = QCheckBox("drop an INPUT_QUANTITY or COMPARISON_QUANTITY naming a removed "
                                              "object (--drop-optional-references)")
        self.update_drop_optional.setToolTip("with 'remove': the INPUT_QUANTITY becomes NO_INPUT_QUANTITY, the "
                                             "COMPARISON_QUANTITY goes (each a warning); without it such a reference "
                                             "refuses the update: nothing is written")
        self.includes = _choice([("keep /include, changes in them are errors", IncludeMode.KEEP),
                                 ("update the included files (--update-includes)", IncludeMode.UPDATE),
                                 ("write them inline (--merge-includes)", IncludeMode.MERGE)],
                                "what happens to the text of /include'd files")
        self.conflict = _choice([("fail, write nothing", ConflictPolicy.ERROR), ("keep the first (keep-first)",
                                 ConflictPolicy.KEEP_FIRST), ("keep the last (keep-last)", ConflictPolicy.KEEP_LAST),
                                 ("rename the later one NAME_<MODULE> (rename)", ConflictPolicy.RENAME)],
                                "two different definitions of one name (--on-conflict)")
        self.measured, self.calibrated, self.group = QLineEdit(), QLineEdit(), QLineEdit()
        self.measured.setPlaceholderText("a regular expression on whole names, e.g. zs.*|outer\\..* "
                                         "(--measurement-regex)")
        self.calibrated.setPlaceholderText("e.g. xs.*|zvLut (--characteristic-regex; a struct: its members)")
        self.group.setPlaceholderText("optional: a GROUP for the new objects, created if missing (--target-group)")
        self.create = QCheckBox("a new A2L from the ELF alone, no A2L read (--create)")
        self.create.setToolTip("ASAP2 1.71, PROJECT and MODULE named after the ELF, MOD_COMMON with its byte order, "
                               "MOD_PAR with its EPK")
        self.structures = QCheckBox("a struct selected whole: one INSTANCE of a TYPEDEF_STRUCTURE (--structures)")
        self.structures.setToolTip("typedefs per member type, shared by every variable of its C type (ASAP2 1.70+)")
        self._removal_fields()
        # one box, ticked per tab: a dry run chosen on one tab is not silently the next tab's
        self.dry_run = QCheckBox("show what would change, write nothing (--dry-run)")
        self._dry_runs: set[str] = set()  # the operations whose dry run is ticked
        self.dry_run.toggled.connect(self._dry_run_toggled)
        self.create.toggled.connect(self._show_fields)
        self.rows = {  # the operations each row serves
            "A2L": (self.a2l, (UPDATE, CHECK, INSERT, REMOVE, CLEANUP, FLATTEN)),
            "ELF": (self.elf, (UPDATE, CHECK, INSERT)),
            "master A2L": (self.master, (MERGE,)), "fragments": (fragments, (MERGE,)),
            "output": (self.output, (UPDATE, MERGE, INSERT, REMOVE, CLEANUP, FLATTEN)),
            "update": (_boxes(self.types, self.epk), (UPDATE,)),
            "insert": (_boxes(self.create, self.structures), (INSERT,)),
            "MEASUREMENTs for": (self.measured, (INSERT,)), "CHARACTERISTICs for": (self.calibrated, (INSERT,)),
            "target group": (self.group, (INSERT,)),
            "remove names": (self.removed, (REMOVE,)), "remove addresses": (self.removed_ranges, (REMOVE,)),
            "remove": (_boxes(self.cleanup_too, self.drop_optional), (REMOVE,)),
            "objects missing in the ELF": (self.missing, (UPDATE,)),
            "removed objects": (_boxes(self.update_drop_optional), (UPDATE,)),  # its box enabled with "remove"
            "includes": (self.includes, (UPDATE, REMOVE, CLEANUP)),
            "on conflict": (self.conflict, (MERGE,)), "dry run": (self.dry_run, _DRY_RUN),
        }
        for label, (widget, _) in self.rows.items():
            self.form.addRow(label, widget)
        return self.form

    def _removal_fields(self) -> None:
        """What ``workbench a2l remove`` takes out, and what becomes of the references to it."""
        self.removed, self.removed_ranges = QLineEdit(), QLineEdit()
        self.removed.setPlaceholderText("a regular expression on whole names, e.g. zsTank.*Filt|xsOld (--regex)")
        self.removed_ranges.setPlaceholderText("MIN MAX, e.g. 0x40020034 0x40020040 (; between ranges): the "
                                               "objects whose address lies in [MIN, MAX) (--range)")
        self.cleanup_too = QCheckBox("then clean up what nothing uses any more (--cleanup)")
        self.drop_optional = QCheckBox("drop an INPUT_QUANTITY or COMPARISON_QUANTITY naming a removed object "
                                       "(--drop-optional-references)")
        self.drop_optional.setToolTip("without it such a reference refuses the removal, as one a kept object needs "
                                      "(an AXIS_PTS_REF ...) always does: nothing is written")

    def _result_area(self, layout: QVBoxLayout) -> None:
        """Progress, the summary (or refusal), the reload offer, the findings and the current one whole."""
        self.progress = QProgressBar()
        self.progress.setFormat("%p %")
        layout.addWidget(self.progress)
        self.status = QLabel()  # the summary, a refusal, or what runs now
        self.status.setWordWrap(True)
        self.status.setTextInteractionFlags(Qt.TextSelectableByMouse)
        layout.addWidget(self.status)
        reload_row = QHBoxLayout()
        self.reload_note = QLabel()
        self.reload_note.setWordWrap(True)
        self.reload_button = QPushButton("Reload the project's A2L")
        self.reload_button.clicked.connect(self._reload)
        reload_row.addWidget(self.reload_note, 1)
        reload_row.addWidget(self.reload_button)
        layout.addLayout(reload_row)
        self.show_all = QCheckBox("show all (the infos too)")
        self.show_all.toggled.connect(lambda on: self.model.set_findings(self.model.findings, on))
        layout.addWidget(self.show_all)
        self.model = FindingsModel(self)
        self.table = QTableView()
        self.table.setModel(self.model)
        self.table.verticalHeader().hide()
        self.table.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.table.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.table.setWordWrap(False)
        self.table.setItemDelegateForColumn(1, _KeepEnd(self.table))
        self.table.setItemDelegateForColumn(2, NameDelegate(self.table))  # names keep their distinct ends
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.Interactive)
        header.setStretchLastSection(True)
        for column, width in enumerate((70, 300, 200)):
            header.resizeSection(column, width)
        layout.addWidget(self.table, 1)
        self.detail = QLabel()  # the current finding whole, as the CLI prints it (the table cuts long messages)
        self.detail.setWordWrap(True)
        self.detail.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.detail.setFont(theme.mono_font(9))
        self.table.selectionModel().currentRowChanged.connect(self._show_detail)
        layout.addWidget(self.detail)

    # --- the fields -----------------------------------------------------------------------------

    def set_in_use(self, paths) -> None:
        """The files of the A2L the window holds now (another project opened): a rewriting of those is offered."""
        self.in_use = list(dict.fromkeys(Path(path).resolve() for path in paths))

    @property
    def operation(self) -> str:
        return _OPERATIONS[self.tabs.currentIndex()]

    def set_operation(self, operation: str) -> None:
        self.tabs.setCurrentIndex(_OPERATIONS.index(operation))
        self._show_fields()

    def _creating(self) -> bool:
        return self.operation == INSERT and self.create.isChecked()

    def _dry(self) -> bool:
        return self.operation in self._dry_runs

    def _dry_run_toggled(self, on: bool) -> None:
        (self._dry_runs.add if on else self._dry_runs.discard)(self.operation)
        self._show_fields()

    def _dropping_optional(self) -> bool | None:
        """The update's --drop-optional-references; None: not asked (it goes with --remove-missing only)."""
        from workbench.a2l.reports import UpdateMode

        return self.update_drop_optional.isChecked() if self.missing.currentData() is UpdateMode.REMOVE_MISSING \
            else None

    def _show_fields(self, *_) -> None:
        operation = self.operation
        self.dry_run.setChecked(self._dry())  # this tab's own (toggled: shows the fields again, the same)
        self.update_drop_optional.setEnabled(self._dropping_optional() is not None)
        for widget, operations in self.rows.values():
            self.form.setRowVisible(widget, operation in operations)
        self.form.setRowVisible(self.a2l, operation in self.rows["A2L"][1] and not self._creating())
        self.form.setRowVisible(self.output, operation in self.rows["output"][1] and not self._dry())
        self.elf.edit.setPlaceholderText("optional: symbols and addresses against it" if operation == CHECK
                                         else "the ELF the build linked")
        self.output.edit.setPlaceholderText("the merged A2L to write" if operation == MERGE else "the new A2L to write"
                                            if self._creating() else _FLATTEN_OUTPUT if operation == FLATTEN
                                            else "the A2L itself (replaced atomically)")
        self.includes.setItemText(0, "keep /include, changes in them are errors" if operation == UPDATE else
                                  "keep /include, a removal in them refuses (nothing written)")
        run = "Create" if self._creating() else _RUN[operation]
        self.run_button.setText(f"{run} (dry run)" if self._dry() else run)

    def fragment_paths(self) -> list[str]:
        return [self.fragments.item(row).text() for row in range(self.fragments.count())]

    def set_fragments(self, paths) -> None:
        self.fragments.clear()
        self.fragments.addItems([str(p) for p in paths])

    def _add_fragments(self) -> None:
        paths, _ = QFileDialog.getOpenFileNames(self, "A2L fragments", self.master.text(), _A2L_FILES)
        self.fragments.addItems([p for p in paths if p not in self.fragment_paths()])

    def _job(self) -> tuple | str:
        """The job the fields ask for, as (function, args, kwargs); a text: what is missing."""
        operation = self.operation
        if operation == MERGE:
            if not self.master.text() or not self.fragment_paths() or not self.output.text():
                return "choose the master A2L, at least one fragment and the output"
            return merge_a2l, (self.master.text(), self.fragment_paths(), self.output.text()), {
                "policy": self.conflict.currentData()}
        a2l = None if self._creating() else self.a2l.text()
        if a2l == "":
            return "choose the A2L"
        if a2l is None and not self.output.text() and not self._dry():
            return "choose where to write the new A2L (or a dry run)"
        output = None if self._dry() else self.output.text() or a2l  # no output named: the A2L itself
        if operation == CHECK:
            return check_a2l, (a2l, self.elf.text() or None), {}
        if operation in (REMOVE, CLEANUP, FLATTEN):
            return self._pruning_job(a2l, output)
        if not self.elf.text():
            return "choose the ELF the build linked"
        if operation == INSERT:
            if not self.measured.text().strip() and not self.calibrated.text().strip():
                return "give a pattern for the MEASUREMENTs or the CHARACTERISTICs to insert"
            return insert_a2l, (a2l, self.elf.text(), output), {
                "measurements": self.measured.text().strip(), "characteristics": self.calibrated.text().strip(),
                "group": self.group.text().strip(), "structures": self.structures.isChecked()}
        return update_a2l, (a2l, self.elf.text(), output), {
            "mode": self.missing.currentData(), "types": self.types.isChecked(), "epk": self.epk.isChecked(),
            "includes": self.includes.currentData(),
            "drop_optional": bool(self._dropping_optional())}

    def _pruning_job(self, a2l: str, output: str | None) -> tuple | str:
        """Remove, clean up or flatten ``a2l`` into ``output`` (None: a dry run)."""
        if self.operation == FLATTEN:  # as the CLI's -o, required: the file itself would lose its /include lines
            return (flatten_a2l, (a2l, output), {}) if self.output.text() else f"choose {_FLATTEN_OUTPUT}"
        if self.operation == CLEANUP:
            return cleanup_a2l, (a2l, output), {"includes": self.includes.currentData()}
        pattern, ranges = self.removed.text().strip(), _ranges(self.removed_ranges.text())
        if isinstance(ranges, str):
            return ranges
        if not pattern and not ranges:
            return "give a pattern for the names or an address range of the objects to remove"
        return remove_a2l, (a2l, output), {
            "regexes": (pattern,) if pattern else (), "ranges": tuple(ranges), "cleanup": self.cleanup_too.isChecked(),
            "drop_optional": self.drop_optional.isChecked(), "includes": self.includes.currentData()}

    # --- running --------------------------------------------------------------------------------

    def run(self) -> Task | None:
        """Start the job the fields describe (in a worker); None when a field is missing (the dialog says which)."""
        if self.task is not None:
            return None
        job = self._job()
        self._show_result(None)
        if isinstance(job, str):
            self._say(job, theme.BAD)
            return None
        function, args, kwargs = job
        self.task = Task(function, *args, progress=True, **kwargs)
        self.buttons.follow(self.task, self._progressed, self._done, self._failed, self._finished)
        self._say(f"{_TITLES[self.operation].lower()} …", theme.MUTED)
        self.started.emit(self.task)
        return self.task.start()

    def cancel(self) -> None:
        if self.task is not None:
            self.task.cancel()
            self._say("cancelling at the next check point …", theme.MUTED)

    def _progressed(self, done: int, total: int, label: str) -> None:
        self.progress.setMaximum(max(total, 1))
        self.progress.setValue(done)
        if label and not (self.task is not None and self.task.progress.cancelled):  # "cancelling …" stays
            self._say(label, theme.MUTED)

    def _done(self, outcome: A2lOutcome) -> None:
        self.progress.setValue(self.progress.maximum())
        if outcome.written is None and outcome.ok and self._dry():
            self.show_all.setChecked(True)  # what would change: the infos
        self._show_result(outcome)
        self.done.emit(outcome)

    def _failed(self, exc: BaseException) -> None:
        self.progress.setValue(0)
        if isinstance(exc, Cancelled):
            self._say("cancelled: nothing written", theme.BAD)
        elif isinstance(exc, WorkbenchError):  # a refusal: a malformed A2L, a missing ELF, an unwritable output
            self._say(f"⚠ {exc}", theme.BAD)
        else:  # not ours: a bug, shown as the window shows one (its traceback in the details)
            self._say(f"failed: unexpected {type(exc).__name__}: {exc}", theme.BAD)
            show_error(self, exc, "A2L tools")
        self.refused.emit(exc)

    def _finished(self) -> None:
        self.task = None

    # --- the result -----------------------------------------------------------------------------

    def _say(self, text: str, colour: str) -> None:
        self.status.setText(text)
        self.status.setStyleSheet(f"color: {colour};")

    def _show_result(self, outcome: A2lOutcome | None) -> None:
        self.outcome = outcome
        findings = outcome.report.findings if outcome is not None else []
        self.model.set_findings(findings)
        self._fit_columns()  # to the problems shown first, not again for "show all" (they are the widest)
        infos = sum(1 for f in findings if f.severity == Severity.INFO)
        self.show_all.setText(f"show all (the {infos} infos too)" if infos else "show all (the infos too)")
        self.show_all.setEnabled(bool(infos))
        if outcome is not None:
            self._say(("done: " if outcome.ok else "failed: ") + outcome.summary, theme.GOOD if outcome.ok
                      else theme.BAD)
        written = {path.resolve() for path in outcome.files_written()} if outcome is not None else set()
        rewritten = [path for path in self.in_use if path in written]
        if rewritten:
            uses = (f"uses {self.in_use[0].name}" if rewritten[0] == self.in_use[0] else
                    f"uses {self.in_use[0].name}, which includes {', '.join(path.name for path in rewritten)}")
            self.reload_note.setText(f"The open project {uses}: the window (and a connection) still hold it as it "
                                     "was read before.")
        self.reload_note.setVisible(bool(rewritten))
        self.reload_button.setVisible(bool(rewritten))

    def _fit_columns(self) -> None:
        """Place and name as wide as they are (up to a third and a quarter of the table); the message takes the rest.
        The first finding is the current one (shown whole below)."""
        if not self.model.rowCount():
            self.detail.setText("no warnings, no errors" if self.outcome is not None else "")
            return
        for column in (1, 2):
            self.table.resizeColumnToContents(column)
            self.table.setColumnWidth(column, min(self.table.columnWidth(column), self.table.width() // (column + 2)))
        self.table.setCurrentIndex(self.model.index(0, 0))

    def _show_detail(self, current, _previous=None) -> None:
        self.detail.setText(str(self.model.rows[current.row()]) if current.isValid() else "")

    def _reload(self) -> None:
        self.reload_requested.emit()
        self.reload_note.setText("reloading the project's A2L (a connection is made again) …")
        self.reload_button.hide()

    def reject(self) -> None:
        """Close, unless a job runs: it is cancelled first (Cancel), never left writing behind a closed dialog."""
        if self.task is None:
            super().reject()
        else:
            self._say("still running: Cancel stops it (nothing is written), then Close", theme.WARN)
