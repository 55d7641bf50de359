"""``measure --record --can2-channel`` on udp_multicast keeps the port given with --bus-kwargs: CAN2 on a group of
its own, on the test's own port, is recorded (on python-can's default port nothing would come)."""

from __future__ import annotations

import json

from workbench import demo
from workbench.cli import main
from workbench.sim import serve_demo

CAN2_GROUP = "239.74.163.9"


def test_a_can2_channel_of_its_own_keeps_the_udp_multicast_port(free_udp_port, capsys, tmp_path):
    xcp = {"interface": "udp_multicast", "port": free_udp_port}
    with serve_demo(xcp, can2={**xcp, "channel": CAN2_GROUP}, pcm_target_bar=25.0):
        code = main(["measure", "xsDC", "--record", str(tmp_path / "can2.mf4"), "--can2", str(demo.dbc_can2()),
                     "--can2-channel", CAN2_GROUP, "--bus-kwargs", f"port={free_udp_port}", "--duration", "1.0",
                     "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    summary = json.loads(out)
    assert summary["can_frames"] >= 10 and summary["samples"] >= 5  # the FLCU's and the PCM's 100 ms frames
