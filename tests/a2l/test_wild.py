"""A2L as other tools write it, end to end through the CLI: options after child blocks (a2ltool),
enumerated parameters with words ASAP2 does not allow, typedef and INSTANCE references."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import run
from grammar_samples import HEAD, TAIL

from workbench import demo
from workbench.a2l import grammar, load_a2l_string
from workbench.a2l.addressed import AddressedObjects

A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")



def at(path: Path, word: str, line_with: str = "") -> str:
    """``line:column`` of ``word`` in the file, on the first line containing ``line_with`` (or ``word``)."""
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if (line_with or word) in line:
            return f"{number}:{line.index(word) + 1}"
    raise AssertionError(f"{word} not in {path}")


def write(tmp_path: Path, body: str, name: str = "wild.a2l") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + body + TAIL)
    return path


@pytest.mark.skipif(A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
def test_a_file_a2ltool_wrote_checks_clean_and_updates(capsys, tmp_path):
    """a2ltool writes SYMBOL_LINK after a CHARACTERISTIC's AXIS_DESCR and IF_DATA blocks."""
    rewritten = tmp_path / "a2ltool.a2l"
    subprocess.run([A2LTOOL, demo.a2l(), "--elffile", demo.elf(), "--update", "ADDRESSES", "--output",
                    rewritten], check=True, capture_output=True, timeout=120)
    doc_text = rewritten.read_text(encoding="utf-8")
    assert doc_text.index("SYMBOL_LINK", doc_text.index("/end AXIS_DESCR")) < doc_text.index("/end CHARACTERISTIC",
                                                                                           doc_text.index("/end AXIS_DESCR"))
    code, out, err = run(capsys, "a2l", "check", rewritten, "--elf", demo.elf(), "--no-cache")
    assert (code, out) == (0, "") and err.endswith(": clean\n")
    updated = tmp_path / "updated.a2l"
    code, out, err = run(capsys, "a2l", "update", rewritten, demo.elf(), "-o", updated, "--no-cache", "--json")
    report = json.loads(out)
    assert code == 0 and report["ok"] and "not-found" not in json.dumps(report["tally"])
    assert updated.read_bytes() == rewritten.read_bytes()  # a2ltool's addresses are ours


@pytest.mark.parametrize("keyword", list(grammar.ADDRESSED_OBJECTS))
def test_symbol_link_and_address_after_the_child_blocks_are_read(keyword):
    spec = grammar.BLOCKS[keyword]
    params = {"MEASUREMENT": 'm "" UBYTE NO_COMPU_METHOD 1 0 0 255', "CHARACTERISTIC": 'm "" VALUE 0x10 RL 0 CM 0 1',
              "AXIS_PTS": 'm "" 0x10 NO_INPUT_QUANTITY RL 0 CM 4 0 1', "BLOB": 'm "" 0x10 4',
              "INSTANCE": 'm "" T 0x10'}[keyword]
    children = " ".join(f"/begin {child} /end {child}" if child != "IF_DATA" else "/begin IF_DATA XCP /end IF_DATA"
                        for child in ("ANNOTATION", "IF_DATA") if child in spec.blocks)
    address = "ECU_ADDRESS 0x10" if keyword == "MEASUREMENT" else ""
    doc = load_a2l_string(HEAD + f'/begin {keyword} {params} {children} SYMBOL_LINK "sym.member" 8 {address} '
                          f"/end {keyword}\n" + TAIL)
    objects = AddressedObjects(doc)
    target = objects.target(0)
    assert (target.symbol, target.symbol_offset) == ("sym.member", 8)
    assert doc.text(target.address_token) == "0x10"


def test_words_asap2_does_not_allow_are_findings_with_the_allowed_ones(capsys, tmp_path):
    path = write(tmp_path, (
        "/begin RECORD_LAYOUT RL FNC_VALUES 1 NOT_A_TYPE ROW_DIR DIRECT /end RECORD_LAYOUT\n"
        "/begin RECORD_LAYOUT RA NO_AXIS_PTS_X 1 UWORD AXIS_PTS_X 2 UWORD COLUMN_DIR DIRECT /end RECORD_LAYOUT\n"
        '/begin MEASUREMENT m "" NOT_A_TYPE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x2000 /end MEASUREMENT\n'
        '/begin CHARACTERISTIC c "" VALUE 0x10 RA 0 NO_COMPU_METHOD 0 1 BYTE_ORDER MOTOROLA /end CHARACTERISTIC\n'))
    code, out, _ = run(capsys, "a2l", "check", path)
    assert code == 1
    assert out.splitlines() == [
        f"{path}:{at(path, 'NOT_A_TYPE')}: error: RECORD_LAYOUT RL: FNC_VALUES: 'NOT_A_TYPE' is not a data type (allowed: UBYTE, SBYTE, UWORD, SWORD, "
        "ULONG, SLONG, A_UINT64, A_INT64, FLOAT16_IEEE, FLOAT32_IEEE, FLOAT64_IEEE)",
        f"{path}:{at(path, 'COLUMN_DIR')}: error: RECORD_LAYOUT RA: AXIS_PTS_X: 'COLUMN_DIR' is not an index order (allowed: INDEX_INCR, INDEX_DECR)",
        f"{path}:{at(path, 'NOT_A_TYPE', 'MEASUREMENT')}: error: MEASUREMENT m: 'NOT_A_TYPE' is not a data type (allowed: UBYTE, SBYTE, UWORD, SWORD, "
        "ULONG, SLONG, A_UINT64, A_INT64, FLOAT16_IEEE, FLOAT32_IEEE, FLOAT64_IEEE)",
        f"{path}:{at(path, 'MOTOROLA')}: error: CHARACTERISTIC c: BYTE_ORDER: 'MOTOROLA' is not a byte order (allowed: MSB_LAST, MSB_FIRST, "
        "MSB_FIRST_MSW_LAST, MSB_LAST_MSW_FIRST, LITTLE_ENDIAN, BIG_ENDIAN)",
    ]
    code, _, err = run(capsys, "a2l", "merge", path, path, "-o", tmp_path / "merged.a2l")
    assert code == 2 and err.startswith(f"error: {path}:{at(path, 'NOT_A_TYPE')}: RECORD_LAYOUT RL: FNC_VALUES: 'NOT_A_TYPE' is not a data type")
    assert err.endswith("FLOAT64_IEEE) (and 3 more problem(s): `workbench a2l check` lists them all)\n")


TYPEDEFS = """\
/begin RECORD_LAYOUT RL FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT
/begin TYPEDEF_MEASUREMENT TM "" UBYTE CM_NONE 1 0 0 1 /end TYPEDEF_MEASUREMENT
/begin TYPEDEF_CHARACTERISTIC TC "" CURVE RL_NONE 0 NO_COMPU_METHOD 0 1
  /begin AXIS_DESCR COM_AXIS NO_INPUT_QUANTITY NO_COMPU_METHOD 8 0 1 AXIS_PTS_REF THIS.axis /end AXIS_DESCR
/end TYPEDEF_CHARACTERISTIC
/begin TYPEDEF_AXIS TA "" THIS.in RL 0 CM_AX 8 0 1 /end TYPEDEF_AXIS
/begin TYPEDEF_BLOB TB "" 8 /end TYPEDEF_BLOB
/begin TYPEDEF_STRUCTURE TS "" 16
  /begin STRUCTURE_COMPONENT m TM 0 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT c TC 1 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT axis TA 2 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT in TM 3 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT x T_NONE 4 /end STRUCTURE_COMPONENT
  /begin STRUCTURE_COMPONENT b TB 5 /end STRUCTURE_COMPONENT
/end TYPEDEF_STRUCTURE
/begin TYPEDEF_STRUCTURE OUTER "" 32 /begin STRUCTURE_COMPONENT inner TS 0 /end STRUCTURE_COMPONENT /end TYPEDEF_STRUCTURE
/begin INSTANCE I "" OUTER 0x1000 MATRIX_DIM 2 /end INSTANCE
/begin INSTANCE J "" T_MISSING 0x2000 /end INSTANCE
/begin MEASUREMENT q "" UBYTE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x3000 /end MEASUREMENT
/begin GROUP G "" /begin REF_MEASUREMENT q I[1].inner.m I.inner.zz K.m /end REF_MEASUREMENT /end GROUP
"""


def test_typedef_and_instance_references_are_checked(capsys, tmp_path):
    path = write(tmp_path, TYPEDEFS)
    code, out, _ = run(capsys, "a2l", "check", path, "--json")
    findings = [(f"{f['line']}:{f['column']}", f["message"]) for f in json.loads(out)["findings"]]
    assert code == 1 and findings == [
        (at(path, "CM_NONE"), "TYPEDEF_MEASUREMENT TM: COMPU_METHOD CM_NONE is not defined"),
        (at(path, "RL_NONE"), "TYPEDEF_CHARACTERISTIC TC: RECORD_LAYOUT RL_NONE is not defined"),
        (at(path, "CM_AX"), "TYPEDEF_AXIS TA: COMPU_METHOD CM_AX is not defined"),
        (at(path, "T_NONE"), "STRUCTURE_COMPONENT x: typedef T_NONE is not defined"),
        (at(path, "T_MISSING"), "INSTANCE J: typedef T_MISSING is not defined"),
        (at(path, "I.inner.zz"), "GROUP G: REF_MEASUREMENT entry I.inner.zz is not defined"),
        (at(path, "K.m"), "GROUP G: REF_MEASUREMENT entry K.m is not defined"),
    ]
    path = write(tmp_path, TYPEDEFS.replace("axis TA 2", "axe TA 2"))
    code, out, _ = run(capsys, "a2l", "check", path)
    assert code == 1 and (f"{at(path, 'THIS.axis')}: error: TYPEDEF_CHARACTERISTIC TC AXIS_DESCR: AXIS_PTS_REF THIS.axis is not a "
                          "component of TYPEDEF_STRUCTURE TS") in out


def test_a_file_written_for_include_is_checked_where_it_belongs(capsys, tmp_path):
    """Module-level blocks alone, or MODULEs without a PROJECT: checked as if included, findings in the file."""
    bare = tmp_path / "signals.a2l"
    bare.write_text('/begin MEASUREMENT m "" UBYTE CM_GONE 1 0 0 1 ECU_ADDRESS 0x10 /end MEASUREMENT\n'
                    '/begin MEASUREMENT n "" NOT_A_TYPE NO_COMPU_METHOD 1 0 0 1 /end MEASUREMENT\n')
    code, out, _ = run(capsys, "a2l", "check", bare)
    assert code == 1 and out.splitlines() == [
        f"{bare}:{at(bare, 'CM_GONE')}: error: MEASUREMENT m: COMPU_METHOD CM_GONE is not defined",
        f"{bare}:{at(bare, 'NOT_A_TYPE')}: error: MEASUREMENT n: 'NOT_A_TYPE' is not a data type (allowed: UBYTE, SBYTE, UWORD, SWORD, "
        "ULONG, SLONG, A_UINT64, A_INT64, FLOAT16_IEEE, FLOAT32_IEEE, FLOAT64_IEEE)"]
    module = tmp_path / "module.a2l"
    module.write_text('/begin MODULE ECU ""\n  /begin COMPU_METHOD CM_GONE "" IDENTICAL "%6.2" "" /end COMPU_METHOD\n'
                      '  /include "signals.a2l"\n/end MODULE\n')
    code, out, _ = run(capsys, "a2l", "check", module)
    assert code == 1 and out.splitlines() == [f"{bare}:{at(bare, 'NOT_A_TYPE')}: error: MEASUREMENT n: 'NOT_A_TYPE' is not a data type "
                                              "(allowed: UBYTE, SBYTE, UWORD, SWORD, ULONG, SLONG, A_UINT64, "
                                              "A_INT64, FLOAT16_IEEE, FLOAT32_IEEE, FLOAT64_IEEE)"]
