"""The HTML report of a requirement-test run: traceability first, then every test with its steps and plots.

``DIR/report.html`` opens with the traceability table (requirement -> tests -> result; the requirements
of a catalogue that no test covers are listed as not tested), then shows per test its outcome, the
failure in one line, its steps, one plot per signal it expected something of (the samples read back from
its MF4 evidence, the expectation bands over them, the stimuli as dashed lines) and links to the MF4 files.
It reads what the plugin left in DIR: ``tests/*.json`` (steps, evidence) and the outcomes of the run.
"""

from __future__ import annotations

import csv
import io
import json
import time
from collections.abc import Sequence
from dataclasses import dataclass
from html import escape
from pathlib import Path

import numpy as np

from workbench.errors import InputError
from workbench.fileio import atomic_write_text, read_text_input
from workbench.logs import logger
from workbench.testbench.svgplot import Band, plot_svg
from workbench.testbench.verdicts import report_anchor

__all__ = ["Requirement", "read_requirements", "write_report"]

log = logger(__name__)

_ORDER = {"failed": 0, "error": 0, "interrupted": 0, "passed": 1, "skipped": 2}


@dataclass(frozen=True)
class Requirement:
    id: str
    name: str = ""
    description: str = ""


def read_requirements(path: str | Path) -> list[Requirement]:
    """A requirements catalogue: CSV with the columns ``id,name,description`` (a header line; ``;`` or tabs between
    them as a spreadsheet saves them too, in UTF-8 or the Windows code page).

    :raises InputError: the file cannot be read or lacks the ``id`` column (file:line named).
    """
    path = Path(path)
    text = read_text_input(path, "a requirements CSV file")
    header = text.partition("\n")[0]
    delimiter = max(",;\t", key=header.count)  # a spreadsheet saves ';' where the locale writes decimal commas
    reader = csv.reader(io.StringIO(text, newline=""), delimiter=delimiter)
    columns = [column.strip().lower() for column in next(reader, [])]
    if columns and "id" not in columns:
        raise InputError(f"{path}:1: the header must name the columns id,name,description (it names "
                         f"{header.strip()!r})")
    requirements = []
    for row in reader:
        fields = dict(zip(columns, (value.strip() for value in row)))
        if not any(fields.values()):  # a blank line, or one a spreadsheet left of empty cells
            continue
        if not fields.get("id"):
            raise InputError(f"{path}:{reader.line_num}: a requirement without an id")
        requirements.append(Requirement(fields["id"], fields.get("name", ""), fields.get("description", "")))
    return requirements


def write_report(directory: str | Path, results: dict[str, dict], *, catalogue: Sequence[Requirement] = (),
                 ecu: str = "") -> Path:
    """Write ``directory/report.html`` from the outcomes ``results`` (node id -> outcome, duration, message,
    requirements), the requirements ``catalogue`` (:func:`read_requirements`) and the records the plugin wrote;
    returns its path."""
    directory = Path(directory)
    records = _records(directory)
    tests = sorted(results.items(), key=lambda item: item[0])
    html = [_HEAD, "<h1>Requirement tests</h1>", _summary(tests, ecu), "<h2>Traceability</h2>",
            _traceability(tests, catalogue), "<h2>Tests</h2>"]
    for nodeid, outcome in tests:
        html.append(_test_section(directory, nodeid, outcome, records.get(nodeid)))
    html.append("</body></html>")
    path = directory / "report.html"
    atomic_write_text(path, "\n".join(html))
    return path


def _records(directory: Path) -> dict[str, dict]:
    records = {}
    for path in sorted((directory / "tests").glob("*.json")):
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            log.warning("%s: not read (%s)", path, exc)
            continue
        records[record["nodeid"]] = record
    return records


def _badge(outcome: str) -> str:
    return f'<span class="badge {escape(outcome)}">{escape(outcome.upper())}</span>'


def _summary(tests: list, ecu: str) -> str:
    counts: dict[str, int] = {}
    for _, outcome in tests:
        counts[outcome["outcome"]] = counts.get(outcome["outcome"], 0) + 1
    text = ", ".join(f"{count} {name}" for name, count in sorted(counts.items(), key=lambda c: _ORDER.get(c[0], 3)))
    return (f"<p>{len(tests)} tests: {escape(text or 'none')}. ECU: {escape(ecu or 'as the options named')}. "
            f"Written {escape(time.strftime('%Y-%m-%d %H:%M:%S'))}.</p>")


def _traceability(tests: list, catalogue: list[Requirement]) -> str:
    by_requirement: dict[str, list[tuple[str, dict]]] = {}
    for nodeid, outcome in tests:
        for requirement_id in outcome.get("requirements", []):
            by_requirement.setdefault(requirement_id, []).append((nodeid, outcome))
    names = {r.id: r for r in catalogue}
    ids = [r.id for r in catalogue] + sorted(set(by_requirement) - set(names))
    rows = ['<table class="trace"><tr><th>Requirement</th><th>Name</th><th>Tests</th><th>Result</th></tr>']
    for requirement_id in ids:
        covering = by_requirement.get(requirement_id, [])
        outcomes = {outcome["outcome"] for _, outcome in covering}
        if not covering:
            result = '<span class="badge untested">NOT TESTED</span>'
        elif "failed" in outcomes:
            result = _badge("failed")
        elif "error" in outcomes:  # a test broke before it judged: neither verified nor failed
            result = '<span class="badge error">NOT JUDGED</span>'
        elif "interrupted" in outcomes:  # the run stopped (Ctrl-C) within a test: it verified nothing
            result = _badge("interrupted")
        elif "passed" in outcomes:
            result = _badge("passed")
        else:
            result = _badge("skipped")
        links = "<br>".join(f'<a href="#{report_anchor(nodeid)}">{escape(nodeid)}</a> {_badge(outcome["outcome"])}'
                            for nodeid, outcome in covering)
        known = names.get(requirement_id)
        title = escape(known.name) if known else ""
        if known and known.description:
            title = f'<span title="{escape(known.description)}">{title or escape(known.description)}</span>'
        rows.append(f"<tr><td>{escape(requirement_id)}</td><td>{title}</td><td>{links or '-'}</td><td>{result}</td></tr>")
    rows.append("</table>")
    untraced = [nodeid for nodeid, outcome in tests if not outcome.get("requirements")]
    if untraced:
        rows.append(f"<p>Tests tracing no requirement: {escape(', '.join(untraced))}</p>")
    return "\n".join(rows)


def _test_section(directory: Path, nodeid: str, outcome: dict, record: dict | None) -> str:
    parts = [f'<section id="{report_anchor(nodeid)}"><h3>{escape(nodeid)} {_badge(outcome["outcome"])}</h3>',
             f"<p>Requirements: {escape(', '.join(outcome.get('requirements', [])) or 'none')}; "
             f"{outcome.get('duration', 0.0):.2f} s</p>"]
    if outcome.get("message"):
        parts.append(f'<p class="message">{escape(outcome["message"])}</p>')
    if record is None:
        parts.append("<p>No steps recorded (the test did not use the ecu fixture).</p></section>")
        return "\n".join(parts)
    evidence = [Path(p) for p in record.get("evidence", [])]
    if evidence:
        links = ", ".join(f'<a href="{escape(_relative(p, directory))}">{escape(p.name)}</a>' for p in evidence)
        parts.append(f"<p>Evidence (MDF4): {links}</p>")
    steps = record.get("steps", [])
    parts.append(_steps_table(steps))
    parts += _plots(evidence, steps, record.get("epoch", 0.0))
    parts.append("</section>")
    return "\n".join(parts)


def _relative(path: Path, directory: Path) -> str:
    try:
        return path.resolve().relative_to(directory.resolve()).as_posix()
    except ValueError:
        return path.resolve().as_uri()


def _steps_table(steps: list[dict]) -> str:
    rows = ['<table class="steps"><tr><th>t [s]</th><th>step</th><th>what</th><th>result</th></tr>']
    for step in steps:
        result = "" if step["passed"] is None else ("ok" if step["passed"] else "FAILED" if step.get("judged", True)
                                                    else "NOT JUDGED")
        detail = f" ({step['detail']})" if step.get("detail") else ""
        css = "" if step["passed"] is None else (' class="ok"' if step["passed"] else ' class="failed"')
        rows.append(f"<tr{css}><td>{step['t_start']:.3f}</td><td>{escape(step['kind'])}</td>"
                    f"<td>{escape(step['text'])}</td><td>{escape(result + detail)}</td></tr>")
    rows.append("</table>")
    return "\n".join(rows)


def _plots(evidence: list[Path], steps: list[dict], epoch: float) -> list[str]:
    signals = list(dict.fromkeys(step["signal"] for step in steps if step.get("signal")))
    if not signals:
        return []
    references = [step["reference"] for step in steps if step.get("reference")]
    recorded = _read_evidence(evidence, list(dict.fromkeys(signals + references)), epoch)
    stimuli = [step["t_start"] for step in steps if step["kind"] == "stimulus"]
    end = max([step["t_end"] for step in steps] + [0.0])
    plots = []
    for name in signals:
        t, y, labels, unit = recorded.get(name, (np.empty(0), np.empty(0), None, ""))
        bands = [band for step in steps if step.get("signal") == name
                 if (band := _band(step, labels, recorded)) is not None]
        unit = unit or next((step.get("unit", "") for step in steps if step.get("signal") == name), "")
        followed = dict.fromkeys(step["reference"] for step in steps if step.get("signal") == name and step.get("reference"))
        overlays = [(*recorded[other][:2], f"{other} (followed)") for other in followed if other in recorded]
        plots.append('<div class="plot">' + plot_svg(t, y, title=name, unit=unit, bands=bands, stimuli=stimuli,
                                                    labels=labels, span=(0.0, max(end, float(t[-1]) if len(t) else 0.0)),
                                                    overlays=overlays)
                     + "</div>")
    return plots


def _band(step: dict, labels: dict[float, str] | None, recorded: dict[str, tuple]) -> Band | None:
    label = step["text"] + (f" ({step['detail']})" if step.get("detail") else "")
    if not step.get("judged", True):  # drawn grey: neither passed nor failed
        step = {**step, "passed": None}
    if step.get("band") is not None:
        low, high = step["band"]
        return Band(step["t_start"], step["t_end"], low, high, step["passed"], label)
    if step.get("reference"):  # the followed signal ± the tolerance over the window judged (0: a line on it) ...
        if step.get("tolerance") is not None and step["reference"] in recorded:
            times, values = recorded[step["reference"]][:2]
            return Band(step["t_start"], step["t_end"], None, None, step["passed"], label, around=(times, values),
                        tolerance=step["tolerance"])
        return Band(step["t_start"], step["t_end"], None, None, step["passed"], label)  # ... else the window
    target = step.get("target")
    if target and labels and not target.startswith("!= "):
        raw = next((value for value, text in labels.items() if text == target), None)
        if raw is not None:
            return Band(step["t_start"], step["t_end"], raw, raw, step["passed"], label)
    return None


def _read_evidence(paths: list[Path], names: list[str], epoch: float) -> dict[str, tuple]:
    """name -> (times on the bench's clock, values, verbal labels or None, unit), over every part."""
    from asammdf import MDF

    found: dict[str, list] = {}
    for path in paths:
        if not path.is_file():
            continue
        try:
            mdf = MDF(path)
        except Exception as exc:  # asammdf raises many kinds; the report says the file is unreadable
            log.warning("%s: not readable (%s)", path, exc)
            continue
        with mdf:
            shift = mdf.header.start_time.timestamp() - epoch
            groups = {group.channel_group.acq_name: index for index, group in enumerate(mdf.groups)}
            for name in names:
                for where in _locations(mdf, groups, name):
                    found.setdefault(name, []).append(_channel(mdf, where, shift))
    result = {}
    for name, pieces in found.items():
        t = np.concatenate([p[0] for p in pieces])
        y = np.concatenate([p[1] for p in pieces])
        labels: dict[float, str] = {}
        for piece in pieces:
            labels.update(piece[2] or {})
        order = np.argsort(t, kind="stable")
        result[name] = (t[order], y[order], labels or None, pieces[0][3])
    return result


def _locations(mdf, groups: dict[str, int], name: str) -> list[tuple[str, int, int]]:
    message, _, signal = name.partition(".")
    if signal and message in groups:
        group = groups[message]
        return [(signal, group, index) for g, index in mdf.whereis(signal) if g == group]
    return [(name, group, index) for group, index in mdf.whereis(name)]


def _channel(mdf, where: tuple[str, int, int], shift: float) -> tuple[np.ndarray, np.ndarray, dict | None, str]:
    name, group, index = where
    raw = mdf.get(name, group=group, index=index, raw=True)
    physical = mdf.get(name, group=group, index=index)
    labels = None
    values = np.asarray(physical.samples)
    if values.dtype.kind in "SOU":
        labels = {float(r): (p.decode(errors="replace") if isinstance(p, bytes) else str(p))
                  for r, p in zip(np.asarray(raw.samples, dtype=float), values)}
        values = np.asarray(raw.samples, dtype=float)
    return np.asarray(physical.timestamps, dtype=float) + shift, values.astype(float), labels, physical.unit or ""


_HEAD = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Requirement tests</title>
<style>
body { font-family: sans-serif; margin: 1.5em; color: #222; max-width: 1100px; }
table { border-collapse: collapse; margin: 0.5em 0 1em; font-size: 13px; }
th, td { border: 1px solid #ccc; padding: 3px 7px; text-align: left; vertical-align: top; }
th { background: #f0f0f0; }
tr.failed td { background: #fdecea; } tr.ok td:last-child { color: #2e7d32; }
.badge { font-size: 11px; font-weight: bold; padding: 1px 6px; border-radius: 3px; color: #fff; }
.badge.passed { background: #2e7d32; } .badge.failed, .badge.error { background: #c62828; }
.badge.skipped { background: #888; } .badge.untested, .badge.interrupted { background: #e08a00; }
.message { color: #c62828; font-family: monospace; }
section { border-top: 1px solid #ddd; margin-top: 1.2em; }
.plot { margin: 4px 0; }
</style></head><body>"""
