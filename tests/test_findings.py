"""One finding type for every package: its location, text and JSON form, and a report's verdicts."""

from workbench.findings import Finding, Report, Severity, summarize


def test_location_says_as_much_as_is_known():
    assert Finding("k", "X", "m", "a.a2l", 3, 7).location == "a.a2l:3:7"
    assert Finding("k", "M.S", "m", "b.dbc", 12).location == "b.dbc:12"
    assert Finding("k", "X", "m", "c.elf").location == "c.elf"
    assert Finding("k", "X", "m").location == ""


def test_text_and_dict():
    finding = Finding("overlap", "M.B", "M.B: overlaps A", "b.dbc", 15, block="SG_", severity=Severity.ERROR)
    assert str(finding) == "b.dbc:15: error: M.B: overlaps A"
    assert str(Finding("merged", "FLCU", "3 blocks merged")) == "info: 3 blocks merged"
    assert finding.to_dict() == {"kind": "overlap", "name": "M.B", "message": "M.B: overlaps A", "file": "b.dbc",
                                 "line": 15, "column": 0, "block": "SG_", "severity": "error"}


def test_report_separates_problems_from_what_was_done():
    done = Finding("address-updated", "a", "a: 0x0 -> 0x10")
    warned = Finding("symbol-not-found", "b", "b: not in x.elf", severity=Severity.WARNING)
    report = Report("update", [done, warned])
    assert (report.problems, report.warnings, report.errors, report.ok) == ([warned], [warned], [], True)
    report.add(Finding("syntax", "", "bad", "x.a2l", 1, 1, severity=Severity.ERROR))
    assert not report.ok and report.to_dict()["counts"] == {"address-updated": 1, "symbol-not-found": 1, "syntax": 1}
    assert summarize(report.findings, shown=2) == "a, b and 1 more"
