"""What a user met on a third-party slave, through the CLI against the simulator's profiles (issue 21): DAQ on a
slave whose MAX_DAQ is 0 before ALLOC_DAQ, and pages on an ECU whose calibrations are in segment 1."""

from __future__ import annotations

import json

import pytest
from cli_helpers import run

from workbench.sim import serve_demo


@pytest.fixture
def served(request, free_udp_port, tmp_path):
    """The demo ECU through the profile the test names (``@pytest.mark.parametrize("served", [...], indirect=True)``),
    the A2L it publishes written as a user's ``--write-a2l`` would, and the options that reach it."""
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}, profile=request.param,
                    pcm_target_bar=25.0) as simulator:
        a2l = tmp_path / f"{request.param}.a2l"
        a2l.write_bytes(simulator.a2l.source.file_bytes(simulator.a2l.data))
        yield ["--a2l", str(a2l), "--bus-kwargs", f"port={free_udp_port}"]



@pytest.mark.parametrize("served", ["daq-counted"], indirect=True)
def test_measure_daq_on_a_slave_whose_max_daq_counts_allocated_lists(served, capsys):
    code, out, err = run(capsys, "measure", "zsRailPressure", "xsDC", "--daq", "--duration", "0.4", "--json", *served)
    assert code == 0, err
    assert {json.loads(line)["event"] for line in out.splitlines()} == {"Task4ms", "Task50ms"}
    assert " 0 lost" in err


@pytest.mark.parametrize("served", ["segments-one-by-one"], indirect=True)
def test_pages_on_an_ecu_whose_calibrations_are_in_segment_1(served, capsys):
    assert run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "23.5", *served)[0] == 0
    code, out, _ = run(capsys, "cal", "get", "xsSWITCH_TANK_THR", "--page", "reference", *served)
    assert code == 0 and out.startswith("xsSWITCH_TANK_THR = 20")  # CAL ROM through segment 1
    code, out, _ = run(capsys, "cal", "page", "reference", *served)
    assert code == 0 and out.splitlines() == ["segment 0: ECU on the reference page, XCP on the reference page",
                                              "segment 1: ECU on the reference page, XCP on the reference page"]
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *served)[1].startswith("xsSWITCH_TANK_THR = 20")
    code, out, _ = run(capsys, "cal", "page", "working", "--json", *served)
    assert [item["xcp"] for item in json.loads(out)] == ["working", "working"]
    assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *served)[1].startswith("xsSWITCH_TANK_THR = 23.5")
