"""``workbench scan`` against the simulated demo ECU on an in-process virtual bus: the slaves found, --identify,
--json, exit 1 with one line when none answers, exit 2 for a broadcast id that is none or an A2L without one."""

from __future__ import annotations

import itertools
import json

import pytest
from cli_helpers import run
from session_helpers import demo_a2l_text, edited_a2l

from workbench.sim import serve_demo

_channels = itertools.count()


@pytest.fixture
def bus():
    channel = f"scan-{next(_channels)}"
    with serve_demo({"interface": "virtual", "channel": channel}, time_scale=None):
        yield ["--interface", "virtual", "--channel", channel]


def test_scan_lists_the_slave_and_checks_the_a2l_ids(bus, capsys):
    code, out, err = run(capsys, "scan", *bus)
    assert (code, err) == (0, "")
    assert out.splitlines() == [
        f"GET_SLAVE_ID (echo and inverse echo) on 0x6F0 (virtual {bus[-1]}): 1 slave answered",
        "slave 1  commands on 0x7F0, answers on 0x7F1",
        "A2L         CAN_ID_MASTER 0x7F0, CAN_ID_SLAVE 0x7F1: a slave answers on them",
    ]


def test_scan_identify_json(bus, capsys):
    code, out, _ = run(capsys, "scan", "--identify", "--json", *bus)
    data = json.loads(out)
    assert code == 0 and data["ok"] is True and data["a2l"]["answered"] is True
    [slave] = data["slaves"]
    assert (slave["can_id_master"], slave["can_id_slave"], slave["confirmed"]) == (0x7F0, 0x7F1, True)
    assert slave["epk"] == "10300020250301" and slave["daq_ids"][0]["can_id"] == 0x7F1


def test_nobody_answering_is_one_line_and_exit_1(bus, capsys):
    code, out, err = run(capsys, "scan", "--broadcast-id", "0x80000100", "--wait", "0.05", *bus)
    assert (code, out) == (1, "")
    assert err == (f"error: no XCP slave answered GET_SLAVE_ID (echo and inverse echo) on 0x100 (extended) "
                   f"(virtual {bus[-1]}) within 0.05 s\n")
    code, out, err = run(capsys, "scan", "--broadcast-id", "0x80000100", "--wait", "0.05", "--json", *bus)
    data = json.loads(out)
    assert (code, data["ok"], data["exit_code"], data["slaves"]) == (1, False, 1, [])
    assert f"error: {data['error']}\n" == err  # as every command's --json failure: ok, error, exit_code


def test_bad_broadcast_ids_are_usage_errors(capsys, tmp_path):
    code, _, err = run(capsys, "scan", "--broadcast-id", "0x900", "--interface", "virtual")
    assert code == 2 and "CAN id 0x900 does not fit a standard frame" in err
    without = edited_a2l(tmp_path, "CAN_ID_BROADCAST 0x6F0\n", "")
    code, _, err = run(capsys, "scan", "--a2l", without, "--interface", "virtual")
    assert code == 2 and err.count("\n") == 1 and err.endswith(
        "XCP_ON_CAN has no CAN_ID_BROADCAST; give the broadcast identifier: --broadcast-id ID\n")
    text = demo_a2l_text()
    module_xcp = text.index("/begin IF_DATA XCP", text.index("/end MOD_PAR"))
    for begin, end, what in (("/begin XCP_ON_CAN", "/end XCP_ON_CAN", "IF_DATA XCP has no XCP_ON_CAN block"),
                             (module_xcp, "/end IF_DATA", "the MODULE has no IF_DATA XCP block")):
        start = begin if isinstance(begin, int) else text.index(begin)
        block = text[start:text.index(end, start) + len(end)]  # the block left out
        code, _, err = run(capsys, "scan", "--a2l", edited_a2l(tmp_path, block, ""), "--interface", "virtual")
        assert code == 2 and err.count("\n") == 1 and what in err
        assert err.endswith("; to scan without it, give --broadcast-id ID instead of --a2l\n")


@pytest.mark.parametrize(("interface", "option", "closest"), [
    ((), "prot=43999", "did you mean port?"),  # the default, udp_multicast: python-can would scan the default port
    (("--interface", "virtual"), "port=43999", "it takes bitrate"),
])
def test_a_bus_option_the_interface_would_ignore_is_refused(capsys, interface, option, closest):
    code, out, err = run(capsys, "scan", *interface, "--bus-kwargs", option)
    assert (code, out, err.count("\n")) == (2, "", 1)
    assert err.startswith(f"error: bus option {option}: python-can's ") and closest in err
