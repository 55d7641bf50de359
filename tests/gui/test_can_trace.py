"""The CAN trace beside the numeric view on a laptop's screen: a classic frame's eight data bytes are shown whole
(they read '02 2E 44 0D 3F…' while the decoded column, empty for XCP's frames, took twice their room)."""

from __future__ import annotations

from gui_helpers import text_room

from workbench.gui.can_monitor import TraceEntry
from workbench.gui.models.trace import TraceModel
from workbench.gui.signal_hub import SignalHub
from workbench.gui.widgets.can_trace import CanTrace

DATA = TraceModel.COLUMNS.index("data")


def test_eight_data_bytes_fit_in_the_trace_as_wide_as_on_a_laptop(qtbot):
    trace = CanTrace(SignalHub())
    qtbot.addWidget(trace)
    trace.resize(620, 220)  # the trace's dock at 1366 x 768
    trace.show()
    qtbot.waitExposed(trace)
    trace.model.set_rows([TraceEntry(6.3321, 0x7F1, False, bytes.fromhex("022E440D3F000000"), "", ""),
                          TraceEntry(6.3400, 0x123, False, bytes(8), "FLCU_TO_PCM_002", "RailPressure=25.03 bar")])
    for row in range(2):
        room, needed = text_room(trace.table, trace.model.index(row, DATA))
        assert room >= needed
    room, needed = text_room(trace.table, trace.model.index(1, TraceModel.COLUMNS.index("message")))
    assert room >= needed  # and the message's name beside them
