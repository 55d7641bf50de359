"""``workbench cal convert`` and ``workbench cal diff``: dataset files, no ECU needed."""

from __future__ import annotations

import argparse
import sys

from workbench.cli import cal_sync
from workbench.cli.ecu_options import add_ecu_arguments
from workbench.cli.options import add_output_arguments, non_negative_float, print_json, print_report

__all__ = ["add_commands"]

ENCODINGS = ("utf-8", "utf-8-sig", "cp1252", "latin-1")
_FORMATS = "DCM (.dcm) or CDFX (.cdfx, .cdf, .xml)"


def add_commands(commands: argparse._SubParsersAction) -> None:
    """Register ``convert`` and ``diff`` in the ``cal`` group's sub-commands."""
    convert = commands.add_parser(
        "convert", help="convert a dataset file between DCM and CDFX (no ECU needed)",
        description=(f"Read IN and write OUT, each {_FORMATS}. Every value and axis point is kept exactly; what the "
                     "output format cannot keep (e.g. the history in DCM, VAR in CDFX) is listed as a warning. "
                     "OUT is written atomically. Exit 0: written (the warnings listed); 2: bad input (IN cannot be "
                     "read or is malformed, an unknown extension; nothing written)."),
    )
    convert.add_argument("input", metavar="IN", help="the dataset file to read")
    convert.add_argument("output", metavar="OUT", help="the dataset file to write")
    convert.add_argument("--encoding", choices=ENCODINGS, default="utf-8",
                         help="character encoding of OUT (default utf-8; cp1252 for tools that want an ANSI DCM)")
    add_output_arguments(convert)
    convert.set_defaults(func=_convert)

    diff = commands.add_parser(
        "diff", help="compare two datasets object by object: files, an s19/hex, or the ECU (exit 1 when they differ)",
        description=(f"Compare A with B, each {_FORMATS}, an S-record or Intel HEX file (its calibrations read "
                     "through --a2l), or 'ecu' for the connected ECU's working page (an image is compared by "
                     "BUILD_CHECKSUM first, a dataset by reading exactly its objects): objects only in A, only in B, "
                     "changed (both values and B - A per element and axis point), shape changed, equal. Exit codes as "
                     "diff(1): 0 the datasets are equal, 1 they differ, 2 bad input."),
    )
    diff.add_argument("a", metavar="A", help="the first dataset file")
    diff.add_argument("b", metavar="B", help="the second dataset file")
    diff.add_argument("--tolerance", type=non_negative_float, default=0.0, metavar="ABS",
                      help="numbers differing by at most ABS are equal (default 0: exactly)")
    diff.add_argument("--rel-tolerance", type=non_negative_float, default=0.0, metavar="REL",
                      help="numbers differing by at most REL times the larger magnitude are equal")
    diff.add_argument("--equal", action="store_true", help="list the equal objects too (text output)")
    add_output_arguments(diff)
    add_ecu_arguments(diff, json_output=False)
    diff.set_defaults(func=_diff)


def _convert(args: argparse.Namespace) -> int:
    from workbench.calib.dataset import format_of, load_dataset, save_dataset
    from workbench.findings import Report

    target = format_of(args.output)
    dataset = load_dataset(args.input)
    report = Report("convert")
    report.extend(dataset.notes)
    losses = save_dataset(dataset, args.output, encoding=args.encoding)
    report.extend(losses)
    written = len(dataset) - sum(f.kind == "left-out" for f in losses)  # what the target cannot hold is left out
    summary = (f"wrote {args.output}: {written} objects ({format_of(args.input).name.upper()} -> "
               f"{target.name.upper()})")
    print_report(report, as_json=args.json, verbose=False, summary=summary, output=args.output)
    return 0


def _diff(args: argparse.Namespace) -> int:
    from functools import partial

    from workbench.a2l.model import value_decimals
    from workbench.calib.dataset import diff_datasets, load_dataset
    from workbench.cli.ecu_options import a2l_document

    if cal_sync.needs_a2l(args):
        result, notes, equal, model = cal_sync.diff_sides(args)
    else:
        a, b = load_dataset(args.a), load_dataset(args.b)
        result = diff_datasets(a, b, abs_tol=args.tolerance, rel_tol=args.rel_tolerance, a_label=args.a,
                               b_label=args.b)
        notes, equal = a.notes + b.notes, result.equal
        model = a2l_document(args).model() if args.a2l else None  # two files: the A2L's decimals only when one is given
    if args.json:
        print_json({"ok": equal, **result.to_dict(), "equal": equal,  # ok: what the exit code says, as a2l diff's
                    "notes": [n.to_dict() if hasattr(n, "to_dict") else n for n in notes]})
    else:
        for note in notes:
            print(note, file=sys.stderr)
        decimals = None if model is None else partial(value_decimals, model)
        print(result.to_text(show_equal=args.equal, decimals=decimals))
    return 0 if equal else 1
