"""The A2L tools dialog's Insert tab: `workbench a2l insert` with one pattern per kind and a target group."""

from __future__ import annotations

from pathlib import Path

from gui_helpers import WAIT_MS

from workbench.a2l import load_a2l
from workbench.gui.widgets.a2l_tools_dialog import INSERT, A2lToolsDialog

ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"
A2L = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n    /begin MOD_COMMON "" BYTE_ORDER MSB_LAST '
       '/end MOD_COMMON\n  /end MODULE\n/end PROJECT\n')


def test_insert_tab_writes_the_objects_and_names_a_bad_pattern(qtbot, tmp_path, monkeypatch):
    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path / "cache"))
    source = tmp_path / "in.a2l"
    source.write_text(A2L)
    dialog = A2lToolsDialog(INSERT, source, ELF)
    qtbot.addWidget(dialog)
    dialog.show()
    assert dialog.run() is None and "pattern" in dialog.status.text()  # nothing to insert yet
    dialog.measured.setText(r"outer\.b\..*")
    dialog.calibrated.setText("csConstant")
    dialog.group.setText("New")
    with qtbot.waitSignal(dialog.done, timeout=WAIT_MS) as done:
        assert dialog.run() is not None
    qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
    assert done.args[0].ok and dialog.status.text().startswith("done: wrote")
    model = load_a2l(source).model()  # no output named: the A2L itself
    assert model.group("New").ref_measurements == ("outer.b.c", "outer.b.d")
    assert model.characteristic("csConstant").record_layout == "__UBYTE_Z"
    dialog.measured.setText("outer(")
    with qtbot.waitSignal(dialog.refused, timeout=WAIT_MS):
        dialog.run()
    qtbot.waitUntil(lambda: dialog.task is None, timeout=WAIT_MS)
    assert "--measurement-regex 'outer('" in dialog.status.text()
