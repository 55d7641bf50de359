"""Small inline SVG plots for the report: recorded samples (held between samples), expectation bands, stimuli,
and the signals an expectation compared with (dashed).

Plain SVG, no script: the report opens in any browser and in a headless one for a screenshot. Long
signals are reduced to the minimum and maximum per pixel column, so a spike is never lost.
"""

from __future__ import annotations

from dataclasses import dataclass
from html import escape

import numpy as np

__all__ = ["Band", "plot_svg"]

WIDTH, HEIGHT = 760, 190
LEFT, RIGHT, TOP, BOTTOM = 56, 12, 22, 28  # LEFT grows with the longest label of a verbal signal
CHAR_PX = 6.5  # the width of a character at 11 px
PASS, FAIL, LINE, OVERLAY = "#2e7d32", "#c62828", "#1f4e9a", "#8e24aa"
NOT_JUDGED = "#757575"


@dataclass(frozen=True, eq=False)
class Band:
    """An expectation drawn over the signal: [t0, t1] x [low, high] (an open side: None); or, with ``around`` (the
    times and values of another signal), that signal ± ``tolerance`` over [t0, t1], a line on it where the tolerance
    is too thin to see (an ``expect_follows`` with tolerance 0)."""

    t0: float
    t1: float
    low: float | None
    high: float | None
    passed: bool | None  # None: not judged (the ECU lost): grey
    label: str = ""
    around: tuple[np.ndarray, np.ndarray] | None = None
    tolerance: float = 0.0


def _colour(band: Band) -> str:
    return PASS if band.passed else FAIL if band.passed is False else NOT_JUDGED


def _nice_ticks(low: float, high: float, count: int = 5) -> list[float]:
    if high <= low:
        return [low]
    raw = (high - low) / count
    magnitude = 10 ** np.floor(np.log10(raw))
    step = min((m * magnitude for m in (1, 2, 2.5, 5, 10) if m * magnitude >= raw), default=raw)
    first = np.ceil(low / step) * step
    return [float(v) for v in np.arange(first, high + step * 1e-9, step)]


def _reduce(t: np.ndarray, y: np.ndarray, columns: int) -> tuple[np.ndarray, np.ndarray]:
    """At most about 2 * ``columns`` points: min and max per column, in time order."""
    if len(t) <= 2 * columns:
        return t, y
    edges = np.linspace(t[0], t[-1], columns + 1)
    index = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, columns - 1)
    keep = []
    for column in np.unique(index):
        members = np.flatnonzero(index == column)
        low, high = members[np.argmin(y[members])], members[np.argmax(y[members])]
        keep += sorted({low, high})
    keep = np.array(keep)
    return t[keep], y[keep]


def plot_svg(t: np.ndarray, y: np.ndarray, *, title: str, unit: str = "", bands: list[Band] = (),
             stimuli: list[float] = (), labels: dict[float, str] | None = None,
             span: tuple[float, float] | None = None, overlays: list[tuple[np.ndarray, np.ndarray, str]] = ()) -> str:
    """One signal over time (s) as an SVG element; ``labels`` names the values of a verbal signal;
    ``overlays`` (times, values, label) are other signals drawn dashed over it on the same scale."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    t0 = min([*(t[:1]), *(b.t0 for b in bands), *stimuli], default=0.0) if span is None else span[0]
    t1 = max([*(t[-1:]), *(b.t1 for b in bands), *stimuli], default=1.0) if span is None else span[1]
    if t1 <= t0:
        t1 = t0 + 1.0
    finite = [v for b in bands for v in (b.low, b.high) if v is not None and np.isfinite(v)]
    overlays = [(np.asarray(ot, dtype=float), np.asarray(oy, dtype=float), label) for ot, oy, label in overlays]
    finite += [float(v) for _, oy, _ in overlays for v in oy[np.isfinite(oy)]]
    values = np.concatenate([y[np.isfinite(y)], finite, list(labels or ())]) if len(y) or finite else np.array([0.0, 1.0])
    y0, y1 = (float(np.min(values)), float(np.max(values))) if len(values) else (0.0, 1.0)
    pad = (y1 - y0) * 0.08 or max(abs(y0) * 0.1, 0.5)
    y0, y1 = y0 - pad, y1 + pad
    left = max(LEFT, 12 + CHAR_PX * max((len(text) for text in (labels or {}).values()), default=0))
    plot_w, plot_h = WIDTH - left - RIGHT, HEIGHT - TOP - BOTTOM

    def x_of(v):
        return left + (np.asarray(v, dtype=float) - t0) / (t1 - t0) * plot_w

    def y_of(v):
        return TOP + (y1 - np.asarray(v, dtype=float)) / (y1 - y0) * plot_h

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
             f'viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="11">',
             f'<rect x="{left:.0f}" y="{TOP}" width="{plot_w:.0f}" height="{plot_h}" fill="#fff" stroke="#999"/>',
             f'<text x="{left:.0f}" y="14" font-weight="bold">{escape(title)}</text>']
    for band in bands:
        if band.around is not None:
            parts.append(_band_around(band, max(band.t0, t0), min(band.t1, t1), plot_w, x_of, y_of, (y0, y1)))
            continue
        low = y0 if band.low is None or not np.isfinite(band.low) else max(band.low, y0)
        high = y1 if band.high is None or not np.isfinite(band.high) else min(band.high, y1)
        if band.low is not None and band.high is not None and band.low == band.high:
            low, high = band.low - (y1 - y0) * 0.02, band.high + (y1 - y0) * 0.02
        colour = _colour(band)
        x_a, x_b = float(x_of(max(band.t0, t0))), float(x_of(min(band.t1, t1)))
        y_a, y_b = float(y_of(high)), float(y_of(low))
        parts.append(f'<rect x="{x_a:.1f}" y="{y_a:.1f}" width="{max(x_b - x_a, 1.5):.1f}" height="{max(y_b - y_a, 1.5):.1f}" '
                     f'fill="{colour}" fill-opacity="0.18" stroke="{colour}" stroke-dasharray="4 2">'
                     f'<title>{escape(band.label)}</title></rect>')
    for moment in stimuli:
        x = float(x_of(moment))
        parts.append(f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{TOP + plot_h}" stroke="#e08a00" '
                     'stroke-dasharray="2 3"/>')
    ticks = sorted(labels) if labels else _nice_ticks(y0, y1)
    for tick in ticks:
        if y0 <= tick <= y1:
            level = float(y_of(tick))
            text = labels[tick] if labels else f"{tick + 0.0:g}"  # + 0.0: no "-0"
            parts.append(f'<line x1="{left - 4:.0f}" y1="{level:.1f}" x2="{left + plot_w:.0f}" y2="{level:.1f}" '
                         f'stroke="#eee"/><text x="{left - 6:.0f}" y="{level + 4:.1f}" text-anchor="end">{escape(text)}</text>')
    for tick in _nice_ticks(t0, t1, 8):
        x = float(x_of(tick))
        parts.append(f'<text x="{x:.1f}" y="{HEIGHT - 10}" text-anchor="middle">{tick:g}</text>')
    parts.append(f'<text x="{WIDTH - RIGHT}" y="{HEIGHT - 10}" text-anchor="end">s</text>')
    if unit and not labels:
        parts.append(f'<text x="{left + 4:.0f}" y="{TOP + 12}" fill="#666">{escape(unit)}</text>')
    line = _held_line(t, y, t0, t1, plot_w, x_of, y_of)
    if line:
        parts.append(f'<polyline points="{line}" fill="none" stroke="{LINE}" stroke-width="1.4"/>')
    else:
        parts.append(f'<text x="{left + plot_w / 2:.0f}" y="{TOP + plot_h / 2}" text-anchor="middle" fill="#999">'
                     'no samples recorded</text>')
    if overlays:  # a legend in the title line: which dashed line is which
        legend = ", ".join(label for _, _, label in overlays)
        parts.append(f'<text x="{WIDTH - RIGHT}" y="14" text-anchor="end" fill="{OVERLAY}">- - {escape(legend)}</text>')
    for ot, oy, label in overlays:  # over the signal: where it follows exactly, the dashes still show
        line = _held_line(ot, oy, t0, t1, plot_w, x_of, y_of)
        if line:
            parts.append(f'<polyline points="{line}" fill="none" stroke="{OVERLAY}" stroke-width="1.6" '
                         f'stroke-dasharray="5 4"><title>{escape(label)}</title></polyline>')
    parts.append("</svg>")
    return "".join(parts)


def _band_around(band: Band, a: float, b: float, columns: int, x_of, y_of, y_range: tuple[float, float]) -> str:
    """``band.around`` held over [a, b], ± ``band.tolerance``: a filled band, or a line where it is under 2 px high."""
    times, values = (np.asarray(v, dtype=float) for v in band.around)
    held = np.searchsorted(times, a, side="right") - 1  # the value the signal holds when the window opens
    index = np.concatenate([[held] if held >= 0 else [], np.flatnonzero((times > a) & (times <= b))]).astype(int)
    if not len(index) or b <= a:
        return ""
    tt, yy = _reduce(np.append(np.maximum(times[index], a), b), np.append(values[index], values[index[-1]]), columns)
    colour = _colour(band)
    title = f"<title>{escape(band.label)}</title>"

    def path(offset: float) -> list[str]:  # held: each value until the next sample's time
        xs, ys = x_of(tt), y_of(np.clip(yy + offset, *y_range))
        return [f"{xs[0]:.1f},{ys[0]:.1f}"] + [point for i in range(1, len(xs))
                                              for point in (f"{xs[i]:.1f},{ys[i - 1]:.1f}", f"{xs[i]:.1f},{ys[i]:.1f}")]

    if abs(float(y_of(0.0) - y_of(2 * band.tolerance))) < 2:
        return (f'<polyline points="{" ".join(path(0.0))}" fill="none" stroke="{colour}" stroke-width="5" '
                f'stroke-opacity="0.45" stroke-linejoin="round">{title}</polyline>')
    return (f'<polygon points="{" ".join(path(band.tolerance) + path(-band.tolerance)[::-1])}" fill="{colour}" '
            f'fill-opacity="0.18" stroke="{colour}" stroke-dasharray="4 2">{title}</polygon>')


def _held_line(t: np.ndarray, y: np.ndarray, t0: float, t1: float, columns: int, x_of, y_of) -> str:
    """The points of a polyline that holds each sample until the next one, as the ECU holds its value
    between two DAQ samples ("" without samples in [t0, t1])."""
    inside = (t >= t0) & (t <= t1)
    tt, yy = _reduce(t[inside], y[inside], columns)
    if not len(tt):
        return ""
    xs, ys = x_of(tt), y_of(yy)
    points = [f"{xs[0]:.1f},{ys[0]:.1f}"]
    for i in range(1, len(xs)):
        points.append(f"{xs[i]:.1f},{ys[i - 1]:.1f} {xs[i]:.1f},{ys[i]:.1f}")
    return " ".join(points)
