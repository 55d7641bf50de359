"""update: addresses (DWARF and .symtab), SYMBOL_LINK, EPK, --types, missing symbols under each mode."""

import codecs
import difflib
import re
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pya2l_oracle import pya2l_import

from workbench.a2l import grammar, load_a2l, load_a2l_string
from workbench.a2l.prune import PruneFailed, remove_document
from workbench.a2l.reports import UpdateMode
from workbench.a2l.update import UpdateFailed, update_document, update_file
from workbench.a2l.values import is_number
from workbench.cli import main
from workbench.elf.debugdata import DebugData
from workbench.elf.symbols import ElfSymbols
from workbench.errors import A2lParseError, InputError

ELF_FIXTURES = Path(__file__).parents[1] / "elf" / "fixtures"
ELF = ELF_FIXTURES / "types_dwarf5.elf"
STRIPPED = ELF_FIXTURES / "types_symtab.elf"


@pytest.fixture(scope="module")
def debug():
    return DebugData(ELF, use_cache=False)


@pytest.fixture
def source(fixtures):
    return fixtures / "types.a2l"


def addresses(doc):
    """name -> address of every object, read back through the document."""
    found = {}
    for block in doc.objects("MEASUREMENT"):
        option = block.option("ECU_ADDRESS")
        found[block.name] = doc.int_value(option[0]) if option else None
    for keyword, index in (("CHARACTERISTIC", 3), ("AXIS_PTS", 2), ("BLOB", 2)):
        for block in doc.objects(keyword):
            found[block.name] = doc.int_value(block.args[index])
    return found


def test_every_address_comes_from_the_elf(source, debug):
    result = update_document(load_a2l(source), debug)
    got = addresses(load_a2l_string(result.data.decode()))
    symtab = ElfSymbols(ELF).symbols
    assert got["zsScalar"] == symtab["zsScalar"].address
    assert got["outer.b.c"] == debug.resolve("outer.b.c").address == symtab["outer"].address + 2
    assert got["outer.arr._2_.d[1]"] == debug.resolve("outer.arr[2].d[1]").address
    assert got["MatrixElement"] == symtab["matrix"].address + (2 * 6 + 3) * 4  # SYMBOL_LINK "matrix[2]" + 12
    assert got["vector"] == symtab["vector"].address  # ECU_ADDRESS was missing: inserted
    assert got["zvLut"] == got["zvLut.BP1"] == symtab["zvLut"].address
    assert got["csConstant"] == symtab["csConstant"].address and got["u"] == symtab["u"].address
    assert got["missing_var"] == 0x1234  # kept as it was
    assert result.report.tally["MEASUREMENT"] == {"updated": 6, "not-found": 1}


def test_only_changed_tokens_differ(source, debug):
    original = source.read_bytes().decode()
    result = update_document(load_a2l(source), debug, epk=False)
    matcher = difflib.SequenceMatcher(None, original.splitlines(), result.data.decode().splitlines(), autojunk=False)
    old_lines, new_lines = original.splitlines(), result.data.decode().splitlines()
    replaced, inserted = 0, []
    for tag, a0, a1, b0, b1 in matcher.get_opcodes():
        if tag == "insert":
            inserted += new_lines[b0:b1]
        elif tag == "replace":
            assert a1 - a0 == b1 - b0
            for before, after in zip(old_lines[a0:a1], new_lines[b0:b1]):
                different = [(x, y) for x, y in zip(before.split(" "), after.split(" ")) if x != y]
                assert len(before.split(" ")) == len(after.split(" ")) and len(different) == 1, (before, after)
                assert all(is_number(x.encode()) and is_number(y.encode()) for x, y in different)
                replaced += 1
        else:
            assert tag == "equal", (tag, old_lines[a0:a1])
    assert replaced == 9 and inserted == ["      ECU_ADDRESS 0x403140"]
    assert "ECU_ADDRESS 0x00403000 /* placeholder, 8 hex digits */" in new_lines[17]  # hex width kept
    assert new_lines[20] == "      ECU_ADDRESS 4206722"  # decimal stays decimal


def test_epk_string_and_address_from_the_elf(source, debug):
    result = update_document(load_a2l(source), debug)
    doc = load_a2l_string(result.data.decode())
    epk_section = ElfSymbols(ELF).sections[".epk"]
    assert doc.epk() == "12000020250101" and doc.addr_epk() == epk_section.address
    assert {f.name for f in result.report.of_kind("epk-updated")} == {"EPK", "ADDR_EPK"}


@pytest.mark.parametrize("mod_par, message", [
    ("EPK", "MOD_PAR: EPK needs a string in quotes, found '/end'"),
    ("EPK 0x10", "MOD_PAR: EPK needs a string in quotes, found '0x10'"),
    ('ADDR_EPK EPK "x"', "MOD_PAR: ADDR_EPK needs an integer address, found 'EPK'"),
])
def test_an_epk_without_its_value_is_refused_not_inserted_again(debug, mod_par, message):
    """The update used to insert a second EPK / ADDR_EPK beside the one it could not read."""
    text = f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n    /begin MOD_PAR "x" {mod_par}\n' \
           '    /end MOD_PAR\n  /end MODULE\n/end PROJECT\n'
    with pytest.raises(A2lParseError) as info:
        update_document(load_a2l_string(text, "u.a2l", validate=False), debug)
    assert (info.value.reason, info.value.line, info.value.column) == (message, 4, 24)
    assert update_document(load_a2l_string(text, validate=False), debug, epk=False).report.ok  # --no-epk: left alone


def test_epk_is_inserted_when_mod_par_lacks_it(debug):
    text = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n    /begin MOD_PAR "x"\n'
            '    /end MOD_PAR\n  /end MODULE\n/end PROJECT\n')
    result = update_document(load_a2l_string(text), debug)
    doc = load_a2l_string(result.data.decode())
    assert doc.epk() == "12000020250101" and doc.addr_epk() == ElfSymbols(ELF).sections[".epk"].address
    assert b'    /begin MOD_PAR "x"\n      EPK "12000020250101"\n      ADDR_EPK 0x4020C0\n' in result.data


@pytest.mark.parametrize("second, expected, kind", [
    (0x840008, 0x840008, None),  # the ELF holds the EPK there (the application header's copy): left alone
    (0x840010, 0x840008, "epk-updated"),  # moved to the one place in APPLICATIVE that holds it
    (0x800010, 0x800010, "epk-address-unknown"),  # BOOT holds no EPK: left, with a warning
])
def test_every_addr_epk_stays_where_the_elf_holds_the_epk(second, expected, kind):
    from workbench import demo

    text = demo.a2l().read_bytes().replace(b"ADDR_EPK 0x840008", f"ADDR_EPK 0x{second:X}".encode())
    result = update_document(load_a2l_string(text.decode(), "two_epks.a2l"), DebugData(demo.elf(), use_cache=False))
    doc = load_a2l_string(result.data.decode())
    assert [epk.address for epk in doc.epk_addresses()] == [0xFC0000, expected]
    found = [(f.kind, f.line) for f in result.report.findings if f.name == "ADDR_EPK"]
    line = text[:text.index(f"ADDR_EPK 0x{second:X}".encode())].count(b"\n") + 1
    assert found == ([(kind, line)] if kind else [])
    moved = f"; ADDR_EPK 0x{second:X} -> 0x{expected:X} (where FLCU.elf holds the EPK in APPLICATIVE)"
    assert result.report.summary("out.a2l").endswith(moved) == (kind == "epk-updated")  # said without -v


@pytest.mark.parametrize("calib, summary", [
    (0xFC0000, ""),  # both as the ELF has them
    (0xFC0004, "; ADDR_EPK 0xFC0004 -> 0xFC0000"),  # CALIB's set from the .epk section, second as it is
])
def test_the_elf_s_epk_symbol_sets_the_addr_epk_of_its_own_part_whichever_comes_first(calib, summary):
    """The application header's ADDR_EPK first: the .epk section (CALIB's) set the first, both then named CALIB's
    address and the application's part had no EPK address left."""
    from workbench import demo

    text = demo.a2l().read_text(encoding="utf-8")
    swapped = text.replace("ADDR_EPK 0xFC0000\n      ADDR_EPK 0x840008",
                           f"ADDR_EPK 0x840008\n      ADDR_EPK 0x{calib:X}")
    assert swapped != text
    result = update_document(load_a2l_string(swapped, "swapped.a2l"), DebugData(demo.elf(), use_cache=False))
    doc = load_a2l_string(result.data.decode())
    assert [(place.address, place.part) for place in doc.epk_addresses()] == [(0x840008, "APPLICATIVE"),
                                                                              (0xFC0000, "CALIB")]
    assert result.report.summary("out.a2l").endswith("AXIS_PTS 2 unchanged" + summary)


def test_missing_symbols_are_kept_and_reported_by_default(source, debug):
    result = update_document(load_a2l(source), debug)
    (missing,) = result.report.of_kind("symbol-not-found")
    assert (missing.name, missing.line, missing.block) == ("missing_var", 36, "MEASUREMENT")
    assert "not in types_dwarf5.elf" in missing.message
    assert b"missing_var" in result.data


def test_many_missing_symbols_get_no_suggestion_from_the_update_but_from_check(debug, tmp_path):
    """More than MOST_SUGGESTED missing symbols are seldom renames (another build, deleted variables) and would
    cost the update an index of every name: `a2l check --elf` suggests for the first of them."""
    from workbench.a2l.check import check_file
    from workbench.elf.suggest import MOST_SUGGESTED as SUGGESTED_UP_TO

    def text(count):
        objects = "".join(f'    /begin MEASUREMENT {name} "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x0 '
                          '/end MEASUREMENT\n' for name in [*(f"zsScalar{n}x" for n in range(count)), "zsScalar"])
        return f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n{objects}  /end MODULE\n/end PROJECT\n'

    def suggested(result):
        return [f.message.endswith("did you mean 'zsScalar'?") for f in result.report.of_kind("symbol-not-found")]

    few = update_document(load_a2l_string(text(SUGGESTED_UP_TO)), debug, epk=False)
    assert suggested(few) == [True] * SUGGESTED_UP_TO
    many = update_document(load_a2l_string(text(SUGGESTED_UP_TO + 1)), debug, epk=False)
    assert suggested(many) == [False] * (SUGGESTED_UP_TO + 1)
    (tmp_path / "many.a2l").write_text(text(SUGGESTED_UP_TO + 1))
    findings = check_file(tmp_path / "many.a2l", ELF, use_cache=False).findings
    checked = [f.message.endswith("did you mean 'zsScalar'?") for f in findings if f.kind == "symbol-not-found"]
    assert checked.count(True) == SUGGESTED_UP_TO, checked


def test_an_elf_holding_none_of_the_objects_is_refused(debug):
    """Another build's ELF: every object missing; its EPK and no address would be written (exit 2, nothing)."""
    objects = "".join(f'    /begin MEASUREMENT {name} "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x0 '
                      '/end MEASUREMENT\n' for name in ("API_Speed", "API_Torque"))
    text = f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n{objects}  /end MODULE\n/end PROJECT\n'
    with pytest.raises(InputError, match=r"^none of the 2 objects of other.a2l is in types_dwarf5.elf \(the first: "
                                         r"MEASUREMENT API_Speed\): is it the ELF of this A2L's software\?"):
        update_document(load_a2l_string(text, "other.a2l"), debug)
    one = text.replace("API_Torque", "zsScalar")  # one found: the other is a warning, as a renamed variable is
    assert [f.name for f in update_document(load_a2l_string(one), debug).report.of_kind("symbol-not-found")] == [
        "API_Speed"]


def test_a_renamed_variable_is_suggested(debug):
    """The usual reason a symbol is missing: the variable was renamed. A stranger gets no suggestion."""
    objects = "".join(f'    /begin MEASUREMENT {name} "" UBYTE NO_COMPU_METHOD 1 0 0 255 ECU_ADDRESS 0x0 /end MEASUREMENT\n'
                      for name in ("zsScaler", "ZSSCALAR", "outr.b.c", "outr.nothing", "missing_var", "zsScalar"))
    text = f'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n{objects}  /end MODULE\n/end PROJECT\n'
    result = update_document(load_a2l_string(text, "renamed.a2l"), debug, epk=False)
    messages = {f.name: f.message for f in result.report.of_kind("symbol-not-found")}
    assert messages == {
        "zsScaler": "MEASUREMENT zsScaler: not in types_dwarf5.elf; did you mean 'zsScalar'?",
        "ZSSCALAR": "MEASUREMENT ZSSCALAR: not in types_dwarf5.elf; did you mean 'zsScalar'?",  # case alone first
        "outr.b.c": "MEASUREMENT outr.b.c: not in types_dwarf5.elf; did you mean 'outer.b.c'?",  # with its members
        "outr.nothing": "MEASUREMENT outr.nothing: not in types_dwarf5.elf; did you mean 'outer'?",  # no such member
        "missing_var": "MEASUREMENT missing_var: not in types_dwarf5.elf",
    }


def test_remove_missing_drops_the_object_and_its_references(source, debug):
    result = update_document(load_a2l(source), debug, mode=UpdateMode.REMOVE_MISSING)
    assert b"missing_var" not in result.data
    doc = load_a2l_string(result.data.decode())
    assert [t for t in doc.blocks_named("REF_MEASUREMENT")[0].args] and \
        [doc.text(t) for t in doc.blocks_named("REF_MEASUREMENT")[0].args] == ["zsScalar", "outer.b.c"]
    assert {f.kind for f in result.report.findings} >= {"removed", "reference-removed"}
    assert b"    /begin MEASUREMENT missing_var" not in result.data and b"\n\n\n" not in result.data


def _referencing(source) -> str:
    """types.a2l where kept objects need others: an AXIS_DESCR's INPUT_QUANTITY, a COM_AXIS's AXIS_PTS_REF,
    a VIRTUAL measurement's input."""
    return source.read_text().replace("STD_AXIS NO_INPUT_QUANTITY", "STD_AXIS zsScalar").replace(
        "    /begin BLOB u", "    /begin CHARACTERISTIC matrix \"\" CURVE 0x0 RL_U8 0 CM 0 255\n"
        "      /begin AXIS_DESCR COM_AXIS NO_INPUT_QUANTITY CM 9 0 5 AXIS_PTS_REF zvLut.BP1 /end AXIS_DESCR\n"
        "    /end CHARACTERISTIC\n"
        "    /begin MEASUREMENT state \"\" UBYTE CM 1 0 0 1 ECU_ADDRESS 0 /begin VIRTUAL outer.b.c /end VIRTUAL"
        " /end MEASUREMENT\n    /begin BLOB u")


def _renamed(text: str, names) -> str:
    """``text`` with every whole occurrence of ``names`` (definitions and references) renamed NAME_gone: objects
    the ELF lacks."""
    for name in names:
        text = re.sub(rf"(?<![\w.\[]){re.escape(name)}(?![\w.\[])", f"{name}_gone", text)
    return text


def test_remove_missing_refuses_when_a_kept_object_needs_a_missing_one(source, debug):
    """`remove`'s rules: each reference a kept object needs is an error at its line and column naming both objects,
    nothing is returned; a2ltool's default drops the AXIS_PTS_REF and leaves the VIRTUAL dangling."""
    text = _renamed(_referencing(source), ["zsScalar", "zvLut.BP1", "outer.b.c"])
    with pytest.raises(UpdateFailed, match="3 kept reference") as info:
        update_document(load_a2l_string(text, "need.a2l"), debug, mode=UpdateMode.REMOVE_MISSING)
    errors = {(f.line, f.column): f.message for f in info.value.report.errors}
    lines = text.splitlines()
    assert all(lines[line - 1][column - 1:].startswith(("zsScalar_gone", "zvLut.BP1_gone", "outer.b.c_gone"))
               for line, column in errors)
    assert sorted(errors.values()) == [
        ("CHARACTERISTIC matrix AXIS_DESCR: AXIS_PTS_REF zvLut.BP1_gone would name a removed object; remove "
         "CHARACTERISTIC matrix too, or keep zvLut.BP1_gone"),
        ("CHARACTERISTIC zvLut AXIS_DESCR: its input quantity zsScalar_gone would name a removed object; "
         "--drop-optional-references drops it"),
        ("MEASUREMENT state VIRTUAL: VIRTUAL outer.b.c_gone would name a removed object; remove MEASUREMENT "
         "state too, or keep outer.b.c_gone")]
    # only the optional reference left: refused, or dropped on request as a2ltool does
    text = _renamed(_referencing(source), ["zsScalar"])
    with pytest.raises(UpdateFailed, match="1 kept reference"):
        update_document(load_a2l_string(text), debug, mode=UpdateMode.REMOVE_MISSING)
    result = update_document(load_a2l_string(text), debug, mode=UpdateMode.REMOVE_MISSING, drop_optional=True)
    assert b"STD_AXIS NO_INPUT_QUANTITY" in result.data and b"zsScalar" not in result.data
    assert [f.message for f in result.report.of_kind("reference-dropped")] == [
        "CHARACTERISTIC zvLut AXIS_DESCR: INPUT_QUANTITY zsScalar_gone is removed: now NO_INPUT_QUANTITY"]
    assert result.report.tally["MEASUREMENT"]["removed"] == 2  # and missing_var, out of its GROUP
    assert "not-found" not in result.report.tally["MEASUREMENT"]  # counted once: "2 removed", not also "2 not-found"


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(gone=st.sets(st.sampled_from(["zsScalar", "outer.b.c", "csConstant", "zvLut.BP1", "u", "state"])),
       drop=st.booleans())
def test_remove_missing_is_remove_after_update(source, debug, gone, drop):
    """One removal engine: an update with objects missing from the ELF and --remove-missing gives what `remove`
    of those names gives after a plain update, or refuses with the errors it refuses with."""
    text = _renamed(_referencing(source), gone)
    kept = update_document(load_a2l_string(text), debug, epk=False)
    try:
        expected = remove_document(load_a2l_string(kept.data.decode()), regexes=(".*_gone|missing_var",),
                                   drop_optional=drop).data
    except PruneFailed as exc:
        with pytest.raises(UpdateFailed) as info:
            update_document(load_a2l_string(text), debug, epk=False, mode=UpdateMode.REMOVE_MISSING,
                            drop_optional=drop)
        assert [f.message for f in info.value.report.errors] == [f.message for f in exc.report.errors]
        return
    got = update_document(load_a2l_string(text), debug, epk=False, mode=UpdateMode.REMOVE_MISSING, drop_optional=drop)
    assert got.data == expected


def test_strict_mode_fails_and_writes_nothing(source, tmp_path):
    out = tmp_path / "out.a2l"
    with pytest.raises(UpdateFailed, match=r"1 object\(s\) cannot be updated \(strict\): missing_var \(.*types.a2l:36:24\)") as info:
        update_file(source, ELF, out, mode=UpdateMode.STRICT, use_cache=False)
    assert info.value.exit_code == 1 and not out.exists()
    assert info.value.report.errors[0].name == "missing_var"


def test_symtab_fallback_updates_plain_names_only(source):
    result = update_document(load_a2l(source), DebugData(STRIPPED, use_cache=False))
    got = addresses(load_a2l_string(result.data.decode()))
    assert got["zsScalar"] == ElfSymbols(STRIPPED).symbols["zsScalar"].address
    missing = {f.name for f in result.report.of_kind("symbol-not-found")}
    assert {"outer.b.c", "MatrixElement", "zvLut.BP1", "missing_var"} <= missing
    assert any("no DWARF type" in f.message for f in result.report.of_kind("symbol-not-found"))


def test_types_correct_datatype_dims_bitmask_and_limits(debug):
    text = ('ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n'
            '    /begin MEASUREMENT vector "" UBYTE NO_COMPU_METHOD 1 0 -5 1e6\n      ECU_ADDRESS 0x0\n'
            '      MATRIX_DIM 3\n    /end MEASUREMENT\n'
            '    /begin MEASUREMENT bits.high "" UWORD NO_COMPU_METHOD 1 0 0 4095\n      ECU_ADDRESS 0x0\n'
            '    /end MEASUREMENT\n'
            '    /begin MEASUREMENT outer "" UWORD NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0x0\n'
            '    /end MEASUREMENT\n'
            '    /begin BLOB u "" 0x0 1 /end BLOB\n'
            '  /end MODULE\n/end PROJECT\n')
    result = update_document(load_a2l_string(text), debug, types=True, epk=False)
    doc = load_a2l_string(result.data.decode())
    vector, bits, outer = doc.objects("MEASUREMENT")
    assert [doc.text(t) for t in vector.args[2:]] == ["UWORD", "NO_COMPU_METHOD", "1", "0", "0", "65535"]
    assert [doc.int_value(t) for t in vector.option("MATRIX_DIM")] == [10]
    assert doc.text(bits.args[2]) == "ULONG" and doc.int_value(bits.option("BIT_MASK")[0]) == 0xFFF00
    assert doc.text(outer.args[2]) == "UWORD"  # a struct cannot be one data type: reported, not changed
    assert result.report.of_kind("type-not-scalar")[0].name == "outer"
    assert doc.int_value(doc.objects("BLOB")[0].args[3]) == 4
    kinds = result.report.counts()
    assert kinds["datatype-updated"] == 2 and kinds["limits-updated"] == 2 and kinds["size-updated"] == 2


@pytest.mark.parametrize("encoding, bom", [("latin-1", b""), ("utf-8", codecs.BOM_UTF8), ("utf-16-le", codecs.BOM_UTF16_LE),
                                           ("utf-16-be", b""), ("utf-32-be", codecs.BOM_UTF32_BE)])
def test_encoding_and_newlines_survive(tmp_path, source, encoding, bom):
    text = source.read_text().replace('"update fixture"', '"Prüfstand Größe"').replace("\n", "\r\n")
    original = tmp_path / "in.a2l"
    original.write_bytes(bom + text.encode(encoding))
    out = tmp_path / "out.a2l"
    update_file(original, ELF, out, use_cache=False)
    data = out.read_bytes()
    assert data.startswith(bom)
    updated = data[len(bom):].decode(encoding)
    assert "Prüfstand Größe" in updated and "\r\n" in updated and "\n" not in updated.replace("\r\n", "")
    assert "      ECU_ADDRESS 0x403140\r\n" in updated  # inserted lines use the file's newline
    lines = updated.replace("      ECU_ADDRESS 0x403140\r\n", "").split("\r\n")
    changed = [(a, b) for a, b in zip(text.split("\r\n"), lines, strict=True) if a != b]
    assert len(changed) == 11  # and in each changed line one value, nothing else:
    assert all(len(a.split()) == len(b.split()) and sum(x != y for x, y in zip(a.split(), b.split())) == 1
               for a, b in changed)


def test_update_in_place_only_when_output_names_the_input(tmp_path, source):
    copy = tmp_path / "in.a2l"
    copy.write_bytes(source.read_bytes())
    update_file(copy, ELF, tmp_path / "out.a2l", use_cache=False)
    assert copy.read_bytes() == source.read_bytes()
    update_file(copy, ELF, copy, use_cache=False)
    assert copy.read_bytes() == (tmp_path / "out.a2l").read_bytes()


def test_pya2ldb_accepts_the_updated_file(tmp_path, source):
    out = tmp_path / "out.a2l"
    update_file(source, ELF, out, types=True, use_cache=False)
    counts = pya2l_import(out)
    assert (counts["MEASUREMENT"], counts["CHARACTERISTIC"], counts["AXIS_PTS"]) == (7, 2, 1)
    assert dict(counts["ECU_ADDRESS"])["zsScalar"] == ElfSymbols(ELF).symbols["zsScalar"].address


WRAP = 'ASAP2_VERSION 1 71\n/begin PROJECT P ""\n  /begin MODULE M ""\n{}  /end MODULE\n/end PROJECT\n'


@pytest.mark.parametrize("body, message, line, column", [
    ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0\n      /begin IF_DATA X /end IF_DATA\n'
     '    /end MEASUREMENT\n', "MEASUREMENT zsScalar: missing parameter(s), 8 expected", 4, 12),
    ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0x12G4\n'
     '    /end MEASUREMENT\n', "the address must be an integer, found '0x12G4'", 5, 19),
    ('    /begin CHARACTERISTIC zsScalar "" VALUE addr RL 0 NO_COMPU_METHOD 0 1 /end CHARACTERISTIC\n',
     "CHARACTERISTIC zsScalar: an integer expected, found 'addr'", 4, 45),
    # a parameter missing moves the next keyword into the parameters: the update would have read ECU_ADDRESS as
    # the upper limit and inserted a second ECU_ADDRESS after it
    ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0\n      ECU_ADDRESS 0x1234\n'
     '    /end MEASUREMENT\n', "MEASUREMENT zsScalar: a number expected, found 'ECU_ADDRESS'", 5, 7),
    ('    /begin MEASUREMENT zsScalar FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x1234 /end MEASUREMENT\n',
     "MEASUREMENT zsScalar: a string expected, found 'FLOAT32_IEEE'", 4, 33),
    ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0x10 ECU_ADDRESS 0x20\n'
     '    /end MEASUREMENT\n', "MEASUREMENT zsScalar: ECU_ADDRESS is given twice (at most once)", 4, 90),
    ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1 2 ECU_ADDRESS 0x1234 /end MEASUREMENT\n',
     "MEASUREMENT zsScalar: unexpected '2' after its 8 parameters (a keyword expected)", 4, 73),
    ('    /begin MEASUREMENT m "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1\n      SYMBOL_LINK zsScalar 0\n'
     '    /end MEASUREMENT\n', "SYMBOL_LINK needs a string and an integer offset", 5, 7),
])
def test_update_checks_the_tokens_it_reads(debug, body, message, line, column):
    with pytest.raises(A2lParseError) as info:
        update_document(load_a2l_string(WRAP.format(body), "u.a2l", validate=False), debug)
    assert message in info.value.reason and (info.value.line, info.value.column) == (line, column)


@pytest.mark.parametrize("body, message, column", [
    ('    /begin MEASUREMENT vector "" UWORD NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0 MATRIX_DIM /end MEASUREMENT\n',
     "MEASUREMENT vector: MATRIX_DIM without its value", 78),
    ('    /begin MEASUREMENT bits.mid "" ULONG NO_COMPU_METHOD 1 0 0 1 ECU_ADDRESS 0 BIT_MASK /end MEASUREMENT\n',
     "MEASUREMENT bits.mid: BIT_MASK without its value", 80),
])
def test_types_refuse_an_option_without_its_value(debug, body, message, column):
    """--types read it as missing: MATRIX_DIM or BIT_MASK was inserted a second time (or the update broke off)."""
    with pytest.raises(A2lParseError) as info:
        update_document(load_a2l_string(WRAP.format(body), "u.a2l", validate=False), debug, types=True)
    assert (info.value.reason, info.value.line, info.value.column) == (message, 4, column)


def test_numbers_spelled_as_words_are_numbers(debug):
    """NaN and INF start with a letter: the check of the parameters' first bytes matches them exactly."""
    body = '    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 NaN INF ECU_ADDRESS 0x0 /end MEASUREMENT\n'
    result = update_document(load_a2l_string(WRAP.format(body), "u.a2l", validate=False), debug)
    assert b"NaN INF ECU_ADDRESS 0x0 " not in result.data and b"NaN INF ECU_ADDRESS 0x" in result.data


def test_validate_checks_the_whole_grammar_first(tmp_path, source):
    bad = tmp_path / "bad.a2l"
    bad.write_text(source.read_text().replace("CM 1 0 0 100", "CM 1 0 0 1O0"))
    update_file(bad, ELF, tmp_path / "out.a2l", use_cache=False)  # the limit is not the update's business
    with pytest.raises(A2lParseError, match="bad number '1O0'") as info:
        update_file(bad, ELF, tmp_path / "out.a2l", use_cache=False, validate=True)
    assert (info.value.line, info.value.column) == (17, 71)


def test_an_address_beyond_32_bits_is_left_unchanged_and_reported(debug):
    body = ('    /begin MEASUREMENT far "" UBYTE NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0x0\n'
            '      SYMBOL_LINK "zsScalar" 0xFFFFFFFF\n    /end MEASUREMENT\n')
    doc = load_a2l_string(WRAP.format(body), "far.a2l")
    result = update_document(doc, debug, epk=False)
    (finding,) = result.report.of_kind("address-out-of-range")
    assert (finding.name, finding.line, finding.severity.name) == ("far", 4, "WARNING")
    assert "does not fit the 32 bits" in finding.message and result.data == doc.data
    with pytest.raises(UpdateFailed, match="far"):
        update_document(doc, debug, epk=False, mode=UpdateMode.STRICT)


def test_an_elf_without_dwarf_and_symbols_is_refused(tmp_path, source):
    """A stripped ELF cannot give one address: an output with every address as it was must not pass a build."""
    data = ELF.read_bytes().replace(b".symtab\0", b".nosyms\0").replace(b".debug_info\0", b".debug_none\0")
    stripped = tmp_path / "stripped.elf"
    stripped.write_bytes(data)
    with pytest.raises(InputError, match=r"stripped\.elf: has neither DWARF nor a symbol table \(stripped\?\)"):
        update_document(load_a2l(source), DebugData(stripped, use_cache=False))
    code = main(["a2l", "update", str(source), str(stripped), "-o", str(tmp_path / "out.a2l"), "--no-cache"])
    assert code == 2 and not (tmp_path / "out.a2l").exists()


def test_canape_link_map_follows_the_new_address(debug):
    body = ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0x0\n'
            '      /begin IF_DATA CANAPE_EXT 100\n        LINK_MAP "zsScalar" 0x0 0x0 0 0x0 1 0x87 0x0\n'
            '        DISPLAY 0 0 1\n      /end IF_DATA\n    /end MEASUREMENT\n'
            '    /begin MEASUREMENT moved "" UBYTE NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0\n'
            '      /begin IF_DATA CANAPE_EXT 100 LINK_MAP "u" 0 0 0 0 1 0x87 0 /end IF_DATA\n'
            '      /begin IF_DATA OTHER_TOOL LINK_MAP "u" 0x99 /end IF_DATA\n'
            '      SYMBOL_LINK "zsScalar" 2\n    /end MEASUREMENT\n')
    doc = load_a2l_string(WRAP.format(body), "canape.a2l")
    result = update_document(doc, debug, epk=False)
    updated = load_a2l_string(result.data.decode())
    scalar = ElfSymbols(ELF).symbols["zsScalar"].address
    assert addresses(updated) == {"zsScalar": scalar, "moved": scalar + 2}
    text = result.data.decode()
    assert f'LINK_MAP "zsScalar" 0x{scalar:X} 0x0 0' in text  # written in the token's own style
    assert f'CANAPE_EXT 100 LINK_MAP "u" {scalar + 2} 0 0' in text  # the object's address, SYMBOL_LINK offset included
    assert 'OTHER_TOOL LINK_MAP "u" 0x99' in text  # another tool's IF_DATA is not ours to change
    assert result.report.tally["IF_DATA CANAPE_EXT LINK_MAP"] == {"updated": 2}
    assert update_document(updated, debug, epk=False).data == result.data  # a second update changes nothing


def test_a_ccp_dp_blob_follows_the_new_address(debug):
    """IF_DATA ASAP1B_CCP DP_BLOB (extension, base address, size) is where a CCP master reads the address."""
    body = ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0x0\n'
            '      /begin IF_DATA ASAP1B_CCP DP_BLOB 0x0 0x0 4 /end IF_DATA\n    /end MEASUREMENT\n'
            '    /begin MEASUREMENT short "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1 SYMBOL_LINK "zsScalar" 0\n'
            '      /begin IF_DATA ASAP1B_CCP DP_BLOB 0 /end IF_DATA\n    /end MEASUREMENT\n')
    with pytest.raises(A2lParseError, match="short: DP_BLOB needs an address extension and a base address"):
        update_document(load_a2l_string(WRAP.format(body), "ccp.a2l"), debug, epk=False)
    body = body.replace("DP_BLOB 0 /end", "DP_BLOB 0 0x10 4 /end")
    result = update_document(load_a2l_string(WRAP.format(body), "ccp.a2l"), debug, epk=False)
    scalar = ElfSymbols(ELF).symbols["zsScalar"].address
    assert result.data.decode().count(f"ASAP1B_CCP DP_BLOB 0x0 0x{scalar:X} 4 /end") == 1
    assert f"ASAP1B_CCP DP_BLOB 0 0x{scalar:X} 4 /end" in result.data.decode()
    assert result.report.tally["IF_DATA ASAP1B_CCP DP_BLOB"] == {"updated": 2}


def test_a_link_map_without_its_address_names_the_place(debug):
    body = ('    /begin MEASUREMENT zsScalar "" FLOAT32_IEEE NO_COMPU_METHOD 1 0 0 1\n      ECU_ADDRESS 0x0\n'
            '      /begin IF_DATA CANAPE_EXT 100 LINK_MAP "zsScalar" /end IF_DATA\n    /end MEASUREMENT\n')
    with pytest.raises(A2lParseError, match="zsScalar: LINK_MAP needs a symbol name and an address") as caught:
        update_document(load_a2l_string(WRAP.format(body), "short.a2l"), debug, epk=False)
    assert "short.a2l:6:" in str(caught.value)


_TYPES_A2L = load_a2l(Path(__file__).parent / "fixtures" / "types.a2l", validate=False)
# the tokens around what an update reads: the last positional parameters, ECU_ADDRESS, EPK, MATRIX_DIM, BIT_MASK
_READ_BY_THE_UPDATE = [token for token in range(len(_TYPES_A2L.tokens)) for word in
                       (b"ECU_ADDRESS", b"EPK", b"ADDR_EPK", b"MATRIX_DIM", b"BIT_MASK", b"SYMBOL_LINK")
                       if _TYPES_A2L.tokens.raw(token) == word for token in (token - 1, token, token + 1)]


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(token=st.sampled_from(_READ_BY_THE_UPDATE) | st.integers(0, len(_TYPES_A2L.tokens) - 1),
       duplicate=st.booleans())
def test_a_damaged_file_is_refused_or_updated_without_new_damage(debug, token, duplicate):
    """One token of a valid file deleted or written twice (a parameter missing, one too many): `update --types`
    refuses the file at a place, or writes one in which no object has an option twice that had it once. It
    used to read a keyword as a value and insert a second ECU_ADDRESS, EPK or MATRIX_DIM beside it."""
    data, (start, end) = _TYPES_A2L.data, _TYPES_A2L.tokens.span(token)
    damaged = data[:start] + data[end:] if not duplicate else data[:end] + b" " + data[start:end] + data[end:]
    try:
        doc = load_a2l_string(damaged.decode(), "damaged.a2l", validate=False)
        result = update_document(doc, debug, types=True)
    except (A2lParseError, InputError):
        return
    updated = load_a2l_string(result.data.decode(), "updated.a2l", validate=False)
    assert _options_twice(updated) <= _options_twice(doc)


def _options_twice(doc) -> set[tuple[str, str, str]]:
    """(block keyword, block name, option) of every option keyword that a block has twice at its own level."""
    found = set()
    for index in range(len(doc.block_begin)):
        block = doc.block(index)
        words = [doc.raw(token).decode("latin-1") for token in block.own_tokens]
        found |= {(block.keyword, block.name or "", word) for word in set(words)
                  if word in grammar.OPTIONS and words.count(word) > 1}
    return found
