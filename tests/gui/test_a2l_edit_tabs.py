"""The A2L tools dialog's Remove, Clean up and Flatten tabs and the Insert tab's --create/--structures: `workbench
a2l remove|cleanup|flatten|insert` from the window, the fields filled as a user fills them, on copies of the demo's
files; the same bytes as the CLI, a refusal's references at file:line:column, a dry run that writes nothing."""

from __future__ import annotations

import shutil

import pytest
from gui_helpers import WAIT_MS, hold_a2l_tools_job
from gui_helpers import run_a2l_tools as _run

from workbench import demo
from workbench.a2l import load_a2l
from workbench.cli import main
from workbench.errors import Cancelled
from workbench.gui.widgets.a2l_tools_dialog import (CHECK, CLEANUP, FLATTEN, INSERT, MERGE, REMOVE, UPDATE,
                                                     A2lToolsDialog)


@pytest.fixture(autouse=True)
def own_elf_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path / "cache"))


@pytest.fixture
def source(tmp_path):
    path = tmp_path / "FLCU.a2l"
    shutil.copy(demo.a2l(), path)
    return path


def _dialog(qtbot, operation, a2l=None, elf=None, in_use=()):
    dialog = A2lToolsDialog(operation, a2l, elf, in_use)
    qtbot.addWidget(dialog)
    dialog.show()
    return dialog


def _shown(dialog) -> list[str]:
    form = dialog.form
    return [form.itemAt(row, form.ItemRole.LabelRole).widget().text() for row in range(form.rowCount())
            if form.isRowVisible(row)]


def _rows(dialog) -> list[tuple[str, ...]]:
    return [tuple(dialog.model.index(row, column).data() for column in range(4))
            for row in range(dialog.model.rowCount())]


def test_each_tab_shows_its_own_fields(qtbot, source):
    dialog = _dialog(qtbot, REMOVE, source)
    assert _shown(dialog) == ["A2L", "output", "remove names", "remove addresses", "remove", "includes", "dry run"]
    dialog.dry_run.setChecked(True)  # nothing written: no output
    assert "output" not in _shown(dialog) and dialog.run_button.text() == "Remove (dry run)"
    dialog.set_operation(FLATTEN)  # no --dry-run in `a2l flatten`
    assert _shown(dialog) == ["A2L", "output"] and dialog.run_button.text() == "Flatten"
    dialog.set_operation(CLEANUP)  # its own dry run, not ticked
    assert _shown(dialog) == ["A2L", "output", "includes", "dry run"]
    dialog.set_operation(INSERT)
    dialog.create.setChecked(True)  # no A2L read
    assert _shown(dialog)[:4] == ["ELF", "output", "insert", "MEASUREMENTs for"]
    dialog.dry_run.setChecked(True)
    assert dialog.run_button.text() == "Create (dry run)" and "output" not in _shown(dialog)


def test_every_tab_fits_a_1366_x_768_screen_and_a_long_path_is_whole_in_its_tooltip(qtbot):
    path = "/projects/hds9/" + "calibration-release-candidates/" * 12 + "FLCU.a2l"  # ~1,200 px written whole
    dialog = _dialog(qtbot, REMOVE, path)
    widths = {}
    for operation in (UPDATE, CHECK, MERGE, INSERT, REMOVE, CLEANUP, FLATTEN):
        dialog.set_operation(operation)
        widths[operation] = dialog.minimumSizeHint().width()
    # no tab wider than the dialog opens (1080 px: on 1366 x 768 beside the window's edge); Remove's check boxes
    # side by side wanted 1,168 px at least
    assert max(widths.values()) <= 1080, widths
    assert dialog.a2l.edit.toolTip() == path


def test_remove_by_pattern_writes_what_the_cli_writes_after_a_dry_run_that_writes_nothing(qtbot, tmp_path, source,
                                                                                          capsys):
    cli_out = tmp_path / "cli.a2l"
    assert main(["a2l", "remove", str(source), "-R", "zsTank.*Filt", "--range", "0x40020034", "0x40020035", "-o",
                 str(cli_out)]) == 0
    cli_summary = capsys.readouterr().err.strip().splitlines()[-1]
    before = source.read_bytes()
    dialog = _dialog(qtbot, REMOVE, source, in_use=[source])  # the window's A2L
    assert dialog.run() is None and dialog.status.text().startswith("give a pattern")
    dialog.removed_ranges.setText("0x10")
    assert dialog.run() is None and dialog.status.text().startswith("address range '0x10': give MIN MAX")
    dialog.removed_ranges.setText("")
    dialog.removed.setText("zsTank.*Filt")
    dialog.dry_run.setChecked(True)
    outcome = _run(dialog, qtbot)
    assert outcome.ok and outcome.written is None and source.read_bytes() == before
    assert dialog.status.text() == "done: would remove 2 MEASUREMENT (2 reference(s) with them); nothing written " \
                                   "(dry run)"
    assert {row[2] for row in _rows(dialog)} == {"zsTank1VoltFilt", "zsTank2VoltFilt"}  # shown: what would go
    assert not dialog.reload_button.isVisibleTo(dialog)
    dialog.dry_run.setChecked(False)  # no output named: the A2L itself
    dialog.removed_ranges.setText("0x40020034 0x40020035")
    outcome = _run(dialog, qtbot)
    assert outcome.ok and outcome.written == source and source.read_bytes() == cli_out.read_bytes()
    assert outcome.summary == cli_summary.replace(str(cli_out), str(source))
    assert dialog.reload_button.isVisibleTo(dialog)  # written over the A2L the window holds: read it again?
    assert "zsTank1VoltFilt" not in load_a2l(source).model().names("MEASUREMENT")


def test_a_removal_a_kept_object_needs_is_refused_with_the_reference_at_its_place(qtbot, tmp_path, source):
    dialog = _dialog(qtbot, REMOVE, source)
    dialog.removed.setText("xaPRV_FF_.*")
    dialog.output.setText(tmp_path / "out.a2l")
    outcome = _run(dialog, qtbot)
    assert not outcome.ok and outcome.files_written() == [] and not (tmp_path / "out.a2l").exists()
    assert dialog.status.text().startswith("failed: remove: 2 problem(s), nothing written: xaPRV_FF_TARGET")
    line = source.read_text().splitlines().index("        AXIS_PTS_REF xaPRV_FF_TARGET") + 1
    severity, where, _, message = _rows(dialog)[0]
    assert (severity, where) == ("error", f"{source}:{line}:22")
    assert message.startswith("CHARACTERISTIC xvPRV_DC_FF AXIS_DESCR: AXIS_PTS_REF xaPRV_FF_TARGET would name a "
                              "removed object")


def test_cleanup_and_flatten_write_what_the_cli_writes(qtbot, tmp_path, source, capsys):
    assert main(["a2l", "cleanup", str(source), "-o", str(tmp_path / "cli.a2l")]) == 0
    capsys.readouterr()
    dialog = _dialog(qtbot, CLEANUP, source)
    dialog.output.setText(tmp_path / "gui.a2l")
    outcome = _run(dialog, qtbot)
    assert outcome.ok and (tmp_path / "gui.a2l").read_bytes() == (tmp_path / "cli.a2l").read_bytes()
    assert len(outcome.report.removed["RECORD_LAYOUT"]) == 7 and dialog.status.text().startswith("done: wrote")
    master = tmp_path / "master" / demo.master_a2l().name  # it includes XCP.aml beside it
    shutil.copytree(demo.master_a2l().parent, master.parent, ignore=shutil.ignore_patterns("modules"))
    dialog.set_operation(FLATTEN)
    dialog.a2l.setText(master)
    dialog.output.setText("")  # required, as the CLI's -o: flattening the A2L itself loses its /include lines
    assert dialog.run() is None and dialog.status.text().startswith("choose the file to write the flattened A2L to")
    assert '/include "XCP.aml"' in master.read_text()
    dialog.output.setText(master)  # in place when asked for
    outcome = _run(dialog, qtbot)
    assert outcome.ok and outcome.written == master
    assert dialog.status.text() == f"done: wrote {master}: 1 /include(s) written inline"
    assert '/include "XCP.aml"' not in master.read_text() and "struct Protocol_Layer" in master.read_text()


def test_insert_creates_a_new_a2l_from_the_elf_with_structures(qtbot, tmp_path, source):
    new = tmp_path / "new.a2l"
    dialog = _dialog(qtbot, INSERT, source, demo.elf())
    dialog.create.setChecked(True)
    dialog.calibrated.setText("zv.*")
    assert dialog.run() is None and dialog.status.text().startswith("choose where to write the new A2L")
    dialog.output.setText(new)
    dialog.structures.setChecked(True)
    outcome = _run(dialog, qtbot)
    assert outcome.ok and outcome.written == new and dialog.status.text() == f"done: wrote {new}: 2 INSTANCE inserted"
    model = load_a2l(new).model()
    assert model.names("INSTANCE") == ["zvTankPConv", "zvRailPConv"]
    assert model.characteristic("zvRailPConv.Table").address > 0  # a member of the INSTANCE, as the ELF places it
    dialog.create.setChecked(False)  # into the demo A2L, which describes its LUTs already
    dialog.calibrated.setText("zvRailPConv")
    dialog.dry_run.setChecked(True)
    before = source.read_bytes()
    outcome = _run(dialog, qtbot)
    assert outcome.ok and outcome.written is None and source.read_bytes() == before
    assert dialog.status.text().endswith("; nothing written (dry run)")


def test_each_tab_has_its_own_dry_run(qtbot, tmp_path, source):
    """A dry run ticked on Remove is not Clean up's: that tab writes unless its own box is ticked."""
    dialog = _dialog(qtbot, REMOVE, source)
    dialog.dry_run.setChecked(True)
    dialog.set_operation(CLEANUP)
    assert not dialog.dry_run.isChecked() and "output" in _shown(dialog) and dialog.run_button.text() == "Clean up"
    dialog.output.setText(tmp_path / "out.a2l")
    assert _run(dialog, qtbot).written == tmp_path / "out.a2l"
    dialog.set_operation(INSERT)
    assert not dialog.dry_run.isChecked() and dialog.run_button.text() == "Insert"
    dialog.set_operation(REMOVE)  # its own still ticked
    assert dialog.dry_run.isChecked() and dialog.run_button.text() == "Remove (dry run)"


@pytest.mark.parametrize(("operation", "at"), [(REMOVE, "settling the references to them"),
                                                (CLEANUP, "finding what nothing uses"), (FLATTEN, "writing")])
def test_cancel_stops_remove_cleanup_and_flatten_mid_job_and_nothing_is_written(qtbot, tmp_path, source, operation,
                                                                                 at):
    dialog = _dialog(qtbot, operation, source)
    dialog.removed.setText("zsTank.*Filt")
    dialog.output.setText(tmp_path / "out.a2l")
    reached, go_on = hold_a2l_tools_job(dialog, at)  # a check point after the A2L was read
    with qtbot.waitSignal(dialog.refused, timeout=WAIT_MS) as refused:
        dialog.run()
        qtbot.waitUntil(reached.is_set, timeout=WAIT_MS)
        dialog.cancel_button.click()
        go_on.set()
    assert isinstance(refused.args[0], Cancelled) and not (tmp_path / "out.a2l").exists()
    qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
    assert dialog.status.text() == "cancelled: nothing written"
