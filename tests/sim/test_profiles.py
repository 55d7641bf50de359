"""Slave profiles: each one's A2L tells the truth about its slave (checked clean, read back equal to what the
slave answers), the IF_DATA writer round-trips the demo's, and ``workbench sim --profile`` lists, serves and
writes them."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from workbench.a2l import check_document, load_a2l, load_a2l_string, read_xcp_config
from workbench.a2l.xcp_write import format_if_data_xcp
from workbench.cli import main
from workbench.errors import InputError
from workbench.sim.demo_ecu import DemoFiles, build_demo_ecu, xcp_parameters
from workbench.sim.profiles import PROFILES, profile
from workbench.sim.xcp.slave import XcpSlave
from workbench.xcp_protocol import Cmd

MANDATORY = {"CONNECT", "DISCONNECT", "GET_STATUS", "SYNCH"}


def test_the_if_data_writer_reads_back_as_the_demo_a2l_says():
    doc = load_a2l(DemoFiles.defaults().a2l)
    config = read_xcp_config(doc)
    block = next(b for b in doc.module().children_named("IF_DATA") if b.name == "XCP")
    start, end = block.span
    rewritten = load_a2l_string((doc.data[:start] + format_if_data_xcp(config).encode() + doc.data[end:]).decode())
    assert read_xcp_config(rewritten) == config


@pytest.mark.parametrize("name", list(PROFILES))
def test_a_profiles_a2l_is_clean_and_says_what_its_slave_does(name):
    demo = build_demo_ecu(slave_profile=name)
    base = load_a2l(demo.files.a2l)
    for transport in ("CAN", "UDP", "TCP"):
        params = PROFILES[name].parameters(xcp_parameters(base, read_xcp_config(base), transport), transport)
        slave = XcpSlave(None, params, None)  # no ECU behind it: it only says what it implements
        config = read_xcp_config(demo.a2l).for_transport(transport)
        assert (config.max_cto, config.max_dto) == (params.max_cto, params.max_dto)
        assert config.byte_order == ("MSB_FIRST" if params.byte_order == ">" else "MSB_LAST")
        assert config.address_granularity == params.address_granularity
        implemented = {c.name for c in slave.commands | params.transport_commands(transport)} - MANDATORY
        assert config.optional_commands == implemented
        assert config.max_segments == len(params.segments or [0]) == len(config.segments)
        assert config.daq.config_type == ("STATIC" if params.daq.static else "DYNAMIC")
        assert (config.daq.min_daq, config.daq.identification_field) == (params.daq.min_daq,
                                                                         params.daq.identification_field)
        assert (config.daq.timestamp.size if config.daq.timestamp else 0) == params.daq.timestamp_size
        assert (config.can.max_dlc or 8) == (64 if name == "large-packets" else 8)
        programming, pgm = params.programming, config.pgm
        assert pgm.max_cto_pgm == programming.max_cto
        block_mode = bool(pgm.communication_mode and pgm.communication_mode.master_block_mode)
        assert block_mode == programming.master_block_mode
        assert [(s.address, s.length) for s in pgm.sectors] == [(s.range.start, s.range.size)
                                                                for s in demo.ecu.memory_map.sectors]
    assert not [finding for finding in check_document(demo.a2l).findings if finding.severity == "error"]


def test_the_demo_profile_is_the_demo_a2l_itself_and_quiet_profiles_keep_it():
    files = DemoFiles.defaults()
    assert build_demo_ecu(slave_profile="demo").a2l.path == files.a2l
    quiet = [p for p in PROFILES.values() if not p.changes_a2l]
    assert {p.name for p in quiet} == {"demo", "long-seed", "unlocked", "chatty"}
    assert all(build_demo_ecu(slave_profile=p).a2l.path == files.a2l for p in quiet)


def test_the_slow_profile_says_its_t1_and_keeps_the_other_timeouts():
    slow, demo = (read_xcp_config(build_demo_ecu(slave_profile=name).a2l).timeouts for name in ("slow", "demo"))
    assert slow.t1 == 0.3 and replace(slow, t1=demo.t1) == demo


def test_an_unknown_profile_names_the_known_ones():
    with pytest.raises(InputError, match="no slave profile 'vendor-x'; the profiles are: demo, daq-counted"):
        profile("vendor-x")
    assert Cmd.GET_ID in build_demo_ecu().ecu.slave.commands


def test_sim_lists_profiles_and_writes_the_a2l_of_the_one_it_serves(capsys, tmp_path):
    assert main(["sim", "--profile", "list", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert [item["name"] for item in listed] == list(PROFILES)
    path = tmp_path / "segments.a2l"
    assert main(["sim", "--interface", "virtual", "--channel", "cli-profile", "--profile", "segments",
                 "--write-a2l", str(path), "--duration", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "profile      segments: the EPK in segment 0" in out and f"A2L          {path}" in out
    assert [s.number for s in read_xcp_config(load_a2l(path)).segments] == [0, 1]
    assert main(["sim", "--profile", "vendor-x"]) == 2
    assert "no slave profile 'vendor-x'" in capsys.readouterr().err
