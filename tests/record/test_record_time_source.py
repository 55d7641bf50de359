"""A recording says which clock its times come from (user trial 6): the ECU's DAQ timestamps, or the master's
receive time when the ECU sends none (the no-timestamp profile) or the plan leaves them no room on classic CAN
(DWORD granularity: a 4-byte timestamp after the PID leaves the first ODT 3 bytes, less than one element). Recorded
through ``workbench measure --record`` on udp_multicast against the simulator's profiles, read with asammdf; a
recording of CAN frames alone says the host's clock."""

from __future__ import annotations

from xml.etree import ElementTree

import numpy as np
import pytest
from mdf_reading import channel, group_index, master

from workbench import demo
from workbench.cli import main
from workbench.record import record
from workbench.sim import serve_demo


def header_properties(mdf) -> dict[str, str]:
    common = ElementTree.fromstring(mdf.header.comment).find("common_properties")
    return {element.get("name"): element.text for element in common}


@pytest.mark.parametrize("profile, stamped", [("demo", True), ("no-timestamp", False), ("granularity-dword", False)])
def test_the_file_says_which_clock_its_times_come_from(profile, stamped, free_udp_port, tmp_path, read_mdf, capsys):
    path = tmp_path / "run.mf4"
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}, profile=profile) as simulator:
        a2l = tmp_path / "ecu.a2l"
        a2l.write_bytes(simulator.a2l.source.file_bytes(simulator.a2l.data))
        code = main(["measure", "zsRailPressure", "--record", str(path), "--duration", "0.5", "--a2l", str(a2l),
                     "--bus-kwargs", f"port={free_udp_port}"])
    assert code == 0, capsys.readouterr().err
    mdf = read_mdf(path)
    properties = header_properties(mdf)
    group = mdf.groups[group_index(mdf, "Task4ms")].channel_group
    host = channel(mdf, "Task4ms", "HostTime_Task4ms")
    times = master(mdf, "Task4ms")
    assert len(times) > 20 and times[0] == 0.0 and np.all(np.diff(times) > 0)
    if stamped:
        assert properties["daq_time_source"].startswith("the ECU's DAQ timestamps (4-byte counter of ")
        assert "DAQ groups: the ECU's DAQ clock (its timestamps)" in properties["time_axis"]
        assert group.comment.endswith("timed by the ECU's DAQ timestamps")
        assert host.comment.endswith("the ECU's timestamp mapped onto the host's clock")
        assert np.allclose(np.diff(times), 0.004, atol=1e-6)  # the ECU's clock: exact steps
    else:
        assert properties["daq_time_source"] == ("the master's receive time (the ECU sends no DAQ timestamps with "
                                                 "these lists)")
        assert "DAQ groups: the master's receive time of each sample" in properties["time_axis"]
        assert "ECU's DAQ clock" not in properties["time_axis"]
        assert group.comment.endswith("timed by the master's receive time (no DAQ timestamps)")
        assert host.comment.endswith("its receive time (the ECU sends no DAQ timestamps)")
        # the receive times themselves: the file's time is the host time less the start time
        assert np.allclose(host.samples - times, mdf.header.start_time.timestamp(), atol=1e-5)


def test_a_can_only_recording_claims_no_ecu_clock(session, tmp_path, read_mdf):
    path = tmp_path / "can2.mf4"
    record(session, path, can2=demo.dbc_can2(), duration=0.3)
    properties = header_properties(read_mdf(path))
    assert properties["time_axis"] == ("time channels: s since the start time. CAN groups: the host's receive time, "
                                       "0 = the start of the recording")
    assert "daq_time_source" not in properties  # nothing was sampled by DAQ
