"""The HTML report: traceability first (requirement -> tests -> result, untested ones named), then each test's
steps and its signals read back from its MF4 evidence, the expectation bands drawn over them."""

from __future__ import annotations

import json
import re
from datetime import datetime, timezone

import numpy as np
import pytest
from asammdf import MDF, Signal

from workbench.errors import InputError
from workbench.testbench.report import read_requirements, write_report

EPOCH = 1_700_000_000.0


def _evidence(path):
    mdf = MDF(version="4.10")
    mdf.header.start_time = datetime.fromtimestamp(EPOCH + 0.5, timezone.utc)  # the recording began 0.5 s in
    t = np.arange(0.0, 2.0, 0.05)
    mdf.append([Signal(np.where(t < 1.0, 10.0, 25.0), t, name="zsRailPressure", unit="bar")], acq_name="Task4ms")
    state = Signal(np.where(t < 1.2, 1, 0).astype(np.uint8), t, name="xsTankCtrlState",
                   conversion={"val_0": 0, "text_0": "OFF", "val_1": 1, "text_1": "TANK1_ON"})
    mdf.append([state], acq_name="Task50ms")
    mdf.save(path, overwrite=True)
    mdf.close()


def _step(kind, text, t0, t1, signal=None, band=None, target=None, passed=None, detail=""):
    return {"kind": kind, "text": text, "t_start": t0, "t_end": t1, "signal": signal, "unit": "bar" if band else "",
            "band": band, "target": target, "passed": passed, "detail": detail}


def test_traceability_steps_and_plots(tmp_path):
    (tmp_path / "evidence").mkdir()
    _evidence(tmp_path / "evidence" / "a.mf4")
    (tmp_path / "tests").mkdir()
    record = {"nodeid": "test_x.py::test_a", "epoch": EPOCH, "evidence": [str(tmp_path / "evidence" / "a.mf4")],
              "steps": [_step("stimulus", "write xsSWITCH_TANK_THR = 5 bar", 1.4, 1.41),
                        _step("expect", "expect zsRailPressure within [24, 26] bar for 0.5 s", 1.6, 2.1,
                              "zsRailPressure", [24.0, 26.0], passed=True, detail="10 samples"),
                        _step("expect", "expect xsTankCtrlState = OFF within 100 ms", 1.41, 1.51, "xsTankCtrlState",
                              target="OFF", passed=False, detail="not within 100 ms")]}
    (tmp_path / "tests" / "a.json").write_text(json.dumps(record))
    catalogue = tmp_path / "requirements.csv"
    catalogue.write_text("id,name,description\nREQ_1,RAIL,the rail\nREQ_2,TANKS,the tanks\nREQ_3,LED,the LED\n")
    results = {"test_x.py::test_a": {"outcome": "failed", "duration": 2.5, "message": "expect xsTankCtrlState ...",
                                     "requirements": ["REQ_1", "REQ_2"]},
               "test_x.py::test_b": {"outcome": "passed", "duration": 0.1, "message": "", "requirements": ["REQ_2", "REQ_9"]}}
    html = write_report(tmp_path, results, catalogue=read_requirements(catalogue), ecu="a test ECU").read_text()
    trace = html[html.index("<h2>Traceability</h2>"):html.index("<h2>Tests</h2>")]
    rows = re.findall(r"<tr><td>(REQ_\d)</td>.*?</tr>", trace)
    assert rows == ["REQ_1", "REQ_2", "REQ_3", "REQ_9"]  # the catalogue's order, then ids it lacks
    assert re.search(r'REQ_3</td><td><span title="the LED">LED</span></td><td>-</td><td><span class="badge untested">', trace)
    assert re.search(r"REQ_2</td>.*test_x.py::test_a.*test_x.py::test_b.*badge failed\">FAILED</span></td></tr>", trace)
    section = html[html.index('id="t-test-x-py--test-a"'):]
    assert 'href="evidence/a.mf4"' in section and "write xsSWITCH_TANK_THR = 5 bar" in section
    plots = re.findall(r"<svg.*?</svg>", section)
    assert len(plots) == 2  # one per signal an expectation named
    rail, state = plots
    assert "zsRailPressure" in rail and 'fill="#2e7d32"' in rail and "<polyline" in rail  # a passed band, the samples
    assert ">TANK1_ON</text>" in state and 'fill="#c62828"' in state  # verbal labels; the failed band in red
    first_x = float(re.search(r'points="([\d.]+),', rail)[1])
    assert first_x > 56 + 0.2 * (760 - 68)  # the samples start 0.5 s into the test, not at its start


def test_a_test_without_steps_and_a_bad_catalogue(tmp_path):
    results = {"test_y.py::test_c": {"outcome": "skipped", "duration": 0.0, "message": "needs the simulated ECU",
                                     "requirements": []}}
    html = write_report(tmp_path, results).read_text()
    assert "No steps recorded" in html and "Tests tracing no requirement: test_y.py::test_c" in html
    bad = tmp_path / "bad.csv"
    bad.write_text("ident,name\nX,Y\n")
    with pytest.raises(InputError, match=r"bad.csv:1: the header must name the columns id,name,description"):
        read_requirements(bad)
    bad.write_text("id,name\nX,Y\n,Z\n")
    with pytest.raises(InputError, match=r"bad.csv:3: a requirement without an id"):
        read_requirements(bad)
    exported = tmp_path / "doors.csv"  # a spreadsheet's CSV export: Windows-1252
    exported.write_bytes("id,name,description\r\nSW_REQ_1,Druck,unter 5 °C in 300 µs\r\n".encode("cp1252"))
    assert read_requirements(exported)[0].description == "unter 5 °C in 300 µs"
    german = tmp_path / "excel.csv"  # Excel where the decimal separator is a comma saves ';' between the columns
    german.write_bytes("ID;Name;Description\r\nSW_REQ_1;Raildruck;folgt ±2,5 bar\r\n;;\r\n".encode("cp1252"))
    assert [(r.id, r.name, r.description) for r in read_requirements(german)] == [
        ("SW_REQ_1", "Raildruck", "folgt ±2,5 bar")]  # was 'the header must name the columns' (user trial 10)


def _points(element: str) -> list[tuple[float, float]]:
    return [tuple(map(float, point.split(","))) for point in re.search(r'points="([^"]*)"', element)[1].split()]


def test_a_follows_expectation_shows_the_followed_signal_and_its_tolerance(tmp_path):
    """expect_follows draws the signal it compared with dashed over the one it judged (same scale), and that signal
    ± the tolerance over the window it judged: with a tolerance of 0 a line on it (a band of no height is invisible)."""
    mdf = MDF(version="4.10")
    mdf.header.start_time = datetime.fromtimestamp(EPOCH, timezone.utc)
    t = np.arange(0.0, 1.0, 0.05)
    mdf.append([Signal(t * 100, t, name="xsDC", unit="%"), Signal(t * 100, t, name="xsPRVDutyCmd", unit="%")],
               acq_name="Task4ms")
    (tmp_path / "evidence").mkdir()
    mdf.save(tmp_path / "evidence" / "f.mf4", overwrite=True)
    mdf.close()
    (tmp_path / "tests").mkdir()
    exact = {**_step("expect", "expect xsPRVDutyCmd = xsDC ± 0 % for 0.3 s", 0.2, 0.5, "xsPRVDutyCmd", passed=True),
             "reference": "xsDC", "tolerance": 0.0}
    loose = {**_step("expect", "expect xsPRVDutyCmd = xsDC ± 5 % for 0.2 s", 0.6, 0.8, "xsPRVDutyCmd", passed=False),
             "reference": "xsDC", "tolerance": 5.0}
    record = {"nodeid": "test_f.py::test_f", "epoch": EPOCH, "evidence": [str(tmp_path / "evidence" / "f.mf4")],
              "steps": [exact, loose]}
    (tmp_path / "tests" / "f.json").write_text(json.dumps(record))
    html = write_report(tmp_path, {"test_f.py::test_f": {"outcome": "failed", "duration": 1.0, "message": "",
                                                        "requirements": []}}).read_text()
    (plot,) = re.findall(r"<svg.*?</svg>", html)
    (followed,) = re.findall(r'<polyline [^>]*stroke-dasharray="5 4"><title>xsDC \(followed\)</title>', plot)
    (line,) = re.findall(r'<polyline [^>]*stroke="#2e7d32" stroke-width="5"[^>]*><title>expect xsPRVDutyCmd = '
                         r"xsDC ± 0 ", plot)
    x_of = lambda seconds: 56 + seconds / 0.95 * (760 - 56 - 12)  # noqa: E731 (the plot spans 0 .. the last sample)
    xs, ys = zip(*_points(line))
    assert (min(xs), max(xs)) == pytest.approx((x_of(0.2), x_of(0.5)), abs=0.1)  # over the window judged ...
    assert set(ys) <= {y for _, y in _points(followed)} and len(set(ys)) >= 6  # ... on xsDC's values, step by step
    (band,) = re.findall(r'<polygon [^>]*fill="#c62828"[^>]*><title>expect xsPRVDutyCmd = xsDC ± 5 ', plot)
    corners = _points(band)
    upper, lower = corners[:len(corners) // 2], corners[len(corners) // 2:][::-1]
    assert [x for x, _ in upper] == [x for x, _ in lower]
    assert min(x for x, _ in upper) == pytest.approx(x_of(0.6), abs=0.1)
    heights = {round(low - high, 1) for (_, high), (_, low) in zip(upper, lower)}
    assert len(heights) == 1 and heights.pop() > 2  # xsDC ± 5 %: a band of one height around it, failed: red
