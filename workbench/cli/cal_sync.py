"""``workbench cal save|load|sync``, and the ECU and image sides of ``cal diff``: calibration data between the ECU
and files."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workbench.cli.cal_image import (IMAGES, add_image_arguments, apply_error, failure_json, image_dataset_of,
                                     load_into_image)
from workbench.cli.ecu_options import a2l_document, add_ecu_arguments, open_session
from workbench.cli.options import print_json
from workbench.cli.progressbar import ProgressBar, cancel_on_interrupt
from workbench.errors import InputError, WorkbenchError, epk_text

if TYPE_CHECKING:
    from workbench.sync.reference import Reference

__all__ = ["add_commands", "diff_sides", "needs_a2l"]

ECU = "ecu"  # the name ``cal diff`` takes for the connected ECU
_DATASETS = ".dcm/.cdfx"


def add_commands(commands: argparse._SubParsersAction) -> None:
    """Register ``save``, ``load`` and ``sync`` in the ``cal`` group's sub-commands."""
    save = commands.add_parser(
        "save", help="save the ECU's calibrations as a dataset, or the working page as an s19/hex",
        description=f"OUT {_DATASETS}: the values of every calibration (or of NAME: names and globs such as "
                    f"'xsPRV_*') read from the working page (--page reference: CAL ROM). OUT {IMAGES} with --region "
                    "CALIB: the working page as that flash region holds it once flashed (the XCP SEGMENT's "
                    "ADDRESS_MAPPING, the EPK kept), which 'workbench flash OUT --region CALIB' takes. OUT is written "
                    "atomically.")
    save.add_argument("output", metavar="OUT", help=f"the file to write: a dataset ({_DATASETS}) or an image ({IMAGES})")
    save.add_argument("names", nargs="*", metavar="NAME", help="calibrations to save (default: all)")
    save.add_argument("--page", choices=("working", "reference"), default="working",
                      help="the page to read a dataset from (default: working)")
    save.add_argument("--region", metavar="NAME", help="the flash region an image is saved for (e.g. CALIB)")
    add_ecu_arguments(save)
    add_image_arguments(save)
    save.set_defaults(func=_save)

    load = commands.add_parser(
        "load", help="apply a dataset to the ECU (every object checked first)",
        description=f"Write the objects of IN ({_DATASETS}) into the working page (whichever page the ECU "
                    "runs: a warning says when it runs another). Every object is checked before "
                    "anything is written (in the A2L, writable, within its limits, of its shape, in writable memory); "
                    "one refusal and nothing is written (exit 2), unless --skip-unknown leaves out the names the A2L "
                    "lacks (a dataset of another software version). Then only the objects whose bytes change are "
                    "written and read back; a failure halfway names the objects that reached the ECU (exit 1). "
                    "With --image FILE -o NEW: applied to a copy of the s19/hex instead, checked the same way (an "
                    "object whose bytes the file lacks is refused too), no ECU.")
    load.add_argument("input", metavar="IN", help="the dataset to apply")
    load.add_argument("--dry-run", action="store_true",
                      help="check and show what would change, write nothing; the exit codes are those of the load "
                           "(2: an object is refused)")
    load.add_argument("--extended-limits", action="store_true", help="allow values up to the EXTENDED_LIMITS")
    load.add_argument("--skip-unknown", action="store_true",
                      help="leave out (and list as skipped) the objects the A2L does not know, instead of refusing "
                           "the whole dataset")
    add_ecu_arguments(load)
    add_image_arguments(load, output=True)
    load.set_defaults(func=_load)

    sync = commands.add_parser(
        "sync", help="compare the ECU's calibration data with a file, then upload or download (cache sync)",
        description="Compare the ECU's working page with the reference (thesis 5.4, figure 39). An image is "
                    "compared per calibration segment by BUILD_CHECKSUM, only the blocks that differ are uploaded; "
                    "a dataset object by object. The differing objects are listed with both values. Then --upload "
                    "writes the reference anew with the ECU's data (ECU -> file, atomically; --output elsewhere), "
                    "--download writes the file's data into the ECU and verifies it (a dataset checked as cal load checks "
                    "it: one object refused and nothing is written, exit 2). Exit codes: 0 equal (or "
                    "uploaded/downloaded), 1 they differ (no direction given) or the operation failed, 2 bad input.")
    sync.add_argument("file", nargs="?", metavar="FILE",
                      help=f"the reference: an image ({IMAGES}) or a dataset ({_DATASETS}); default: the demo's s19 "
                           "with the demo's A2L")
    sync.add_argument("--reference", metavar="FILE", help="the reference, as FILE")
    direction = sync.add_mutually_exclusive_group()
    direction.add_argument("--upload", action="store_true", help="ECU -> file: write the reference with the ECU's data")
    direction.add_argument("--download", action="store_true", help="file -> ECU: write the reference's data into the ECU")
    sync.add_argument("--output", metavar="FILE", help="with --upload: write this file instead of the reference")
    sync.add_argument("--skip-unknown", action="store_true",
                      help="with --download of a dataset: leave out the objects the A2L does not know (as the "
                           "compare does), as cal load --skip-unknown")
    add_ecu_arguments(sync)
    sync.set_defaults(func=_sync)


def _progress(args: argparse.Namespace, label: str) -> ProgressBar:
    return ProgressBar(label, enabled=False if args.json else None)


# --- save ---------------------------------------------------------------------------------------


def _save(args: argparse.Namespace) -> int:
    from workbench.calib.dataset import format_of, save_dataset
    from workbench.image.files import is_image_file
    from workbench.sync import read_dataset

    if args.image is None and is_image_file(args.output):
        return _save_image(args)
    if args.region:
        raise InputError(f"--region is for an image ({IMAGES}); {args.output} is saved as a dataset")
    format_of(args.output)  # an unknown extension is refused before the bus is opened
    if args.image is not None:
        dataset, source = image_dataset_of(args), {"image": args.image}
    else:
        with open_session(args, reading=True) as session, \
                _progress(args, f"reading the {args.page} page") as progress:
            dataset = read_dataset(session, args.names or None, page=args.page, progress=progress)
        source = {"page": args.page}
    warnings = dataset.notes + save_dataset(dataset, args.output)
    if args.json:
        print_json({"output": args.output, "objects": len(dataset), **source,
                    "warnings": [w.to_dict() for w in warnings]})
        return 0
    for warning in warnings:
        print(warning, file=sys.stderr)
    where = args.image if args.image is not None else f"the {args.page} page"
    print(f"wrote {args.output}: {len(dataset)} calibrations of {where}")
    return 0


def _save_image(args: argparse.Namespace) -> int:
    from workbench.sync import calibration_image

    if not args.region:
        raise InputError("an image holds one flash region of the working page: give --region (e.g. --region CALIB)")
    if args.names:
        raise InputError("an image holds the whole region: give no NAME (save a dataset for some objects)")
    if args.page != "working":
        raise InputError("an image is saved from the working page (the reference page is what CAL ROM holds already)")
    with open_session(args, reading=True) as session, _progress(args, "reading the working page") as progress:
        image = calibration_image(session, args.region, progress=progress)
        epk = session.epk.ecu
    image.save(args.output)
    region = args.region.upper()
    if args.json:
        print_json({"output": args.output, "region": region, "bytes": image.size,
                    "ranges": [[r.start, r.end] for r in image.ranges], "epk": epk})
        return 0
    print(f"wrote {args.output}: {region} {' '.join(map(str, image.ranges))} ({image.size} bytes, "
          f"EPK {epk_text(epk or '')})")
    return 0


# --- load ---------------------------------------------------------------------------------------


def _load(args: argparse.Namespace) -> int:
    from workbench.calib.dataset import load_dataset
    from workbench.sync import ApplyFailed, ApplyRefused, apply_dataset

    if args.image is not None:
        return load_into_image(args)
    if args.output is not None:
        raise InputError("-o/--output names the image --image FILE is written to")
    dataset = load_dataset(args.input)
    for note in dataset.notes:
        print(note, file=sys.stderr)
    with open_session(args) as session, _progress(args, "applying") as progress, \
            cancel_on_interrupt(progress, "object"):
        try:
            result = apply_dataset(session, dataset, dry_run=args.dry_run, allow_extended_limits=args.extended_limits,
                                   skip_unknown=args.skip_unknown, progress=progress, source=args.input)
            if not result.ok:  # a dry run that lists a refusal fails as the load itself would: exit 2
                raise ApplyRefused(result)
        except (ApplyRefused, ApplyFailed) as exc:
            error = apply_error(exc, session.model)
            _show(exc.report, args, session.model, error)
            raise error from None
    _show(result, args, session.model)
    return 0


def _show(result, args: argparse.Namespace, model, error: WorkbenchError | None = None) -> None:
    """``cal load``'s report; a dry run's values with ``model``'s decimals, as cal get shows them."""
    from functools import partial

    from workbench.a2l.model import value_decimals

    if args.json:
        print_json({**result.to_dict(), **failure_json(error)})
    else:
        print(result.to_text(partial(value_decimals, model)))


# --- sync ---------------------------------------------------------------------------------------


def _sync(args: argparse.Namespace) -> int:
    from functools import partial

    from workbench.a2l.model import value_decimals
    from workbench.sync import ApplyFailed, ApplyRefused, sync_compare, sync_download, sync_upload

    if args.output and not args.upload:
        raise InputError("--output names the file --upload writes")
    reference = _reference(args)
    with open_session(args) as session:
        with _progress(args, "comparing") as progress:
            report = sync_compare(session, reference, progress=progress)
        result: dict = {"report": report.to_dict()}
        if not args.json:
            print(report.to_text(partial(value_decimals, session.model)), flush=True)
        if report.equal:
            code = 0
        elif args.upload:
            written = sync_upload(report, args.output)
            result["upload"] = str(written)
            message, code = f"upload: wrote {written} with the ECU's data", 0
        elif args.download:
            with _progress(args, "downloading") as progress:
                try:
                    done = sync_download(session, report, skip_unknown=args.skip_unknown, progress=progress)
                except (ApplyRefused, ApplyFailed) as exc:  # a dataset: checked as cal load checks it
                    error = apply_error(exc, session.model)
                    if args.json:
                        print_json({**failure_json(error), **result, "download": exc.report.to_dict()})
                    else:
                        print(exc.report.to_text())
                    raise error from None
            result["download"] = {"objects": done.objects, "bytes": done.bytes, "verified": done.verified}
            message, code = done.describe(), 0
        else:
            message, code = "choose --upload (ECU -> file) or --download (file -> ECU)", 1
    if args.json:
        print_json({"ok": code == 0, **result})  # what the exit code says, as cal diff's and a2l diff's
    elif not report.equal:
        print(message)
    return code


def _reference(args: argparse.Namespace) -> Reference:
    """The reference file (loaded, so a bad file is refused before the bus is opened)."""
    from workbench import demo
    from workbench.sync import load_reference

    if args.file and args.reference:
        raise InputError("give the reference FILE or --reference FILE, not both")
    if args.reference or args.file:
        return load_reference(args.reference or args.file)
    if not _is_demo_a2l(args.a2l):
        raise InputError("give the reference FILE (an s19/hex or a dataset): the default is the demo's s19, for the "
                         "demo's A2L only")
    if args.upload and not args.output:
        raise InputError("--upload would overwrite the built-in demo's s19: give the reference FILE or --output FILE")
    return load_reference(demo.s19())


def _is_demo_a2l(a2l) -> bool:
    from workbench import demo

    return a2l is None or Path(a2l).resolve() == Path(demo.a2l()).resolve()


# --- diff with the ECU or an image ----------------------------------------------------------------


def needs_a2l(args: argparse.Namespace) -> bool:
    """Whether ``cal diff`` compares more than two dataset files (the ECU, or an image decoded by the A2L)."""
    from workbench.image.files import is_image_file

    return any(side.lower() == ECU or is_image_file(side) for side in (args.a, args.b))


def diff_sides(args: argparse.Namespace):
    """``(DatasetDiff, notes, equal, model)`` of ``cal diff A B`` when a side is ``ecu`` or an image; ``model``: the
    A2L the sides were read through."""
    from workbench.calib.dataset import diff_datasets

    sides = [args.a, args.b]
    if all(side.lower() == ECU for side in sides):
        raise InputError("compare the ECU with a file: give 'ecu' as one side only")
    if any(side.lower() == ECU for side in sides):
        return _diff_with_ecu(args)
    from workbench.sync import file_dataset

    from workbench.image.files import is_image_file

    model = a2l_document(args).model()
    a, b = (file_dataset(model, side) for side in sides)
    images = [is_image_file(side) for side in sides]
    if images.count(True) == 1:  # an image against a parameter set: the set's objects, as the ECU is compared with it
        image, dataset = (a, b) if images[0] else (b, a)
        for name in [name for name in image if name not in dataset]:
            del image[name]
    diff = diff_datasets(a, b, abs_tol=args.tolerance, rel_tol=args.rel_tolerance, a_label=args.a, b_label=args.b)
    return diff, [str(n) for n in a.notes + b.notes], diff.equal, model


def _diff_with_ecu(args: argparse.Namespace):
    from workbench.sync import load_reference, sync_compare

    ecu_first = args.a.lower() == ECU
    reference = load_reference(args.b if ecu_first else args.a)
    progress = ProgressBar("comparing", enabled=False if args.json else None)
    with open_session(args, reading=True) as session, progress:
        report = sync_compare(session, reference, progress=progress)
    diff = report.with_tolerance(args.tolerance, args.rel_tolerance)
    notes = [f"outside the objects: {d}" for d in report.outside] + report.notes
    return (diff.reversed() if ecu_first else diff), notes, diff.equal and not report.outside, session.model
