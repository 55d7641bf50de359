"""Another master's DAQ on the ECU (CANape beside us), as ``workbench measure`` meets it: DTOs of lists that are
not ours come on the ECU's id. The command warns before CONNECT and sums them up at the end, saying what they
probably are, in one line each."""

from __future__ import annotations

import re

import can
import pytest

from workbench.cli import main
from workbench.session import session as session_module
from workbench.sim import serve_demo


@pytest.mark.parametrize("record", [False, True])
def test_dtos_of_no_list_of_ours_are_warned_of_and_summed_up(record, capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(session_module, "LISTEN_BEFORE_CONNECT_S", 0.2)  # a loaded machine misses no 5 ms DTO in it
    channel = f"other-master-{record}"
    with serve_demo({"interface": "virtual", "channel": channel}), can.Bus(interface="virtual", channel=channel) as other:
        foreign = can.Message(arbitration_id=0x7F1, is_extended_id=False, data=bytes((0xF0, 1, 2, 3, 4, 5, 6, 7)))
        task = other.send_periodic(foreign, 0.005)  # the other master's list, PID 0xF0 (not one of ours)
        try:
            output = ["--record", str(tmp_path / "run.mf4")] if record else ["--daq", "--json"]
            code = main(["measure", "zsRailPressure", *output, "--duration", "0.5",
                         "--interface", "virtual", "--channel", channel])
        finally:
            task.stop()
    out, err = capsys.readouterr()
    assert code == 0, err
    assert err.startswith("warning: before CONNECT, the ECU's id 0x7F1 carried ") and "DTO(s) within 200 ms" in err
    summary = out.splitlines()[-1] if record else err.splitlines()[-1]
    assert re.search(r"; [1-9]\d* DTO\(s\) of no DAQ list of this measurement: another master's DAQ on this ECU "
                     r"\(CANape, a second workbench\), or lists an earlier session left running$", summary), summary
    assert summary.startswith("recorded " if record else "measure: ")


def test_no_stray_dtos_no_words(capsys):
    channel = "other-master-none"
    with serve_demo({"interface": "virtual", "channel": channel}):
        code = main(["measure", "zsRailPressure", "--daq", "--json", "--duration", "0.3",
                     "--interface", "virtual", "--channel", channel])
    err = capsys.readouterr().err
    assert code == 0 and re.fullmatch(r"measure: \d+ samples, 0 lost, 0 overload indications\n", err), err
