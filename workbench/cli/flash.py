"""``workbench flash``: CALIB or APPLICATIVE from an s19/hex, or the working page into CAL ROM."""

from __future__ import annotations

import argparse
import sys

from workbench.cli.ecu_options import a2l_document, add_ecu_arguments, open_session
from workbench.cli.options import positive_float, print_json
from workbench.cli.progressbar import ProgressBar, cancel_on_interrupt
from workbench.errors import Cancelled, InputError
from workbench.image.files import image_suffixes

__all__ = ["add_app_key_arguments", "add_subparser", "app_key", "filled_regions", "run"]

EPILOG = """\
The plan comes first, once the checks against the ECU passed: per region of the A2L the ranges the
file fills ("Partial: FC0000h-FC01C3h FDFFF0h-FDFFFFh"), only those are programmed. Refused before
anything is erased, with the reason alone (--json: the report with "ok": false, the reason and the
option that flashes anyway): an image whose EPK differs from the A2L's; a flash of part of the
software (CALIB only, APPLICATIVE only) whose EPK differs from the ECU's, which the part that stays
belongs to (--accept-epk-mismatch flashes it anyway); data outside the flash regions; BOOT without
--allow-boot; a sector to erase that holds data outside the file's ranges, which the file would
not give back (--erase-beyond-file loses it). The part that stays is read where the A2L says it
keeps its EPK: with one ADDR_EPK (GET_ID reads it), a mismatch accepted once is not seen again (a
CALIB flash writes ADDR_EPK, so a later CALIB flash of that build needs no flag although the
application is still the other build's; the flash says so). An A2L with an ADDR_EPK in each part
(the demo's: CALIB FC0000h, the application header 840008h) compares that part's own EPK, so an
accepted mismatch stays visible to the next flash, `workbench info` and the session; flash
APPLICATIVE too to make them one software. The application-valid key is cleared first and set
last, so a flash that breaks off leaves the ECU in its boot loader, where the same command
finishes it. Ctrl-C stops at the next block the same way. Each part's EPK (the bytes at its
ADDR_EPK) is programmed last within the part, so a part that broke off keeps it erased; the key is
set only when every part the application needs holds its EPK (read back first), else exit 1 with
the part, the address, what was found there and what to flash, the ECU left in its boot loader.
A flash that finds the key cleared (one did not finish) compares the other regions the file fills
with the ECU and is refused while one differs (flash it too); `workbench info` shows the key.
Exit codes: 0 flashed (or --dry-run found nothing to refuse, or --verify-only no difference),
1 refused, failed, cancelled or differing, 2 bad input; a dry run refuses what the flash would.

examples:
  workbench flash assets/FLCU.s19 --region CALIB --dry-run
  workbench flash new.hex --region APPLICATIVE --interface socketcan --channel can0
  workbench flash assets/FLCU.s19 --verify-only            # every region the file fills
  workbench flash --from-working-page
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG,
                                   description="Flash regions of an S-record or Intel HEX file into the ECU over XCP, "
                                               "or the working page (CAL RAM) into CAL ROM.",
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("file", nargs="?", metavar="FILE", help=f"S-record or Intel HEX file ({image_suffixes()})")
    what = parser.add_argument_group("what to flash")
    what.add_argument("--region", "-r", action="append", metavar="NAME",
                      help="flash region of the A2L (CALIB, APPLICATIVE ...); repeat for several")
    what.add_argument("--from-working-page", action="store_true",
                      help="flash the working page (CAL RAM) into CAL ROM instead of a file")
    what.add_argument("--allow-boot", action="store_true", help="allow flashing the boot loader's region")
    what.add_argument("--erase-beyond-file", action="store_true",
                      help="erase a sector although it holds data outside the file's ranges (lost: the file does "
                           "not give it back); refused otherwise")
    how = parser.add_argument_group("how")
    how.add_argument("--dry-run", action="store_true",
                     help="connect, check what the flash checks first, print the plan and the time it takes, flash "
                          "nothing (exit codes as the flash's)")
    how.add_argument("--verify-only", action="store_true",
                     help="compare the ECU's flash with the file by checksums, flash nothing (exit 1 on a difference); "
                          "without --region every flash region the file fills")
    how.add_argument("--verify", choices=("checksum", "readback"), default="checksum",
                     help="checksum (BUILD_CHECKSUM of every erased sector, the default) or readback (and UPLOAD)")
    how.add_argument("--no-verify", action="store_true", help="skip the verification (not recommended)")
    how.add_argument("--reconnect", type=positive_float, default=5.0, metavar="S",
                     help="seconds to try CONNECT after PROGRAM_RESET, T6 a try (default 5: an ECU whose boot takes "
                          "longer, e.g. checking its application first)")
    add_app_key_arguments(how)
    add_ecu_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workbench.a2l import read_xcp_config
    from workbench.errors import WorkbenchError
    from workbench.flash import FlashLayout, plan_file

    _check_usage(args)
    plan = None
    try:
        doc = a2l_document(args)
        key = app_key(args)
        if not args.from_working_page:  # refusals come before the bus is even opened
            layout = FlashLayout.from_a2l(doc, read_xcp_config(doc))
            regions = args.region or filled_regions(args.file, layout)  # only --verify-only may leave it out
            plan = plan_file(args.file, layout, regions, allow_boot=args.allow_boot or not args.region, app_key=key)
        with open_session(args, doc) as session:
            if plan is None:
                plan = _working_page_plan(session, key, args)
            if args.dry_run:
                return _dry_run(session, plan, args)
            if args.verify_only:
                return _verify_only(session, plan, args)
            return _flash(session, plan, args)
    except WorkbenchError as exc:  # the line on stderr is main's; --json also gets the report a script reads
        if args.json:
            print_json(_failure(args, plan, exc))
        raise


def _failure(args: argparse.Namespace, plan, exc: Exception) -> dict:
    """The --json report of a flash (dry run, verify) that was refused, failed or cancelled: ``ok`` false, why, the
    option that would flash anyway (a refusal's), the plan when there was one."""
    from workbench.errors import Cancelled
    from workbench.flash import FlashRefused

    refused = isinstance(exc, FlashRefused)
    code = 130 if isinstance(exc, Cancelled) else getattr(exc, "exit_code", 1)
    return {"operation": "dry-run" if args.dry_run else "verify-only" if args.verify_only else "flash", "ok": False,
            "refused": refused, "error": str(exc), "exit_code": code,
            "override": f"--{exc.override.replace('_', '-')}" if refused and exc.override else None,
            "regions_too": list(exc.regions) if refused else [], "plan": plan.to_dict() if plan is not None else None}


def _check_usage(args: argparse.Namespace) -> None:
    if args.from_working_page:
        if args.file or args.region:
            raise InputError("--from-working-page flashes the working page: give no FILE and no --region")
        if args.verify_only:
            raise InputError("--verify-only compares a file; the working page is compared by flashing it")
    elif not args.file or not (args.region or args.verify_only):
        raise InputError("give FILE and --region NAME (e.g. --region CALIB), or --from-working-page")
    if args.dry_run and args.verify_only:
        raise InputError("--dry-run and --verify-only exclude each other")


def filled_regions(path: str, layout) -> list[str]:
    """The flash regions the file fills (what --verify-only compares without --region).

    :raises InputError: it fills none.
    """
    from workbench.image import load_image

    image = load_image(path)
    names = [r.name for r in layout.regions if r.selectable and image.crop(r.start, r.end).size]
    if not names:
        raise InputError(f"{path}: fills no flash region of the A2L ({', '.join(r.name for r in layout.regions)})")
    return names


def add_app_key_arguments(group) -> None:
    key = group.add_mutually_exclusive_group()
    key.add_argument("--app-key", metavar="ADDRESS=HEX",
                     help="the boot's application-valid key as stored in flash (default: the demo ECU's "
                          "0xFE0000=3CC3A55A, 0x5AA5C33C little-endian; info reads it only where the A2L's "
                          "flash has a sector for it)")
    key.add_argument("--no-app-key", action="store_true", help="the ECU's boot has no application-valid key")


def app_key(args: argparse.Namespace):
    """The application-valid key the options name (None: ``--no-app-key``)."""
    from workbench.flash import DEMO_APP_KEY, AppKey

    if args.no_app_key:
        return None
    if not args.app_key:
        return DEMO_APP_KEY
    address, _, value = args.app_key.partition("=")
    try:
        return AppKey(int(address, 0), bytes.fromhex(value))
    except ValueError:
        raise InputError(f"--app-key {args.app_key!r}: expected ADDRESS=HEXBYTES, e.g. 0xFE0000=3CC3A55A") from None


def _working_page_plan(session, app_key, args: argparse.Namespace):
    from workbench.flash import plan_working_page

    with ProgressBar("reading the working page", enabled=None if not args.json else False) as progress:
        return plan_working_page(session, app_key=app_key, progress=progress)


def _dry_run(session, plan, args: argparse.Namespace) -> int:
    from workbench.flash import check_flash
    from workbench.flash.plan import programming_frames

    plan, notes = check_flash(session, plan, _options(args))  # refused as the flash would be: exit 1, nothing touched
    block, per_frame = programming_frames(session.config)
    bitrate = (session.bus_spec.bitrate if session.bus_spec else None) or (
        session.config.can.baudrate if session.config.can else None)
    estimate = plan.bus_time_s(bitrate, block, per_frame) if bitrate and session.link.is_can else None
    state = "boot loader (programming only)" if session.in_boot else "application running"
    if args.json:
        print_json({"operation": "dry-run", "ok": True, "plan": plan.to_dict(), "ecu": {"epk": session.epk.describe(), "state": state},
                    "bitrate": bitrate, "seconds": list(estimate) if estimate else None, "notes": notes})
        return 0
    print(plan.describe())
    for note in notes:
        print(f"note: {note}")
    print(f"ECU: {state}; {session.epk.describe()}")
    if estimate:
        print(f"programming on the bus at {bitrate / 1000:g} kbit/s: {estimate[0]:.2g}-{estimate[1]:.2g} s "
              f"({block} bytes a block, {per_frame} a frame; erasing and checksums as fast as the ECU's flash)")
    print("dry run: nothing was flashed")
    return 0


def _verify_only(session, plan, args: argparse.Namespace) -> int:
    from workbench.flash import verify_ecu

    with ProgressBar("comparing", enabled=None if not args.json else False) as progress:
        checks = verify_ecu(session, plan, progress=progress)
    differing = [c for c in checks if not c.matches]
    if args.json:
        print_json({"operation": "verify-only", "ok": not differing, "matches": not differing, "ranges": [
            {"region": c.region, "start": c.range.start, "end": c.range.end,
             "differing": [[d.start, d.end] for d in c.differing]} for c in checks]})
    else:
        for check in checks:
            print(check)
        print(f"{len(checks) - len(differing)} of {len(checks)} ranges match the file", file=sys.stderr)
    return 1 if differing else 0


def _flash(session, plan, args: argparse.Namespace) -> int:
    from workbench.flash import flash_ecu

    options = _options(args)

    def show(checked) -> None:  # once the checks passed: a refusal comes alone, no plan as if it ran
        if not args.json:
            print(checked.describe(), flush=True)

    with ProgressBar("flashing", enabled=None if not args.json else False) as progress, \
            cancel_on_interrupt(progress, "block"):
        try:
            result = flash_ecu(session, plan, progress=progress, options=options, checked=show)
        except Cancelled as exc:
            print(f"error: {exc}", file=sys.stderr)
            if args.json:
                print_json(_failure(args, plan, exc))
            return 130
    if args.json:
        print_json({"operation": "flash", "ok": True, **result.to_dict()})
    else:
        print(result.describe())
    return 0


def _options(args: argparse.Namespace):
    from workbench.flash import FlashOptions, Verify

    return FlashOptions(verify=Verify.NONE if args.no_verify else Verify(args.verify),
                        erase_beyond_file=args.erase_beyond_file, accept_epk_mismatch=args.accept_epk_mismatch,
                        reconnect_s=args.reconnect)
