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


CAN_EXTRAS = """MAX_BUS_LOAD 500000
        MEASUREMENT_SPLIT_ALLOWED
        TRANSPORT_LAYER_INSTANCE "CAN1"
        /begin CAN_FD
          MAX_DLC 8
          CAN_FD_DATA_TRANSFER_BAUDRATE 4000000
          SAMPLE_POINT 70   /* data phase */
          BTL_CYCLES 20
          SJW 4
          SYNC_EDGE DUAL
          SECONDARY_SAMPLE_POINT 75
          TRANSCEIVER_DELAY_COMPENSATION ON
        /end CAN_FD
        MAX_DLC_REQUIRED"""
REWRITTEN_TAGS = {"MAX_DLC_REQUIRED": 0, "OPTIONAL_TL_SUBCMD": 1}


def _items(doc, keyword: str) -> tuple[list[str], list[str]]:
    """The words of the XCP block ``keyword``'s own items, but those a profile rewrites, and of its CAN_FD."""
    block = next(b for b in doc.module().children_named("IF_DATA") if b.name == "XCP").first(keyword)
    words, skip = [], 0
    for token in block.own_tokens:
        text = doc.text(token)
        if skip:
            skip -= 1
        elif text in REWRITTEN_TAGS:
            skip = REWRITTEN_TAGS[text]
        else:
            words.append(text)
    fd = block.first("CAN_FD")
    return words, [doc.text(token) for token in fd.own_tokens] if fd is not None else []


@pytest.mark.parametrize("name", ["large-packets", "daq-can-ids-variable", "motorola", "slow"])
def test_a_profiles_a2l_keeps_every_transport_field_it_does_not_change(tmp_path, name):
    """A profile writes its XCP_ON_CAN's MAX_DLC_REQUIRED, OPTIONAL_TL_SUBCMD, DAQ_LIST_CAN_ID and CAN FD's MAX_DLC
    and data bit rate; SAMPLE_RATE, BTL_CYCLES, SJW, SYNC_EDGE (the demo's), MAX_BUS_LOAD, the rest of CAN_FD and an
    XCP_ON_UDP_IP's own fields stay as the source says (the writer of the whole IF_DATA dropped them)."""
    from session_helpers import demo_a2l_text

    from workbench.sim.memory_map import HDS9
    from workbench.sim.profile_a2l import profile_document

    text = demo_a2l_text().replace("        MAX_DLC_REQUIRED\n", f"        {CAN_EXTRAS}\n", 1)
    text = text.replace('ADDRESS "127.0.0.1"\n', 'ADDRESS "127.0.0.1"\n        MAX_BUS_LOAD 100000000\n', 1)
    (tmp_path / "FLCU.a2l").write_text(text, encoding="utf-8")
    source = load_a2l(tmp_path / "FLCU.a2l")
    chosen, config = profile(name), read_xcp_config(source)
    described = {t: chosen.parameters(xcp_parameters(source, config, t), t) for t in ("CAN", "UDP", "TCP")}
    written = profile_document(source, described, chosen.memory_map(HDS9), name)
    can, fd = _items(written, "XCP_ON_CAN")
    assert can == _items(source, "XCP_ON_CAN")[0]
    assert {"SAMPLE_RATE", "BTL_CYCLES", "SJW", "SYNC_EDGE", "MAX_BUS_LOAD", "MEASUREMENT_SPLIT_ALLOWED"} <= set(can)
    assert _items(written, "XCP_ON_UDP_IP")[0][-2:] == ["MAX_BUS_LOAD", "100000000"]
    assert fd == ([] if name != "large-packets" else [  # a classic CAN slave's A2L says no CAN FD
        "MAX_DLC", "64", "CAN_FD_DATA_TRANSFER_BAUDRATE", "2000000", "SAMPLE_POINT", "70", "BTL_CYCLES", "20", "SJW",
        "4", "SYNC_EDGE", "DUAL", "SECONDARY_SAMPLE_POINT", "75", "TRANSCEIVER_DELAY_COMPENSATION", "ON"])
    assert read_xcp_config(written).can.max_dlc_required == described["CAN"].max_dlc_required


@pytest.mark.parametrize(("name", "kept"), [("daq-can-ids", True), ("segments", False)])
def test_a_profiles_a2l_keeps_the_calibration_memory_segment_it_does_not_change(name, kept):
    """daq-can-ids keeps the demo's calibration pages: its MEMORY_SEGMENT stays as written (comments, layout), as
    the IF_DATA blocks a profile does not change do; 'segments' splits it in two, written anew."""
    from workbench.sim.memory_map import HDS9
    from workbench.sim.profile_a2l import profile_document

    source = load_a2l(DemoFiles.defaults().a2l)
    chosen, config = profile(name), read_xcp_config(source)
    described = {t: chosen.parameters(xcp_parameters(source, config, t), t) for t in ("CAN", "UDP", "TCP")}
    written = profile_document(source, described, chosen.memory_map(HDS9), name)
    calib = next(m for m in source.memory_segments() if m.name == config.segments[0].memory_segment)
    text = source.data[slice(*calib.block.span)]
    assert (text in written.data) is kept


def test_get_id_reports_the_calibration_datas_epk_whatever_the_order_of_the_addr_epks(tmp_path):
    """An A2L naming the application header's ADDR_EPK before CALIB's: GET_ID 5 still reports CALIB's EPK (the one
    a calibration flash changes), as it did with CALIB's first (it reported the application header's)."""
    text = DemoFiles.defaults().a2l.read_text(encoding="latin-1")
    assert text.count("ADDR_EPK 0xFC0000\n      ADDR_EPK 0x840008") == 1
    swapped = tmp_path / "swapped.a2l"
    swapped.write_text(text.replace("ADDR_EPK 0xFC0000\n      ADDR_EPK 0x840008",
                                    "ADDR_EPK 0x840008\n      ADDR_EPK 0xFC0000"), encoding="latin-1")
    for path in (DemoFiles.defaults().a2l, swapped):
        doc = load_a2l(path)
        assert xcp_parameters(doc, read_xcp_config(doc)).epk_address == 0xFC0000
