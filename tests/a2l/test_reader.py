"""The lossless reader: bytes kept, tokens and blocks found, encodings and includes handled."""

import codecs

import pytest

from workbench.a2l import load_a2l, load_a2l_string
from workbench.errors import A2lParseError, InputError

SMALL = """ASAP2_VERSION 1 71
/* comment with "quotes" and /begin inside */
/begin PROJECT P "project"
  /begin MODULE M "module // not a comment"
    /begin MEASUREMENT speed "vehicle \\"speed\\"" UWORD CM 1 0 0 300 // trailing comment
      ECU_ADDRESS 0x0000ABCD
      /begin IF_DATA XCP /begin DAQ_EVENT FIXED_EVENT_LIST EVENT 1 /end DAQ_EVENT /end IF_DATA
      SYMBOL_LINK "speed" 0
    /end MEASUREMENT
  /end MODULE
/end PROJECT
"""


def test_tokens_blocks_and_values():
    doc = load_a2l_string(SMALL)
    (measurement,) = doc.objects("MEASUREMENT")
    assert measurement.name == "speed"
    args = measurement.args
    assert [doc.text(t) for t in args] == ["speed", 'vehicle "speed"', "UWORD", "CM", "1", "0", "0", "300"]
    (address,) = measurement.option("ECU_ADDRESS")
    assert doc.int_value(address) == 0xABCD and doc.raw(address) == b"0x0000ABCD"
    assert [doc.value(t) for t in measurement.option("SYMBOL_LINK")] == ["speed", 0]
    assert measurement.position[1:] == (5, 5)
    assert doc.token_position(address)[1:] == (6, 19)
    (if_data,) = measurement.children_named("IF_DATA")
    assert if_data.name == "XCP" and if_data.parent == measurement
    assert doc.module().text().startswith('/begin MODULE M "module // not a comment"')


def test_option_tokens_finds_keywords_at_the_blocks_own_level():
    text = SMALL.replace("  /end MODULE", """    /begin MEASUREMENT ECU_ADDRESS "named like the keyword" UBYTE CM 1 0 0 1 /end MEASUREMENT
    /begin MEASUREMENT inner "" UBYTE CM 1 0 0 1 /begin IF_DATA X ECU_ADDRESS 0x1 /end IF_DATA /end MEASUREMENT
  /end MODULE""")
    doc = load_a2l_string(text)
    blocks, tokens = doc.option_tokens("MEASUREMENT", "ECU_ADDRESS")
    assert [doc.blocks.keyword[b] for b in blocks] == ["MEASUREMENT"] and doc.raw(int(tokens[0]) + 1) == b"0x0000ABCD"


def test_bytes_survive_untouched(tmp_path):
    text = SMALL.replace("\n", "\r\n").replace("project", "Projekt für Öl")
    path = tmp_path / "crlf.a2l"
    path.write_bytes(codecs.BOM_UTF8 + text.encode("utf-8"))
    doc = load_a2l(path)
    assert doc.data == text.encode("utf-8")
    assert (doc.encoding, doc.source.bom, doc.source.newline) == ("utf-8", codecs.BOM_UTF8, "\r\n")
    assert doc.text(doc.project.args[1]) == "Projekt für Öl"


def test_latin1_is_detected_and_columns_count_characters(tmp_path):
    path = tmp_path / "latin1.a2l"
    path.write_bytes(SMALL.replace('"project"', '"Größe"').replace("UWORD CM 1", "UWORD ÄÖ 1").encode("latin-1"))
    doc = load_a2l(path, validate=False)
    assert doc.encoding == "latin-1"
    assert doc.text(doc.project.args[1]) == "Größe"
    (measurement,) = doc.objects("MEASUREMENT")
    assert doc.token_position(measurement.args[4])[1:] == (5, 59)  # one column per character, not per byte


def test_utf8_columns_count_characters():
    doc = load_a2l_string(SMALL.replace("UWORD CM 1", "UWORD ÄÖ 1"), validate=False)
    (measurement,) = doc.objects("MEASUREMENT")
    assert doc.token_position(measurement.args[4])[1:] == (5, 59)  # Ä and Ö are two bytes each in UTF-8


def test_nested_includes_are_spliced_with_their_positions(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "main.a2l").write_text(
        'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n    /include "sub/objects.a2l"\n'
        '  /end MODULE\n/end PROJECT\n')
    (tmp_path / "sub" / "objects.a2l").write_text(
        '/begin COMPU_METHOD CM "" IDENTICAL "%4.0" "" /end COMPU_METHOD\n/include deeper.a2l\n')
    (tmp_path / "sub" / "deeper.a2l").write_text(
        '\n/begin MEASUREMENT m "" UBYTE CM 1 0 0 255 ECU_ADDRESS 0x12 /end MEASUREMENT\n')
    doc = load_a2l(tmp_path / "main.a2l")
    assert doc.include_count == 2
    assert [b.name for b in doc.module().children] == ["CM", "m"]
    (measurement,) = doc.objects("MEASUREMENT")
    file, line, column = measurement.position
    assert file.endswith("deeper.a2l") and (line, column) == (2, 1)
    assert b"/include" not in doc.data


def test_include_errors_point_at_the_directive(tmp_path):
    (tmp_path / "a.a2l").write_text('ASAP2_VERSION 1 71\n/include "b.a2l"\n')
    (tmp_path / "b.a2l").write_text('\n\n  /include "a.a2l"\n')
    with pytest.raises(A2lParseError, match="cycle") as info:
        load_a2l(tmp_path / "a.a2l")
    assert info.value.path.endswith("b.a2l") and (info.value.line, info.value.column) == (3, 3)
    (tmp_path / "c.a2l").write_text('ASAP2_VERSION 1 71\n /include "missing.a2l"\n')
    with pytest.raises(A2lParseError, match="cannot include .*missing.a2l") as info:
        load_a2l(tmp_path / "c.a2l")
    assert (info.value.line, info.value.column) == (2, 2)


def test_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_a2l(tmp_path / "nope.a2l")
