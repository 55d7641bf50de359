"""Malformed A2L: one A2lParseError naming file, line and column, for each kind of mistake."""

import codecs

import pytest

from workbench.a2l import load_a2l, load_a2l_string
from workbench.errors import A2lParseError

HEAD = 'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n'  # lines 1-3
TAIL = '  /end MODULE\n/end PROJECT\n'
GOOD_MEASUREMENT = '    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255\n      ECU_ADDRESS 0x10\n    /end MEASUREMENT\n'

CASES = [
    # (body between HEAD and TAIL, expected message part, line, column)
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255\n', "/end MODULE found while /begin MEASUREMENT (line 4, column 5) is still open", 5, 3),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255\n    /end CHARACTERISTIC\n', "/end CHARACTERISTIC found while /begin MEASUREMENT", 5, 5),
    ('    /begin MEASUREMENT m "unterminated UBYTE NO_COMPU_METHOD 1 0 0 255\n', "unterminated string", 4, 26),
    ('    /* never closed\n', "unterminated comment", 4, 5),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255\n      ECU_ADDRESS 0x12G4\n    /end MEASUREMENT\n', "bad number '0x12G4'", 5, 19),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 2.5.5\n    /end MEASUREMENT\n', "bad number '2.5.5'", 4, 57),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255\n      ECU_ADRESS 0x10\n    /end MEASUREMENT\n', "unknown keyword ECU_ADRESS is not allowed in MEASUREMENT", 5, 7),
    ('    /begin CHARACTERISTIC c "" VALUE 0x10 RL 0 NO_COMPU_METHOD 0 1\n      ECU_ADDRESS 0x10\n    /end CHARACTERISTIC\n', "keyword ECU_ADDRESS is not allowed in CHARACTERISTIC", 5, 7),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0\n    /end MEASUREMENT\n', "MEASUREMENT m: missing parameter", 5, 5),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255\n      /begin MEASUREMENT n "" UBYTE NO_COMPU_METHOD 1 0 0 255 /end MEASUREMENT\n    /end MEASUREMENT\n', "block /begin MEASUREMENT is not allowed in MEASUREMENT", 5, 14),
    ('    /begin MESUREMENT m "" /end MESUREMENT\n', "unknown block /begin MESUREMENT is not allowed in MODULE", 4, 12),
    ('    /end MEASUREMENT\n', "/end MEASUREMENT found while /begin MODULE", 4, 5),
    ('    /begin CHARACTERISTIC c "" VALUE 0x10 RL 0 NO_COMPU_METHOD 0 1\n' + GOOD_MEASUREMENT,  # its /end forgotten
     "/begin MEASUREMENT cannot stand inside /begin CHARACTERISTIC (line 4, column 5): is its /end CHARACTERISTIC "
     "missing?", 5, 5),
    ('    /begin\n', "/begin must be followed by a block keyword", 4, 5),
    ('    /begn MEASUREMENT\n', "unexpected '/begn'", 4, 5),
    ('    /begin MEASUREMENT 42 "" UBYTE NO_COMPU_METHOD 1 0 0 255 /end MEASUREMENT\n', "a name expected, found '42'", 4, 24),
    ('    /begin MEASUREMENT m 42 UBYTE NO_COMPU_METHOD 1 0 0 255 /end MEASUREMENT\n', "a string expected, found '42'", 4, 26),
    ('    /begin MEASUREMENT m "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS "x" /end MEASUREMENT\n', "an integer expected, found a string", 4, 73),
    ('    /begin COMPU_VTAB V "" TAB_VERB 2 0 "a" 1 /end COMPU_VTAB\n', "COMPU_VTAB V: missing parameter (a string expected)", 4, 47),
    ('    /begin COMPU_VTAB V "" TAB_VERB 999999999999 0 "a" 1 "b" /end COMPU_VTAB\n', "COMPU_VTAB V: missing parameter (a number expected)", 4, 62),
]


@pytest.mark.parametrize("body, message, line, column", CASES, ids=[c[1][:40] for c in CASES])
def test_malformed_text_names_line_and_column(body, message, line, column):
    with pytest.raises(A2lParseError) as info:
        load_a2l_string(HEAD + body + TAIL, "bad.a2l")
    error = info.value
    assert message in error.reason
    assert (error.path, error.line, error.column) == ("bad.a2l", line, column), str(error)
    assert str(error).startswith(f"bad.a2l:{line}:{column}: ")


def test_good_text_parses():
    doc = load_a2l_string(HEAD + GOOD_MEASUREMENT + TAIL)
    assert [b.name for b in doc.objects("MEASUREMENT")] == ["m"]
    leading_zero = load_a2l_string(HEAD + '    /begin COMPU_VTAB V "" TAB_VERB 02 0 "a" 1 "b" /end COMPU_VTAB\n' + TAIL)
    assert leading_zero.objects("COMPU_VTAB")[0].name == "V"  # an A2L integer may start with 0 (not octal)


def test_junk_at_the_top_level():
    with pytest.raises(A2lParseError, match="unexpected 'hello' at the top level") as info:
        load_a2l_string("ASAP2_VERSION 1 71\nhello\n")
    assert (info.value.line, info.value.column) == (2, 1)


def test_unclosed_block_at_end_of_file():
    with pytest.raises(A2lParseError, match="/begin PROJECT is never closed") as info:
        load_a2l_string('ASAP2_VERSION 1 71\n\n  /begin PROJECT P ""\n')
    assert (info.value.line, info.value.column) == (3, 3)


def test_invalid_utf8_after_a_bom(tmp_path):
    path = tmp_path / "bom.a2l"
    path.write_bytes(codecs.BOM_UTF8 + b'ASAP2_VERSION 1 71\n/begin PROJECT P "Gr\xf6\xdfe"\n')
    with pytest.raises(A2lParseError, match="invalid UTF-8 byte 0xF6 .*UTF-8 BOM") as info:
        load_a2l(path)
    assert (info.value.line, info.value.column) == (2, 21)


def test_damaged_utf16_names_the_position(tmp_path):
    path = tmp_path / "utf16.a2l"
    path.write_bytes(codecs.BOM_UTF16_LE + "ASAP2_VERSION 1 71\n/begin".encode("utf-16-le") + b"\x00\xdc")
    with pytest.raises(A2lParseError, match="invalid UTF-16-LE data") as info:
        load_a2l(path)
    assert (info.value.line, info.value.column) == (2, 7)


def test_binary_file(tmp_path):
    path = tmp_path / "program.a2l"
    path.write_bytes(b"ASAP2_VERSION 1 71\n/begin\x01\x00\x00\x00")
    with pytest.raises(A2lParseError, match="binary file") as info:
        load_a2l(path)
    assert (info.value.line, info.value.column) == (2, 8)
    path.write_bytes(b"\x7fELF\x02\x01\x01\x00\x00\x00")
    with pytest.raises(A2lParseError, match="this is an ELF file, not an A2L file") as info:
        load_a2l(path)
    assert (info.value.line, info.value.column) == (1, 1)
