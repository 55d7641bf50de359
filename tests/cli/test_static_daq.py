"""``workbench measure --daq`` against ``workbench sim --static-daq`` in a process of its own, on a udp_multicast
port of the test's own: the same command as against dynamic DAQ, and a measurement too big for the lists refused."""

from __future__ import annotations

import json
import signal

import pytest
from sim_process import start_sim_process

from workbench import demo
from workbench.a2l import load_a2l
from workbench.a2l.xcp import read_daq_events
from workbench.cli import main


@pytest.fixture
def static_sim_port(free_udp_port):
    process, banner = start_sim_process("--interface", "udp_multicast", "--bus-kwargs", f"port={free_udp_port}",
                                        "--pcm", "--static-daq")
    try:
        assert "DAQ          static, 4 lists (ODTs x entries): 8x3 on Task4ms, 12x3 on Task50ms, 16x4, 4x4" in banner
        yield free_udp_port
    finally:
        process.send_signal(signal.SIGTERM)
        try:
            process.communicate(timeout=15)
        finally:
            process.kill()


def test_measure_daq_against_a_static_slave(static_sim_port, capsys):
    code = main(["measure", "zsRailPressure", "zsSensVolt", "xsDC", "--daq", "--duration", "0.6", "--json",
                 "--bus-kwargs", f"port={static_sim_port}"])
    out, err = capsys.readouterr()
    lines = [json.loads(line) for line in out.splitlines()]
    assert code == 0, err
    events = {line["event"] for line in lines}
    assert events == {"Task4ms", "Task50ms"} and len(lines) > 60
    fast = [line for line in lines if line["event"] == "Task4ms"]
    assert set(fast[0]["values"]) == {"zsRailPressure", "zsSensVolt"} and len(fast[0]["values"]["zsSensVolt"]) == 4
    assert " 0 lost" in err
    # every Task4ms and Task50ms signal on one event: more ODTs than any list has
    model = load_a2l(demo.a2l()).model()
    names = [name for name in model.names("MEASUREMENT") if read_daq_events(model.block(name)).preferred in (0, 1)]
    code = main(["measure", *names, "--daq", "--event", "Task4ms", "--duration", "0.2",
                 "--bus-kwargs", f"port={static_sim_port}"])
    out, err = capsys.readouterr()
    assert (code, out) == (2, "") and err.count("\n") == 1
    assert err.startswith("error: the slave's static DAQ lists cannot take this measurement: event 0 (Task4ms) fits no list")
