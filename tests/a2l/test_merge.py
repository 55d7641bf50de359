"""merge: fragments into a master, nested includes, identical and conflicting definitions under each policy."""

import pytest
from pya2l_oracle import pya2l_import

from workbench.a2l import load_a2l, load_a2l_string
from workbench.a2l.merge import MergeFailed, merge_documents, merge_files
from workbench.a2l.reports import ConflictPolicy
from workbench.errors import A2lParseError

MASTER = """/* master */
ASAP2_VERSION 1 71
/begin PROJECT P "project"
  /begin MODULE ECU "the ECU"
    /begin MOD_PAR "ecu"
      /begin MEMORY_SEGMENT Ram "" DATA RAM INTERN 0x1000 0x1000 -1 -1 -1 -1 -1 /end MEMORY_SEGMENT
    /end MOD_PAR
    /begin MOD_COMMON "" BYTE_ORDER MSB_LAST /end MOD_COMMON
    /begin COMPU_METHOD CM "shared" IDENTICAL "%6.2" "" /end COMPU_METHOD
    /begin RECORD_LAYOUT RL FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT
  /end MODULE
/end PROJECT
"""


def fragment(module: str, body: str, common: str = "MSB_LAST") -> str:
    return (f'ASAP2_VERSION 1 71\n/begin PROJECT {module} ""\n  /begin MODULE {module} "fragment"\n'
            f'    /begin MOD_COMMON "" BYTE_ORDER {common} /end MOD_COMMON\n{body}  /end MODULE\n/end PROJECT\n')


def measurement(name: str, conversion: str = "CM", upper: int = 255, comment: str = "") -> str:
    return (f'    {comment}/begin MEASUREMENT {name} "" UBYTE {conversion} 1 0 0 {upper}\n'
            f'      ECU_ADDRESS 0x0\n    /end MEASUREMENT\n')


SAME_CM = '    /begin COMPU_METHOD CM "shared"   IDENTICAL "%6.2" "" /* same tokens */ /end COMPU_METHOD\n'
OTHER_CM = '    /begin COMPU_METHOD CM "other" LINEAR "%6.2" "" COEFFS_LINEAR 2 0 /end COMPU_METHOD\n'


def run(fragments, policy=ConflictPolicy.ERROR, master=MASTER):
    return merge_documents(load_a2l_string(master, "master.a2l"), [load_a2l_string(text, f"f{i}.a2l") for i, text in enumerate(fragments)],
                 policy=policy)


def test_fragment_content_goes_verbatim_into_the_masters_module():
    body = "    /* sensors */\n" + measurement("a") + SAME_CM + measurement("b")
    result = run([fragment("Sensors", body)])
    text = result.data.decode()
    doc = load_a2l_string(text)
    assert [b.name for b in doc.objects("MEASUREMENT")] == ["a", "b"]
    assert len(doc.objects("COMPU_METHOD")) == 1  # identical: merged silently
    assert "    /* ---- merged from f0.a2l ---- */\n    /* sensors */\n    /begin MEASUREMENT a" in text
    assert text.startswith(MASTER.split("  /end MODULE")[0])  # the master's text is untouched
    assert text.endswith("    /end MEASUREMENT\n  /end MODULE\n/end PROJECT\n")
    assert len(doc.modules[0].children_named("MOD_COMMON")) == 1
    kinds = result.report.counts()
    assert kinds == {"duplicate-identical": 1, "ignored": 1, "merged": 1}


def test_different_mod_common_is_reported():
    result = run([fragment("Big", measurement("a"), common="MSB_FIRST")])
    (finding,) = result.report.of_kind("mod-common-differs")
    assert "BYTE_ORDER" in finding.message and finding.line == 4


def test_conflict_is_an_error_by_default():
    with pytest.raises(MergeFailed, match=r"1 conflicting definition\(s\): CM \(f0.a2l:5:12\)") as info:
        run([fragment("A", OTHER_CM + measurement("a"))])
    assert info.value.exit_code == 1
    (conflict,) = info.value.report.of_kind("conflict")
    assert conflict.message.endswith('differs from the definition at master.a2l:9 (first difference at line 5: '
                                     '"other" here, "shared" there)')


def test_keep_first_keeps_the_masters_definition():
    result = run([fragment("A", OTHER_CM + measurement("a"))], ConflictPolicy.KEEP_FIRST)
    doc = load_a2l_string(result.data.decode())
    (cm,) = doc.objects("COMPU_METHOD")
    assert doc.text(cm.args[1]) == "shared"
    assert result.report.of_kind("kept-first")[0].name == "CM"


def test_keep_last_replaces_the_master_and_earlier_fragments():
    result = run([fragment("A", OTHER_CM + measurement("x", upper=1)), fragment("B", measurement("x", upper=2))],
                 ConflictPolicy.KEEP_LAST)
    doc = load_a2l_string(result.data.decode())
    (cm,) = doc.objects("COMPU_METHOD")
    assert doc.text(cm.args[1]) == "other"  # replaced in the master, in place
    (x,) = doc.objects("MEASUREMENT")
    assert doc.text(x.args[7]) == "2" and doc.block_begin[x.index] > doc.block_begin[cm.index]
    assert [f.name for f in result.report.of_kind("kept-last")] == ["CM", "x"]


def test_keep_last_twice_over_a_master_definition_leaves_one_the_last():
    third = OTHER_CM.replace('"other"', '"third"')
    result = run([fragment("A", OTHER_CM), fragment("B", third + measurement("b"))], ConflictPolicy.KEEP_LAST)
    doc = load_a2l_string(result.data.decode())
    (cm,) = doc.objects("COMPU_METHOD")
    assert doc.text(cm.args[1]) == "third" and cm.position[1] == 9  # in the master's place
    assert [f.name for f in result.report.of_kind("kept-last")] == ["CM", "CM"]


def test_rename_renames_the_definition_and_the_fragments_references():
    body = OTHER_CM + measurement("a") + measurement("x", upper=7)
    result = run([fragment("A", measurement("x")), fragment("B", body)], ConflictPolicy.RENAME)
    doc = load_a2l_string(result.data.decode())
    names = sorted(b.name for b in doc.objects("COMPU_METHOD"))
    assert names == ["CM", "CM_B"]
    by_name = {b.name: b for b in doc.objects("MEASUREMENT")}
    assert sorted(by_name) == ["a", "x", "x_B"]
    assert doc.text(by_name["a"].args[3]) == "CM_B"  # B's reference follows B's renamed COMPU_METHOD
    assert doc.text(by_name["x"].args[3]) == "CM"
    link = by_name["x_B"].option("SYMBOL_LINK")  # the renamed object still finds its variable
    assert doc.text(link[0]) == "x" and doc.int_value(link[1]) == 0
    renamed = {f.name: f.message for f in result.report.of_kind("renamed")}
    assert set(renamed) == {"CM", "x"} and "renamed to x_B" in renamed["x"]


def test_rename_refuses_a_name_a_fragment_defines_twice_differently():
    """Its own references cannot tell the two apart: renaming made both x_B; with an identical third copy left out
    the merge raised 'overlapping edits' (a hypothesis find). Keep-first/keep-last drop one and stay unambiguous."""
    body = measurement("x") + measurement("x") + measurement("x", upper=7)
    with pytest.raises(MergeFailed, match=r"\(choose --on-conflict keep-first or keep-last\)$") as info:
        run([fragment("B", body)], ConflictPolicy.RENAME)
    (conflict,) = info.value.report.of_kind("conflict")
    assert conflict.message.startswith("MEASUREMENT x is defined twice in f0.a2l, differently, also at f0.a2l:5 (")
    assert conflict.message.endswith("correct the fragment, or merge with --on-conflict keep-first/keep-last")
    for policy, upper in ((ConflictPolicy.KEEP_FIRST, "255"), (ConflictPolicy.KEEP_LAST, "7")):
        doc = load_a2l_string(run([fragment("B", body)], policy).data.decode())
        assert [(b.name, doc.text(b.args[-1])) for b in doc.objects("MEASUREMENT")] == [("x", upper)]


def test_rename_follows_references_into_definitions_that_only_looked_identical():
    vtab = '    /begin COMPU_VTAB V "" TAB_VERB 1 0 "{}" /end COMPU_VTAB\n'
    method = '    /begin COMPU_METHOD CM_V "" TAB_VERB "%4.0" "" COMPU_TAB_REF V /end COMPU_METHOD\n'
    a = fragment("A", method + vtab.format("off") + measurement("a", "CM_V"))
    b = fragment("B", method + vtab.format("OFF") + measurement("b", "CM_V"))  # CM_V's tokens equal A's
    result = run([a, b], ConflictPolicy.RENAME)
    doc = load_a2l_string(result.data.decode())
    tables = {m.name: doc.text(m.option("COMPU_TAB_REF")[0]) for m in doc.objects("COMPU_METHOD") if m.name != "CM"}
    assert tables == {"CM_V": "V", "CM_V_B": "V_B"}
    by_name = {m.name: doc.text(m.args[3]) for m in doc.objects("MEASUREMENT")}
    assert by_name == {"a": "CM_V", "b": "CM_V_B"}  # b keeps its own enumeration
    assert sorted(f.name for f in result.report.of_kind("renamed")) == ["CM_V", "V"]
    assert not result.report.of_kind("duplicate-identical")


def test_nested_includes_in_master_and_fragments(tmp_path):
    (tmp_path / "inc").mkdir()
    (tmp_path / "master.a2l").write_text(MASTER.replace('    /begin COMPU_METHOD CM', '    /include "inc/cm.a2l"\n'
                                                        '    /begin COMPU_METHOD CM0'))
    (tmp_path / "inc" / "cm.a2l").write_text('/include "more.a2l"\n')
    (tmp_path / "inc" / "more.a2l").write_text('    /begin UNIT U "" "x" DERIVED /end UNIT\n')
    (tmp_path / "frag.a2l").write_text(fragment("F", '    /include "frag_objects.a2l"\n'))
    (tmp_path / "frag_objects.a2l").write_text(measurement("m", "CM0") + '    /include "inc/more.a2l"\n')
    out = tmp_path / "out.a2l"
    report = merge_files(tmp_path / "master.a2l", [tmp_path / "frag.a2l"], out)
    doc = load_a2l(out)
    assert b"/include" not in out.read_bytes()
    assert [b.name for b in doc.objects("MEASUREMENT")] == ["m"] and len(doc.objects("UNIT")) == 1
    assert report.of_kind("includes-inlined") and report.of_kind("duplicate-identical")[0].name == "U"


def test_encodings_and_newlines_follow_the_master(tmp_path):
    master = tmp_path / "master.a2l"
    master.write_bytes(MASTER.replace("\n", "\r\n").encode("utf-8"))
    frag = tmp_path / "frag.a2l"
    body = measurement("level").replace('level ""', 'level "Füllstand"')
    frag.write_bytes(fragment("F", body).replace('"fragment"', '"Größe"').encode("latin-1"))
    out = tmp_path / "out.a2l"
    merge_files(master, [frag], out)
    data = out.read_bytes()
    assert "Größe".encode("utf-8") not in data  # the fragment's MODULE header is not copied
    assert "Füllstand".encode("utf-8") in data and b"\n" not in data.replace(b"\r\n", b"")


def test_pya2ldb_accepts_the_merged_demo(tmp_path):
    from workbench import demo

    out = tmp_path / "merged.a2l"
    merge_files(demo.master_a2l(), demo.fragment_a2ls(), out)
    counts = pya2l_import(out)
    assert counts["MEASUREMENT"] == sum(len(load_a2l(p).objects("MEASUREMENT")) for p in demo.fragment_a2ls())


TWO_MODULES = MASTER.replace("/end PROJECT", '  /begin MODULE BODY "second ECU"\n'
                             '    /begin MOD_COMMON "" BYTE_ORDER MSB_FIRST /end MOD_COMMON\n  /end MODULE\n/end PROJECT')
BARE = ('/* sensor signals, written for /include */\n' + measurement("level") + measurement("pressure", "CM_P")
        + '/begin COMPU_METHOD CM_P "" LINEAR "%6.2" "bar" COEFFS_LINEAR 0.1 0 /end COMPU_METHOD\n')


def _cli(capsys, *argv):
    from workbench.cli import main

    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_a_master_with_several_modules_needs_module(capsys, tmp_path):
    (tmp_path / "master.a2l").write_text(TWO_MODULES)
    (tmp_path / "frag.a2l").write_text(fragment("Sensors", measurement("a")))
    out = tmp_path / "out.a2l"
    code, _, err = _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "frag.a2l", "-o", out)
    assert (code, err) == (2, f"error: {tmp_path / 'master.a2l'}: 2 MODULEs (ECU, BODY): choose one with --module "
                              "NAME\n") and not out.exists()
    code, _, err = _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "frag.a2l", "-o", out,
                        "--module", "GEARBOX")
    assert (code, err) == (2, f"error: {tmp_path / 'master.a2l'}: no MODULE named GEARBOX (its MODULEs: ECU, BODY)\n")
    with pytest.raises(A2lParseError, match=r"expected exactly one MODULE, found 2 \(ECU, BODY\)"):
        load_a2l(tmp_path / "master.a2l").module()  # what a reader of one MODULE says
    code, _, _ = _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "frag.a2l", "-o", out,
                      "--module", "BODY")
    doc = load_a2l(out)
    assert code == 0 and [[b.name for b in m.children_named("MEASUREMENT")] for m in doc.modules] == [[], ["a"]]
    # the fragment's MOD_COMMON is compared with the chosen MODULE's
    assert "MOD_COMMON of frag.a2l differs from the master's in BYTE_ORDER" in _cli(
        capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "frag.a2l", "-o", out, "--module", "BODY")[1]


def test_a_bare_fragment_merges_like_a_whole_one(capsys, tmp_path):
    (tmp_path / "master.a2l").write_text(MASTER)
    (tmp_path / "sensors.a2l").write_text("ASAP2_VERSION 1 71\n" + BARE)
    (tmp_path / "whole.a2l").write_text(fragment("Sensors", BARE))
    bare_out, whole_out = tmp_path / "bare_out.a2l", tmp_path / "whole_out.a2l"
    assert _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "sensors.a2l", "-o", bare_out)[0] == 0
    assert _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "whole.a2l", "-o", whole_out)[0] == 0
    bare, whole = load_a2l(bare_out), load_a2l(whole_out)
    assert [(b.keyword, b.name) for b in bare.modules[0].children] == [
        (b.keyword, b.name) for b in whole.modules[0].children]
    assert bare_out.read_text().count("ASAP2_VERSION") == 1  # the fragment's is left out
    # a rename takes the file's name where a bare fragment has no MODULE name
    (tmp_path / "other.a2l").write_text(BARE.replace('"bar"', '"kPa"'))
    code, out, _ = _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "sensors.a2l",
                        tmp_path / "other.a2l", "-o", bare_out, "--on-conflict", "rename")
    assert code == 0 and "COMPU_METHOD CM_P of other.a2l renamed to CM_P_other" in out


def test_a_bare_fragment_is_validated_as_module_content(capsys, tmp_path):
    (tmp_path / "master.a2l").write_text(MASTER)
    (tmp_path / "bad.a2l").write_text(BARE + '/begin HEADER "not module content" /end HEADER\n')
    code, _, err = _cli(capsys, "a2l", "merge", tmp_path / "master.a2l", tmp_path / "bad.a2l", "-o", tmp_path / "o.a2l")
    assert (code, err) == (2, f"error: {tmp_path / 'bad.a2l'}:9:8: block /begin HEADER is not allowed in MODULE\n")
