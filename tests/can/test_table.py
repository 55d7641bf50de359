"""The message table: the thesis's Message properties, roles, and the canMap mailboxes."""

from __future__ import annotations

import shutil

import pytest

from crafted import timing
from workbench import demo
from workbench.can.dbc_file import load_dbc
from workbench.can.mailboxes import MailboxOrder
from workbench.can.model import Role
from workbench.can.table import build_table, guess_network, load_networks, network_of
from workbench.errors import InputError

# The CAN3 validation network of thesis figure 76: ids "0x300".."0x331" as decimal-looking
# hex (0x300..0x309, 0x310..0x319, ...), 32 received by the ECU (EAXLE) and 32 sent by it.
CAN3_RX_IDS = [base + i for base in (0x300, 0x310, 0x320) for i in range(10)] + [0x330, 0x331]
CAN3_TX_IDS = [base + 0x300 for base in CAN3_RX_IDS]


def _can3(order=MailboxOrder.FILE):
    return build_table(load_networks([demo.dbc_can3()]), "EAXLE", order)


def _flcu(node="FLCU", order=MailboxOrder.FILE):
    return build_table(load_networks([demo.dbc_can2()]), node, order)


def test_can3_table_has_the_thesis_validation_messages():
    table = _can3()
    assert len(table.messages) == 64 and table.others == ()
    rx = [m for m in table.messages if m.role is Role.RX]
    tx = [m for m in table.messages if m.role is Role.TX]
    assert [m.frame_id for m in rx] == CAN3_RX_IDS
    assert [m.frame_id for m in tx] == CAN3_TX_IDS
    assert all(m.name.startswith("C3RX") for m in rx) and all(m.name.startswith("C3TX") for m in tx)
    assert [m.dlc for m in rx] == [1 + i % 8 for i in range(32)]
    assert {m.period_ms for m in table.messages} == {10, 50, 100, 1000}
    assert all(m.timeout_ms == 3 * m.period_ms and not m.timeout_is_default for m in table.messages)
    assert all(m.network == "CAN3" and m.type == "std" and m.unique_id and m.enable for m in table.messages)
    assert all(len(m.signals) == m.dlc for m in table.messages)  # one signal per byte
    assert [m.mailbox for m in rx] == [f"CAN3_MSG_RX_{i:03d}" for i in range(32)]
    assert [m.mailbox for m in tx] == [f"CAN3_MSG_TX_{i:03d}" for i in range(32)]


# Rows of figure 76 that the thesis's text renders legibly: (name, id, DLC, cycle time ms). The
# DBC follows them; where the figure's text is garbled it continues their five-period cycle.
FIGURE_76_ROWS = [
    ("C3RXAAA", 0x300, 1, 100), ("C3RXAAB", 0x301, 2, 50), ("C3RXAAI", 0x308, 1, 10), ("C3RXAAJ", 0x309, 2, 1000),
    ("C3RXAAK", 0x310, 3, 100), ("C3RXAAQ", 0x316, 1, 50), ("C3RXABA", 0x326, 3, 50), ("C3RXABF", 0x331, 8, 50),
    ("C3TXAAA", 0x600, 1, 1000), ("C3TXAAB", 0x601, 2, 100), ("C3TXAAJ", 0x609, 2, 10), ("C3TXAAK", 0x610, 3, 1000),
    ("C3TXAAL", 0x611, 4, 100), ("C3TXAAM", 0x612, 5, 50),
]


def test_can3_table_has_the_legible_rows_of_figure_76():
    messages = {m.name: m for m in _can3().messages}
    rows = [(name, messages[name].frame_id, messages[name].dlc, messages[name].period_ms) for name, *_ in FIGURE_76_ROWS]
    assert rows == FIGURE_76_ROWS


def test_can3_figure_77_under_reverse_order():
    table = _can3(MailboxOrder.REVERSE)
    c3rxaaa = next(m for m in table.messages if m.name == "C3RXAAA")
    assert (c3rxaaa.mailbox, c3rxaaa.frame_id, c3rxaaa.dlc, c3rxaaa.period_ms, c3rxaaa.timeout_ms) == (
        "CAN3_MSG_RX_031", 0x300, 1, 100, 300)
    assert c3rxaaa.role is Role.RX and c3rxaaa.type == "std" and c3rxaaa.signals[0].name == "Sgn1"


def test_flcu_table_in_file_order_matches_the_demo_api_h():
    table = _flcu()
    assert [(m.mailbox, m.name, m.frame_id, m.dlc) for m in table.messages] == [
        ("CAN2_MSG_TX_000", "FLCU_TO_PCM_001", 0x167, 4),
        ("CAN2_MSG_TX_001", "FLCU_TO_PCM_002", 0x123, 4),
        ("CAN2_MSG_TX_002", "FLCU_TO_PCM_003", 0x145, 8),
        ("CAN2_MSG_RX_000", "PCM_TO_FLCU_001", 0x110, 1),
        ("CAN2_MSG_RX_001", "PCM_TO_FLCU_002", 0x220, 4),
    ]
    assert all((m.period_ms, m.timeout_ms) == (100, 300) for m in table.messages)


def test_flcu_reverse_order_reproduces_thesis_figure_55():
    table = _flcu(order=MailboxOrder.REVERSE)
    assert [(m.mailbox, m.name) for m in table.messages] == [
        ("CAN2_MSG_TX_000", "FLCU_TO_PCM_003"),
        ("CAN2_MSG_TX_001", "FLCU_TO_PCM_002"),
        ("CAN2_MSG_TX_002", "FLCU_TO_PCM_001"),
        ("CAN2_MSG_RX_000", "PCM_TO_FLCU_002"),
        ("CAN2_MSG_RX_001", "PCM_TO_FLCU_001"),
    ]


def test_flcu_signal_properties():
    table = _flcu()
    fuel = next(m for m in table.messages if m.name == "FLCU_TO_PCM_001")
    level = fuel.signals[1].to_dict()
    assert level == {
        "Name": "FuelLevel", "BitStart": 8, "Length": 16, "ByteOrder": "Intel", "ValueType": "unsigned",
        "Factor": 0.01, "Offset": 0, "Min": 0, "Max": 100, "Unit": "%",
        "Comment": "Indicates the actual fuel level",
    }
    assert fuel.signals[1].raw_c_type == "uint16_T"


def test_order_by_id_and_by_name():
    by_id = _flcu(order=MailboxOrder.ID)
    assert [m.name for m in by_id.messages] == [
        "FLCU_TO_PCM_002", "FLCU_TO_PCM_003", "FLCU_TO_PCM_001", "PCM_TO_FLCU_001", "PCM_TO_FLCU_002"]
    by_name = _flcu("PCM", MailboxOrder.NAME)
    assert [(m.mailbox, m.name) for m in by_name.messages][:2] == [
        ("CAN2_MSG_TX_000", "PCM_TO_FLCU_001"), ("CAN2_MSG_TX_001", "PCM_TO_FLCU_002")]


def test_second_dbc_on_the_same_network_takes_the_next_free_mailboxes(write_dbc, tmp_path):
    extra = write_dbc(
        'BO_ 1024 ECU_STATUS: 2 FLCU\n SG_ Alive : 0|8@1+ (1,0) [0|255] "" PCM\n\n'
        'BO_ 1025 PCM_CMD: 1 PCM\n SG_ Cmd : 0|8@1+ (1,0) [0|255] "" FLCU\n',
        timing(1024, 20) + timing(1025, 20),
        name="extra_CAN2.dbc", nodes="FLCU PCM",
    )
    flcu = shutil.copy(demo.dbc_can2(), tmp_path / "FLCU_CAN2.dbc")
    table = build_table(load_networks([flcu, extra]), "FLCU")
    assert [(m.mailbox, m.name) for m in table.messages] == [
        ("CAN2_MSG_TX_000", "FLCU_TO_PCM_001"),
        ("CAN2_MSG_TX_001", "FLCU_TO_PCM_002"),
        ("CAN2_MSG_TX_002", "FLCU_TO_PCM_003"),
        ("CAN2_MSG_TX_003", "ECU_STATUS"),
        ("CAN2_MSG_RX_000", "PCM_TO_FLCU_001"),
        ("CAN2_MSG_RX_001", "PCM_TO_FLCU_002"),
        ("CAN2_MSG_RX_002", "PCM_CMD"),
    ]


def test_same_id_on_one_network_clears_unique_id(write_dbc, tmp_path):
    first = write_dbc('BO_ 272 A: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] "" PEER\n', timing(272, 10), name="a_CAN1.dbc")
    second = write_dbc('BO_ 272 B: 1 PEER\n SG_ T : 0|8@1+ (1,0) [0|255] "" ECU\n', timing(272, 10), name="b_CAN1.dbc")
    table = build_table(load_networks([first, second]), "ECU")
    assert {m.name: m.unique_id for m in table.messages} == {"A": False, "B": False}
    other_network = build_table(load_networks([first]) + [(load_dbc(second), "CAN4")], "ECU")
    assert all(m.unique_id for m in other_network.messages)


def test_messages_the_node_neither_sends_nor_receives_are_listed_apart(write_dbc):
    path = write_dbc(
        'BO_ 1 MINE: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] "" PEER\n\n'
        'BO_ 2 NOT_MINE: 1 PEER\n SG_ T : 0|8@1+ (1,0) [0|255] "" Vector__XXX\n',
        timing(1, 10) + timing(2, 10),
    )
    table = build_table(load_networks([path]), "ECU")
    assert [m.name for m in table.messages] == ["MINE"]
    assert [m.name for m in table.others] == ["NOT_MINE"] and table.others[0].mailbox is None
    assert table.to_dict()["not_in_table"] == ["NOT_MINE"]


def test_without_a_node_there_are_no_roles_or_mailboxes():
    table = _flcu(None)
    assert len(table.messages) == 5
    assert all(m.role is None and m.mailbox is None for m in table.messages)


def test_missing_timeout_is_three_periods(write_dbc):
    path = write_dbc('BO_ 5 M: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] "" PEER\n', timing(5, 40))
    (message,) = build_table(load_networks([path]), "ECU").messages
    assert (message.period_ms, message.timeout_ms, message.timeout_is_default) == (40, 120, True)


def test_unknown_node_is_an_input_error():
    with pytest.raises(InputError, match=r"node 'BCM' is not in this DBC \(nodes: PCM, FLCU\)"):
        _flcu("BCM")


def test_network_comes_from_the_option_or_the_file_name(tmp_path):
    assert guess_network("dbc/FLCU_CAN2.dbc") == "CAN2"
    assert guess_network("CAN3_validation.dbc") == "CAN3"
    assert guess_network("vehicle.dbc") is None
    assert guess_network("CAN1_to_CAN2.dbc") is None
    assert network_of("vehicle.dbc", "can4") == "CAN4"
    with pytest.raises(InputError, match="give --network"):
        network_of(tmp_path / "vehicle.dbc")
    with pytest.raises(InputError, match="unknown network 'CAN7'"):
        network_of("x.dbc", "CAN7")
