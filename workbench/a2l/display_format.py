"""The display format of an A2L object (its FORMAT, its COMPU_METHOD's format): the decimals its values are shown with.

ASAP2 writes ``"%Length.Layout"``: ``"%8.3"`` is 8 characters with 3 decimals. Generators leave the length out
(a2ltool and XCPlite write ``"%.3"``, which every tool reads alike: accepted), and files in the wild carry C's
conversions (``"%8.3f"``, ``"%6.2lf"``, ``"%5d"``). Every view (cal get, cal diff, the GUI's editors, recordings)
reads a format with :func:`format_parts`, which takes those leniently; ``a2l check`` warns about each format that
is not ASAP2's form (:func:`format_problem`, :func:`check_formats`), at file:line:column, saying how it is shown.

ASAP2 sets no bound on the Layout; the views show at most :data:`MAX_DECIMALS` (a FLOAT64 holds about 17 significant
digits: more decimals show only noise, ``"%8.20"`` printed 20), and check warns about a Layout beyond that or beyond
its own Length.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from workbench.a2l.document import A2lDocument
    from workbench.findings import Report

__all__ = ["MAX_DECIMALS", "check_formats", "format_decimals", "format_parts", "format_problem"]

MAX_DECIMALS = 17  # the most decimals a view shows: a FLOAT64's significant digits (ASAP2 sets no bound)

# "%" [Length] ["." Layout] [C length modifier and conversion], blanks around it tolerated
_LENIENT = re.compile(r"\s*%\s*(\d+)?(?:\.(\d+))?(?:[hlLqjzt]{0,2}([a-zA-Z]))?\s*")
_ASAP2 = re.compile(r"\s*%\d*\.\d+\s*")  # the Length may be left out (see the module's note)
_FIXED = "fF"  # conversions whose precision is a number of decimals, as ASAP2's Layout is
_INTEGER = "diu"  # whole numbers: no decimals


def format_parts(text: str | None) -> tuple[int | None, int | None]:
    """(width, decimals) of a display format: ``"%8.3"``, ``"%.3"``, ``"%8.3f"``, ``"%6.2lf"`` -> decimals 3, 3, 3,
    2; ``"%5d"`` -> 0. None where absent or not a number of decimals (``"%8"``, ``"%.3e"``, ``"%x"``, ``"abc"``):
    such values are shown with as many decimals as they need. More than :data:`MAX_DECIMALS` read as that many."""
    match = _LENIENT.fullmatch(text or "")
    if match is None:
        return None, None
    width, decimals, conversion = match.groups()
    width_value = int(width) if width else None
    if conversion is None or conversion in _FIXED:
        return width_value, min(int(decimals), MAX_DECIMALS) if decimals else None
    if conversion in _INTEGER:
        return width_value, 0
    return (width_value, None) if conversion in "eEgGaA" else (None, None)


def format_decimals(text: str | None) -> int | None:
    """The decimals a display format shows (:func:`format_parts`), None: as many as the value needs."""
    return format_parts(text)[1]


def format_problem(text: str) -> str | None:
    """Why ``text`` is not ASAP2's ``"%Length.Layout"``, or has a Layout beyond :data:`MAX_DECIMALS` or its Length,
    and how the views show it; None when it is fine."""
    width, decimals = format_parts(text)
    if _ASAP2.fullmatch(text):
        layout = int(text.partition(".")[2])
        if layout > MAX_DECIMALS:
            return f'FORMAT "{text}": {layout} decimals are more than a FLOAT64 holds (about {MAX_DECIMALS} ' \
                   f"significant digits): shown with {MAX_DECIMALS}"
        if width and layout > width:
            return f'FORMAT "{text}": {layout} decimals are more than its Length of {width} characters: write ' \
                   f'"%{layout + 2}.{layout}"'
        return None
    if decimals is None:
        return f'FORMAT "{text}" is not ASAP2\'s "%Length.Layout" (e.g. "%8.3"): its values are shown with as many ' \
               "decimals as they need"
    return f'FORMAT "{text}" is not ASAP2\'s "%Length.Layout": read as "%{width or ""}.{decimals}" ({decimals} ' \
           "decimals); write it so"


def check_formats(doc: "A2lDocument", report: "Report") -> None:
    """A warning in ``report`` for each display format of ``doc`` (a FORMAT option, a COMPU_METHOD's format) that is
    not ASAP2's form, at its string, naming the object (an AXIS_DESCR's: its CHARACTERISTIC)."""
    from workbench.a2l import grammar
    from workbench.a2l.reports import findings_at
    from workbench.findings import Severity

    strings: list[tuple[int, int]] = []  # (block, token of the format string)
    for keyword, spec in grammar.BLOCKS.items():
        if "FORMAT" in spec.options:
            owners, tokens = doc.option_occurrences(keyword, "FORMAT")
            strings += zip(owners.tolist(), (tokens + 1).tolist())
    for block in doc.blocks_named("COMPU_METHOD"):
        arguments = block.args
        if len(arguments) > 3:
            strings.append((block.index, arguments[3]))
    items = []
    for block, token in strings:
        if token >= len(doc.tokens) or doc.raw(token)[:1] != b'"':
            continue  # a FORMAT without its string: a syntax finding already
        problem = format_problem(doc.text(token))
        if problem is not None:
            keyword = doc.blocks.keyword[block]
            found = doc.block(block)
            while found.parent is not None and not found.name:
                found = found.parent
            # named as the other checks name an object: "CHARACTERISTIC c AXIS_DESCR: FORMAT ..."
            where = f"{found.keyword} {found.name or ''}" + (f" {keyword}" if found.index != block else "")
            if keyword == "COMPU_METHOD":  # its format is a parameter, not the FORMAT option
                problem = "format" + problem.removeprefix("FORMAT")
            items.append((token, "format", found.name or "", f"{where}: {problem}", keyword, Severity.WARNING))
    if items:
        report.findings.extend(findings_at(doc, items))
