"""The driver configuration between api.c's // <initCbk> markers: round trip and marker errors."""

from __future__ import annotations

import shutil

import pytest

from workbench import demo
from workbench.can.callbacks import callback_lines, splice, write_callbacks
from workbench.can.mailboxes import MailboxOrder
from workbench.can.table import build_table, load_networks
from workbench.errors import InputError

# Thesis figure 55, lines 3112-3142 (the OCR'd typos of the figure corrected).
FIGURE_55 = """
//callbacks automatically generated for FLCU_TO_PCM_003
API_CAN_setPduInitValues(CAN2_MSG_TX_000, DataInitPduIntel);
CanNetwork_SetTxPeriod(CAN2_MSG_TX_000, 100);
CanNetwork_SetTxDlc(CAN2_MSG_TX_000, 8);
CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_000, TRUE);

//callbacks automatically generated for FLCU_TO_PCM_002
API_CAN_setPduInitValues(CAN2_MSG_TX_001, DataInitPduIntel);
CanNetwork_SetTxPeriod(CAN2_MSG_TX_001, 100);
CanNetwork_SetTxDlc(CAN2_MSG_TX_001, 4);
CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_001, TRUE);

//callbacks automatically generated for FLCU_TO_PCM_001
API_CAN_setPduInitValues(CAN2_MSG_TX_002, DataInitPduIntel);
CanNetwork_SetTxPeriod(CAN2_MSG_TX_002, 100);
CanNetwork_SetTxDlc(CAN2_MSG_TX_002, 4);
CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_002, TRUE);

//callbacks automatically generated for PCM_TO_FLCU_002
CanNetwork_SetRxPeriod(CAN2_MSG_RX_000, 100);
CanNetwork_SetRxTimeout(CAN2_MSG_RX_000, 300);
CanNetwork_SetRxDlc(CAN2_MSG_RX_000, 4);
CanNetwork_EnableDisableReceivedMessages(CAN2_MSG_RX_000, TRUE);

//callbacks automatically generated for PCM_TO_FLCU_001
CanNetwork_SetRxPeriod(CAN2_MSG_RX_001, 100);
CanNetwork_SetRxTimeout(CAN2_MSG_RX_001, 300);
CanNetwork_SetRxDlc(CAN2_MSG_RX_001, 1);
CanNetwork_EnableDisableReceivedMessages(CAN2_MSG_RX_001, TRUE);
"""

API_C = (
    "/* api.c */\r\n"
    "#include \"api.h\"\r\n"
    "\r\n"
    "void API_CAN2_initCbk(void)\r\n"
    "{\r\n"
    "    // DO NOT DELETE THESE MARKERS FOR CALLBACKS GENERATION\r\n"
    "    //  <initCbk>  \r\n"
    "    stale_call();\r\n"
    "\t// </initCbk>\r\n"
    "}\r\n"
    "/* caf\xe9 */ int tail;   \r\n"
).encode("latin-1")


def _messages(order=MailboxOrder.FILE):
    return build_table(load_networks([demo.dbc_can2()]), "FLCU", order).messages


def test_reverse_order_generates_thesis_figure_55():
    assert "\n".join(callback_lines(_messages(MailboxOrder.REVERSE))) == FIGURE_55


def test_demo_api_c_regenerates_without_a_diff(tmp_path):
    api = shutil.copy(demo.path("assets", "ecu", "api.c"), tmp_path / "api.c")
    before = api.read_bytes()
    assert write_callbacks(api, _messages()) is False
    assert api.read_bytes() == before


def test_round_trip_keeps_everything_outside_the_markers(tmp_path):
    api = tmp_path / "api.c"
    api.write_bytes(API_C)
    assert write_callbacks(api, _messages()) is True
    first = api.read_bytes()
    head, rest = first.split(b"    //  <initCbk>  \r\n")
    body, tail = rest.split(b"\t// </initCbk>\r\n")
    assert head == API_C.split(b"    //  <initCbk>")[0]
    assert tail == "}\r\n/* caf\xe9 */ int tail;   \r\n".encode("latin-1")
    assert b"stale_call" not in body
    assert body.startswith(b"\r\n    //callbacks automatically generated for FLCU_TO_PCM_001\r\n")
    assert all(line.startswith(b"    ") or line == b"" for line in body.split(b"\r\n"))
    assert b"\n" not in body.replace(b"\r\n", b"")  # the start marker's CRLF throughout
    assert write_callbacks(api, _messages()) is False  # generating twice: no diff
    assert api.read_bytes() == first


def test_order_change_rewrites_only_between_the_markers(tmp_path):
    api = tmp_path / "api.c"
    api.write_bytes(API_C)
    write_callbacks(api, _messages())
    file_order = api.read_bytes()
    assert write_callbacks(api, _messages(MailboxOrder.REVERSE)) is True
    reverse = api.read_bytes()
    assert reverse != file_order
    assert reverse.split(b"//  <initCbk>")[0] == file_order.split(b"//  <initCbk>")[0]
    assert reverse.split(b"// </initCbk>")[1] == file_order.split(b"// </initCbk>")[1]


@pytest.mark.parametrize(
    "content, error",
    [
        (b"int a;\n// </initCbk>\n", r"api\.c: no '// <initCbk>' marker line"),
        (b"// <initCbk>\nint a;\n", r"api\.c: no '// </initCbk>' marker line"),
        (b"// <initCbk>\n// <initCbk>\n// </initCbk>\n", r"api\.c:2: second '// <initCbk>' marker \(the first is at line 1\)"),
        (b"// <initCbk>\n// </initCbk>\n\n  // </initCbk>\n", r"api\.c:4: second '// </initCbk>' marker \(the first is at line 2\)"),
        (b"x;\n// </initCbk>\n// <initCbk>\n", r"api\.c:2: '// </initCbk>' comes before '// <initCbk>' \(line 3\)"),
        (b"/* // <initCbk> */\n// </initCbk>\n", r"api\.c: no '// <initCbk>' marker line"),
    ],
)
def test_marker_errors_leave_the_file_untouched(tmp_path, content, error):
    api = tmp_path / "api.c"
    api.write_bytes(content)
    stamp = api.stat().st_mtime_ns
    with pytest.raises(InputError, match=error):
        write_callbacks(api, _messages())
    assert api.read_bytes() == content and api.stat().st_mtime_ns == stamp
    assert [p.name for p in tmp_path.iterdir()] == ["api.c"]  # no temporary file left behind


def test_message_without_period_is_refused_before_writing(tmp_path, write_dbc):
    dbc = write_dbc('BO_ 16 M: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] "" PEER\n')
    messages = build_table(load_networks([dbc]), "ECU").messages
    api = tmp_path / "api.c"
    api.write_bytes(API_C)
    with pytest.raises(InputError, match=r"crafted_CAN2\.dbc:13: message M has no period"):
        write_callbacks(api, messages)
    assert api.read_bytes() == API_C


def test_a_node_without_messages_does_not_empty_the_block(tmp_path, write_dbc):
    dbc = write_dbc('BO_ 16 M: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] "" PEER\n', nodes="ECU PEER OTHER")
    api = tmp_path / "api.c"
    api.write_bytes(API_C)
    with pytest.raises(InputError, match=r"api\.c: the node sends and receives no message"):
        write_callbacks(api, build_table(load_networks([dbc]), "OTHER").messages)
    assert api.read_bytes() == API_C


def test_motorola_message_gets_motorola_init_data(write_dbc):
    dbc = write_dbc(
        'BO_ 16 M: 2 ECU\n SG_ A : 7|16@0+ (1,0) [0|65535] "" PEER\n',
        'BA_ "GenMsgCycleTime" BO_ 16 20;\n',
    )
    lines = callback_lines(build_table(load_networks([dbc]), "ECU").messages)
    assert "API_CAN_setPduInitValues(CAN2_MSG_TX_000, DataInitPduMotorola);" in lines


def test_end_marker_on_the_last_line_without_newline():
    assert splice("api.c", b"// <initCbk>\n// </initCbk>", ["", "x();", ""]) == b"// <initCbk>\n\nx();\n\n// </initCbk>"
