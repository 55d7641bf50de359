"""What CANdb++ reads and cantools refuses: one crafted DBC per class, loaded with a located warning each.

For every class: the warning's kind, line and words; the values read are the file's; the
file loads the same way for ``dbc table``, ``dbc check`` and ``dbc fixcal``.
"""

from __future__ import annotations

import json

import pytest
from crafted import timing

from workbench.can.dbc_file import load_dbc
from workbench.can.dbc_repair_attributes import FRAME_FORMATS
from workbench.can.model import messages_of
from workbench.cli import main
from workbench.errors import InputError
from workbench.findings import Severity

SIGNAL = '"" PEER'
PLAIN = f" SG_ S : 0|8@1+ (1,0) [0|255] {SIGNAL}\n"


def _line(path, text: str) -> int:
    """The 1-based line of the first occurrence of ``text`` in the file."""
    return next(number for number, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def _warnings(dbc) -> list[tuple[str, int, str]]:
    return [(w.kind, w.line, w.message) for w in dbc.warnings]


def _message_m_with(write_dbc, statements: str):
    """A DBC of one message M (id 16, signal S, period 10 ms) followed by ``statements``."""
    return write_dbc(f"BO_ 16 M: 1 ECU\n{PLAIN}", timing(16, 10, 30) + statements)


def _message(dbc, name: str):
    return dbc.database.get_message_by_name(name)


def test_standard_id_above_0x7ff_is_read_as_extended_with_its_references(write_dbc):
    path = write_dbc(
        "BO_ 2048 BIG: 4 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] \"\" PEER\n SG_ F : 0|32@1- (1,0) [0|0] \"\" PEER\n",
        timing(2048, 20, 100) + 'CM_ BO_ 2048 "big";\nVAL_ 2048 A 1 "one" 0 "zero" ;\nSIG_VALTYPE_ 2048 F : 1;\n',
    )
    dbc = load_dbc(path)
    assert _warnings(dbc) == [("id-format", 13, "message BIG: id 0x800 does not fit in 11 bits but the BO_ id lacks "
                               "the extended flag: read as extended id 0x800, as CANdb++ does (write 2147485696)")]
    big = _message(dbc, "BIG")
    assert (big.frame_id, big.is_extended_frame, big.comment) == (0x800, True, "big")
    assert big.get_signal_by_name("A").choices == {1: "one", 0: "zero"} and big.get_signal_by_name("F").is_float
    (message,) = messages_of(dbc, None, None)
    assert (message.period_ms, message.timeout_ms, message.type) == (20, 100, "ext")


@pytest.mark.parametrize(("frame_id", "spelled"), [
    (1075054137, "id 1075054137 (0x40140639)"),  # 30 bits without the extended flag
    (4294967295, "id 4294967295 (0x7FFFFFFF, extended)"),  # 31 bits with it
    (8589934592, "id 8589934592"),  # beyond 32 bits: cantools would cut it to 0
    (-16, "id -16"),
])
def test_an_id_no_can_frame_has_skips_its_message_and_references(write_dbc, frame_id, spelled):
    path = write_dbc(f"BO_ {frame_id} ODD: 1 ECU\n{PLAIN}\nBO_ 16 KEPT: 1 ECU\n{PLAIN}",
                     timing(frame_id, 10, 30) + timing(16, 10, 30) + f'VAL_ {frame_id} S 1 "one" ;\n'
                     f'CM_ SG_ {frame_id} S "gone with it";\n')
    dbc = load_dbc(path)
    (warning,) = _warnings(dbc)
    assert warning[:2] == ("id-range", 13) and spelled in warning[2]
    assert warning[2].endswith("is no CAN id (those have 11 or 29 bits): message skipped with its signals and "
                               "references")
    assert [m.name for m in dbc.database.messages] == ["KEPT"]


@pytest.mark.parametrize("placeholder_id", [0x40000000, 0xC0000000, 3])
def test_candb_placeholder_message_is_skipped_whatever_its_id(write_dbc, tmp_path, placeholder_id, capsys):
    path = write_dbc(
        f"BO_ {placeholder_id} VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\n"
        f" SG_ Loose : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n SG_ Other : 0|16@1+ (1,0) [0|0] \"\" Vector__XXX\n\n"
        f"BO_ 16 REAL: 1 ECU\n{PLAIN}",
        timing(16, 10, 30) + f'CM_ SG_ {placeholder_id} Loose "unassigned";\nVAL_ {placeholder_id} Loose 1 "x" ;\n'
        f'BA_ "GenMsgCycleTime" BO_ {placeholder_id} 10;\n',
    )
    dbc = load_dbc(path)
    assert dbc.warnings == () and [m.name for m in dbc.database.messages] == ["REAL"]
    # one loader: table, check and fixcal agree (table used to refuse id 0x40000000 while check loaded it)
    assert main(["dbc", "table", str(path), "--json"]) == 0
    assert [m["Name"] for m in json.loads(capsys.readouterr().out)["messages"]] == ["REAL"]
    assert main(["dbc", "check", str(path)]) == 0
    assert main(["dbc", "fixcal", str(path), "--node", "ECU", "-o", str(tmp_path / "out")]) == 0
    assert "3 calibrations for ECU" in capsys.readouterr().err


def test_names_that_start_with_a_digit_are_kept_as_written(write_dbc, capsys):
    path = write_dbc(
        "BO_ 16 2017_5: 2 1ECU\n SG_ 0_COUNTER M : 0|4@1+ (1,0) [0|15] \"\" 2PEER,PEER\n"
        " SG_ 5_SEC m1 : 8|8@1+ (1,0) [0|255] \"\" 2PEER\n",
        timing(16, 10, 30) + 'VAL_ 16 0_COUNTER 1 "one" ;\nCM_ SG_ 16 5_SEC "five";\nVAL_TABLE_ 3T 1 "x" ;\n',
        nodes="ECU PEER 1ECU 2PEER",
    )
    dbc = load_dbc(path)
    assert [w[:2] for w in _warnings(dbc)] == [("name-syntax", 11), ("name-syntax", 11), ("name-syntax", 13),
                                                ("name-syntax", 14), ("name-syntax", 15),
                                                ("name-syntax", _line(path, "VAL_TABLE_"))]
    assert dbc.warnings[2].message == "message name 2017_5 starts with a digit, which DBC names may not: kept as written"
    message = _message(dbc, "2017_5")
    counter, five = message.signals
    assert (counter.name, counter.choices, counter.receivers, message.senders) == ("0_COUNTER", {1: "one"},
                                                                                    ["2PEER", "PEER"], ["1ECU"])
    assert (five.name, five.comment, five.multiplexer_signal, five.multiplexer_ids) == ("5_SEC", "five", "0_COUNTER", [1])
    assert [n.name for n in dbc.database.nodes] == ["ECU", "PEER", "1ECU", "2PEER"]
    assert list(dbc.database.dbc.value_tables) == ["3T"]
    assert message.decode(bytes([1, 7])) == {"0_COUNTER": "one", "5_SEC": 7}
    assert main(["dbc", "table", str(path), "--node", "1ECU", "--csv"]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert rows[1].startswith("CAN2_MSG_TX_000,TX,2017_5,0x10,") and ",0_COUNTER,0,4," in rows[1]


def test_numbers_without_a_leading_zero(write_dbc):
    path = write_dbc("BO_ 16 M: 2 ECU\n SG_ T : 4|13@0+ (.25,-500) [-.5|1547.5] \"Nm\" PEER\n", timing(16, 10, 30))
    dbc = load_dbc(path)
    assert _warnings(dbc) == [("number-syntax", 14, ".25, -.5 written without a leading 0: read as 0.25, -0.5")]
    signal = _message(dbc, "M").signals[0]
    assert (signal.scale, signal.offset, signal.minimum, signal.maximum) == (0.25, -500, -0.5, 1547.5)


def test_comments_without_text_or_object(write_dbc):
    path = _message_m_with(write_dbc, 'CM_ SG_ 16 S;\nCM_ BO_ 16 ;\nCM_ SG_ 16 "which signal?";\n'
                                      'CM_ 16 "which object?";\nCM_ VAL_ 16 S 1 "one";\nCM_ BU_ ECU;\nCM_ "the file";\n')
    dbc = load_dbc(path)
    first = _line(path, "CM_ SG_ 16 S;")
    assert _warnings(dbc) == [
        ("comment-syntax", first, "CM_ SG_ 16 S: comment without text: read as an empty comment"),
        ("comment-syntax", first + 1, "CM_ BO_ 16: comment without text: read as an empty comment"),
        ("comment-syntax", first + 2, "CM_ SG_ ...: a signal comment without the signal's name: ignored"),
        ("comment-syntax", first + 3, "CM_ 16 ...: a comment belongs to BU_, BO_, SG_ or EV_ (or to the file): ignored"),
        ("comment-syntax", first + 4, "CM_ VAL_ ...: a comment belongs to BU_, BO_, SG_ or EV_ (or to the file): "
                                      "ignored"),
        ("comment-syntax", first + 5, "CM_ BU_ ECU: comment without text: read as an empty comment"),
    ]
    message = _message(dbc, "M")
    assert (message.comment, message.signals[0].comment, dbc.database.buses[0].comment) == ("", "", "the file")


@pytest.mark.parametrize("statement", [
    'VAL_ 16 NOPE 1 "x" ;', 'VAL_ 99 S 1 "x" ;', "SIG_VALTYPE_ 16 NOPE : 1;", "SG_MUL_VAL_ 16 NOPE S 1-1;",
    'CM_ SG_ 16 NOPE "x";', 'CM_ BO_ 99 "x";', 'BA_ "GenMsgCycleTime" BO_ 99 10;',
    'BA_ "GenMsgCycleTime" SG_ 16 NOPE 10;', "BO_TX_BU_ 99 : PEER;",
])
def test_references_to_messages_or_signals_that_do_not_exist_are_ignored(write_dbc, statement):
    path = _message_m_with(write_dbc, statement + "\n")
    dbc = load_dbc(path)
    ((kind, line, message),) = _warnings(dbc)
    assert (kind, line) == ("unknown-reference", _line(path, statement))
    assert message.endswith("no BO_ has id 0x63: ignored" if " 99 " in statement else
                            "message M has no signal NOPE: ignored")
    assert [s.name for s in _message(dbc, "M").signals] == ["S"]


def test_value_descriptions_without_text_and_statements_without_semicolon(write_dbc):
    path = _message_m_with(write_dbc, 'VAL_ 16 S 3 "three" 2 1 "one" 0\nCM_ "no end"\nBA_ "GenMsgTimeoutTime" BO_ 16 99')
    dbc = load_dbc(path)
    line = _line(path, "VAL_ 16")
    assert _warnings(dbc) == [
        ("value-description", line, "VAL_ 16 S: values 2, 0 without text: read with an empty one"),
        ("missing-semicolon", line, "VAL_ 16 S ...: no closing ';': closed at the end of line " + str(line)),
        ("missing-semicolon", line + 1, "CM_ \"no end\" ...: no closing ';': closed at the end of line " + str(line + 1)),
        ("missing-semicolon", line + 2, 'BA_ "GenMsgTimeoutTime" BO_ ...: no closing \';\': closed at the end of line '
                                        + str(line + 2)),
    ]
    assert _message(dbc, "M").signals[0].choices == {3: "three", 2: "", 1: "one", 0: ""}
    assert dbc.database.buses[0].comment == "no end" and messages_of(dbc, None, None)[0].timeout_ms == 99


def test_attributes_without_definition_are_defined_from_their_values(write_dbc):
    path = _message_m_with(write_dbc, 'BA_ "Count" BO_ 16 3;\nBA_ "Gain" SG_ 16 S 1.5;\nBA_ "Owner" BU_ ECU "me";\n'
                                      'BA_ "Mode" Fast;\nBA_REL_ "Wire" BU_SG_REL_ PEER SG_ 16 S 2;\n')
    dbc = load_dbc(path)
    count = _line(path, '"Count"')
    assert _warnings(dbc) == [
        ("attribute-definition", count, "attribute Count has no BA_DEF_: read as INT (1 value, as written)"),
        ("attribute-definition", count + 1, "attribute Gain has no BA_DEF_: read as FLOAT (1 value, as written)"),
        ("attribute-definition", count + 2, "attribute Owner has no BA_DEF_: read as STRING (1 value, as written)"),
        ("attribute-definition", count + 3, "attribute Mode has no BA_DEF_: read as STRING (1 value, as written)"),
        ("attribute-definition", count + 4, "attribute Wire has no BA_DEF_REL_: read as INT (1 value, as written)"),
    ]
    message = _message(dbc, "M")
    assert message.dbc.attributes["Count"].value == 3 and message.signals[0].dbc.attributes["Gain"].value == 1.5
    assert dbc.database.nodes[0].dbc.attributes["Owner"].value == "me"
    assert dbc.database.dbc.attributes["Mode"].value == "Fast"


def test_attribute_types_and_values_cantools_cannot_read(write_dbc):
    path = write_dbc(
        f"BO_ 16 M: 1 ECU\n{PLAIN}\nBO_ 17 N: 1 ECU\n{PLAIN}\nBO_ 18 O: 1 ECU\n{PLAIN}",
        timing(16, 10, 30) + timing(17, 10, 30) + timing(18, 10, 30)
        + 'BA_DEF_ BO_ "Receivable" BOOL False True;\nBA_DEF_ BO_ "GenMsgSendType" INT 0 8;\n'
        'BA_DEF_ BO_ "Level" ENUM "Low","High";\n'
        'BA_ "Receivable" BO_ 16 False;\nBA_ "GenMsgSendType" BO_ 16 1;\nBA_ "Level" BO_ 16 "High";\n'
        'BA_ "Level" BO_ 17 5;\nBA_ "VFrameFormat" BO_ 17 "ExtendedCAN";\nBA_ "VFrameFormat" BO_ 18 7;\n'
        'BA_ "GenMsgCycleTime" BO_ 18 "25";\nBA_ "GenMsgTimeoutTime" BO_ 17 soon;\n',
    )
    dbc = load_dbc(path)
    line = _line(path, '"Receivable" BOOL')
    assert _warnings(dbc) == [
        ("attribute-type", line, "attribute Receivable: type BOOL is not a DBC attribute type: read as STRING (its "
                                 "values as written)"),
        ("attribute-type", line + 1, "attribute GenMsgSendType is INT: cantools reads a send type only as a name, so "
                                     "it is read as STRING (its values as written)"),
        ("attribute-value", line + 5, 'attribute Level: ENUM value given by name "High": read as its index 1'),
        ("attribute-value", line + 6, "attribute Level: value 5 is none of its 2 choices (0..1): ignored"),
        ("attribute-value", line + 7, 'attribute VFrameFormat: ENUM value given by name "ExtendedCAN": read as its '
                                      "index 1"),
        ("attribute-value", line + 8, "attribute VFrameFormat: value 7 is none of its 2 choices (0..1): ignored"),
        ("attribute-value", line + 9, 'attribute GenMsgCycleTime is INT but the value is written as text "25": read '
                                      "as 25"),
        ("attribute-value", line + 10, "attribute GenMsgTimeoutTime is INT but the value is soon: ignored"),
    ]
    m, n, o = (_message(dbc, name) for name in "MNO")
    assert (m.dbc.attributes["Receivable"].value, m.send_type, m.dbc.attributes["Level"].value) == ("False", "1", 1)
    assert "Level" not in n.dbc.attributes and n.dbc.attributes["VFrameFormat"].value == 1
    assert o.dbc.attributes["GenMsgCycleTime"].value == 25 and "VFrameFormat" not in o.dbc.attributes


def test_frame_format_as_int_without_default_and_as_string(write_dbc):
    messages = f"BO_ 16 M: 1 ECU\n{PLAIN}\nBO_ 17 N: 1 ECU\n{PLAIN}"
    path = write_dbc(messages, timing(16, 10, 30) + timing(17, 10, 30) + 'BA_ "VFrameFormat" BO_ 17 20;\n')
    path.write_text(path.read_text().replace('BA_DEF_ BO_ "VFrameFormat" ENUM "StandardCAN","ExtendedCAN";',
                                             'BA_DEF_ BO_ "VFrameFormat" INT 0 15;')
                    .replace('BA_DEF_DEF_ "VFrameFormat" "StandardCAN";', ""))
    dbc = load_dbc(path)
    assert [w[::2] for w in _warnings(dbc)] == [
        ("attribute-value", "attribute VFrameFormat: value 20 is none of its 16 choices (0..15): ignored"),
        ("attribute-definition", "attribute VFrameFormat is INT without a BA_DEF_DEF_: its default is its minimum 0, "
                                 "as in CANdb++"),
    ]
    assert [m.is_fd for m in dbc.database.messages] == [False, False]
    path.write_text(path.read_text().replace("INT 0 15;", "STRING;").replace("BO_ 17 20;", 'BO_ 17 "ExtendedCAN_FD";'))
    dbc = load_dbc(path)
    assert [w[0] for w in _warnings(dbc)] == ["attribute-type"]
    assert [m.is_fd for m in dbc.database.messages] == [False, True]


def test_a_numeric_attributes_default_that_is_no_number_is_ignored(write_dbc, capsys):
    # cantools refused the whole file: "[<class 'decimal.ConversionSyntax'>]", without a place
    path = _message_m_with(
        write_dbc, 'BA_DEF_ BO_ "Level" INT 0 9;\nBA_DEF_DEF_ "Level" "high";\nBA_DEF_ SG_ "Gain" FLOAT 0 1;\n'
                   'BA_DEF_DEF_ "Gain" "";\nBA_DEF_ BO_ "Mask" HEX 0 255;\nBA_DEF_DEF_  "Mask" many;\n'
                   'BA_DEF_REL_ BU_SG_REL_ "Wire" INT 0 9;\nBA_DEF_DEF_REL_ "Wire" "x";\n'
                   'BA_DEF_ BO_ "Quoted" INT 0 99;\nBA_DEF_DEF_ "Quoted" "10";\nBA_ "Level" BO_ 16 4;\n')
    dbc = load_dbc(path)
    line = _line(path, 'BA_DEF_DEF_ "Level"')
    assert [(w.kind, w.line, w.column, w.message) for w in dbc.warnings] == [
        ("attribute-value", line, 21, 'attribute Level is INT but its default "high" is no number: ignored (no '
                                      "default)"),
        ("attribute-value", line + 2, 20, 'attribute Gain is FLOAT but its default "" is no number: ignored (no '
                                          "default)"),
        ("attribute-value", line + 4, 21, "attribute Mask is HEX but its default many is no number: ignored (no "
                                          "default)"),
        ("attribute-value", line + 6, 24, 'attribute Wire is INT but its default "x" is no number: ignored (no '
                                          "default)"),
    ]
    definitions = dbc.database.dbc.attribute_definitions
    assert [definitions[name].default_value for name in ("Level", "Gain", "Mask", "Quoted")] == [None, None, None, 10]
    assert dbc.database.dbc.relation_attribute_definitions["Wire"].default_value is None
    assert _message(dbc, "M").dbc.attributes["Level"].value == 4
    assert main(["dbc", "table", str(path)]) == 0
    assert f"{path}:{line}:21: warning: attribute Level is INT but its default" in capsys.readouterr().err


def test_frame_format_used_without_definition_is_candbs_enum(write_dbc, capsys):
    # the repair's INT definition without a default made cantools refuse the file
    path = write_dbc(f"BO_ 16 M: 1 ECU\n{PLAIN}\nBO_ 2147483665 X: 1 ECU\n{PLAIN}\nBO_ 18 F: 1 ECU\n{PLAIN}",
                     'BA_ "VFrameFormat" BO_ 2147483665 1;\nBA_ "VFrameFormat" BO_ 18 StandardCAN_FD;\n'
                     'BA_ "VFrameFormat" BO_ 16 20;\n')
    path.write_text(path.read_text().replace('BA_DEF_ BO_ "VFrameFormat" ENUM "StandardCAN","ExtendedCAN";\n', "")
                    .replace('BA_DEF_DEF_ "VFrameFormat" "StandardCAN";\n', ""))
    dbc = load_dbc(path)
    line = _line(path, 'BA_ "VFrameFormat"')
    assert _warnings(dbc) == [
        ("attribute-definition", line, "attribute VFrameFormat has no BA_DEF_: read as the ENUM of CANdb++'s frame "
                                       "formats (StandardCAN, ExtendedCAN, J1939PG, ...) with the default "
                                       "StandardCAN, as CANdb++ defines it, its values by index or name"),
        ("attribute-value", line + 2, "attribute VFrameFormat: value 20 is none of its 16 choices (0..15): ignored"),
    ]
    definition = dbc.database.dbc.attribute_definitions["VFrameFormat"]
    assert (definition.type_name, tuple(definition.choices), definition.default_value) == (
        "ENUM", FRAME_FORMATS, "StandardCAN")
    assert dbc.content.frame_formats == {"X": "ExtendedCAN", "F": "StandardCAN_FD"}
    assert [(m.name, m.is_extended_frame, m.is_fd) for m in dbc.database.messages] == [
        ("M", False, False), ("X", True, False), ("F", False, True)]
    assert main(["dbc", "table", str(path)]) == 0
    assert f"{path}:{line}: warning: attribute VFrameFormat has no BA_DEF_" in capsys.readouterr().err


def test_signal_syntax_cantools_refuses(write_dbc):
    path = write_dbc(
        " SG_ ORPHAN : 0|8@1+ (1,0) [0|255] \"\" PEER\n\n"
        "BO_ 16 M: 4\n SG_ S : 0|8@1+ (1,0) [0|255] \"\" ECU PEER\n SG_ EMPTY : 8|0@1+ (1,0) [0|0] \"\" PEER\n"
        " SG_ F : 0|32@1- (1,0) [0|0] \"\" PEER\n",
        'VAL_ 16 EMPTY 1 "x" ;\nSIG_VALTYPE_ 16 F 1;\n',
    )
    dbc = load_dbc(path)
    assert _warnings(dbc) == [
        ("orphan-signal", 13, "signal ORPHAN follows no BO_: ignored"),
        ("statement-syntax", 15, "message M: no sender after the DLC: read as none (Vector__XXX, as CANdb++ writes it)"),
        ("receivers", 16, "M.S: receivers separated by spaces instead of commas: read as ECU, PEER"),
        ("signal-length", 17, "M.EMPTY: a signal of 0 bits carries nothing: ignored with its references"),
        ("statement-syntax", _line(path, "SIG_VALTYPE_"), "SIG_VALTYPE_ 16 F 1: no ':' before the value type: read as "
                                                          "type 1"),
    ]
    message = _message(dbc, "M")
    assert [s.name for s in message.signals] == ["S", "F"] and message.senders == []
    assert message.signals[0].receivers == ["ECU", "PEER"] and message.signals[1].is_float


def test_statements_cantools_has_no_support_for(write_dbc):
    path = _message_m_with(write_dbc, 'SGTYPE_ T : 8@1+ (1,0) [0|0] "" 0 , V ;\nCAT_DEF_ 1 Cat 0;\n'
                                      'BA_DEF_REL_ BU_EV_REL_ "Link" INT 0 1;\nBA_REL_ "Link" BU_EV_REL_ ECU E 1;\n')
    path.write_text(path.read_text().replace("BS_:", "BS_: 500 : 12,34"))
    dbc = load_dbc(path)
    assert [w[:2] for w in _warnings(dbc)] == [("bit-timing", 9), ("unsupported-statement", _line(path, "SGTYPE_")),
                                              ("unsupported-statement", _line(path, "CAT_DEF_")),
                                              ("unsupported-statement", _line(path, "BU_EV_REL_"))]
    assert dbc.warnings[0].message == "BS_: 500 : 12 , 34: the obsolete bit timing is not read"
    assert [m.name for m in dbc.database.messages] == ["M"]


def test_lines_stay_where_they_are_so_later_syntax_errors_point_into_the_file(write_dbc):
    path = _message_m_with(write_dbc, 'CM_ SG_ 99 S "a comment\nover\nthree lines";\nBO_ 17 BAD 1 ECU\n')
    with pytest.raises(InputError) as error:
        load_dbc(path)
    assert str(error.value).startswith(f"{path}:{_line(path, 'BO_ 17 BAD')}:12: Invalid syntax")


def test_names_in_errors_are_the_files(write_dbc):
    path = write_dbc("BO_ 16 2M: 1 ECU\n SG_ 3S : 0|8@1+ (1,0) [0|255] \"\" PEER\n SG_ X : 0|8@1+ (1,0) [0|255] ?\n")
    with pytest.raises(InputError) as error:
        load_dbc(path)
    assert "wb_digit_" not in str(error.value)


def test_a_signal_defined_twice_in_a_message_is_a_check_error(write_dbc, capsys):
    path = write_dbc(f"BO_ 16 M: 2 ECU\n{PLAIN} SG_ S : 8|8@1+ (1,0) [0|255] {SIGNAL}\n", timing(16, 10, 30))
    assert main(["dbc", "check", str(path)]) == 1
    error, hint = capsys.readouterr().out.splitlines()
    assert error == f"{path}:13: error: M: signal S is defined 2 times"
    assert hint.endswith("would define 1 fix calibration name more than once (cfS_EN/_VALUE by M.S, M.S)")


def test_every_command_prints_the_load_warnings_and_check_counts_them(write_dbc, tmp_path, capsys):
    path = write_dbc(f"BO_ 2048 BIG: 1 ECU\n{PLAIN}", timing(2147485696, 10, 30))
    warning = f"{path}:13: warning: message BIG: id 0x800 does not fit in 11 bits"
    for command in (["table"], ["callbacks", "--node", "ECU", "--api", str(tmp_path / "api.c")],
                    ["fixcal", "--node", "ECU", "-o", str(tmp_path)]):
        if command[0] == "callbacks":
            (tmp_path / "api.c").write_text("// <initCbk>\n// </initCbk>\n")
        assert main(["dbc", command[0], str(path), *command[1:]]) == 0
        assert capsys.readouterr().err.startswith(warning)
    assert main(["dbc", "check", str(path), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    (finding,) = report["findings"]
    assert finding["kind"] == "id-format" and finding["severity"] == Severity.WARNING.name.lower()
    assert report["ok"] is False
