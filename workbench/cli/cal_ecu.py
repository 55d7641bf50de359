"""``workbench cal get|set|list|fix|page``: calibrations in the ECU, by name, in physical units."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from workbench.a2l.display_format import format_decimals
from workbench.cli.cal_image import (add_image_arguments, open_image, require_output, save_image, values_of,
                                     written_note)
from workbench.cli.cal_values import split_cell, typed_value, value_from_file
from workbench.cli.ecu_options import a2l_document, add_ecu_arguments, can2_dbc, open_session
from workbench.cli.options import add_can2_bus_arguments, can2_bus_spec, print_json
from workbench.cli.render import jsonable, value_block, value_text
from workbench.errors import InputError

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument

__all__ = ["add_commands"]


def add_commands(commands: argparse._SubParsersAction) -> None:
    """Register the ECU commands in the ``cal`` group's sub-commands."""
    get = commands.add_parser("get", help="read calibrations (and measurements) by name",
                              description="Read objects by name (or glob) in physical units; curves and maps with their "
                                          "axes named, a map with X across and Y down as the window shows it "
                                          "(--json: the value indexed [x][y], as cal set takes it).")
    get.add_argument("names", nargs="+", metavar="NAME", help="a name or a glob ('xsPRV_*', as cal list and save take), "
                     "or NAME[x,y]: one value of an array, as cal set writes it")
    get.add_argument("--page", choices=("working", "reference"), help="read this page (default: the one XCP is on)")
    get.add_argument("--raw", action="store_true", help="raw values, as the ECU holds them (no conversion)")
    add_ecu_arguments(get)
    add_image_arguments(get)
    get.set_defaults(func=_get)

    put = commands.add_parser(
        "set", help="write a calibration by name (checked before connecting, read back)",
        description="Write NAME in physical units: a number (or a number and the object's unit, '25.5 bar', as "
                    "cal get prints it), an enum's text, a list for a curve or value block "
                    "('[1, 2, 3]' or '1,2,3'), a nested list for a map (indexed [x][y], as cal get --json gives "
                    "it), or --from a .json file (that, or what cal get NAME --json printed) or a .csv file laid "
                    "out as cal get prints it: a curve one row, a map X across and Y down (one row per Y point), "
                    "with or without the axis points (then written too where they differ); another shape is refused "
                    "naming the rows x columns expected. 'NAME[x,y]' writes one value of a curve, map or value "
                    "block, 'NAME[i]' one point of an AXIS_PTS (its order checked against the points the ECU holds, "
                    "once connected). Limits, shape, texts, write access and writable memory are checked before connecting "
                    "(exit 2, nothing sent); once connected, a read-only session (EPK mismatch) or the reference "
                    "page refuses the write before it is sent (exit 1). Only what changes is written, and that "
                    "is read back and printed. With --image FILE -o NEW: written into a copy of the s19/hex instead "
                    "(the same checks; a value whose bytes the file does not hold is refused), no ECU.")
    put.add_argument("name", metavar="NAME")
    put.add_argument("value", metavar="VALUE", nargs="?")
    put.add_argument("--from", dest="source", metavar="FILE", help="the value from a .json or .csv file")
    put.add_argument("--extended-limits", action="store_true", help="allow values up to the EXTENDED_LIMITS")
    add_ecu_arguments(put)
    add_image_arguments(put, output=True)
    put.set_defaults(func=_set)

    listing = commands.add_parser("list", help="list calibrations with their values",
                                  description="List the A2L's calibration objects (matching PATTERN: a glob, e.g. "
                                              "'xsPRV_*') with type, value, unit and limits, read from the ECU.")
    listing.add_argument("pattern", nargs="?", default="*", metavar="PATTERN")
    add_ecu_arguments(listing)
    add_image_arguments(listing)
    listing.set_defaults(func=_list)

    fix = commands.add_parser(
        "fix", help="override a signal with its _EN/_VALUE fix calibration, release it, or list them",
        description="cal fix SIGNAL VALUE: write <fix>_VALUE, then <fix>_EN = 1. cal fix SIGNAL --release: "
                    "<fix>_EN = 0. cal fix --list: every fixable signal with its live value and override. SIGNAL is "
                    "the fix's stem (cfRAILPRESSURE), its _EN/_VALUE name, or the signal's name. A CAN signal that "
                    "no measurement of the A2L shows is listed with its value on CAN2, found in the DBC by the fix's "
                    "name (--can2 DBC; the demo's with the demo's A2L), else with why it has none. With --image "
                    "FILE: the switches and override values an s19/hex starts the ECU with (-o NEW to change them).")
    fix.add_argument("signal", nargs="?", metavar="SIGNAL")
    fix.add_argument("value", nargs="?", metavar="VALUE")
    fix.add_argument("--release", action="store_true", help="give the signal back to the ECU (_EN = 0)")
    fix.add_argument("--list", action="store_true", help="list every fixable signal")
    can2 = fix.add_argument_group("CAN2 (--list: the live value of CAN signals no measurement shows)")
    can2.add_argument("--can2", metavar="DBC", help="the CAN2 DBC (default: the demo's with the demo's A2L)")
    add_can2_bus_arguments(can2)
    add_ecu_arguments(fix)
    add_image_arguments(fix, output=True)
    fix.set_defaults(func=_fix)

    page = commands.add_parser("page", help="show or switch the calibration page",
                               description="Without an argument: the pages the ECU and XCP use. working/reference: "
                                           "switch both to that page. copy: copy the reference page (CAL ROM) onto "
                                           "the working page (CAL RAM), undoing every change since start-up: it "
                                           "says first what it overwrites (each segment, its addresses and "
                                           "calibrations) and, in a terminal, asks before it copies (--yes: "
                                           "without asking; a script is not asked, as flash and cal load are not; "
                                           "--dry-run: say it, copy nothing). Every calibration segment of the A2L "
                                           "at once, unless --segment names one; --json gives a list, one object "
                                           "per segment. Exit codes: 0 done (a dry run: the copy would be "
                                           "allowed), 1 not confirmed, refused (a read-only session) or failed, "
                                           "2 bad input.")
    page.add_argument("action", nargs="?", choices=("working", "reference", "copy"))
    page.add_argument("--segment", type=int, help="only this calibration segment (default: every one)")
    page.add_argument("--yes", "-y", action="store_true", help="copy: do not ask (a terminal asks first)")
    page.add_argument("--dry-run", action="store_true", help="copy: say what it would overwrite, copy nothing")
    add_ecu_arguments(page)
    page.set_defaults(func=_page)


# --- get / set ------------------------------------------------------------------------------------


def _get(args: argparse.Namespace) -> int:
    doc = a2l_document(args)
    model = doc.model()
    wanted: dict[str, tuple[str, tuple[int, ...] | None]] = {}  # label -> (name, the cell's index or None)
    # an image holds calibrations only: a glob takes those (a measurement named is refused, saying why)
    kind, what = (("CHARACTERISTIC", "AXIS_PTS"), "calibration") if args.image else (None, "object")
    for text in args.names:  # a name the A2L lacks is said before connecting
        name, index = split_cell(model, text)
        if index is not None and name in model:
            wanted[f"{name}[{', '.join(map(str, index))}]"] = (name, index)
        else:
            wanted.update((found, (found, None)) for found in model.expand([text], kind, what=what))
    page = {"page": args.page} if args.page else {}
    with values_of(args, doc, reading=True) as session:
        found = {}
        for label, (name, index) in wanted.items():
            kind = model.kind_of(name)
            if args.raw:
                value = session.read(name, raw=True, **page)
            elif kind in ("CHARACTERISTIC", "AXIS_PTS"):
                value = session.read_value(name, **page)
            else:
                value = session.read(name, **page)
            found[label] = value if index is None else _cell_of(name, getattr(value, "value", value), index,
                                                                 "points" if kind == "AXIS_PTS" else "values")
    if args.json:
        print_json({label: _value_dict(value) for label, value in found.items()})
        return 0
    for label, value in found.items():
        obj = model.object(wanted[label][0])
        places = None if args.raw else format_decimals(model.format_of(obj))
        if hasattr(value, "axes"):
            print(value_block(label, value.value, value.axes, value.unit, places, axis_places=_axis_places(model, obj)))
        else:
            print(value_block(label, value, unit="" if args.raw else model.unit_of(obj), places=places))
    return 0


def _axis_places(model, obj) -> tuple[int | None, ...]:
    """The decimals of each axis' points, X first, as the window shows them."""
    from workbench.a2l.model import axis_decimals

    return tuple(axis_decimals(model, axis) for axis in getattr(obj, "axes", ()))


def _cell_of(name: str, value: Any, index: tuple[int, ...], noun: str) -> Any:
    """One value (``noun``: "values", "points") of an array, indexed as cal set takes it ([x, y] for a map)."""
    import numpy as np

    from workbench.calib.cells import index_problem

    problem = index_problem(name, np.shape(value), index, noun)
    if problem is not None:
        raise InputError(problem)
    return np.asarray(value)[index].item()


def _value_dict(value: Any) -> Any:
    if hasattr(value, "axes"):
        return {"kind": value.kind, "value": jsonable(value.value), "unit": value.unit,
                "axes": [{"kind": a.kind, "name": a.name, "unit": a.unit, "points": jsonable(a.values)}
                         for a in value.axes]}
    return jsonable(value)


def _offline(args: argparse.Namespace) -> tuple[A2lDocument, list | None]:
    """The A2L and the memory it lets calibrations be written to: what a write is checked against before
    connecting (a refusal then sends nothing; the bus is not even opened)."""
    from workbench.a2l import read_xcp_config
    from workbench.calib.writable import writable_spans

    doc = a2l_document(args)
    return doc, writable_spans(doc.memory_segments(), read_xcp_config(doc).segments)


def _set(args: argparse.Namespace) -> int:
    from workbench.calib.writable import checked_cells, checked_value

    if args.source is not None and args.value is not None:
        raise InputError("give VALUE or --from FILE, not both")
    if args.image is not None:
        require_output(args)
    elif args.output is not None:
        raise InputError("-o/--output names the image --image FILE is written to")
    doc, writable = _offline(args)
    model = doc.model()
    name, index = split_cell(model, args.name)
    single = index is not None or getattr(model.object(name), "type", "") == "VALUE"
    unit = model.unit_of(model.object(name)) if single else ""
    value = typed_value(args.value, single=single, unit=unit) if args.source is None else None
    if args.source is not None:
        value = value_from_file(Path(args.source), model, name, cell=index is not None)
    extended = args.extended_limits
    if index is None:
        checked_value(model, name, value, extended=extended, writable=writable)
    else:  # an AXIS_PTS' point: its order against the others is checked by the session, with the points it reads
        checked_cells(model, name, {index: value}, extended=extended, writable=writable)
    if args.image is not None:
        return _set_in_image(args, doc, name, index, value)
    with open_session(args, doc) as session:
        if index is not None:
            read_back = session.write_cells(name, {index: value}, allow_extended_limits=extended)[index]
            return _print_cell(args, model, name, index, read_back)
        written = session.write(name, value, allow_extended_limits=extended)
    _print_written(args, model, name, written, " (written, read back)")
    return 0


def _set_in_image(args: argparse.Namespace, doc, name: str, index: tuple[int, ...] | None, value: Any) -> int:
    """``cal set --image FILE -o NEW``: the value written into the image, NEW written, shown as online."""
    image = open_image(args, doc)
    extended = args.extended_limits
    if index is not None:
        written = image.write_cells(name, {index: value}, allow_extended_limits=extended)[index]
    else:
        written = image.write(name, value, allow_extended_limits=extended)
    note = written_note(args, image.modified)
    notes = save_image(args, image)
    if index is not None:
        return _print_cell(args, image.model, name, index, written, note, notes)
    _print_written(args, image.model, name, written, note, notes)
    return 0


def _print_written(args: argparse.Namespace, model, name: str, written, note: str,
                   notes: list[str] | None = None) -> None:
    """``notes``: an image's (``--image``), beside the value in the JSON."""
    if args.json:
        print_json({args.name: _value_dict(written), **({} if notes is None else {"notes": notes})})
        return
    obj = model.object(name)  # shown as cal get shows it
    print(value_block(args.name, written.value, written.axes, written.unit, format_decimals(model.format_of(obj)),
                      note=note, axis_places=_axis_places(model, obj)))


def _print_cell(args: argparse.Namespace, model, name: str, index: tuple[int, ...], value: Any,
                note: str = " (written, read back)", notes: list[str] | None = None) -> int:
    label = f"{name}[{', '.join(str(i) for i in index)}]"
    if args.json:
        print_json({label: jsonable(value), **({} if notes is None else {"notes": notes})})
        return 0
    obj = model.object(name)
    print(f"{label} = {value_text(value, model.unit_of(obj), format_decimals(model.format_of(obj)))}{note}")
    return 0


# --- list ---------------------------------------------------------------------------------------


def _list(args: argparse.Namespace) -> int:
    doc = a2l_document(args)
    model = doc.model()
    names = [s.name for s in model.find(args.pattern, kind=("CHARACTERISTIC", "AXIS_PTS"))]
    if not names:  # said before connecting
        raise InputError(f"no calibration matches {args.pattern!r}")
    with values_of(args, doc, reading=True) as session:
        values = session.read_many(names)
    rows = []
    for name in names:
        obj = model.object(name)
        kind = getattr(obj, "type", "AXIS_PTS")
        rows.append({"name": name, "type": kind, "value": jsonable(values[name]), "unit": model.unit_of(obj),
                     "lower": obj.lower_limit, "upper": obj.upper_limit, "functions": list(obj.functions)})
    if args.json:
        print_json(rows)
        return 0
    width = max(len(row["name"]) for row in rows)
    for row, name in zip(rows, names):
        places = format_decimals(model.format_of(model.object(name)))
        shown = value_text(values[name], row["unit"], places)
        print(f"{row['name']:<{width}}  {row['type']:<8} {shown:<30} [{row['lower']:g} .. {row['upper']:g}]")
    return 0


# --- fix ----------------------------------------------------------------------------------------


def _fix(args: argparse.Namespace) -> int:
    if args.list == bool(args.signal):
        raise InputError("give SIGNAL (with VALUE or --release) or --list")
    if args.signal and args.release == (args.value is not None):
        raise InputError("give either VALUE (override) or --release, not both or neither")
    if args.image is not None and not args.list:
        require_output(args)
    elif args.output is not None and args.image is None:
        raise InputError("-o/--output names the image --image FILE is written to")
    doc, value = None, None
    if args.value is not None:  # the override value checked before connecting
        from workbench.calib.fixes import fix_pairs_of, resolve_fix
        from workbench.calib.writable import checked_value

        doc, writable = _offline(args)
        model = doc.model()
        pair = resolve_fix(fix_pairs_of(model), args.signal)
        value = typed_value(args.value, single=True, unit=model.unit_of(model.object(pair.value)))
        checked_value(model, pair.value, value, writable=writable)
    dbc, notes = can2_dbc(args), None  # a wrong --can2 file: before connecting
    with values_of(args, doc or a2l_document(args), reading=args.list) as session:
        if args.list:
            bus = None if args.image else can2_bus_spec(args, session.bus_spec)
            states = session.fixes() if args.image else session.fixes(dbc, can2_bus=bus)
        elif args.release:
            states = [session.release(args.signal)]
        else:
            states = [session.override(args.signal, value)]
        if args.image is not None and not args.list:
            notes = save_image(args, session)
    if args.json:  # written into an image: its notes with the fix
        print_json([{"fix": s.pair.stem, "kind": s.pair.kind, "signal": s.signal, "enable": s.pair.enable,
                     "value": s.pair.value, "live": jsonable(s.live), "live_from": s.live_from,
                     "measured": jsonable(s.measured), "no_live": s.no_live, "override": jsonable(s.override),
                     "active": s.active, **({} if notes is None else {"notes": notes})} for s in states])
        return 0
    model = session.model
    width = max(len(s.pair.stem) for s in states)
    for state in states:  # live and override in the _VALUE's terms: its table, format and unit
        value = model.object(state.pair.value)
        unit, places = model.unit_of(value), format_decimals(model.format_of(value))
        live = "-" if state.live is None else value_text(state.live, unit, places)
        flag = "ON " if state.active else "off"
        via = f", {state.live_from}" if (state.live_from or "").startswith("CAN2") else ""
        if state.measured is not None and state.measured != state.live:  # xsLEDEn's OFF, which the _VALUE calls Normal
            via = ("" if state.live_from == state.signal else f"; {state.live_from}") + \
                f" = {value_text(state.measured)}"
        print(f"{state.pair.stem:<{width}}  {flag}  override {value_text(state.override, unit, places):<14} "
              f"live {live:<14} ({state.pair.kind}: {state.signal}{via})")
    for state in states if args.image is None else ():  # an image has no live values at all: no note for each
        if state.no_live:
            print(f"note: {state.pair.stem}: no live value: {state.no_live}", file=sys.stderr)
    return 0


# --- page ---------------------------------------------------------------------------------------


def _page(args: argparse.Namespace) -> int:
    if args.action != "copy" and (args.yes or args.dry_run):
        raise InputError("--yes and --dry-run are for 'cal page copy'")
    copies = []
    with open_session(args) as session:
        if args.action in ("working", "reference"):
            session.set_page(args.action, args.segment)
        elif args.action == "copy":
            copies = session.page_copies(args.segment)
            session.require_writable()  # a read-only session refuses before it asks, a dry run as the copy would
            if not args.json:
                verb = "would overwrite" if args.dry_run else "overwrites"
                print("\n".join(f"copy {verb} {copy} with the reference page {copy.reference}" for copy in copies),
                      flush=True)
            if args.dry_run:
                pass
            elif not (args.yes or _confirmed("copy the reference page onto the working page, losing every change "
                                             "since start-up?")):
                print("not confirmed: nothing copied", file=sys.stderr)
                return 1
            else:
                session.copy_reference_to_working(args.segment)
        states = session.pages() if args.segment is None else [session.page(args.segment)]
    if args.json:
        by_segment = {copy.segment: copy for copy in copies}
        print_json([{"segment": state.segment, "ecu": state.name(state.ecu_page), "xcp": state.name(state.xcp_page),
                     **({"copy": {**by_segment[state.segment].to_dict(), "done": not args.dry_run}}
                        if state.segment in by_segment else {})} for state in states])
        return 0
    if args.action == "copy":
        print("dry run: nothing was copied" if args.dry_run else "copied the reference page onto the working page")
    for state in states:
        print(f"segment {state.segment}: ECU on the {state.name(state.ecu_page)} page, "
              f"XCP on the {state.name(state.xcp_page)} page")
    return 0


def _confirmed(question: str) -> bool:
    """Whether the user answers yes in a terminal (stdin one); a script (no terminal) is not asked."""
    if not sys.stdin.isatty():
        return True
    print(f"{question} [y/N] ", end="", file=sys.stderr, flush=True)
    return sys.stdin.readline().strip().lower() in ("y", "yes")
