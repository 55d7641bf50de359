"""DBC loading errors and every validation finding, on crafted bad DBCs."""

from __future__ import annotations

from pathlib import Path

import pytest
from crafted import timing

from workbench import demo
from workbench.can.dbc_file import load_dbc
from workbench.can.model import SignalOfMsg, messages_of
from workbench.can.validation import bit_positions, check_dbcs
from workbench.errors import InputError
from workbench.findings import Severity

SIGNAL = '"" PEER'


def _findings(path, network="CAN2", node=None):
    return check_dbcs([(load_dbc(path), network)], node).findings


def _codes(findings):
    """(kind, message, signal or None, line) of each finding; its name is MESSAGE or MESSAGE.SIGNAL."""
    return [(f.kind, *_message_and_signal(f.name), f.line) for f in findings]


def _message_and_signal(name):
    message, _, signal = name.partition(".")
    return message, signal or None


def test_demo_flcu_dbc_is_clean():
    assert _findings(demo.dbc_can2()) == []
    assert _findings(demo.dbc_can2(), node="FLCU") == []


def test_overlapping_signals(write_dbc):
    path = write_dbc(
        "BO_ 16 M: 2 ECU\n"
        f" SG_ A : 0|4@1+ (1,0) [0|15] {SIGNAL}\n"
        f" SG_ B : 2|4@1+ (1,0) [0|15] {SIGNAL}\n"
        f" SG_ C : 8|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 10, 30),
    )
    (finding,) = _findings(path)
    assert _codes([finding]) == [("overlap", "M", "B", 15)]
    assert str(finding) == f"{path}:15: error: M.B: overlaps A in bits 2..3"
    assert (finding.block, finding.severity) == ("SG_", Severity.ERROR)


def test_motorola_signal_overlap_and_layout(write_dbc):
    # Motorola 7|16: byte 0 bits 7..0 then byte 1 bits 15..8; it meets the Intel signal in byte 1.
    signal = SignalOfMsg("X", 7, 16, "Motorola", False, False, 1, 0, None, None, "", "")
    assert bit_positions(signal) == [7, 6, 5, 4, 3, 2, 1, 0, 15, 14, 13, 12, 11, 10, 9, 8]
    path = write_dbc(
        "BO_ 16 M: 3 ECU\n"
        f" SG_ BIG : 7|16@0+ (1,0) [0|65535] {SIGNAL}\n"
        f" SG_ LITTLE : 12|4@1+ (1,0) [0|15] {SIGNAL}\n"
        f" SG_ FREE : 16|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 10, 30),
    )
    assert _codes(_findings(path)) == [("overlap", "M", "LITTLE", 15)]


def test_multiplexed_signals_overlap_only_under_the_same_selector(write_dbc):
    path = write_dbc(
        "BO_ 16 M: 2 ECU\n"
        f" SG_ MUX M : 0|4@1+ (1,0) [0|15] {SIGNAL}\n"
        f" SG_ ONE m1 : 8|8@1+ (1,0) [0|255] {SIGNAL}\n"
        f" SG_ TWO m2 : 8|8@1+ (1,0) [0|255] {SIGNAL}\n"
        f" SG_ ALSO_ONE m1 : 12|4@1+ (1,0) [0|15] {SIGNAL}\n",
        timing(16, 10, 30),
    )
    assert _codes(_findings(path)) == [("overlap", "M", "ALSO_ONE", 17)]


def test_signal_beyond_dlc(write_dbc):
    path = write_dbc(f"BO_ 16 M: 1 ECU\n SG_ WIDE : 4|8@1+ (1,0) [0|255] {SIGNAL}\n", timing(16, 10, 30))
    (finding,) = _findings(path)
    assert _codes([finding]) == [("beyond-dlc", "M", "WIDE", 14)]
    assert "bits 8..11 lie beyond the DLC of 1 bytes" in str(finding)


def test_signal_whose_raw_value_fits_no_c_type(write_dbc):
    path = write_dbc(
        "BO_ 16 M: 8 ECU\n"
        f" SG_ HALF : 0|16@1- (1,0) [0|0] {SIGNAL}\n"
        f" SG_ SINGLE : 16|32@1- (1,0) [0|0] {SIGNAL}\n",
        timing(16, 10, 30) + "SIG_VALTYPE_ 16 HALF : 1;\nSIG_VALTYPE_ 16 SINGLE : 1;\n",
    )
    (finding,) = _findings(path)
    assert _codes([finding]) == [("signal-type", "M", "HALF", 14)]
    assert finding.message == "M.HALF: a float CAN signal is 32 or 64 bits long, not 16"
    (message,) = messages_of(load_dbc(path), None, None)
    assert [s.value_type for s in message.signals] == ["float16", "float32"]  # as the DBC says, not float64


def test_duplicate_ids_and_names_in_one_file(write_dbc):
    path = write_dbc(
        f"BO_ 16 FIRST: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n"
        f"BO_ 16 SECOND: 1 ECU\n SG_ B : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n"
        f"BO_ 17 FIRST: 1 ECU\n SG_ C : 0|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 10, 30) + timing(17, 10, 30),
    )
    codes = _codes(_findings(path))
    assert ("duplicate-id", "SECOND", None, 16) in codes
    assert ("duplicate-name", "FIRST", None, 19) in codes  # the second BO_ named FIRST


def test_duplicate_ids_across_dbcs_of_one_network(write_dbc):
    first = write_dbc(f"BO_ 16 A: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|255] {SIGNAL}\n", timing(16, 10, 30), name="a.dbc")
    second = write_dbc(f"BO_ 16 B: 1 ECU\n SG_ T : 0|8@1+ (1,0) [0|255] {SIGNAL}\n", timing(16, 10, 30), name="b.dbc")
    same_network = check_dbcs([(load_dbc(first), "CAN2"), (load_dbc(second), "CAN2")]).findings
    assert [(f.kind, f.name, Path(f.file).name) for f in same_network] == [("duplicate-id", "B", "b.dbc")]
    assert f"also used by A ({first}:13)" in str(same_network[0])
    assert check_dbcs([(load_dbc(first), "CAN2"), (load_dbc(second), "CAN3")]).findings == []
    assert check_dbcs([(load_dbc(first), None), (load_dbc(second), None)]).findings == []  # no network: each file alone


def test_extended_and_standard_ids_do_not_collide(write_dbc):
    path = write_dbc(
        f"BO_ 16 STD: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n"
        f"BO_ 2147483664 EXT: 1 ECU\n SG_ B : 0|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 10, 30) + timing(2147483664, 10, 30) + 'BA_ "VFrameFormat" BO_ 2147483664 1;\n',
    )
    assert _findings(path) == []


def test_missing_period_and_timeout(write_dbc):
    path = write_dbc(
        f"BO_ 16 NO_TIMEOUT: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n"
        f"BO_ 17 NOTHING: 1 ECU\n SG_ B : 0|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 20),
    )
    findings = _findings(path)
    assert _codes(findings) == [("missing-timeout", "NO_TIMEOUT", None, 13), ("missing-period", "NOTHING", None, 16)]
    assert "no GenMsgTimeoutTime: using 3 × period = 60 ms" in str(findings[0])
    assert "NOTHING: no GenMsgCycleTime (or 0) and no GenMsgTimeoutTime: period and timeout are unknown" in str(
        findings[1])  # one finding for the message, not one per attribute
    assert {f.severity for f in findings} == {Severity.WARNING}


def test_attributes_a_dbc_never_defines_are_one_finding_for_the_file(write_dbc):
    messages = "".join(f"BO_ {16 + i} M{i}: 1 ECU\n SG_ S{i} : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n" for i in range(5))
    path = write_dbc(messages)
    path.write_text(path.read_text().replace("GenMsgCycleTime", "OtherTime").replace("GenMsgTimeoutTime", "Other2"))
    (finding,) = _findings(path)
    assert (finding.kind, finding.severity, finding.line, finding.location) == (
        "missing-period", Severity.WARNING, 0, str(path))
    assert finding.message == (f"{path.name}: the DBC defines no GenMsgCycleTime: the periods (and so the default "
                               "timeouts) of its 5 messages are unknown")
    path.write_text(path.read_text().replace("OtherTime", "GenMsgCycleTime") + "".join(timing(16 + i, 10)
                                                                                        for i in range(5)))
    (finding,) = _findings(path)
    assert (finding.kind, finding.severity) == ("missing-timeout", Severity.INFO)
    assert "defines no GenMsgTimeoutTime: the timeout of each of its 5 messages with a period is 3 × period" in str(
        finding)


def test_attribute_default_counts_as_given(write_dbc):
    path = write_dbc(f"BO_ 16 M: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n")
    text = path.read_text().replace('BA_DEF_DEF_ "GenMsgCycleTime" 0;', 'BA_DEF_DEF_ "GenMsgCycleTime" 50;')
    path.write_text(text.replace('BA_DEF_DEF_ "GenMsgTimeoutTime" 0;', 'BA_DEF_DEF_ "GenMsgTimeoutTime" 500;'))
    assert _findings(path) == []


def test_standard_id_above_0x7ff_is_one_load_warning_the_check_repeats(write_dbc):
    path = write_dbc(
        f"BO_ 2048 TOO_BIG: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(2048, 10, 30) + 'CM_ BO_ 2048 "kept with its message";\n',
    )
    dbc = load_dbc(path)
    (finding,) = _findings(path)
    assert dbc.warnings == (finding,) and _codes([finding]) == [("id-format", "TOO_BIG", None, 13)]
    assert str(finding) == (f"{path}:13: warning: message TOO_BIG: id 0x800 does not fit in 11 bits but the BO_ id "
                            "lacks the extended flag: read as extended id 0x800, as CANdb++ does (write 2147485696)")
    (message,) = dbc.database.messages
    assert (message.frame_id, message.is_extended_frame, message.comment) == (0x800, True, "kept with its message")
    assert messages_of(dbc, None, None)[0].period_ms == 10  # its BA_ follows it


def test_vframeformat_disagreeing_with_the_id(write_dbc):
    path = write_dbc(
        f"BO_ 16 SAYS_EXTENDED: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n"
        f"BO_ 2147483665 SAYS_STANDARD: 1 ECU\n SG_ B : 0|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 10, 30) + timing(2147483665, 10, 30)
        + 'BA_ "VFrameFormat" BO_ 16 1;\nBA_ "VFrameFormat" BO_ 2147483665 0;\n',
    )
    findings = _findings(path)
    assert _codes(findings) == [("id-format", "SAYS_EXTENDED", None, 13), ("id-format", "SAYS_STANDARD", None, 16)]
    assert "VFrameFormat is ExtendedCAN but the id is standard" in str(findings[0])
    assert "VFrameFormat is StandardCAN but the id is extended" in str(findings[1])


def test_fixcal_name_collisions(write_dbc):
    path = write_dbc(
        f"BO_ 16 A: 1 ECU\n SG_ Level : 0|8@1+ (1,0) [0|255] {SIGNAL}\n\n"
        f"BO_ 17 B: 1 PEER\n SG_ LEVEL : 0|8@1+ (1,0) [0|255] \"\" ECU\n\n"
        f"BO_ 18 C: 1 PEER\n SG_ Level : 0|8@1+ (1,0) [0|255] \"\" Vector__XXX\n",
        timing(16, 10, 30) + timing(17, 10, 30) + timing(18, 10, 30),
    )
    (finding,) = _findings(path)
    assert _codes([finding]) == [("fixcal-collision", "A", "Level", 14)]
    assert finding.severity is Severity.INFO  # a hint: fixcal refuses the names, the DBC is not wrong
    assert str(finding) == (f"{path}:14: info: A.Level: workbench dbc fixcal would define 1 fix calibration name "
                            "more than once (cfLEVEL_EN/_VALUE by A.Level, B.LEVEL, C.Level); message-qualified "
                            "names (--qualified) avoid this")
    (for_ecu,) = _findings(path, node="ECU")  # C is not in ECU's table
    assert "by A.Level, B.LEVEL)" in str(for_ecu)


def test_can3_validation_dbc_shares_signal_names_between_messages():
    (hint,) = _findings(demo.dbc_can3(), network="CAN3")  # one hint, not one error per shared name
    assert (hint.kind, hint.severity) == ("fixcal-collision", Severity.INFO)
    assert "would define 8 fix calibration names more than once (cfSGN1_EN/_VALUE by C3RXAAA.Sgn1, C3RXAAB.Sgn1, " \
           "C3RXAAC.Sgn1 and 61 more; cfSGN2_EN/_VALUE by" in hint.message
    assert hint.message.endswith("and 5 more); message-qualified names (--qualified) avoid this")
    assert check_dbcs([(load_dbc(demo.dbc_can3()), "CAN3")], qualified=True).findings == []  # cfC3RXAAA_SGN1_EN ...


def test_unknown_node_in_check():
    with pytest.raises(InputError, match="node 'BCM'"):
        _findings(demo.dbc_can2(), node="BCM")


def test_syntax_error_names_file_line_and_column(write_dbc):
    path = write_dbc(f"BO_ 16 M: 1 ECU\n SG_ A 0|8@1+ (1,0) [0|255] {SIGNAL}\n")
    with pytest.raises(InputError) as error:
        load_dbc(path)
    message = str(error.value)
    assert message.startswith(f"{path}:14:8: Invalid syntax") and "\n" not in message




def test_unreadable_file(tmp_path):
    with pytest.raises(InputError, match=r"missing\.dbc: no such file$"):
        load_dbc(tmp_path / "missing.dbc")


@pytest.mark.parametrize(
    ("content", "error"),
    [
        (b"", r"empty\.dbc: not a DBC: the file is empty$"),
        (b"  \r\n\n", r"empty\.dbc: not a DBC: the file is empty$"),
        (b"\x7fELF\x01\x01\x01\x00\x00", r"empty\.dbc: not a DBC: binary content \(a NUL byte at offset 7\)$"),
    ],
)
def test_empty_and_binary_files_are_not_dbcs(tmp_path, content, error):
    path = tmp_path / "empty.dbc"
    path.write_bytes(content)
    with pytest.raises(InputError, match=error):
        load_dbc(path)


def test_utf16_with_bom_loads(tmp_path):
    path = tmp_path / "FLCU_CAN2.dbc"
    path.write_bytes(demo.dbc_can2().read_text(encoding="utf-8").encode("utf-16"))  # BOM + UTF-16
    assert [m.name for m in load_dbc(path).database.messages][:2] == ["PCM_TO_FLCU_001", "PCM_TO_FLCU_002"]


def test_syntax_error_quotes_a_short_excerpt_without_control_characters(write_dbc):
    path = write_dbc(f'BO_ 16 M: 1 ECU\n SG_ {"A" * 100} : 0|8@1+ (1,0) [0|0] "" PEER ? {"b" * 100}\n')
    with pytest.raises(InputError) as error:
        load_dbc(path)
    assert str(error.value) == f'{path}:14:136: Invalid syntax: "… : 0|8@1+ (1,0) [0|0] "" PEER >>!<<? {"b" * 28}…"'
    path = write_dbc("BO_ 16 M: 1 ECU\x01\n")
    with pytest.raises(InputError, match=r':13:16: Invalid syntax: "BO_ 16 M: 1 ECU>>!<<\?"$'):
        load_dbc(path)


def test_windows_1252_comments_load(write_dbc):
    path = write_dbc(f"BO_ 16 M: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] {SIGNAL}\n", timing(16, 10, 30))
    path.write_bytes(path.read_bytes() + 'CM_ SG_ 16 A "Öldruck in °C";\n'.encode("cp1252"))
    assert load_dbc(path).database.messages[0].signals[0].comment == "Öldruck in °C"


def test_signals_keep_file_order(write_dbc):
    path = write_dbc(
        f"BO_ 16 M: 2 ECU\n SG_ HIGH : 8|8@1+ (1,0) [0|255] {SIGNAL}\n SG_ LOW : 0|8@1+ (1,0) [0|255] {SIGNAL}\n",
        timing(16, 10, 30),
    )
    dbc = load_dbc(path)
    assert [s.name for s in dbc.database.messages[0].signals] == ["HIGH", "LOW"]
    assert (dbc.message_line("M"), dbc.signal_line(13, "LOW"), dbc.message_line("M", 1)) == (13, 15, 0)
