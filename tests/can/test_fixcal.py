"""Fix calibrations: the demo ECU's names, the A2L fragment (pya2ldb) and the C pair (gcc)."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from elftools.elf.elffile import ELFFile
from pya2l import import_a2l, model
from pya2l.api.validate import Level, Validator

from workbench import demo
from workbench.can.dbc_file import load_dbc
from workbench.can.fixcal import FixKind, fix_calibrations
from workbench.can.fixcal_c import c_literal
from workbench.can.fixcal_output import fixcal_files, read_signal_measurements
from workbench.can.model import messages_of
from workbench.can.naming import fix_enable_name, fix_value_name, raw_c_type
from workbench.errors import InputError

ECU_SOURCES = demo.path("assets", "ecu")
CAL_RAM_DEFINITION = re.compile(r"^CAL_RAM\s+(\w+)\s+(c[fs]\w+)\s*=\s*([^;]+);", re.MULTILINE)
C_SIZES = {"uint8_T": 1, "int8_T": 1, "uint16_T": 2, "int16_T": 2, "uint32_T": 4, "int32_T": 4, "real32_T": 4}


DEMO_MEASUREMENTS = demo.path("dbc", "FLCU_CAN2_measurements.csv")  # the signals' live measurements


def _flcu_files(**parts):
    parts.setdefault("measurements", read_signal_measurements(DEMO_MEASUREMENTS))
    return fixcal_files(load_dbc(demo.dbc_can2()), "FLCU", master_a2l=demo.master_a2l(), **parts)


def _definitions(text: str) -> set[tuple[str, str, str]]:
    return {(name, c_type, value.strip()) for c_type, name, value in CAL_RAM_DEFINITION.findall(text)}


def test_flcu_fixcals_equal_the_demo_ecu_sources():
    demo_definitions = set()
    for source in sorted(ECU_SOURCES.glob("*.c")):
        demo_definitions |= _definitions(source.read_text())
    generated = _definitions(_flcu_files().texts["FLCU_CAN2_fixcal.c"])
    assert len(generated) == 29
    assert generated == demo_definitions


def test_calibration_kinds_types_and_limits():
    calibrations = {c.name: c for c in _flcu_files().calibrations}
    assert [n for n, c in calibrations.items() if c.kind is FixKind.TX_ENABLE] == [
        "csFLCU_TO_PCM_001_En", "csFLCU_TO_PCM_002_En", "csFLCU_TO_PCM_003_En"]
    level = calibrations["cfFUELLEVEL_VALUE"]
    assert (level.c_type, level.initial_raw, level.lower, level.upper) == ("uint16_T", 0, 0, 100)
    assert (level.signal.factor, level.signal.unit) == (0.01, "%")
    assert level.description == ("Fixed raw value of CAN signal FuelLevel: Indicates the actual fuel level "
                                 "(16 bit, 0.01 %/bit)")
    assert calibrations["cfENABLEFLCU_EN"].description == "Fix switch of CAN signal EnableFLCU (1: use cfENABLEFLCU_VALUE)"


def test_limits_without_dbc_range_and_initial_value_nearest_zero(write_dbc):
    path = write_dbc(
        'BO_ 16 M: 4 ECU\n'
        ' SG_ Temp : 0|8@1+ (1,-40) [0|0] "degC" PEER\n'
        ' SG_ Torque : 8|12@1- (0.5,0) [-100|100] "Nm" PEER\n'
        ' SG_ Level : 20|4@1+ (2,10) [14|30] "" PEER\n',
    )
    calibrations = {c.name: c for c in fix_calibrations(messages_of(load_dbc(path), None, "ECU"))}
    temp = calibrations["cfTEMP_VALUE"]
    assert (temp.c_type, temp.lower, temp.upper, temp.initial_raw) == ("uint8_T", -40, 215, 40)
    torque = calibrations["cfTORQUE_VALUE"]
    assert (torque.c_type, torque.lower, torque.upper, torque.initial_raw) == ("int16_T", -100, 100, 0)
    level = calibrations["cfLEVEL_VALUE"]
    assert (level.lower, level.upper, level.initial_raw) == (14, 30, 2)  # raw 2 = 14, the nearest to 0


def test_colliding_names_are_refused_with_the_remedy():
    with pytest.raises(InputError, match=r"CAN3_validation\.dbc:\d+: cfSGN1_VALUE would be defined by C3RXAAA\.Sgn1, "
                                         r"C3RXAAB\.Sgn1, C3RXAAC\.Sgn1 and 61 more \(and 7 more names\); "
                                         r"message-qualified names \(--qualified\) avoid this$"):
        fixcal_files(load_dbc(demo.dbc_can3()), "EAXLE")


def test_qualified_names_carry_the_message():
    assert (fix_enable_name("Sgn1", "C3RXAAA"), fix_value_name("Sgn1", "C3RXAAA")) == (
        "cfC3RXAAA_SGN1_EN", "cfC3RXAAA_SGN1_VALUE")
    assert (fix_enable_name("FuelLevel"), fix_value_name("FuelLevel")) == ("cfFUELLEVEL_EN", "cfFUELLEVEL_VALUE")
    calibrations = fix_calibrations(messages_of(load_dbc(demo.dbc_can3()), None, "EAXLE"), qualified=True)
    names = [c.name for c in calibrations]
    assert len(names) == len(set(names)) == 32 + 2 * 2 * (4 * 36)  # TX enables; 2 per signal, 1..8 signals
    assert names[:4] == ["cfC3RXAAA_SGN1_EN", "cfC3RXAAA_SGN1_VALUE", "cfC3RXAAB_SGN1_EN", "cfC3RXAAB_SGN1_VALUE"]
    assert "csC3TXAAA_En" in names and "cfC3TXABF_SGN8_VALUE" in names
    enable = calibrations[0]
    assert enable.description == "Fix switch of CAN signal Sgn1 (1: use cfC3RXAAA_SGN1_VALUE)"


def test_same_message_collision_is_refused_without_suggesting_qualified_names(write_dbc):
    path = write_dbc('BO_ 16 M: 2 ECU\n SG_ Level : 0|8@1+ (1,0) [0|0] "" PEER\n SG_ LEVEL : 8|8@1+ (1,0) [0|0] "" PEER\n')
    for qualified in (False, True):
        with pytest.raises(InputError, match=r"crafted_CAN2\.dbc:15: cfM?_?LEVEL_VALUE would be defined by M\.Level, M\.LEVEL$"):
            fixcal_files(load_dbc(path), "ECU", qualified=qualified)


def test_a_node_without_messages_has_no_fix_calibrations(write_dbc):
    path = write_dbc('BO_ 16 M: 1 ECU\n SG_ A : 0|8@1+ (1,0) [0|255] "" PEER\n', nodes="ECU PEER OTHER")
    with pytest.raises(InputError, match=r"crafted_CAN2\.dbc: node OTHER neither sends nor receives a message"):
        fixcal_files(load_dbc(path), "OTHER")


def test_signal_without_a_c_type_is_refused(write_dbc):
    path = write_dbc('BO_ 16 M: 8 ECU\n SG_ F : 0|16@1- (1,0) [0|0] "" PEER\n', "SIG_VALTYPE_ 16 F : 1;\n")
    with pytest.raises(InputError, match=r"crafted_CAN2\.dbc:14: M\.F: a float CAN signal is 32 or 64 bits long"):
        fixcal_files(load_dbc(path), "ECU")


def test_file_names_are_ascii_identifiers(write_dbc):
    path = write_dbc('BO_ 16 M: 1 ECU\n SG_ S : 0|8@1+ (1,0) [0|0] "" PEER\n', name="2 Fahrzeug-Bus_ü.dbc")
    files = fixcal_files(load_dbc(path), "ECU")
    assert list(files.texts) == ["dbc_2_Fahrzeug_Bus___fixcal.h", "dbc_2_Fahrzeug_Bus___fixcal.c",
                                 "dbc_2_Fahrzeug_Bus___fixcal.a2l"]
    assert "#ifndef DBC_2_FAHRZEUG_BUS___FIXCAL_H" in files.texts["dbc_2_Fahrzeug_Bus___fixcal.h"]


def test_float_signal_value_is_a_real32(write_dbc):
    path = write_dbc('BO_ 16 M: 8 ECU\n SG_ F : 0|32@1- (1,0) [-5|5] "V" PEER\n', "SIG_VALTYPE_ 16 F : 1;\n")
    files = fixcal_files(load_dbc(path), "ECU")
    value = next(c for c in files.calibrations if c.name == "cfF_VALUE")
    assert (value.c_type, value.initial_raw, value.lower, value.upper) == ("real32_T", 0.0, -5, 5)
    assert "CAL_RAM real32_T cfF_VALUE = 0.0F;" in files.texts["crafted_CAN2_fixcal.c"]
    assert "Scalar_FLOAT32_IEEE" in files.texts["crafted_CAN2_fixcal.a2l"]


def test_raw_c_types():
    assert [raw_c_type(n, False) for n in (1, 8, 9, 16, 17, 32, 33, 64)] == [
        "uint8_T", "uint8_T", "uint16_T", "uint16_T", "uint32_T", "uint32_T", "uint64_T", "uint64_T"]
    assert raw_c_type(12, True) == "int16_T"
    assert (raw_c_type(32, True, is_float=True), raw_c_type(64, True, is_float=True)) == ("real32_T", "real_T")
    with pytest.raises(ValueError):
        raw_c_type(65, False)
    with pytest.raises(ValueError):
        raw_c_type(16, False, is_float=True)


def test_c_literals():
    assert [c_literal("uint8_T", 1), c_literal("int16_T", -3), c_literal("real32_T", 0.5), c_literal("real_T", 0)] == [
        "1U", "-3", "0.5F", "0.0"]
    assert c_literal("int32_T", -(1 << 31)) == "(-2147483647 - 1)"
    assert c_literal("uint64_T", 7) == "7ULL"


def test_parts_can_be_chosen_and_written(tmp_path):
    assert list(_flcu_files(c=False).texts) == ["FLCU_CAN2_fixcal.a2l"]
    assert list(_flcu_files(a2l=False).texts) == ["FLCU_CAN2_fixcal.h", "FLCU_CAN2_fixcal.c"]
    written = _flcu_files().write(tmp_path / "out")
    assert sorted(p.name for p in written) == ["FLCU_CAN2_fixcal.a2l", "FLCU_CAN2_fixcal.c", "FLCU_CAN2_fixcal.h"]
    with pytest.raises(InputError, match=r"FLCU_CAN2_fixcal\.h: not a folder"):
        _flcu_files().write(written[0])


def _import_a2l(path: Path, text: str):
    path.write_text(text, encoding="utf-8")
    return import_a2l(str(path), in_memory=True, encoding="utf-8", progress_bar=False, loglevel="ERROR")


@pytest.fixture(scope="module")
def fragment(tmp_path_factory):
    path = tmp_path_factory.mktemp("a2l") / "FLCU_CAN2_fixcal.a2l"
    session = _import_a2l(path, _flcu_files(c=False).texts[path.name])
    yield session
    session.close()


def test_a2l_fragment_is_read_by_pya2ldb(fragment):
    assert [d.text for d in Validator(fragment)() if d.type >= Level.ERROR] == []
    module = fragment.query(model.Module).one()
    assert module.name == "FLCU_CAN2_fixcal"
    characteristics = {c.name: c for c in fragment.query(model.Characteristic).all()}
    assert list(characteristics) == [c.name for c in _flcu_files().calibrations]
    level = characteristics["cfFUELLEVEL_VALUE"]
    assert (level.type, level.address, level.deposit, level.conversion) == ("VALUE", 0, "Scalar_UWORD", "CM_CAN_0p01_Percent")
    assert (level.lowerLimit, level.upperLimit) == (0, 100)
    assert characteristics["csFLCU_TO_PCM_001_En"].conversion == "CM_OnOff"
    assert characteristics["cfTANK1PSDIAGSTATUS_VALUE"].conversion == "CM_Std_eDiagStatusT"
    methods = {m.name: m for m in fragment.query(model.CompuMethod).all()}
    assert set(methods) == {c.conversion for c in characteristics.values()}
    linear = methods["CM_CAN_0p01_bar"]
    assert (linear.conversionType, linear.unit, linear.coeffs_linear.a, linear.coeffs_linear.b) == ("LINEAR", "bar", 0.01, 0)
    tables = {t.name: t for t in fragment.query(model.CompuVtab).all()}
    assert [(p.inVal, p.outVal) for p in tables["VTAB_Std_eDiagStatusT"].pairs][:2] == [(0, "NO_ERROR"), (1, "SHORT_TO_GND")]
    assert {r.name for r in fragment.query(model.RecordLayout).all()} == {"Scalar_UBYTE", "Scalar_UWORD"}
    linked = {name: c.comparison_quantity.name for name, c in characteristics.items() if c.comparison_quantity}
    assert len(linked) == 13 and set(linked) == {c.name for c in _flcu_files().calibrations
                                                 if c.kind is FixKind.FIX_VALUE}
    assert (linked["cfFUELLEVELLOW_VALUE"], linked["cfENABLEFLCU_VALUE"]) == ("xsLEDEn", "csPCM_TO_FLCU_001_EnableFLCU")


def test_signal_measurements_by_name_or_as_message_signal_and_refused_when_unknown_or_ambiguous():
    text = _flcu_files(c=False, measurements={"FLCU_TO_PCM_001.FuelLevelLow": "xsLEDEn"}).texts["FLCU_CAN2_fixcal.a2l"]
    assert text.count("COMPARISON_QUANTITY") == 1
    assert re.search(r"cfFUELLEVELLOW_VALUE\n(?:.*\n){8}      COMPARISON_QUANTITY xsLEDEn\n    /end CHARACTERISTIC",
                     text)
    with pytest.raises(InputError, match=r"FLCU_CAN2\.dbc: FuelLevelLo \(given the measurement xsLEDEn\): not a "
                                         r"signal of the node's messages$"):
        _flcu_files(measurements={"FuelLevelLo": "xsLEDEn"})
    with pytest.raises(InputError, match=r"Sgn1 \(given the measurement x\): a signal of 64 messages "
                                         r"\(C3RXAAA\.Sgn1, .*\): name it as Message\.Signal$"):
        fixcal_files(load_dbc(demo.dbc_can3()), "EAXLE", c=False, qualified=True, measurements={"Sgn1": "x"})


@pytest.mark.parametrize(("text", "error"), [
    ("FuelLevelLow,xsLEDEn\n", r"x\.csv:1: the first row must be 'signal,measurement'$"),
    ("signal,measurement\nFuelLevelLow\n",
     r"x\.csv:2: expected 'signal,measurement' \(two names\), got 'FuelLevelLow'$"),
    ("signal,measurement\n# a comment\n\nFuelLevelLow,xs LED\n", r"x\.csv:4: expected .* got 'FuelLevelLow,xs LED'$"),
    ("signal,measurement\nFuelLevelLow,a\nFuelLevelLow,b\n", r"x\.csv:3: FuelLevelLow is given twice$"),
])
def test_a_signal_measurements_file_is_refused_at_the_line_that_is_wrong(tmp_path, text, error):
    path = tmp_path / "x.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match=error):
        read_signal_measurements(path)


def test_qualified_can3_fragment_is_read_by_pya2ldb(tmp_path):
    files = fixcal_files(load_dbc(demo.dbc_can3()), "EAXLE", c=False, master_a2l=demo.master_a2l(), qualified=True)
    session = _import_a2l(tmp_path / "CAN3_validation_fixcal.a2l", files.texts["CAN3_validation_fixcal.a2l"])
    try:
        assert [d.text for d in Validator(session)() if d.type >= Level.ERROR] == []
        characteristics = [c.name for c in session.query(model.Characteristic).all()]
        assert characteristics == [c.name for c in files.calibrations]
        assert {c.conversion for c in session.query(model.Characteristic).all()} == {"CM_OnOff", "CM_Identity"}
    finally:
        session.close()


def test_conversions_that_would_share_a_name_keep_their_own(write_dbc, tmp_path):
    """°C and degC both spell CM_CAN_1_degC; Mode has other value texts in B than in A."""
    path = write_dbc(
        'BO_ 16 A: 3 ECU\n SG_ T : 0|8@1+ (1,0) [0|0] "°C" PEER\n SG_ Mode : 8|8@1+ (1,0) [0|0] "" PEER\n'
        ' SG_ Tiny : 16|8@1+ (1e-06,0) [0|0] "V" PEER\n\n'
        'BO_ 17 B: 2 ECU\n SG_ T : 0|8@1+ (1,0) [0|0] "degC" PEER\n SG_ Mode : 8|8@1+ (1,0) [0|0] "" PEER\n',
        'VAL_ 16 Mode 0 "Off" 1 "On" ;\nVAL_ 17 Mode 0 "Idle" 3 "Run" ;\n',
    )
    files = fixcal_files(load_dbc(path), "ECU", c=False, qualified=True)
    session = _import_a2l(tmp_path / "crafted.a2l", files.texts["crafted_CAN2_fixcal.a2l"])
    try:
        characteristics = {c.name: c.conversion for c in session.query(model.Characteristic).all()}
        methods = {m.name: m for m in session.query(model.CompuMethod).all()}
        tables = {t.name: {p.inVal: p.outVal for p in t.pairs} for t in session.query(model.CompuVtab).all()}
    finally:
        session.close()
    assert [characteristics[f"cf{m}_T_VALUE"] for m in "AB"] == ["CM_CAN_1_degC", "CM_CAN_1_degC_2"]
    assert [methods[characteristics[f"cf{m}_T_VALUE"]].unit for m in "AB"] == ["°C", "degC"]
    assert [characteristics[f"cf{m}_MODE_VALUE"] for m in "AB"] == ["CM_CAN_Mode", "CM_CAN_B_Mode"]
    assert (tables["VTAB_CAN_Mode"], tables["VTAB_CAN_B_Mode"]) == ({0: "Off", 1: "On"}, {0: "Idle", 3: "Run"})
    assert methods["CM_CAN_1em06_V"].format == "%8.6"  # one raw step is 0.000001 V


def _blocks(text: str) -> dict[str, str]:
    """Named A2L blocks (COMPU_METHOD, COMPU_VTAB, RECORD_LAYOUT, CHARACTERISTIC) by name, as written."""
    found = {}
    for match in re.finditer(r"/begin (COMPU_METHOD|COMPU_VTAB|RECORD_LAYOUT|CHARACTERISTIC)\s+(?:/\*[^*]*\*/\s*)?(\w+)"
                             r".*?/end \1", text, re.DOTALL):
        found[match.group(2)] = match.group(0)
    return found


def test_a2l_definitions_equal_the_demo_fragments_so_they_merge():
    """Token for token, long identifiers included: a cf…_VALUE's comes from the DBC signal comment."""
    demo_blocks = {}
    for module in ("CANRX", "CANTX"):
        demo_blocks.update(_blocks(demo.path("a2l", "modules", f"{module}.a2l").read_text()))
    generated = _blocks(_flcu_files(c=False).texts["FLCU_CAN2_fixcal.a2l"])
    assert len(generated) == 29 + 10 + 2
    assert {name: text for name, text in generated.items() if demo_blocks.get(name) != text} == {}


def _mod_common(text: str) -> str:
    return re.search(r"/begin MOD_COMMON.*?/end MOD_COMMON", text, re.DOTALL).group(0)


def test_a2l_mod_common_is_the_masters_as_in_every_demo_fragment(tmp_path):
    generated = _flcu_files(c=False).texts["FLCU_CAN2_fixcal.a2l"]
    assert _mod_common(generated) == _mod_common(demo.path("a2l", "modules", "CANTX.a2l").read_text())
    without_master = fixcal_files(load_dbc(demo.dbc_can2()), "FLCU", c=False).texts["FLCU_CAN2_fixcal.a2l"]
    assert "MOD_COMMON" not in without_master
    with pytest.raises(InputError, match=r"nope\.a2l: no such file$"):
        fixcal_files(load_dbc(demo.dbc_can2()), "FLCU", master_a2l=tmp_path / "nope.a2l")
    with pytest.raises(InputError, match=r"FLCU_CAN2\.dbc:1:1: no /begin PROJECT in the file$"):
        fixcal_files(load_dbc(demo.dbc_can2()), "FLCU", master_a2l=demo.dbc_can2())


def test_a2l_mod_common_is_read_as_a2l_not_as_text(tmp_path):
    """The master's MOD_COMMON as the A2L reader sees it: a commented-out one and comments inside are not
    options, a latin-1 file keeps its text, and a malformed master is refused at its line and column."""
    master = tmp_path / "master.a2l"
    master.write_bytes("""ASAP2_VERSION 1 71
/* /begin MOD_COMMON "old" BYTE_ORDER MSB_FIRST /end MOD_COMMON */
/begin PROJECT P "Prüfstand"
  /begin MODULE M ""
    /begin MOD_COMMON "Motorola, Ä"
      BYTE_ORDER MSB_FIRST   /* big-endian target */
      ALIGNMENT_LONG 2
    /end MOD_COMMON
  /end MODULE
/end PROJECT
""".encode("latin-1"))
    fragment = fixcal_files(load_dbc(demo.dbc_can2()), "FLCU", c=False, master_a2l=master).texts["FLCU_CAN2_fixcal.a2l"]
    assert _mod_common(fragment).splitlines()[1:-1] == ["      BYTE_ORDER MSB_FIRST", "      ALIGNMENT_LONG 2"]
    master.write_text(master.read_text(encoding="latin-1").replace("  /end MODULE\n", ""), encoding="latin-1")
    with pytest.raises(InputError, match=r"master\.a2l:9:1: "):
        fixcal_files(load_dbc(demo.dbc_can2()), "FLCU", c=False, master_a2l=master)


_A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")


@pytest.mark.skipif(_A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
def test_a2l_fragment_passes_a2ltool_and_merges_into_the_master(tmp_path):
    fragment = tmp_path / "FLCU_CAN2_fixcal.a2l"
    fragment.write_text(_flcu_files(c=False, measurements=None).texts[fragment.name])  # standalone: no links

    def a2ltool(*args) -> str:
        done = subprocess.run([_A2LTOOL, *map(str, args)], capture_output=True, text=True, check=True)
        return done.stdout + done.stderr

    assert "No problems found" in a2ltool(fragment, "--check", "--strict")
    merged = tmp_path / "merged.a2l"
    a2ltool(demo.master_a2l(), "--merge", fragment, "--output", merged)
    merged_text = merged.read_text()
    assert ".MERGE" not in merged_text  # the master's CM_OnOff, CM_CAN_0p01_bar ... are the same
    master_count = demo.master_a2l().read_text(encoding="utf-8").count("/begin CHARACTERISTIC")
    assert merged_text.count("/begin CHARACTERISTIC") == master_count + 29

    # linked to the signals' live measurements, with every demo fragment: CANRX/CANTX define the same 29
    # calibrations (links included), the others the measurements they name
    fragment.write_text(_flcu_files(c=False).texts[fragment.name])
    modules = [arg for path in demo.fragment_a2ls() for arg in ("--merge", path)]
    a2ltool(demo.master_a2l(), "--merge-includes", *modules, "--merge", fragment, "--output", merged)
    merged_text = merged.read_text()
    assert ".MERGE" not in merged_text  # identical definitions fold, different ones would be renamed
    assert merged_text.count("/begin CHARACTERISTIC") == demo.a2l().read_text(encoding="utf-8").count(
        "/begin CHARACTERISTIC")
    assert "No problems found" in a2ltool(merged, "--check", "--strict")


@pytest.mark.gcc
@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs a host gcc")
@pytest.mark.parametrize(("dbc", "node", "qualified"), [("FLCU_CAN2.dbc", "FLCU", False),
                                                        ("CAN3_validation.dbc", "EAXLE", True)])
def test_generated_c_compiles_into_cal_ram(tmp_path, dbc, node, qualified):
    files = fixcal_files(load_dbc(demo.path("dbc", dbc)), node, a2l=False, qualified=qualified)
    files.write(tmp_path)
    source = tmp_path / dbc.replace(".dbc", "_fixcal.c")
    obj = tmp_path / "fixcal.o"
    subprocess.run(
        ["gcc", "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-I", str(ECU_SOURCES),
         "-c", str(source), "-o", str(obj)],
        check=True, capture_output=True, text=True,
    )
    with obj.open("rb") as handle:
        elf = ELFFile(handle)
        cal_ram = elf.get_section_by_name(".cal_ram")
        index = next(i for i, s in enumerate(elf.iter_sections()) if s.name == ".cal_ram")
        symbols = {s.name: s for s in elf.get_section_by_name(".symtab").iter_symbols()}
        for calibration in files.calibrations:
            symbol = symbols[calibration.name]
            assert symbol["st_shndx"] == index and symbol["st_size"] == C_SIZES[calibration.c_type]
            value = cal_ram.data()[symbol["st_value"]:symbol["st_value"] + symbol["st_size"]]
            assert int.from_bytes(value, "little") == calibration.initial_raw, calibration.name
    # next to the demo's flcu_types.h, which defines the same CAL_RAM macro
    subprocess.run(
        ["gcc", "-std=c99", "-Wall", "-Werror", "-I", str(ECU_SOURCES), "-include", "flcu_types.h",
         "-c", str(source), "-o", str(obj)],
        check=True, capture_output=True, text=True,
    )
