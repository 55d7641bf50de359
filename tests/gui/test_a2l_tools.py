"""The A2L tools from the window (Tools menu): update from the ELF as `workbench a2l update` does, check with
findings at file:line:column, merge; refusals in one line, Cancel, and the offer to read the project's A2L
again after it was rewritten."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from gui_helpers import WAIT_MS, hold_a2l_tools_job, offline_window
from gui_helpers import run_a2l_tools as _run

from workbench import demo
from workbench.a2l.reports import IncludeMode, UpdateMode
from workbench.cli import main
from workbench.errors import Cancelled, InputError
from workbench.gui.widgets.a2l_tools_dialog import CHECK, MERGE, REMOVE, UPDATE, A2lToolsDialog


@pytest.fixture(autouse=True)
def own_elf_cache(tmp_path, monkeypatch):
    """The ELF index cache of the test's own (the dialog uses the user's, as the CLI does by default)."""
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path / "cache"))


@pytest.fixture
def placeholder_a2l(tmp_path):
    """The demo's A2L as a build's A2L is before its update: every ECU_ADDRESS 0, another EPK."""
    text = demo.a2l().read_text(encoding="utf-8")
    text, count = re.subn(r"ECU_ADDRESS 0x[0-9A-Fa-f]+", "ECU_ADDRESS 0x00000000", text)
    assert count > 50
    text = text.replace('EPK "10300020250301"', 'EPK "00000000000000"')
    path = tmp_path / "build" / "FLCU.a2l"
    path.parent.mkdir()
    path.write_text(text, encoding="utf-8")
    return path


def _measurement(text: str, name: str) -> tuple[int, int]:
    """Where the demo A2L's MEASUREMENT ``name`` starts and ends in ``text``."""
    start = text.index(f"    /begin MEASUREMENT\n      /* Name                   */ {name}")
    return start, text.index("/end MEASUREMENT", start) + len("/end MEASUREMENT")


def _window_on(qtbot, a2l):
    """The window offline on the demo project with ``a2l`` as its A2L."""
    from workbench.gui.project import demo_project

    project = demo_project()
    project.a2l = a2l
    return offline_window(qtbot, project)


@pytest.fixture
def including_a2l(placeholder_a2l):
    """The placeholder A2L with one MEASUREMENT (xsOTV1Cmd) in a file it includes, part.a2l."""
    text = placeholder_a2l.read_text(encoding="utf-8")
    start, end = _measurement(text, "xsOTV1Cmd")
    (placeholder_a2l.parent / "part.a2l").write_text(text[start:end] + "\n", encoding="utf-8")
    placeholder_a2l.write_text(text[:start] + '    /include "part.a2l"' + text[end:], encoding="utf-8")
    return placeholder_a2l


@pytest.fixture
def dialog(qtbot):
    dialog = A2lToolsDialog(UPDATE)
    qtbot.addWidget(dialog)
    dialog.show()
    return dialog


def _rows(dialog) -> list[tuple[str, ...]]:
    model = dialog.model
    return [tuple(model.index(row, column).data() for column in range(model.columnCount()))
            for row in range(model.rowCount())]


def test_an_update_writes_the_bytes_the_cli_writes_and_says_its_summary(dialog, qtbot, tmp_path, placeholder_a2l,
                                                                        capsys):
    cli_out = tmp_path / "cli.a2l"
    assert main(["a2l", "update", str(placeholder_a2l), str(demo.elf()), "-o", str(cli_out)]) == 0
    cli_summary = capsys.readouterr().err.strip().splitlines()[-1]
    gui_out = tmp_path / "gui.a2l"
    dialog.a2l.setText(placeholder_a2l)
    dialog.elf.setText(demo.elf())
    dialog.output.setText(gui_out)
    outcome = _run(dialog, qtbot)
    assert gui_out.read_bytes() == cli_out.read_bytes() != placeholder_a2l.read_bytes()
    assert outcome.ok and outcome.summary == cli_summary.replace(str(cli_out), str(gui_out))
    assert dialog.status.text() == f"done: {outcome.summary}"
    assert dialog.progress.value() == dialog.progress.maximum()
    # the infos (every address updated) only on "show all"; the problems (none here) first
    assert dialog.model.rowCount() == len(outcome.report.problems) == 0
    assert dialog.detail.text() == "no warnings, no errors"
    dialog.show_all.setChecked(True)
    rows = _rows(dialog)
    assert len(rows) == len(outcome.report.findings) > 80
    assert any(row[0] == "info" and row[1].startswith(f"{placeholder_a2l}:") and "xsOTV1Cmd" in row[2]
               for row in rows)
    assert not dialog.reload_button.isVisibleTo(dialog)  # not the window's A2L


def test_an_update_in_place_with_the_cli_options(dialog, qtbot, tmp_path, placeholder_a2l, capsys):
    copy = tmp_path / "cli.a2l"
    shutil.copy(placeholder_a2l, copy)
    assert main(["a2l", "update", str(copy), str(demo.elf()), "-o", str(copy), "--types", "--no-epk",
                 "--remove-missing"]) == 0
    capsys.readouterr()
    dialog.a2l.setText(placeholder_a2l)  # no output: the A2L itself
    dialog.elf.setText(demo.elf())
    dialog.types.setChecked(True)
    dialog.epk.setChecked(False)
    dialog.missing.setCurrentIndex(dialog.missing.findText("remove (--remove-missing)"))
    outcome = _run(dialog, qtbot)
    assert outcome.written == placeholder_a2l and placeholder_a2l.read_bytes() == copy.read_bytes()
    assert b'EPK "00000000000000"' in copy.read_bytes()  # the EPK left alone


def test_an_update_with_errors_is_a_failure_as_in_the_cli(dialog, qtbot, tmp_path, including_a2l, capsys):
    """A change in an included file that the update may not write (includes kept): an error, the output written."""
    placeholder_a2l = including_a2l
    assert main(["a2l", "update", str(placeholder_a2l), str(demo.elf()), "-o", str(tmp_path / "cli.a2l")]) == 1
    capsys.readouterr()
    dialog.a2l.setText(placeholder_a2l)
    dialog.elf.setText(demo.elf())
    dialog.output.setText(tmp_path / "gui.a2l")
    outcome = _run(dialog, qtbot)
    assert not outcome.ok and outcome.written == tmp_path / "gui.a2l"
    assert (tmp_path / "gui.a2l").read_bytes() == (tmp_path / "cli.a2l").read_bytes()
    assert dialog.status.text() == f"failed: {outcome.summary}"
    rows = _rows(dialog)
    assert rows[0][0] == "error" and rows[0][1].startswith(str(placeholder_a2l.parent / "part.a2l"))
    dialog.includes.setCurrentIndex(dialog.includes.findData(IncludeMode.UPDATE))  # --update-includes
    outcome = _run(dialog, qtbot)
    assert outcome.ok and "ECU_ADDRESS 0x40020090" in (placeholder_a2l.parent / "part.a2l").read_text()
    assert outcome.includes_written == (placeholder_a2l.parent / "part.a2l",)


def test_a_strict_update_refuses_an_object_missing_in_the_elf_and_writes_nothing(dialog, qtbot, tmp_path,
                                                                                 placeholder_a2l, capsys):
    text = placeholder_a2l.read_text(encoding="utf-8")
    start, end = _measurement(text, "xsOTV1Cmd")
    placeholder_a2l.write_text(text[:end] + "\n" + text[start:end].replace("xsOTV1Cmd", "xsNotInTheElf") + text[end:],
                               encoding="utf-8")
    before = placeholder_a2l.read_bytes()
    assert main(["a2l", "update", str(placeholder_a2l), str(demo.elf()), "-o", str(placeholder_a2l), "--strict"]) == 1
    cli_summary = capsys.readouterr().err.strip().splitlines()[-1]
    dialog.a2l.setText(placeholder_a2l)  # in place: the A2L itself would be replaced
    dialog.elf.setText(demo.elf())
    dialog.missing.setCurrentIndex(dialog.missing.findText("refuse: write nothing (--strict)"))
    outcome = _run(dialog, qtbot)
    assert not outcome.ok and outcome.written is None and outcome.files_written() == []
    assert outcome.summary == cli_summary and cli_summary.endswith("; nothing written")
    assert "xsNotInTheElf" in outcome.summary and placeholder_a2l.read_bytes() == before
    assert dialog.status.text() == f"failed: {outcome.summary}"
    rows = _rows(dialog)
    assert rows[0][0] == "error" and rows[0][1].startswith(f"{placeholder_a2l}:") and rows[0][2] == "xsNotInTheElf"
    assert not dialog.reload_button.isVisibleTo(dialog)


def test_a_check_of_a_malformed_file_lists_its_finding_at_file_line_column(dialog, qtbot, tmp_path):
    bad = tmp_path / "bad.a2l"
    bad.write_text('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n /begin MODULE M ""\n'
                   '  /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x10\n'
                   '  /begin COMPU_METHOD CM "" LINEAR "%5.2" "" /end COMPU_METHOD\n'
                   '  /end MEASUREMENT\n /end MODULE\n/end PROJECT\n', encoding="utf-8")
    dialog.set_operation(CHECK)
    dialog.a2l.setText(bad)
    dialog.elf.setText("")
    outcome = _run(dialog, qtbot)
    assert not outcome.ok and outcome.summary == f"{bad}: {len(outcome.report.problems)} problem(s)"
    assert dialog.status.text().startswith("failed: ")
    rows = _rows(dialog)
    assert rows and rows[0][0] == "error"
    assert any(re.fullmatch(re.escape(str(bad)) + r":\d+:\d+", row[1]) for row in rows), rows
    problem = outcome.report.problems[0]
    assert rows[0][1] == f"{bad}:{problem.line}:{problem.column}" and rows[0][3] == problem.message
    assert dialog.detail.text() == str(problem)  # the first problem whole, as the CLI prints it


def test_a_refused_update_says_one_line_and_writes_nothing(dialog, qtbot, tmp_path, placeholder_a2l):
    output = tmp_path / "out.a2l"
    dialog.a2l.setText(placeholder_a2l)
    dialog.elf.setText(tmp_path / "missing.elf")
    dialog.output.setText(output)
    with qtbot.waitSignal(dialog.refused, timeout=WAIT_MS) as refused:
        dialog.run()
    qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
    assert isinstance(refused.args[0], InputError)
    assert dialog.status.text() == f"⚠ {tmp_path / 'missing.elf'}: no such file"
    assert "\n" not in dialog.status.text() and dialog.model.rowCount() == 0 and not output.exists()
    # a malformed A2L: its file:line:column
    bad = tmp_path / "bad.a2l"
    bad.write_text('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n', encoding="utf-8")
    dialog.a2l.setText(bad)
    dialog.elf.setText(demo.elf())
    with qtbot.waitSignal(dialog.refused, timeout=WAIT_MS):
        dialog.run()
    assert dialog.status.text() == f"⚠ {bad}:2:1: /begin PROJECT is never closed (missing /end PROJECT)"
    assert not output.exists()
    qtbot.waitUntil(lambda: dialog.run_button.isEnabled(), timeout=WAIT_MS)
    dialog.elf.setText("")  # a field missing: said, nothing started
    assert dialog.run() is None and dialog.status.text() == "choose the ELF the build linked"


def test_cancel_stops_a_running_update_and_nothing_is_written(dialog, qtbot, tmp_path, placeholder_a2l):
    output = tmp_path / "out.a2l"
    dialog.a2l.setText(placeholder_a2l)
    dialog.elf.setText(demo.elf())
    dialog.output.setText(output)
    reached, go_on = hold_a2l_tools_job(dialog)  # at its first report until the test has pressed Cancel
    with qtbot.waitSignal(dialog.refused, timeout=WAIT_MS) as refused:
        dialog.run()
        qtbot.waitUntil(reached.is_set, timeout=WAIT_MS)
        assert dialog.cancel_button.isEnabled() and not dialog.run_button.isEnabled()
        dialog.close_button.click()  # not while it runs (disabled), nor Escape: said, the dialog stays
        dialog.reject()
        assert dialog.isVisible() and dialog.status.text().startswith("still running: Cancel stops it")
        dialog.cancel_button.click()
        go_on.set()
    assert isinstance(refused.args[0], Cancelled)
    qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
    assert dialog.status.text() == "cancelled: nothing written" and not output.exists()
    assert dialog.run_button.isEnabled() and not dialog.cancel_button.isEnabled()


def test_a_merge_of_the_demo_fragments_writes_what_the_cli_writes(dialog, qtbot, tmp_path, capsys):
    cli_out = tmp_path / "cli.a2l"
    fragments = [str(p) for p in demo.fragment_a2ls()]
    assert main(["a2l", "merge", str(demo.master_a2l()), *fragments, "-o", str(cli_out)]) == 0
    capsys.readouterr()
    dialog.set_operation(MERGE)
    dialog.master.setText(demo.master_a2l())
    dialog.set_fragments(fragments)
    dialog.output.setText(tmp_path / "gui.a2l")
    outcome = _run(dialog, qtbot)
    assert outcome.ok and (tmp_path / "gui.a2l").read_bytes() == cli_out.read_bytes()
    assert outcome.summary == f"merged {len(fragments)} fragment(s) into {tmp_path / 'gui.a2l'}"


def test_the_tools_menu_opens_the_dialog_on_the_project_and_offers_to_reload_its_a2l(qtbot, tmp_path,
                                                                                    placeholder_a2l):
    window = _window_on(qtbot, placeholder_a2l)
    try:
        menus = {action.text().replace("&", ""): action.menu() for action in window.menuBar().actions()}
        assert [a.text() for a in menus["Tools"].actions()] == [
            "Update A2L from ELF…", "Check A2L…", "Merge A2L fragments…", "", "Insert into A2L from ELF…",
            "Remove from A2L…", "Clean up A2L…", "Flatten A2L includes…", "", "Requirement tests…"]
        window.a2l_update_action.trigger()
        dialog = window.a2l_tools
        assert dialog.isVisible() and dialog.operation == UPDATE and not dialog.isModal()
        assert (dialog.a2l.text(), dialog.elf.text(), dialog.output.text()) == (str(placeholder_a2l),
                                                                                str(demo.elf()), "")
        before = window.workspace
        _run(dialog, qtbot)
        assert dialog.reload_button.isVisibleTo(dialog) and placeholder_a2l.name in dialog.reload_note.text()
        with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
            dialog.reload_button.click()
        assert window.workspace is not before
        address = window.workspace.model.measurement("xsOTV1Cmd").address
        assert address == 0x40020090  # the updated A2L's, not the placeholder
        window.a2l_check_action.trigger()
        assert window.a2l_tools is dialog and dialog.operation == CHECK
        window.a2l_remove_action.trigger()
        assert window.a2l_tools is dialog and dialog.operation == REMOVE
    finally:
        window.close()


def test_reloading_the_a2l_while_connected_connects_again_with_it(qtbot, tmp_path, demo_ecu, project):
    from gui_helpers import open_window

    project.a2l = tmp_path / "FLCU.a2l"
    shutil.copy(demo.a2l(), project.a2l)
    window = open_window(qtbot, project)
    try:
        dialog = window.open_a2l_tools(UPDATE)
        _run(dialog, qtbot)  # the same addresses: written again all the same
        assert dialog.reload_button.isVisibleTo(dialog)
        before = window.workspace
        with qtbot.waitSignals([window.controller.disconnected, window.loaded, window.controller.connected],
                               order="strict", timeout=WAIT_MS):
            dialog.reload_button.click()
        assert window.workspace is not before and window.controller.session.doc is window.workspace.doc
    finally:
        window.close()


def test_an_update_that_rewrites_a_file_the_projects_a2l_includes_offers_to_reload_it(qtbot, tmp_path,
                                                                                      including_a2l):
    window = _window_on(qtbot, including_a2l)
    try:
        dialog = window.open_a2l_tools(UPDATE)
        dialog.output.setText(tmp_path / "elsewhere.a2l")  # not the project's A2L: the file it includes is rewritten
        dialog.includes.setCurrentIndex(dialog.includes.findData(IncludeMode.UPDATE))
        assert _run(dialog, qtbot).ok
        assert dialog.reload_button.isVisibleTo(dialog)
        assert dialog.reload_note.text().startswith(f"The open project uses {including_a2l.name}, which includes "
                                                    "part.a2l:")
        with qtbot.waitSignal(window.loaded, timeout=WAIT_MS):
            dialog.reload_button.click()
        assert window.workspace.model.measurement("xsOTV1Cmd").address == 0x40020090  # read from part.a2l again
        dialog.includes.setCurrentIndex(dialog.includes.findData(IncludeMode.MERGE))  # only elsewhere.a2l written
        assert _run(dialog, qtbot).ok and not dialog.reload_button.isVisibleTo(dialog)
    finally:
        window.close()


def test_a_removal_in_an_included_file_is_refused_unless_the_included_files_are_updated(dialog, qtbot, tmp_path,
                                                                                        including_a2l):
    part = including_a2l.parent / "part.a2l"
    dialog.set_operation(REMOVE)
    dialog.a2l.setText(including_a2l)
    dialog.removed.setText("xsOTV1Cmd")
    before = part.read_bytes()
    outcome = _run(dialog, qtbot)  # includes kept: the removal would fall into part.a2l
    assert not outcome.ok and outcome.files_written() == [] and part.read_bytes() == before
    assert _rows(dialog)[0][:2] == ("error", f"{part}:1:1")
    dialog.includes.setCurrentIndex(dialog.includes.findData(IncludeMode.UPDATE))  # --update-includes
    outcome = _run(dialog, qtbot)
    assert outcome.ok and outcome.includes_written == (part,) and "xsOTV1Cmd" not in part.read_text()


def test_an_update_removing_missing_objects_drops_optional_references_when_asked(dialog, qtbot, tmp_path):
    """`a2l update --remove-missing --drop-optional-references`: an axis' INPUT_QUANTITY naming an object missing in
    the ELF refuses the update, unless dropped (NO_INPUT_QUANTITY); the switch goes with 'remove' only (the CLI's
    rule)."""
    fixtures = Path(__file__).parents[1]
    source = tmp_path / "in.a2l"  # zsScalar missing from the ELF (renamed), zvLut's axis input
    source.write_text((fixtures / "a2l" / "fixtures" / "types.a2l").read_text()
                      .replace("MEASUREMENT zsScalar ", "MEASUREMENT zsScalar_gone ")
                      .replace("REF_MEASUREMENT zsScalar ", "REF_MEASUREMENT zsScalar_gone ")
                      .replace("STD_AXIS NO_INPUT_QUANTITY", "STD_AXIS zsScalar_gone"))
    dialog.a2l.setText(source)
    dialog.elf.setText(fixtures / "elf" / "fixtures" / "types_dwarf5.elf")
    dialog.output.setText(tmp_path / "out.a2l")
    dialog.epk.setChecked(False)
    assert dialog.update_drop_optional.isVisibleTo(dialog) and not dialog.update_drop_optional.isEnabled()
    dialog.update_drop_optional.setChecked(True)  # not asked without --remove-missing
    assert dialog._job()[2]["drop_optional"] is False
    dialog.missing.setCurrentIndex(dialog.missing.findData(UpdateMode.REMOVE_MISSING))
    dialog.update_drop_optional.setChecked(False)
    outcome = _run(dialog, qtbot)
    assert not outcome.ok and outcome.files_written() == [] and "would name a removed object" in _rows(dialog)[0][3]
    assert dialog.update_drop_optional.isEnabled()
    dialog.update_drop_optional.setChecked(True)
    outcome = _run(dialog, qtbot)
    assert outcome.ok and "STD_AXIS NO_INPUT_QUANTITY" in (tmp_path / "out.a2l").read_text()
    assert any("INPUT_QUANTITY zsScalar_gone is removed: now NO_INPUT_QUANTITY" in row[3] for row in _rows(dialog))
