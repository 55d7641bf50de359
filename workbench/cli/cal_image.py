"""``--image FILE`` of ``workbench cal get|set|list|save|load``: the calibrations of an s19/hex the build produced,
no ECU (offline calibration, as CANape and INCA edit a HEX file).

The commands read and check exactly as against the ECU (:class:`~workbench.sync.offline.ImageCalibration` stands
in for the session); a command that changes the image writes ``-o FILE`` (the input's format, only the records of
changed bytes rewritten, atomically), never the input unless ``-o`` names it, and says on stderr what to know
before flashing it.
"""

from __future__ import annotations

import argparse
import sys
from contextlib import nullcontext
from pathlib import Path
from typing import TYPE_CHECKING

from workbench.cli.options import output_file, print_json
from workbench.errors import InputError, WorkbenchError, epk_text
from workbench.image.files import image_suffixes, is_image_file, refuse_elf

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument
    from workbench.sync.offline import ImageCalibration

__all__ = ["IMAGES", "add_image_arguments", "apply_error", "failure_json", "image_dataset_of", "load_into_image",
           "open_image", "require_output", "save_image", "values_of", "written_note"]

IMAGES = image_suffixes()  # the image files the cal commands read and write: ".s19/.s28/.../.ihex"


def add_image_arguments(parser: argparse.ArgumentParser, *, output: bool = False) -> None:
    """``--image FILE`` (and, for a command that changes it, ``-o/--output FILE``)."""
    group = parser.add_argument_group("offline: an s19/hex instead of the ECU (no bus is opened)")
    group.add_argument("--image", metavar="FILE",
                       help=f"the flash file ({IMAGES}) the build produced, read at the A2L's addresses (its "
                            "calibration segments' ADDRESS_MAPPING: CAL RAM onto CAL ROM)")
    if output:
        group.add_argument("-o", "--output", type=output_file, metavar="FILE",
                           help="with --image: the image to write, atomically, in the input's format with only the "
                                "records of changed bytes rewritten (another extension converts it); naming the "
                                "input changes it in place")


def open_image(args: argparse.Namespace, doc: A2lDocument | None = None, *, reading: bool = False
               ) -> ImageCalibration:
    """The image of ``--image`` with the A2L of ``--a2l`` (default: the demo's); an EPK other than the A2L's is a
    warning when ``reading`` or writing anyway (--accept-epk-mismatch), else the write's error says it."""
    from workbench.cli.ecu_options import a2l_document
    from workbench.sync.offline import ImageCalibration

    refuse_elf(args.image)
    if not is_image_file(args.image):
        raise InputError(f"--image {args.image}: an s19/hex is named {IMAGES}")
    image = ImageCalibration.open(args.image, doc or a2l_document(args),
                                  accept_epk_mismatch=getattr(args, "accept_epk_mismatch", False))
    expected = image.doc.epk(image.module)
    if image.epk is not None and image.epk != expected and (reading or image.accept_epk_mismatch):
        then = "written anyway (--accept-epk-mismatch)" if image.accept_epk_mismatch else "read-only"
        print(f"warning: {args.image} holds the EPK {epk_text(image.epk)}, the A2L {epk_text(expected or '')}: the "
              f"A2L may not describe this software; {then}", file=sys.stderr)
    return image


def values_of(args: argparse.Namespace, doc: A2lDocument, *, reading: bool = False):
    """A context giving what values are read from and written to: the image of ``--image``, else the ECU's session."""
    from workbench.cli.ecu_options import open_session

    if getattr(args, "image", None) is None:
        return open_session(args, doc, reading=reading)
    if getattr(args, "page", None):
        raise InputError("--page is for the ECU: an image holds one set of values (CAL ROM, what the ECU starts with)")
    return nullcontext(open_image(args, doc, reading=reading))


def require_output(args: argparse.Namespace) -> None:
    """:raises InputError: a command that changes the image without ``-o FILE`` (checked before anything is read)."""
    if args.output is None:
        raise InputError(f"--image {args.image} is not changed in place unless you name it: give -o NEW_FILE "
                         f"(or -o {args.image} to change it)")


def save_image(args: argparse.Namespace, image: ImageCalibration) -> list[str]:
    """Write ``-o FILE`` (skipped when it names the input and nothing changed); what to know before flashing it
    (:meth:`ImageCalibration.notes`), said on stderr unless ``--json``, whose report carries them as ``notes``."""
    notes = image.notes(args.output)
    same = Path(args.output).resolve() == Path(args.image).resolve()
    if not (same and not image.modified):
        image.save(args.output)
    if not args.json:
        for note in notes:
            print(f"note: {note}", file=sys.stderr)
    return notes


def written_note(args: argparse.Namespace, changed: bool) -> str:
    """What ``cal set`` prints after the value: where it went."""
    same = Path(args.output).resolve() == Path(args.image).resolve()
    if not changed:
        return f" (unchanged in {args.image}{'' if same else f'; wrote {args.output}'})"
    return f" (written into {args.output})"


def load_into_image(args: argparse.Namespace) -> int:
    """``cal load DATASET --image FILE -o NEW``: every object checked as against the ECU, then written into the
    image; ``--dry-run`` writes no file."""
    from functools import partial

    from workbench.a2l.model import value_decimals
    from workbench.calib.dataset import load_dataset
    from workbench.sync import ApplyRefused, apply_dataset

    if not args.dry_run:
        require_output(args)
    elif args.output is not None:
        raise InputError("--dry-run writes no file: leave out -o")
    dataset = load_dataset(args.input)
    for note in dataset.notes:
        print(note, file=sys.stderr)
    image = open_image(args, reading=args.dry_run)
    try:
        result = apply_dataset(image, dataset, dry_run=args.dry_run, allow_extended_limits=args.extended_limits,
                               skip_unknown=args.skip_unknown, source=args.input)
        if not result.ok:  # a dry run that lists a refusal fails as the load itself would: exit 2
            raise ApplyRefused(result)
    except ApplyRefused as exc:
        error = apply_error(exc, image.model)
        _show(args, {**exc.report.to_dict(), **failure_json(error)} if args.json
              else exc.report.to_text(partial(value_decimals, image.model)))
        raise error from None
    notes = [] if args.dry_run else save_image(args, image)
    shown = result.to_text(partial(value_decimals, image.model))
    _show(args, {**result.to_dict(), "output": args.output, "notes": notes} if args.json else shown)
    return 0


def apply_error(exc: WorkbenchError, model) -> WorkbenchError:
    """The error a refused or failed ``apply_dataset`` ends a command with: ``exc``, or, when it refused names
    ``model`` lacks, an InputError with its message and the option that leaves them out."""
    from workbench.sync import ApplyRefused

    if isinstance(exc, ApplyRefused) and any(name not in model for name in exc.report.named("refused")):
        return InputError(f"{exc}; --skip-unknown leaves out the objects the A2L lacks")
    return exc


def failure_json(error: WorkbenchError | None) -> dict:
    """What ``--json`` adds to a report when ``error`` ends the command, as every failing command gives it."""
    return {} if error is None else {"ok": False, "error": str(error), "exit_code": error.exit_code}


def image_dataset_of(args: argparse.Namespace):
    """``cal save DATASET --image FILE``: the image's calibrations (or NAMEs) as a dataset."""

    if is_image_file(args.output):
        raise InputError("with --image, save writes a dataset (.dcm/.cdfx): an image is written by "
                         "cal set/load --image FILE -o NEW")
    if args.page != "working":
        raise InputError("--page is for the ECU: an image holds one set of values")
    return open_image(args, reading=True).dataset(args.names or None)


def _show(args: argparse.Namespace, shown) -> None:
    if args.json:
        print_json(shown)
    else:
        print(shown)
