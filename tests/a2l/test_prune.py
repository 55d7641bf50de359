"""``remove`` and ``cleanup``: what they take out is what a2ltool 3.4 takes out (the oracle, where it is right),
what refers to it is settled or refuses, and only the removed text differs from the input."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from workbench import demo
from workbench.a2l import (
    IncludeMode,
    PruneFailed,
    check_document,
    cleanup_document,
    cleanup_file,
    flatten_file,
    load_a2l,
    load_a2l_string,
    remove_document,
    remove_file,
)
from workbench.errors import Cancelled
from workbench.findings import Severity

A2LTOOL = shutil.which("a2ltool", path=str(Path(sys.executable).parent)) or shutil.which("a2ltool")
needs_a2ltool = pytest.mark.skipif(A2LTOOL is None, reason="a2ltool is not installed (pip install -e .[dev])")
CORPUS = Path(__file__).parents[1] / "corpus" / "a2l"
DEMO = demo.a2l()
OBJECTS = ("MEASUREMENT", "CHARACTERISTIC", "AXIS_PTS", "BLOB", "INSTANCE")


def _names(data: bytes | Path, keywords: tuple[str, ...] | None = None) -> set[tuple[str, str]]:
    """(keyword, name) of every named block of the file's MODULEs (of ``keywords`` only, when given)."""
    doc = load_a2l(data, validate=False) if isinstance(data, Path) else load_a2l_string(data.decode("utf-8"),
                                                                                          validate=False)
    return {(block.keyword, block.name) for module in doc.modules for block in module.children
            if block.name and (keywords is None or block.keyword in keywords)}


def _a2ltool(tmp_path: Path, source: Path, *options: str) -> Path:
    out = tmp_path / f"a2ltool_{len(list(tmp_path.iterdir()))}.a2l"
    subprocess.run([A2LTOOL, str(source), *options, "--output", str(out)], check=True, capture_output=True,
                   timeout=60)
    return out


def _removed(doc, **options) -> set[tuple[str, str]]:
    """What remove_document takes out, whether it then writes or refuses."""
    try:
        report = remove_document(doc, **options).report
    except PruneFailed as failed:
        report = failed.report
    return {(keyword, name) for keyword, names in report.removed.items() for name in names}


@needs_a2ltool
@pytest.mark.parametrize(("source", "options"), [
    (DEMO, ("-R", "zs.*", "-R", "xaPRV_FF_.*")),
    (DEMO, ("--remove-range", "0x40020000", "0x40020040", "--remove-range", "0x400000F8", "0x40000100")),
    (CORPUS / "a2ltool" / "remove_test.a2l", ("-R", ".*_Value", "--remove-range", "0x4000", "0x5001")),
    (CORPUS / "a2ltool" / "update_test1.a2l", ("-R", "^Curve.*", "-R", "Map_.*xis$")),
])
def test_remove_takes_out_what_a2ltool_takes_out(tmp_path, source, options):
    regexes = tuple(value for flag, value in zip(options, options[1:]) if flag == "-R")
    ranges = tuple((int(low, 0), int(high, 0)) for flag, low, high in zip(options, options[1:], options[2:])
                   if flag == "--remove-range")
    doc = load_a2l(source, validate=False)
    theirs = _names(source, OBJECTS) - _names(_a2ltool(tmp_path, source, *options), OBJECTS)
    assert theirs and _removed(doc, regexes=regexes, ranges=ranges) == theirs


@needs_a2ltool
@pytest.mark.parametrize("source", [DEMO, CORPUS / "a2ltool" / "cleanup_test.a2l",
                                    CORPUS / "a2ltool" / "update_test2.a2l", CORPUS / "domohuhn-a2l" / "example-ecu.a2l"])
def test_cleanup_takes_out_what_a2ltool_takes_out(tmp_path, source):
    ours = cleanup_document(load_a2l(source, validate=False)).data
    assert _names(source) - _names(ours) == _names(source) - _names(_a2ltool(tmp_path, source, "--cleanup"))
    assert _names(source) != _names(ours)


@needs_a2ltool
def test_cleanup_keeps_what_a2ltool_breaks(tmp_path):
    """a2ltool takes the COMPU_METHODs only an INSTANCE's OVERWRITE uses for unused (its output fails check); a UNIT
    only a removed UNIT used stays until its next run; an AXIS_PTS in a GROUP is no dangling entry."""
    source = CORPUS / "a2ltool" / "from_source_structs.a2l"
    theirs = load_a2l(_a2ltool(tmp_path, source, "--cleanup"), validate=False)
    assert [f.name for f in check_document(theirs).problems if "CONVERSION" in f.message] == [
        "shapes_a2l.Conversion_Copy1", "shapes_a2l.Conversion"]
    ours = cleanup_document(load_a2l(source, validate=False))
    assert not [f for f in check_document(load_a2l_string(ours.data.decode())).problems if "CONVERSION" in f.message]
    text = MODULE.format(body="""
    /begin UNIT U_unused "" "s" DERIVED REF_UNIT U_base /end UNIT
    /begin UNIT U_base "" "s" EXTENDED_SI /end UNIT
    /begin RECORD_LAYOUT RL FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin AXIS_PTS a1 "" 0x300 NO_INPUT_QUANTITY RL 0 NO_COMPU_METHOD 3 0 10 /end AXIS_PTS
    /begin GROUP G_axis "" /begin REF_CHARACTERISTIC a1 /end REF_CHARACTERISTIC /end GROUP""")
    source = tmp_path / "units.a2l"
    source.write_text(text)
    kept = _names(cleanup_document(load_a2l(source)).data)
    assert {("GROUP", "G_axis"), ("RECORD_LAYOUT", "RL")} <= kept and not {n for k, n in kept if k == "UNIT"}
    theirs = _names(_a2ltool(tmp_path, source, "--cleanup"))
    assert ("GROUP", "G_axis") not in theirs and ("UNIT", "U_base") in theirs


MODULE = """ASAP2_VERSION 1 71
/begin PROJECT P ""
  /begin MODULE M ""{body}
  /end MODULE
/end PROJECT
"""

LAYOUT = MODULE.format(body="""

    /begin MEASUREMENT keep1 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x100 /end MEASUREMENT

    /begin MEASUREMENT gone1 ""
      UBYTE NO_COMPU_METHOD 0 0 0 1
      ECU_ADDRESS 0x101
    /end MEASUREMENT

    /begin MEASUREMENT keep2 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x102 /end MEASUREMENT
    /begin MEASUREMENT gone2 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x103 /end MEASUREMENT
    /begin MEASUREMENT gone3 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x104 /end MEASUREMENT

    /* the section of keep3 */
    /begin MEASUREMENT gone4 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x105 /end MEASUREMENT
    /begin MEASUREMENT keep3 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x106 /end MEASUREMENT
    /begin GROUP g "" /begin REF_MEASUREMENT keep1 gone1 keep2 gone2 gone3 /end REF_MEASUREMENT /end GROUP
    /begin GROUP h ""
      /begin REF_MEASUREMENT
        gone1
        gone4
      /end REF_MEASUREMENT
      /begin REF_CHARACTERISTIC c /end REF_CHARACTERISTIC
    /end GROUP
    /begin CHARACTERISTIC c "" VALUE 0x200 RL 0 NO_COMPU_METHOD 0 1 /end CHARACTERISTIC
    /begin RECORD_LAYOUT RL FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT

    /begin MEASUREMENT gone5 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x107 /end MEASUREMENT""")


def test_the_text_around_a_removed_block_reads_as_if_it_was_never_written():
    """A block between blank lines leaves one, adjacent ones go as one, a section's blank line and comment stay,
    entries sharing a line leave single blanks, an emptied list goes whole, the last block its blank line."""
    result = remove_document(load_a2l_string(LAYOUT), regexes=("gone.*",))
    assert result.data.decode() == MODULE.format(body="""

    /begin MEASUREMENT keep1 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x100 /end MEASUREMENT

    /begin MEASUREMENT keep2 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x102 /end MEASUREMENT

    /* the section of keep3 */
    /begin MEASUREMENT keep3 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x106 /end MEASUREMENT
    /begin GROUP g "" /begin REF_MEASUREMENT keep1 keep2 /end REF_MEASUREMENT /end GROUP
    /begin GROUP h ""
      /begin REF_CHARACTERISTIC c /end REF_CHARACTERISTIC
    /end GROUP
    /begin CHARACTERISTIC c "" VALUE 0x200 RL 0 NO_COMPU_METHOD 0 1 /end CHARACTERISTIC
    /begin RECORD_LAYOUT RL FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT""")
    report = result.report
    assert report.removed == {"MEASUREMENT": ["gone1", "gone2", "gone3", "gone4", "gone5"]}
    taken = [(f.line, f.column, f.name) for f in report.of_kind("reference-removed")]
    assert taken == [(19, 52, "gone1"), (19, 64, "gone2"), (19, 70, "gone3"), (22, 9, "gone1"), (23, 9, "gone4")]
    assert not check_document(load_a2l_string(result.data.decode())).problems


def test_a_kept_object_that_needs_a_removed_one_refuses():
    """The demo's map needs its AXIS_PTS (refused, both named at the reference); its curve names a measurement as
    input quantity and a fix calibration one as COMPARISON_QUANTITY (refused, or dropped when asked)."""
    doc = load_a2l(DEMO, validate=False)
    with pytest.raises(PruneFailed) as refused:
        remove_document(doc, regexes=("xaPRV_FF_TARGET", "zsRailVoltFilt", "zsTank1Pressure"))
    errors = refused.value.report.errors
    assert [(f.kind, f.name, f.block) for f in errors] == [
        ("still-referenced", "xaPRV_FF_TARGET", "AXIS_DESCR"), ("still-referenced", "zsRailVoltFilt", "AXIS_DESCR"),
        ("still-referenced", "zsTank1Pressure", "CHARACTERISTIC")]
    assert "CHARACTERISTIC xvPRV_DC_FF" in errors[0].message and "--drop-optional-references" in errors[1].message
    assert all(f.file.endswith("FLCU.a2l") and f.line and f.column for f in errors)
    with pytest.raises(PruneFailed):  # dropping optional references does not drop an axis
        remove_document(doc, regexes=("xaPRV_FF_TARGET",), drop_optional=True)
    result = remove_document(doc, regexes=("zsRailVoltFilt", "zsTank1Pressure"), drop_optional=True)
    assert [f.severity for f in result.report.of_kind("reference-dropped")] == [Severity.WARNING] * 2
    text = result.data.decode()
    assert "*/ NO_INPUT_QUANTITY" in text and "COMPARISON_QUANTITY zsTank1Pressure" not in text
    assert not check_document(load_a2l_string(text)).problems
    both = remove_document(doc, regexes=("xaPRV_FF_TARGET", "xvPRV_DC_FF"))  # with its user it may go
    assert both.report.removed == {"CHARACTERISTIC": ["xvPRV_DC_FF"], "AXIS_PTS": ["xaPRV_FF_TARGET"]}


def test_frames_variants_and_instance_components():
    text = MODULE.format(body="""
    /begin TYPEDEF_MEASUREMENT T "" UBYTE NO_COMPU_METHOD 0 0 0 1 /end TYPEDEF_MEASUREMENT
    /begin TYPEDEF_STRUCTURE S "" 1 /begin STRUCTURE_COMPONENT x T 0 /end STRUCTURE_COMPONENT /end TYPEDEF_STRUCTURE
    /begin INSTANCE inst "" S 0x500 /end INSTANCE
    /begin MEASUREMENT m1 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x100 /end MEASUREMENT
    /begin MEASUREMENT m2 "" UBYTE NO_COMPU_METHOD 0 0 0 1 ECU_ADDRESS 0x101 /end MEASUREMENT
    /begin CHARACTERISTIC c1 "" VALUE 0x200 RL 0 NO_COMPU_METHOD 0 1 /end CHARACTERISTIC
    /begin RECORD_LAYOUT RL FNC_VALUES 1 UBYTE ROW_DIR DIRECT /end RECORD_LAYOUT
    /begin FRAME f1 "" 1 10 FRAME_MEASUREMENT m1 m2 /end FRAME
    /begin FRAME f2 "" 1 10 FRAME_MEASUREMENT m2 /end FRAME
    /begin GROUP g "" /begin REF_MEASUREMENT inst.x m1 /end REF_MEASUREMENT /end GROUP
    /begin VARIANT_CODING
      /begin VAR_CRITERION crit "" A B /end VAR_CRITERION
      /begin VAR_CHARACTERISTIC c1 crit /begin VAR_ADDRESS 0x200 0x300 /end VAR_ADDRESS /end VAR_CHARACTERISTIC
    /end VARIANT_CODING""")
    doc = load_a2l_string(text)
    out = remove_document(doc, regexes=("inst", "m2", "c1")).data.decode()
    assert "FRAME_MEASUREMENT m1 /end FRAME" in out and '/begin FRAME f2 "" 1 10 /end FRAME' in out
    assert "REF_MEASUREMENT m1 /end" in out and "VAR_CHARACTERISTIC" not in out and "VAR_CRITERION crit" in out
    assert not check_document(load_a2l_string(out)).problems


def test_changes_in_an_included_file(tmp_path):
    (tmp_path / "part.a2l").write_text('/begin MEASUREMENT gone "" UBYTE NO_COMPU_METHOD 0 0 0 1 /end MEASUREMENT\n'
                                       '/begin MEASUREMENT kept "" UBYTE NO_COMPU_METHOD 0 0 0 1 /end MEASUREMENT\n')
    group = '/begin GROUP g "" /begin REF_MEASUREMENT gone kept /end REF_MEASUREMENT /end GROUP'
    (tmp_path / "main.a2l").write_text(MODULE.format(body=f'\n    /include "part.a2l"\n    {group}'))
    doc = load_a2l(tmp_path / "main.a2l")
    with pytest.raises(PruneFailed) as refused:
        remove_document(doc, regexes=("gone",))
    assert [(f.kind, f.file, f.line) for f in refused.value.report.errors] == [
        ("include-not-updated", str(tmp_path / "part.a2l"), 1)]
    merged = remove_document(doc, regexes=("gone",), includes=IncludeMode.MERGE).data.decode()
    assert "/include" not in merged and "gone" not in merged and "kept" in merged
    updated = remove_document(doc, regexes=("gone",), includes=IncludeMode.UPDATE)
    assert '/include "part.a2l"' in updated.data.decode() and "gone" not in updated.data.decode()
    assert updated.included == {tmp_path / "part.a2l": b'/begin MEASUREMENT kept "" UBYTE NO_COMPU_METHOD 0 0 0 1 '
                                                       b"/end MEASUREMENT\n"}


@needs_a2ltool
def test_flatten_writes_what_a2ltool_merges(tmp_path):
    master = demo.master_a2l()
    report = flatten_file(master, tmp_path / "flat.a2l")
    assert [(f.kind, f.name, f.line) for f in report.findings] == [("include-inlined", "XCP.aml", 18)]
    flat = (tmp_path / "flat.a2l").read_bytes()
    assert b"/include" not in flat.replace(b"with /include", b"") and flat == load_a2l(master).data
    assert _names(flat) == _names(_a2ltool(tmp_path, master, "--merge-includes"))


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.sets(st.sampled_from(sorted(name for _, name in _names(DEMO, OBJECTS))), min_size=1, max_size=12),
       st.booleans())
def test_what_remains_checks_clean(names, cleanup):
    """Any removal the demo accepts leaves a file `check` finds clean (and the one it refuses, a reason)."""
    doc = load_a2l(DEMO, validate=False)
    try:
        result = remove_document(doc, regexes=tuple(map(re.escape, names)), drop_optional=True, cleanup=cleanup)
    except PruneFailed as failed:
        assert {f.kind for f in failed.report.errors} == {"still-referenced"}
        return
    assert {name for names in result.report.removed.values() for name in names} >= names
    assert not check_document(load_a2l_string(result.data.decode())).problems
    assert not {name for _, name in _names(result.data)} & names


def test_cleanup_leaves_a_name_defined_twice_alone():
    """Which of two COMPU_METHODs of one name a MEASUREMENT means is not known: neither goes (check reports them)."""
    text = MODULE.format(body="""
    /begin COMPU_METHOD CM "" IDENTICAL "%6.2" "" /end COMPU_METHOD
    /begin COMPU_METHOD CM "" LINEAR "%6.2" "" COEFFS_LINEAR 2 0 /end COMPU_METHOD
    /begin COMPU_METHOD unused "" IDENTICAL "%6.2" "" /end COMPU_METHOD
    /begin MEASUREMENT m "" UBYTE CM 0 0 0 1 ECU_ADDRESS 0x100 /end MEASUREMENT""")
    result = cleanup_document(load_a2l_string(text))
    assert result.report.removed == {"COMPU_METHOD": ["unused"]} and result.data.decode().count("COMPU_METHOD CM") == 2


def test_a_pattern_that_names_an_instances_object_says_that_whole_instances_go(tmp_path):
    from demo_instances import write_demo_instances_a2l

    doc = load_a2l(write_demo_instances_a2l(tmp_path))
    report = remove_document(doc, regexes=(r"tank\.kp", "nothing")).report
    assert [f.message for f in report.of_kind("regex-matched-nothing")] == [
        r"--regex 'tank\.kp' matches no MEASUREMENT, CHARACTERISTIC, AXIS_PTS, BLOB or INSTANCE; it matches tank.kp "
        "of INSTANCE tank: remove takes whole INSTANCEs (-R tank)",  # the pattern as typed, not its repr
        "--regex 'nothing' matches no MEASUREMENT, CHARACTERISTIC, AXIS_PTS, BLOB or INSTANCE"]


class _CancelAt:
    """A Progress cancelled at the check point labelled ``label`` (Cancel pressed while the job runs there)."""

    def __init__(self, label: str | None):
        self.at, self.labels, self.cancelled = label, [], False

    def update(self, done: int, total: int, label: str = "") -> None:
        self.labels.append(label)
        self.cancelled = label == self.at


@pytest.mark.parametrize(("job", "labels"), [
    (lambda a2l, out, progress: remove_file(a2l, out, regexes=("zsTank.*Filt",), cleanup=True, progress=progress),
     ["reading FLCU.a2l", "selecting the objects", "settling the references to them", "writing"]),
    (lambda a2l, out, progress: cleanup_file(a2l, out, progress=progress),
     ["reading FLCU.a2l", "finding what nothing uses", "writing"]),
    (lambda a2l, out, progress: flatten_file(a2l, out, progress=progress), ["reading FLCU.a2l", "writing"]),
], ids=["remove", "cleanup", "flatten"])
def test_a_cancel_at_any_check_point_stops_the_job_and_nothing_is_written(tmp_path, job, labels):
    source, output = tmp_path / "FLCU.a2l", tmp_path / "out.a2l"
    shutil.copy(DEMO, source)
    for label in labels:
        progress = _CancelAt(label)
        with pytest.raises(Cancelled):
            job(source, output, progress)
        assert progress.labels == labels[:labels.index(label) + 1] and not output.exists()
    progress = _CancelAt(None)
    job(source, output, progress)
    assert progress.labels == labels and output.exists()
