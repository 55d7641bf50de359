"""read_xcp_config: the IF_DATA XCP of a file, read through the generic IF_DATA tree."""

from dataclasses import replace

import pytest

from workbench import demo
from workbench.a2l import load_a2l, load_a2l_string
from workbench.a2l.ifdata import Word, read_if_data
from workbench.a2l.xcp import XcpDaqListCanId, read_xcp_config
from workbench.errors import A2lParseError
from workbench.xcp_protocol import CanId


@pytest.fixture
def config(fixtures):
    return read_xcp_config(load_a2l(fixtures / "xcp_ecu.a2l"))


def test_protocol_layer(config):
    assert config.protocol_version == 0x0104
    assert config.timeouts.t1 == pytest.approx(0.025)
    assert config.timeouts.t7 == pytest.approx(0.050)
    assert (config.max_cto, config.max_dto) == (8, 8)
    assert config.byte_order == "MSB_FIRST"
    assert config.address_granularity == 2
    assert config.optional_commands == {"GET_ID", "SHORT_UPLOAD"}
    assert config.communication_mode.interleaved_queue_size == 4
    assert not config.communication_mode.master_block_mode
    assert config.seed_and_key_function == "SeedNKey.dll"


def test_daq_properties_and_events(config):
    daq = config.daq
    assert (daq.config_type, daq.max_daq, daq.max_event_channels, daq.min_daq) == ("STATIC", 2, 2, 1)
    assert daq.identification_field == "RELATIVE_WORD" and daq.pid_size == 3
    assert daq.granularity == 2 and daq.max_odt_entry_size == 6
    assert daq.overload_indication == "OVERLOAD_INDICATION_PID" and daq.prescaler_supported
    assert daq.timestamp.size == 2 and daq.timestamp.unit_s == pytest.approx(1e-6)
    assert daq.timestamp.ticks == 10 and daq.timestamp.fixed
    assert daq.timestamp.resolution_s == pytest.approx(1e-5)
    fast, background = daq.events
    assert (fast.number, fast.name, fast.short_name, fast.priority) == (0, "10 ms task", "10ms", 0x10)
    assert fast.period_s == pytest.approx(0.010)
    assert background.period_s is None and background.direction == "DAQ_STIM"
    assert daq.event("bg") is background


def test_pages_segments_and_sectors(config):
    assert config.max_segments == 1 and config.freeze_supported
    (segment,) = config.segments
    assert (segment.memory_segment, segment.address, segment.size) == ("Cal", 0x20000000, 0x1000)
    assert (segment.number, segment.page_count) == (1, 2)
    assert segment.checksum_type == "XCP_ADD_44" and segment.checksum_max_block_size == 0xFFFF
    assert segment.pages[0].init_segment == 1
    assert segment.pages[1].xcp_write_access == "XCP_WRITE_ACCESS_WITH_ECU_ONLY"
    assert segment.address_mappings[0].destination == 0x9000
    (sector,) = config.pgm.sectors
    assert (sector.name, sector.address, sector.length, sector.clear_sequence) == ("Code", 0, 0x8000, 1)


def test_can_extended_ids_and_daq_list_ids(config):
    can = config.can
    assert (can.can_id_master, can.can_id_slave) == (CanId(0x12345, extended=True), CanId(0x12346, extended=True))
    assert can.can_id_broadcast == CanId(0x100)
    assert (can.baudrate, can.sample_point, can.max_dlc_required) == (500000, 75, False)
    assert can.daq_list_can_ids == (XcpDaqListCanId(0, CanId(0x310, extended=True)), XcpDaqListCanId(1, None))
    assert (can.max_dlc, can.fd_data_baudrate) == (64, 2000000)


def test_ethernet(config):
    assert (config.udp.port, config.udp.host) == (5555, "192.168.0.10")
    assert (config.tcp.protocol, config.tcp.port, config.tcp.host) == ("TCP", 5556, "ecu.local")


def test_a_transport_without_blocks_of_its_own_keeps_the_common_ones(config):
    assert config.udp.protocol_layer is None and config.udp.daq is None and config.udp.pgm is None
    assert config.for_transport("udp") == config


def test_a_missing_transport_block_is_named():
    config = read_xcp_config(load_a2l(demo.master_a2l()))
    without_tcp = replace(config, tcp=None)
    with pytest.raises(KeyError, match="XCP_ON_TCP_IP"):
        without_tcp.for_transport("TCP")


def test_a_transport_block_overrules_the_common_blocks():
    doc = load_a2l_string('''ASAP2_VERSION 1 71
/begin PROJECT P "" /begin MODULE M ""
  /begin IF_DATA XCP
    /begin PROTOCOL_LAYER 0x0100 1 2 3 4 5 6 7 8 8 BYTE_ORDER_MSB_LAST ADDRESS_GRANULARITY_BYTE /end PROTOCOL_LAYER
    /begin DAQ DYNAMIC 4 1 0 OPTIMISATION_TYPE_DEFAULT ADDRESS_EXTENSION_FREE IDENTIFICATION_FIELD_TYPE_ABSOLUTE
      GRANULARITY_ODT_ENTRY_SIZE_DAQ_BYTE 4 NO_OVERLOAD_INDICATION /end DAQ
    /begin XCP_ON_UDP_IP 0x0100 5555 HOST_NAME "ecu"
      /begin PROTOCOL_LAYER 0x0100 10 20 30 40 50 60 70 252 1400 BYTE_ORDER_MSB_LAST ADDRESS_GRANULARITY_BYTE
        OPTIONAL_CMD GET_ID /end PROTOCOL_LAYER
      /begin DAQ DYNAMIC 8 1 0 OPTIMISATION_TYPE_DEFAULT ADDRESS_EXTENSION_FREE IDENTIFICATION_FIELD_TYPE_RELATIVE_BYTE
        GRANULARITY_ODT_ENTRY_SIZE_DAQ_BYTE 255 NO_OVERLOAD_INDICATION /end DAQ
    /end XCP_ON_UDP_IP
  /end IF_DATA
/end MODULE /end PROJECT
''')
    config = read_xcp_config(doc)
    assert (config.max_cto, config.max_dto, config.daq.max_daq) == (8, 8, 4)  # the common blocks
    udp = config.for_transport("UDP")
    assert (udp.max_cto, udp.max_dto, udp.optional_commands) == (252, 1400, {"GET_ID"})
    assert udp.timeouts.t1 == pytest.approx(0.010)
    assert (udp.daq.max_daq, udp.daq.pid_size, udp.daq.max_odt_entry_size) == (8, 2, 255)
    assert udp.udp.host == "ecu" and udp.pgm is None


def test_mod_par_accessors(fixtures):
    doc = load_a2l(fixtures / "xcp_ecu.a2l")
    assert doc.epk() == "EPK_2024_01" and doc.addr_epk() == 0x8000
    assert [(s.name, s.memory_type, s.address, s.size) for s in doc.memory_segments()] == [
        ("Code", "FLASH", 0, 0x8000), ("Cal", "RAM", 0x20000000, 0x1000)]


def test_generic_if_data_tree(fixtures):
    doc = load_a2l(fixtures / "xcp_ecu.a2l")
    (if_data,) = doc.module().children_named("IF_DATA")
    tree = read_if_data(if_data)
    assert tree.values == ("XCP",) and isinstance(tree.values[0], Word)
    event = tree.block("DAQ").blocks("EVENT")[0]
    assert event.values[:4] == ("10 ms task", "10ms", 0, "DAQ")
    assert not isinstance(event.values[0], Word) and isinstance(event.values[3], Word)
    assert event.location[1:] == (38, 9)


def test_demo_master_states_the_demo_contract():
    config = read_xcp_config(load_a2l(demo.master_a2l()))
    assert (config.can.can_id_master, config.can.can_id_slave) == (CanId(0x7F0), CanId(0x7F1))
    assert config.can.baudrate == 1_000_000 and config.max_cto == config.max_dto == 8
    assert config.can.optional_tl_subcommands == ("GET_SLAVE_ID", "GET_DAQ_ID")  # no SET_DAQ_ID: no VARIABLE list
    assert config.daq.identification_field == "ABSOLUTE" and config.daq.max_odt_entry_size == 4
    assert config.daq.timestamp.size == 4 and config.daq.timestamp.unit_s == pytest.approx(1e-5)
    assert [(e.number, e.name, e.period_s) for e in config.daq.events] == [
        (0, "Task4ms", pytest.approx(0.004)), (1, "Task50ms", pytest.approx(0.05)),
        (2, "Task100ms", pytest.approx(0.1))]
    (segment,) = config.segments
    assert segment.address_mappings[0].source == 0x40000000
    assert segment.address_mappings[0].destination == 0xFC0000
    assert (segment.checksum_type, segment.checksum_max_block_size) == ("XCP_CRC_32", 0x20000)


def test_demo_master_states_the_ethernet_contract():
    config = read_xcp_config(load_a2l(demo.master_a2l()))
    for transport, block in (("UDP", config.udp), ("TCP", config.tcp)):
        assert (block.protocol, block.port, block.host) == (transport, 5555, "127.0.0.1")
        ethernet = config.for_transport(transport)
        assert (ethernet.max_cto, ethernet.max_dto, ethernet.pgm.max_cto_pgm) == (255, 1024, 255)
        # everything but the sizes and XCP on CAN's TRANSPORT_LAYER_CMD is the common blocks' (a test of the
        # simulator checks the slave says so)
        assert ethernet.optional_commands == config.optional_commands - {"TRANSPORT_LAYER_CMD"}
        assert ethernet.timeouts == config.timeouts
        assert ethernet.pgm.sectors == config.pgm.sectors and ethernet.daq == config.daq
    can = config.for_transport("CAN")
    assert (can.max_cto, can.max_dto, can.pgm.max_cto_pgm) == (8, 8, 8)
    assert "TRANSPORT_LAYER_CMD" in can.optional_commands  # GET_SLAVE_ID, GET_DAQ_ID: OPTIONAL_TL_SUBCMD


def test_missing_if_data_is_an_error():
    doc = load_a2l_string('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n/begin MODULE M ""\n/end MODULE\n/end PROJECT\n')
    with pytest.raises(A2lParseError, match="no IF_DATA XCP") as info:
        read_xcp_config(doc)
    assert info.value.line == 3


def test_a_measurement_names_its_daq_events():
    from workbench.a2l import load_a2l_string
    from workbench.a2l.xcp import read_daq_events

    doc = load_a2l_string("""/begin PROJECT P "" /begin MODULE M ""
      /begin MEASUREMENT fixed "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x10
        /begin IF_DATA XCP /begin DAQ_EVENT FIXED_EVENT_LIST EVENT 2 EVENT 0x3 /end DAQ_EVENT /end IF_DATA
      /end MEASUREMENT
      /begin MEASUREMENT variable "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x11
        /begin IF_DATA XCP /begin DAQ_EVENT VARIABLE
          /begin AVAILABLE_EVENT_LIST EVENT 0 EVENT 1 /end AVAILABLE_EVENT_LIST
          /begin DEFAULT_EVENT_LIST EVENT 1 /end DEFAULT_EVENT_LIST
        /end DAQ_EVENT /end IF_DATA
      /end MEASUREMENT
      /begin MEASUREMENT plain "" UBYTE NO_COMPU_METHOD 0 0 0 255 ECU_ADDRESS 0x12 /end MEASUREMENT
    /end MODULE /end PROJECT""", validate=False)
    fixed, variable, plain = (read_daq_events(block) for block in doc.objects("MEASUREMENT"))
    assert (fixed.fixed, fixed.preferred) == ((2, 3), 2)
    assert (variable.default, variable.available, variable.preferred) == ((1,), (0, 1), 1)
    assert plain.preferred is None


def test_the_demo_measurements_are_sampled_on_their_task():
    from workbench import demo
    from workbench.a2l import load_a2l
    from workbench.a2l.xcp import read_daq_events

    doc = load_a2l(demo.a2l())
    events = {block.name: read_daq_events(block).preferred for block in doc.objects("MEASUREMENT")}
    assert events["zsRailPressure"] == 0 and events["xsDC"] == 1 and events["csPCM_TO_FLCU_001_EnableFLCU"] == 2
    assert None not in events.values()


def _can_block(ids: str):
    return load_a2l_string(f"""ASAP2_VERSION 1 71
/begin PROJECT P "" /begin MODULE M ""
  /begin IF_DATA XCP
    /begin PROTOCOL_LAYER 0x0100 1 2 3 4 5 6 7 8 8 BYTE_ORDER_MSB_LAST ADDRESS_GRANULARITY_BYTE /end PROTOCOL_LAYER
    /begin XCP_ON_CAN 0x0100
      {ids}
    /end XCP_ON_CAN
  /end IF_DATA
/end MODULE /end PROJECT
""")


def test_every_can_id_keeps_its_extended_flag_through_a_round_trip():
    from workbench.a2l.xcp_write import format_if_data_xcp

    config = read_xcp_config(_can_block("CAN_ID_BROADCAST 0x80000100 CAN_ID_MASTER 0x98FF0000 CAN_ID_SLAVE 0x7F1"))
    can = config.can
    assert (can.can_id_broadcast, can.can_id_master, can.can_id_slave) == (
        CanId(0x100, extended=True), CanId(0x18FF0000, extended=True), CanId(0x7F1))
    written = format_if_data_xcp(config)
    assert "CAN_ID_BROADCAST 0x80000100" in written and "CAN_ID_MASTER 0x98FF0000" in written
    assert "CAN_ID_SLAVE 0x7F1" in written


def test_a_standard_can_id_out_of_range_says_how_an_extended_one_is_written():
    with pytest.raises(A2lParseError, match=r"XCP_ON_CAN CAN_ID_MASTER: CAN id 0x18FF0000 does not fit a standard "
                                            r"frame; a 29-bit id has bit 31 set in the A2L \(0x98FF0000\)") as info:
        read_xcp_config(_can_block("CAN_ID_MASTER 0x18FF0000 CAN_ID_SLAVE 0x7F1"))
    assert info.value.line == 5
