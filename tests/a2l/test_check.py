"""check: every finding kind with its position; a clean file has none."""

import re

import pytest
from pathlib import Path

from workbench import demo
from workbench.a2l import load_a2l_string
from workbench.a2l.check import check_document, check_file
from workbench.elf.debugdata import DebugData
from workbench.image import load_image

ELF = Path(__file__).parents[1] / "elf" / "fixtures" / "types_dwarf5.elf"

TEXT = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /begin MOD_PAR ""
      /begin MEMORY_SEGMENT Flash "" DATA FLASH INTERN 0x1000 0x100 -1 -1 -1 -1 -1 /end MEMORY_SEGMENT
      /begin MEMORY_SEGMENT CalRam "" DATA RAM INTERN 0x2000 0x100 -1 -1 -1 -1 -1 /end MEMORY_SEGMENT
    /end MOD_PAR
    /begin COMPU_METHOD CM "" IDENTICAL "%6.2" "" /end COMPU_METHOD
    /begin RECORD_LAYOUT RL FNC_VALUES 1 ULONG ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin MEASUREMENT ok "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2000 /end MEASUREMENT
    /begin MEASUREMENT badcm "" UBYTE CM_MISSING 1 0 0 1 ECU_ADDRESS 0x2010 /end MEASUREMENT
    /begin MEASUREMENT partial "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2002 /end MEASUREMENT
    /begin MEASUREMENT twin "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2000 /end MEASUREMENT
    /begin MEASUREMENT nowhere "" UWORD CM 1 0 0 1 ECU_ADDRESS 0x9000 /end MEASUREMENT
    /begin MEASUREMENT ok "" UBYTE CM 1 0 0 1 ECU_ADDRESS 0x2020 /end MEASUREMENT
    /begin CHARACTERISTIC inflash "" VALUE 0x1000 RL 0 CM 0 1 /end CHARACTERISTIC
    /begin CHARACTERISTIC badrl "" VALUE 0x2030 RL_MISSING 0 CM 0 1 /end CHARACTERISTIC
    /begin FUNCTION F "" /begin SUB_FUNCTION G /end SUB_FUNCTION /begin OUT_MEASUREMENT ok ghost /end OUT_MEASUREMENT /end FUNCTION
  /end MODULE
/end PROJECT
"""


def test_every_problem_is_found_with_its_position():
    report = check_document(load_a2l_string(TEXT, "bad.a2l"))
    found = {(f.kind, f.name, f.line, f.column) for f in report.findings}
    assert found == {
        ("undefined-reference", "CM_MISSING", 11, 39),
        ("overlap", "partial", 12, 64),
        ("same-address", "twin", 13, 61),
        ("outside-memory", "nowhere", 14, 64),
        ("duplicate-name", "ok", 15, 24),
        ("calibration-outside-cal-ram", "inflash", 16, 44),
        ("undefined-reference", "RL_MISSING", 17, 49),
        ("undefined-reference", "G", 18, 46),
        ("undefined-reference", "ghost", 18, 92),
    }
    messages = {f.name: f.message for f in report.findings}
    assert messages["inflash"].startswith("CHARACTERISTIC inflash at 0x1000 is in Flash (DATA FLASH)")
    assert messages["G"] == "FUNCTION F: SUB_FUNCTION entry G is not defined"
    assert str(report.findings[0]).startswith("bad.a2l:11:39: error: MEASUREMENT badcm: COMPU_METHOD CM_MISSING")


def test_syntax_problems_are_all_reported():
    text = TEXT.replace("ECU_ADDRESS 0x2010", "ECU_ADDRESS 0x20Z0").replace("FNC_VALUES 1 ULONG", "FNC_VALUE 1 ULONG")
    syntax = [f for f in check_document(load_a2l_string(text, validate=False)).findings if f.kind == "syntax"]
    assert [(f.line, f.column) for f in syntax] == [(9, 29), (11, 70)]
    assert syntax[0].message == "RECORD_LAYOUT RL: unknown keyword FNC_VALUE is not allowed in RECORD_LAYOUT"
    assert "bad number '0x20Z0'" in syntax[1].message


def test_against_the_elf_addresses_and_symbols():
    text = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n'
            '    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x403004 /end MEASUREMENT\n'
            '    /begin MEASUREMENT gone "" UBYTE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x403000 /end MEASUREMENT\n'
            '    /begin MEASUREMENT vectr "" UWORD NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x403010 /end MEASUREMENT\n'
            '  /end MODULE\n/end PROJECT\n')
    report = check_document(load_a2l_string(text, "x.a2l"), DebugData(ELF, use_cache=False))
    assert {(f.kind, f.name, f.line) for f in report.findings} == {
        ("address-mismatch", "zsScalar", 4), ("symbol-not-found", "gone", 5), ("symbol-not-found", "vectr", 6),
        ("byte-order-mismatch", "MOD_COMMON", 3)}
    assert report.of_kind("symbol-not-found")[1].message == \
        "MEASUREMENT vectr: not in types_dwarf5.elf; did you mean 'vector'?"  # a renamed variable
    mismatch = report.of_kind("address-mismatch")[0]
    assert "the A2L says 0x403004, types_dwarf5.elf says 0x403000" in mismatch.message


def test_a_byte_order_other_than_the_elfs_is_reported():
    head = 'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n'
    tail = '    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x403000 /end MEASUREMENT\n' \
           '  /end MODULE\n/end PROJECT\n'
    found = {}
    for order in ("MSB_FIRST", "BIG_ENDIAN", "MSB_LAST", "LITTLE_ENDIAN", None):  # the ELF is little-endian x86
        common = f'    /begin MOD_COMMON "" BYTE_ORDER {order} /end MOD_COMMON\n' if order else ""
        report = check_document(load_a2l_string(head + common + tail, "x.a2l"), DebugData(ELF, use_cache=False))
        found[order] = [(f.severity.name.lower(), f.line, f.column, f.message) for f in report.findings]
    assert found["MSB_LAST"] == found["LITTLE_ENDIAN"] == []
    assert found["MSB_FIRST"] == [("error", 4, 37, "MODULE M: MOD_COMMON says BYTE_ORDER MSB_FIRST, types_dwarf5.elf is "
                                   "MSB_LAST (little-endian): every value would be read with its bytes swapped")]
    assert found["BIG_ENDIAN"][0][0] == "error"
    assert found[None] == [("warning", 3, 10, "MODULE M: MOD_COMMON says no BYTE_ORDER (ASAP2's default MSB_FIRST), "
                            "types_dwarf5.elf is MSB_LAST (little-endian): every value would be read with its bytes "
                            "swapped")]
    # without the ELF nothing is known of the ECU's byte order
    assert check_document(load_a2l_string(head + tail, "x.a2l")).findings == []


def test_the_demo_a2l_is_clean_against_its_elf():
    report = check_file(demo.a2l(), demo.elf(), use_cache=False)
    assert report.findings == []


def test_an_address_beyond_32_bits_is_an_error():
    text = TEXT.replace("ECU_ADDRESS 0x9000", "ECU_ADDRESS 0x1000000000000000000000")
    (finding,) = check_document(load_a2l_string(text, "far.a2l")).of_kind("address-out-of-range")
    assert (finding.name, finding.line, finding.column) == ("nowhere", 14, 64)


BITFIELDS = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""
    /begin MEASUREMENT whole "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x100 /end MEASUREMENT
    /begin MEASUREMENT b0 "" UBYTE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x100 BIT_MASK 0x01 /end MEASUREMENT
    /begin MEASUREMENT b1 "" UBYTE NO_COMPU_METHOD 1 0 0 7 ECU_ADDRESS 0x100 BIT_MASK 0x0E /end MEASUREMENT
    /begin MEASUREMENT b2 "" UBYTE NO_COMPU_METHOD 1 0 0 7 ECU_ADDRESS 0x100 BIT_MASK 0x0C /end MEASUREMENT
    /begin MEASUREMENT w0 "" A_UINT64 NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x200 BIT_MASK 0x8000000000000000 /end MEASUREMENT
    /begin MEASUREMENT w1 "" A_UINT64 NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x200 BIT_MASK 0x7FFFFFFFFFFFFFFF /end MEASUREMENT
    /begin MEASUREMENT w2 "" A_UINT64 NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x200 BIT_MASK 0xC000000000000000 /end MEASUREMENT
    /begin MEASUREMENT twin "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x100 /end MEASUREMENT
  /end MODULE
/end PROJECT
"""


def test_bitfields_of_the_same_bytes_overlap_only_where_their_masks_do():
    """A whole byte and its bitfields (a view of it) and bitfields with disjoint masks, 64-bit ones too, are
    fine; a bitfield that repeats another's bits and a second whole object are warnings."""
    report = check_document(load_a2l_string(BITFIELDS, "bits.a2l"))
    assert [(f.kind, f.name, f.line, f.severity.name) for f in report.findings] == [
        ("same-address", "b2", 7, "WARNING"), ("same-address", "w2", 10, "WARNING"),
        ("same-address", "twin", 11, "WARNING")]
    messages = [f.message for f in report.findings]
    assert messages[0] == ("MEASUREMENT b2 (BIT_MASK 0xC) occupies the same 1 byte(s) at 0x100 as MEASUREMENT b1 "
                           "(BIT_MASK 0xE)")
    assert messages[1].endswith("as MEASUREMENT w0 (BIT_MASK 0x8000000000000000)")
    assert messages[2] == "MEASUREMENT twin occupies the same 1 byte(s) at 0x100 as MEASUREMENT whole"
    clean = BITFIELDS.replace("0xC000000000000000", "0x0").replace("0x0C /end", "0x30 /end")
    clean = clean.replace("twin", "other").replace("0 255 ECU_ADDRESS 0x100 /end MEASUREMENT\n  /end", "0 255 ECU_ADDRESS 0x101 /end MEASUREMENT\n  /end")
    assert check_document(load_a2l_string(clean, "bits.a2l")).findings == []


def test_address_spaces_and_placeholders():
    """Each ECU_ADDRESS_EXTENSION is an address space of its own, outside the MEMORY_SEGMENTs (XCPlite puts
    stack variables there); address 0 is the placeholder of a file not updated yet: neither overlaps."""
    objects = ('    /begin MEASUREMENT stack "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2000 ECU_ADDRESS_EXTENSION 2 /end MEASUREMENT\n'
               '    /begin MEASUREMENT far "" ULONG CM 1 0 0 1 ECU_ADDRESS 0xFFF0 ECU_ADDRESS_EXTENSION 2 /end MEASUREMENT\n'
               '    /begin MEASUREMENT near "" ULONG CM 1 0 0 1 ECU_ADDRESS 0xFFF2 ECU_ADDRESS_EXTENSION 2 /end MEASUREMENT\n'
               '    /begin MEASUREMENT todo1 "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x0 /end MEASUREMENT\n'
               '    /begin MEASUREMENT todo2 "" ULONG CM 1 0 0 1 ECU_ADDRESS 0 /end MEASUREMENT\n')
    text = TEXT.split("    /begin MEASUREMENT badcm")[0] + objects + "  /end MODULE\n/end PROJECT\n"
    report = check_document(load_a2l_string(text, "spaces.a2l"))
    assert [(f.kind, f.name) for f in report.findings] == [("overlap", "near")]  # within extension 2 only
    # a file whose every object is at 0 (extensions too) forgot its update: one warning, since check fails on it
    unplaced = (TEXT.split("    /begin MEASUREMENT ok")[0] + re.sub(r"ECU_ADDRESS 0x\w+", "ECU_ADDRESS 0", objects)
                + "  /end MODULE\n/end PROJECT\n")
    report = check_document(load_a2l_string(unplaced, "unplaced.a2l"))
    assert [(f.kind, f.name, f.line, f.severity.name) for f in report.findings] == [
        ("placeholder-address", "stack", 10, "WARNING")]
    assert report.findings[0].message.startswith("5 object(s) still at address 0, the placeholder of an A2L not "
                                                 "updated from its ELF (stack, far, near and 2 more): workbench a2l "
                                                 "update")


def test_an_include_that_is_missing_is_one_finding_and_the_rest_is_checked(tmp_path, capsys):
    """As xcplite's files ship without their XCP_104.aml: the check goes on, nested includes too."""
    from workbench.cli import main

    (tmp_path / "objects.a2l").write_text('/include "nested_missing.a2l"\n'
                                          '/begin MEASUREMENT m "" UBYTE CM_MISSING 1 0 0 1 ECU_ADDRESS 0x2000 '
                                          '/end MEASUREMENT\n')
    main_text = TEXT.split("    /begin MEASUREMENT ok")[0] + '    /include "XCP_104.aml"\n    /include "objects.a2l"\n' \
        + "  /end MODULE\n/end PROJECT\n"
    (tmp_path / "main.a2l").write_text(main_text)
    report = check_file(tmp_path / "main.a2l")
    found = [(f.kind, f.name, Path(f.file).name, f.line) for f in report.findings]
    assert found == [("include-not-found", "XCP_104.aml", "main.a2l", 10),
                     ("include-not-found", "nested_missing.a2l", "objects.a2l", 1),
                     ("undefined-reference", "CM_MISSING", "objects.a2l", 2)]
    assert report.findings[0].message == f"cannot include {tmp_path / 'XCP_104.aml'}: no such file (the rest is " \
                                         "checked without it)"
    assert main(["a2l", "check", str(tmp_path / "main.a2l")]) == 1
    with_update = main(["a2l", "update", str(tmp_path / "main.a2l"), str(ELF), "-o", str(tmp_path / "o.a2l")])
    assert with_update == 2 and "cannot include" in capsys.readouterr().err  # other commands still need every file


def test_a_malformed_memory_segment_is_a_finding_not_the_end_of_the_check():
    """A parameter written twice moves INTERN into the address: the grammar's finding is listed and the rest checked
    (the memory placement used to raise at it)."""
    text = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n /begin MODULE M ""\n  /begin MOD_PAR ""\n'
            '   /begin MEMORY_SEGMENT Data "" DATA DATA RAM INTERN 0x1000 0x100 -1 -1 -1 -1 /end MEMORY_SEGMENT\n'
            '  /end MOD_PAR\n  /begin MEASUREMENT m "" UBYTE CM_GONE 1 0 0 255 ECU_ADDRESS 0x1000 /end MEASUREMENT\n'
            ' /end MODULE\n/end PROJECT\n')
    report = check_document(load_a2l_string(text, "m.a2l", validate=False))
    assert {finding.kind for finding in report.problems} >= {"syntax"} and \
        any("CM_GONE" in finding.message for finding in report.problems)


def test_an_option_given_twice_is_named_where_asap2_allows_it_once():
    """Two BIT_MASKs, FORMATs, PHYS_UNITs, MATRIX_DIMs in one object: which one a tool takes is not told. What may
    repeat (SYSTEM_CONSTANT and ADDR_EPK in MOD_PAR, RESERVED in a RECORD_LAYOUT; IF_DATA and ANNOTATION blocks)
    passes; loading the file does not refuse it (other tools read such files)."""
    text = TEXT.replace('/begin MOD_PAR ""', '/begin MOD_PAR "" SYSTEM_CONSTANT "a" "1" SYSTEM_CONSTANT "b" "2" '
                        'ADDR_EPK 0x1000 ADDR_EPK 0x1004')
    text = text.replace("FNC_VALUES 1 ULONG ROW_DIR DIRECT", "FNC_VALUES 1 ULONG ROW_DIR DIRECT RESERVED 5 BYTE "
                        "RESERVED 6 BYTE")
    text = text.replace('/begin MEASUREMENT ok "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2000',
                        '/begin MEASUREMENT ok "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2000 BIT_MASK 0x1 FORMAT "%4.1"\n'
                        '      /begin IF_DATA X /end IF_DATA /begin IF_DATA X /end IF_DATA /begin ANNOTATION /end '
                        'ANNOTATION /begin ANNOTATION /end ANNOTATION\n'
                        '      BIT_MASK 0x2 PHYS_UNIT "bar" FORMAT "%4.2" PHYS_UNIT "kPa"')
    text = text.replace('VALUE 0x1000 RL 0 CM 0 1', 'VAL_BLK 0x1000 RL 0 CM 0 1 MATRIX_DIM 2 MATRIX_DIM 3')
    doc = load_a2l_string(text, "twice.a2l")
    twice = [(f.kind, f.name, f.line, f.column, f.message) for f in check_document(doc).findings
             if f.kind == "option-twice"]
    assert twice == [
        ("option-twice", "ok", 12, 7, "MEASUREMENT ok: BIT_MASK is given twice (at most once; the first at line 10)"),
        ("option-twice", "ok", 12, 36, "MEASUREMENT ok: FORMAT is given twice (at most once; the first at line 10)"),
        ("option-twice", "ok", 12, 50, "MEASUREMENT ok: PHYS_UNIT is given twice (at most once; the first at line 12)"),
        ("option-twice", "inflash", 18, 78,
         "CHARACTERISTIC inflash: MATRIX_DIM is given twice (at most once; the first at line 18)"),
    ]


def test_instance_objects_take_part_in_the_memory_checks():
    """The objects an INSTANCE stands for are placed at its address plus their offsets, each its typedef's size:
    a CHARACTERISTIC INSTANCE in flash is not in CAL RAM, a structure reaching beyond its segment lies outside it,
    a component a plain object partly covers overlaps it; the findings stand at the INSTANCE's address."""
    typedefs = ('    /begin TYPEDEF_CHARACTERISTIC T_cal "" VALUE RL 0 CM 0 1 /end TYPEDEF_CHARACTERISTIC\n'
                '    /begin TYPEDEF_MEASUREMENT T_u16 "" UWORD CM 1 0 0 1 /end TYPEDEF_MEASUREMENT\n'
                '    /begin TYPEDEF_STRUCTURE T_pair "" 8\n'
                '      /begin STRUCTURE_COMPONENT gain T_cal 0 /end STRUCTURE_COMPONENT\n'
                '      /begin STRUCTURE_COMPONENT raw T_u16 4 MATRIX_DIM 2 /end STRUCTURE_COMPONENT\n'
                '    /end TYPEDEF_STRUCTURE\n')
    instances = ('    /begin INSTANCE inflash "" T_cal 0x1010 /end INSTANCE\n'
                 '    /begin INSTANCE pairs "" T_pair 0x20F0 MATRIX_DIM 3 /end INSTANCE\n'
                 '    /begin INSTANCE fine "" T_pair 0x2040 /end INSTANCE\n'
                 '    /begin MEASUREMENT plain "" ULONG CM 1 0 0 1 ECU_ADDRESS 0x2046 /end MEASUREMENT\n')
    text = TEXT.split("    /begin MEASUREMENT ok")[0] + typedefs + instances + "  /end MODULE\n/end PROJECT\n"
    report = check_document(load_a2l_string(text, "inst.a2l"))
    assert [(f.kind, f.name, f.line, f.column) for f in report.findings] == [
        ("calibration-outside-cal-ram", "inflash", 16, 38),
        ("outside-memory", "pairs[2].raw", 17, 37),  # 0x2104: past CalRam's 0x100 bytes
        ("outside-memory", "pairs[2].gain", 17, 37),
        ("overlap", "plain", 19, 62)]
    messages = [f.message for f in report.findings]
    assert messages[0] == ("CHARACTERISTIC inflash of INSTANCE inflash at 0x1010 is in Flash (DATA FLASH), not in a "
                           "DATA RAM segment (CalRam)")
    assert messages[1] == ("MEASUREMENT pairs[2].raw of INSTANCE pairs (0x2104, 4 bytes) lies outside every "
                           "MEMORY_SEGMENT")
    assert messages[3] == ("MEASUREMENT plain (0x2046, 4 bytes) overlaps MEASUREMENT fine.raw of INSTANCE fine "
                           "(0x2044, 4 bytes)")  # raw: UWORD[2] at the structure's offset 4
    # the same objects placed where they belong: clean
    moved = text.replace("T_cal 0x1010", "T_cal 0x2010").replace("0x20F0 MATRIX_DIM 3", "0x20C0 MATRIX_DIM 3")
    assert check_document(load_a2l_string(moved.replace("0x2046", "0x2048"), "inst.a2l")).findings == []


def test_where_an_addr_epk_may_lie():
    """Each ADDR_EPK in a MEMORY_SEGMENT with room for the EPK, one a segment (a2ltool --check finds none of these)."""
    text = TEXT.replace('    /end MOD_PAR', '      EPK "BUILD_1"\n      ADDR_EPK 0x1000\n      ADDR_EPK 0x10FC\n'
                        '      ADDR_EPK 0x1000\n      ADDR_EPK 0x5000\n      ADDR_EPK 0x2000\n    /end MOD_PAR')
    report = check_document(load_a2l_string(text, "epk.a2l"))
    found = [(f.severity.name, f.kind, f.line, f.column, f.message) for f in report.findings if f.name == "ADDR_EPK"]
    assert found == [
        ("ERROR", "epk-beyond-segment", 9, 16, "ADDR_EPK 0x10FC: the EPK 'BUILD_1' (7 bytes) runs 3 byte(s) beyond "
         "Flash (which ends at 0x10FF)"),
        ("WARNING", "epk-same-segment", 9, 16, "ADDR_EPK 0x10FC: lies in Flash, in the same part as the ADDR_EPK at "
         "line 8: a part of the software keeps one EPK, so one of them is likely stale"),
        ("WARNING", "epk-same-segment", 10, 16, "ADDR_EPK 0x1000: lies in Flash, the same address as the ADDR_EPK at "
         "line 8: a part of the software keeps one EPK, so one of them is likely stale"),
        ("ERROR", "epk-outside-memory", 11, 16, "ADDR_EPK 0x5000: lies outside every MEMORY_SEGMENT: no part of the "
         "software holds the EPK there, so neither a flash file nor an image can show it"),
    ]
    assert str(report.findings[[f.kind for f in report.findings].index("epk-outside-memory")]).startswith(
        "epk.a2l:11:16: error: ADDR_EPK 0x5000")


@pytest.mark.parametrize("mod_par, expected", [
    ('      EPK "BUILD_1"\n', ("epk-without-address", "EPK", 7, 11, "EPK 'BUILD_1' without ADDR_EPK: a master "
                                "cannot read the ECU's EPK where it lies to compare it with the A2L's (CANape reads it "
                                "at ADDR_EPK): add ADDR_EPK (workbench a2l update sets it from the ELF)")),
    ('      ADDR_EPK 0x1000\n      ADDR_EPK 0x2000\n',
     ("addr-epk-without-epk", "ADDR_EPK", 7, 16, "ADDR_EPK 0x1000 without MOD_PAR EPK: the bytes there are compared "
      "with nothing, so an ECU or a file of another build is taken for this A2L's: add EPK \"...\" (workbench a2l "
      "update inserts it from the ELF)")),
])
def test_an_epk_and_its_address_come_together(mod_par, expected):
    """MOD_PAR's EPK without ADDR_EPK, or ADDR_EPK without EPK: one finding at the one there."""
    report = check_document(load_a2l_string(TEXT.replace("    /end MOD_PAR", mod_par + "    /end MOD_PAR"), "epk.a2l"))
    found = [(f.kind, f.name, f.line, f.column, f.message) for f in report.findings if f.block == "MOD_PAR"]
    assert found == [expected] and not report.ok
    assert str(report.findings[[f.kind for f in report.findings].index(expected[0])]).startswith(
        f"epk.a2l:7:{expected[3]}: warning: ")


def test_the_elf_must_hold_the_epk_at_every_addr_epk():
    text = demo.a2l().read_text(encoding="utf-8")
    assert text.count("ADDR_EPK 0x840008") == 1
    line = text[:text.index("ADDR_EPK 0x840008")].count("\n") + 1
    edited = text.replace("ADDR_EPK 0x840008", "ADDR_EPK 0x840010\n      ADDR_EPK 0x900000\n      ADDR_EPK 0x40030000\n"
                          "      ADDR_EPK 0x40000000")  # the last in CAL RAM: compared where CAL ROM holds it
    with DebugData(demo.elf(), use_cache=False) as debug:
        report = check_document(load_a2l_string(edited, "FLCU.a2l"), debug)
        moved = [(f.severity.name, f.kind, f.line, f.message) for f in report.findings if f.name == "ADDR_EPK"]
        assert moved == [
            ("ERROR", "epk-differs", line, "ADDR_EPK 0x840010: FLCU.elf holds '250301' there, MOD_PAR's EPK is "
             "'10300020250301' (an A2L of another build, or an ADDR_EPK not updated: workbench a2l update)"),
            ("WARNING", "epk-same-segment", line + 1, "ADDR_EPK 0x900000: lies in APPLICATIVE, in the same part as "
             f"the ADDR_EPK at line {line}: a part of the software keeps one EPK, so one of them is likely stale"),
            ("ERROR", "epk-differs", line + 1, "ADDR_EPK 0x900000: FLCU.elf puts nothing there (the FLASH stays erased "
             "when this build is flashed), MOD_PAR's EPK is '10300020250301'"),
            ("INFO", "epk-not-in-elf", line + 2, "ADDR_EPK 0x40030000: FLCU.elf holds no initial data there (memory it "
             "does not initialise): the EPK cannot be compared"),
        ]
        image = ("FLCU.s19", load_image(demo.s19()))
        in_image = check_document(load_a2l_string(edited, "FLCU.a2l"), image=image)
        assert [(f.kind, f.line) for f in in_image.findings if f.name == "ADDR_EPK"] == [
            ("epk-differs", line), ("epk-same-segment", line + 1), ("epk-not-in-image", line + 1),
            ("epk-not-in-image", line + 2)]
        other = check_document(load_a2l_string(text.replace('EPK "10300020250301"', 'EPK "10300020259999"'),
                                               "FLCU.a2l"), debug)
        held = (" FLCU.elf holds '10300020250301' there, MOD_PAR's EPK is '10300020259999' (an A2L of another build, "
                "or an ADDR_EPK not updated")
        assert [(f.line, f.message.split(":")[1]) for f in other.findings] == [(line - 1, held), (line, held)]


def test_a_calibration_on_the_epk_s_bytes_is_a_warning():
    """At the ADDR_EPK, or in the CAL RAM its IF_DATA XCP ADDRESS_MAPPING loads CAL ROM to (the demo's 1:1 mirror)."""
    text = demo.a2l().read_text(encoding="utf-8")
    for addr_epk in ("0xFC00E0", "0x400000E0"):
        edited = text.replace("ADDR_EPK 0x840008", f"ADDR_EPK 0x840008 ADDR_EPK {addr_epk}")
        found = {f.name: f for f in check_document(load_a2l_string(edited, "FLCU.a2l")).findings
                 if f.kind == "calibration-on-epk"}
        assert sorted(found) == ["xsPRV_KD", "xsPRV_KI", "xsPRV_KP", "xsSWITCH_TANK_THR"], addr_epk  # 14 bytes
        thr = found["xsSWITCH_TANK_THR"]
        assert (thr.severity.name, thr.line, thr.block) == ("WARNING", _line(edited, "@xsSWITCH_TANK_THR@"),
                                                            "CHARACTERISTIC")
        assert thr.message == (f"CHARACTERISTIC xsSWITCH_TANK_THR (0x400000E0, 4 bytes) lies on the EPK's bytes "
                               f"(ADDR_EPK {addr_epk} at line {_line(edited, addr_epk)}, 14 bytes): a write to it "
                               "would change the identifier of the software")


def _line(text: str, part: str) -> int:
    return text[:text.index(part)].count("\n") + 1
