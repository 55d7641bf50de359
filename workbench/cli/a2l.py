"""``workbench a2l``: merge, update from ELF, check and diff A2L files (the thesis's ASAP2 Merger/Updater).

Thin commands over :mod:`workbench.a2l`; every result is a report of findings that
prints as one line each (``file:line:column: severity: message``) or as ``--json``.
"""

from __future__ import annotations

import argparse
import ctypes
import functools
import gc
import sys

from workbench.cli.options import add_output_arguments, integer_within, output_file, print_json, print_report
from workbench.errors import InputError

__all__ = ["add_subparser"]

_DESCRIPTION = """\
The A2L tool chain of a build:
  merge   fragments into a master A2L (the master's MOD_PAR, MOD_COMMON and IF_DATA apply)
  update  every address (and with --types data types, sizes, limits) and the EPK from an ELF
  insert  new MEASUREMENTs/CHARACTERISTICs from the ELF's variables (by name pattern or address range;
          --create: into a new A2L made from the ELF alone)
  remove  objects by name pattern or address range, with the references to them
  cleanup what nothing uses: COMPU_METHODs, conversion tables, RECORD_LAYOUTs, UNITs, empty GROUPs/FUNCTIONs
  flatten the text of every /include written inline
  check   syntax, references, duplicate names and memory placement, with file:line:column
  diff    object-level differences of two A2L files
Outputs keep the input's text: only the changed tokens differ.
Findings print one a line on stdout (file:line:column: severity: message; -v: every finding),
the one-line summary on stderr; --json prints one JSON report on stdout instead.
Exit codes: 0 success (check: clean, diff: no differences), 1 the operation failed or found
problems, 2 bad input (malformed A2L, not an ELF, bad option)."""


def add_subparser(subparsers: argparse._SubParsersAction, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, description=_DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(title="commands", dest="command", metavar="COMMAND", required=True)

    merge = commands.add_parser("merge", help="merge module fragments into a master A2L",
                                description="Insert each fragment's MODULE content into the master's MODULE (a "
                                "fragment may also be a bare file of module-level blocks, as written for /include). "
                                "Identical definitions of a name merge silently; different ones are an error "
                                "unless --on-conflict says otherwise. The output is a new, self-contained file: the "
                                "text of every /include is written inline (--keep-includes keeps the master's own "
                                "/include lines; a fragment's included text is always inlined). Exit codes: 0 "
                                "written, 1 a conflict or another error (nothing written), 2 bad input.")
    merge.add_argument("master", metavar="MASTER.a2l")
    merge.add_argument("fragments", nargs="+", metavar="FRAGMENT.a2l")
    merge.add_argument("-o", "--output", required=True, type=output_file, metavar="OUT.a2l",
                       help="file to write (atomically)")
    merge.add_argument("--on-conflict", choices=["error", "keep-first", "keep-last", "rename"], default="error",
                       help="two different definitions of one name: fail (default), keep the first, keep the "
                            "last, or rename the later one NAME_<MODULE> (every rename is reported)")
    merge.add_argument("--module", metavar="NAME", help="the master's MODULE to merge into, when it has several")
    merge.add_argument("--keep-includes", action="store_true",
                       help="keep the master's /include lines instead of writing the included text inline")
    _output_options(merge)
    merge.set_defaults(func=_as_batch(_merge))

    update = commands.add_parser("update", help="set every address (and the EPK) from an ELF",
                                 description="Set MEASUREMENT ECU_ADDRESS, CHARACTERISTIC/AXIS_PTS/BLOB/INSTANCE "
                                 "addresses and MOD_PAR EPK/ADDR_EPK from the ELF's DWARF (struct members a.b, "
                                 "array elements a[3] or a._3_, SYMBOL_LINK) or its .symtab. Objects whose "
                                 "symbol is missing are warnings and kept (exit 0) unless --strict or "
                                 "--remove-missing says otherwise. Only the changed tokens differ; /include lines "
                                 "stay, and changes that fall into included files are an error (exit 1, the output "
                                 "written) unless --update-includes or --merge-includes says what to do. Exit codes: "
                                 "0 written (warnings allowed), 1 errors (see above; --strict: nothing written), "
                                 "2 bad input (malformed A2L, not an ELF or a stripped one).")
    update.add_argument("a2l", metavar="IN.a2l")
    update.add_argument("elf", metavar="ELF")
    update.add_argument("-o", "--output", required=True, type=output_file, metavar="OUT.a2l",
                        help="file to write (atomically; may be IN.a2l itself)")
    missing = update.add_mutually_exclusive_group()
    missing.add_argument("--remove-missing", action="store_true",
                         help="remove objects whose symbol is not in the ELF by `a2l remove`'s rules: their entries "
                              "in grouping lists go with them; a kept object that needs one (an AXIS_PTS_REF or "
                              "CURVE_AXIS_REF, a VIRTUAL's or DEPENDENT_/VIRTUAL_CHARACTERISTIC's input, a MAP_LIST "
                              "...) refuses the update, an error at each reference, nothing written (a2ltool's "
                              "default drops such references and leaves a COM_AXIS without its axis)")
    missing.add_argument("--strict", action="store_true", help="any symbol missing is an error; nothing is written")
    update.add_argument("--drop-optional-references", action="store_true",
                        help="with --remove-missing: an INPUT_QUANTITY that names a removed object becomes "
                             "NO_INPUT_QUANTITY, a COMPARISON_QUANTITY is dropped (each a warning), as a2ltool "
                             "does, instead of refusing the update")
    update.add_argument("--types", action="store_true",
                        help="also check and update data types, array sizes, bit masks and limits from DWARF (a struct "
                             "member by member at its RECORD_LAYOUT's positions; an enum becomes a COMPU_METHOD "
                             "TAB_VERB with its COMPU_VTAB)")
    update.add_argument("--no-epk", action="store_true", help="leave MOD_PAR EPK and ADDR_EPK alone")
    _include_options(update)
    update.add_argument("--validate", action="store_true",
                        help="also check the whole file against the ASAP2 grammar first (as `check` does); "
                             "without it only the structure and the tokens the update touches are checked")
    update.add_argument("--epk-symbol", metavar="NAME", help="the ELF variable holding the EPK (default: EPK/epk, "
                        "then the .epk section)")
    _cache_options(update)
    _output_options(update)
    update.set_defaults(func=_as_batch(_update))

    insert = commands.add_parser("insert", help="new MEASUREMENTs/CHARACTERISTICs from the ELF's variables",
                                 description="Make MEASUREMENTs and CHARACTERISTICs from the ELF's DWARF variables, "
                                 "with a2ltool's options: each variable, struct member (a.b.c) and array element "
                                 "(a[2], a._2_ before ASAP2 1.70) whose whole name a --*-regex matches (a struct it "
                                 "matches brings all its members) or whose address lies in a --*-range [MIN, MAX) or a --*-section "
                                 "becomes one object: a scalar or bitfield (BIT_MASK), an array as one object with "
                                 "MATRIX_DIM (a CHARACTERISTIC: VAL_BLK), an enum with a COMPU_METHOD TAB_VERB; "
                                 "data type, limits and address from DWARF. A name the file has is left alone and "
                                 "reported; nothing else changes: the new blocks go before /end MODULE. Exit codes: "
                                 "0 written (warnings allowed: a pattern or range that selects nothing, a name that "
                                 "exists), 1 an error, 2 bad input (a bad pattern or range, malformed A2L, an ELF "
                                 "without DWARF).")
    insert.add_argument("a2l", nargs="?", metavar="IN.a2l", help="the A2L to insert into (not with --create)")
    insert.add_argument("elf", metavar="ELF")
    insert.add_argument("--create", action="store_true",
                        help="make a new A2L instead of reading one: ASAP2 1.71, PROJECT and MODULE named after the "
                             "ELF (--module NAME names them), MOD_COMMON with the ELF's byte order, MOD_PAR with its "
                             "EPK and ADDR_EPK when it has one")
    insert.add_argument("-o", "--output", type=output_file, metavar="OUT.a2l",
                        help="file to write (atomically; may be IN.a2l itself); required unless --dry-run")
    for kind in ("measurement", "characteristic"):
        insert.add_argument(f"--{kind}-regex", action="append", default=[], type=_pattern, metavar="REGEX",
                            help=f"insert a {kind.upper()} for every variable, member or element whose whole name "
                                 "it matches (repeatable; ^ or $ in it: searched as written, as a2ltool does)")
        insert.add_argument(f"--{kind}-range", action="append", default=[], nargs=2, type=_address,
                            metavar=("MIN", "MAX"), help=f"insert a {kind.upper()} for every variable, member or "
                            "element whose address lies in [MIN, MAX) (repeatable; 0x hex allowed)")
        insert.add_argument(f"--{kind}-section", action="append", default=[], metavar="SECTION",
                            help=f"insert a {kind.upper()} for every variable in this ELF section (e.g. .cal_ram; "
                                 "repeatable)")
        insert.add_argument(f"-{kind[0].upper()}", f"--{kind}", action="append", default=[], metavar="PATH",
                            dest=f"{kind}_paths", help=f"insert a {kind.upper()} for this symbol path (a.b[2].c; "
                            "a struct: its members; repeatable)")
    insert.add_argument("--target-group", metavar="NAME", help="put the new objects into this GROUP (created, ROOT, "
                        "when the file lacks it)")
    insert.add_argument("--module", metavar="NAME", help="the MODULE to insert into, when the file has several "
                        "(--create: the new PROJECT's and MODULE's name)")
    insert.add_argument("-t", "--structures", "--enable-structures", action="store_true",
                        help="a struct selected whole becomes one INSTANCE of a TYPEDEF_STRUCTURE (typedefs per member "
                        "type, shared by every variable of its C type), as a2ltool -t writes it (ASAP2 1.70+)")
    insert.add_argument("--old-arrays", action="store_true",
                        help="name array elements a._2_ and write MATRIX_DIM with three numbers as before ASAP2 1.70, "
                             "in a 1.70+ file too (a2ltool's --old-arrays)")
    insert.add_argument("--dry-run", action="store_true", help="report what would be inserted; write nothing")
    _cache_options(insert)
    _output_options(insert)
    insert.set_defaults(func=_as_batch(_insert), files_after=[])
    _take_files_after_create(insert)

    _add_remove(commands)
    _add_cleanup(commands)
    flatten = commands.add_parser("flatten", help="write the text of every /include inline",
                                  description="a2ltool's --merge-includes: the file with the text of every /include "
                                  "(nested ones too) in place of the directive, included files in another encoding "
                                  "converted to the main file's; nothing else changes. Exit codes: 0 written, "
                                  "2 bad input (malformed A2L, an included file missing).")
    flatten.add_argument("a2l", metavar="IN.a2l")
    flatten.add_argument("-o", "--output", required=True, type=output_file, metavar="OUT.a2l",
                         help="file to write (atomically; may be IN.a2l itself)")
    _output_options(flatten)
    flatten.set_defaults(func=_as_batch(_flatten))

    check = commands.add_parser("check", help="syntax, references, names and memory placement",
                                description="Report every problem with file:line:column: syntax, undefined "
                                "COMPU_METHOD/RECORD_LAYOUT/FUNCTION/... references, duplicate names, overlapping "
                                "objects, objects outside every MEMORY_SEGMENT, calibrations outside CAL RAM, a file whose "
                                "objects are all still at address 0 (not updated from its ELF); with --elf also "
                                "symbols missing from the ELF, addresses that differ and a MOD_COMMON byte order "
                                "other than the ELF's. MOD_PAR's EPK and ADDR_EPK come as a pair (either alone: a "
                                "warning); each ADDR_EPK must lie in a MEMORY_SEGMENT with room "
                                "for the EPK (two in one segment: a warning); the ELF (--elf) and the flash file "
                                "(--image) must hold MOD_PAR's EPK there. Exit 0 only when clean (no warning).")
    check.add_argument("a2l", metavar="A2L")
    check.add_argument("--elf", metavar="ELF", help="also check every object's symbol and address against this ELF")
    check.add_argument("--image", metavar="FILE.s19", help="a flash file (s19/hex) of the build: it must hold "
                       "MOD_PAR's EPK at every ADDR_EPK it has bytes at, and no byte outside the MEMORY_SEGMENTs")
    _cache_options(check)
    _output_options(check, verbose=False)  # every finding of a check is a problem
    check.set_defaults(func=_as_batch(_check))

    diff = commands.add_parser("diff", help="object-level differences of two A2L files",
                               description="Objects added, removed and changed (with the fields that changed) "
                               "from A to B. Exit 0 when there is no difference, 1 when there is.")
    diff.add_argument("a", metavar="A.a2l")
    diff.add_argument("b", metavar="B.a2l")
    add_output_arguments(diff)
    diff.set_defaults(func=_as_batch(_diff))


def _add_remove(commands) -> None:
    remove = commands.add_parser("remove", help="objects by name pattern or address range, with the references to them",
                                 description="a2ltool's --remove and --remove-range: take out every MEASUREMENT, "
                                 "CHARACTERISTIC, AXIS_PTS, BLOB and INSTANCE whose whole name a --regex matches or "
                                 "whose address lies in a --range [MIN, MAX). Their entries in lists that group "
                                 "objects (GROUP REF_MEASUREMENT/REF_CHARACTERISTIC, FUNCTION DEF_/REF_CHARACTERISTIC "
                                 "and IN_/OUT_/LOC_MEASUREMENT, FRAME_MEASUREMENT, TRANSFORMER_IN/OUT_OBJECTS) go with "
                                 "them, a list left empty too. A kept object that needs a removed one (an AXIS_DESCR's "
                                 "AXIS_PTS_REF or CURVE_AXIS_REF, the inputs of a VIRTUAL measurement or a "
                                 "DEPENDENT_/VIRTUAL_CHARACTERISTIC, a MAP_LIST, VAR_MEASUREMENT, "
                                 "VAR_SELECTION_CHARACTERISTIC) refuses the removal: each is an error at its "
                                 "file:line:column naming both objects, and nothing is written; so does an optional "
                                 "reference (INPUT_QUANTITY, COMPARISON_QUANTITY) unless --drop-optional-references. "
                                 "Only the removed text differs from the input. Exit codes: 0 written (warnings "
                                 "allowed: a pattern or range that selects nothing), 1 refused (nothing written), "
                                 "2 bad input (a bad pattern or range, malformed A2L).")
    remove.add_argument("a2l", metavar="IN.a2l")
    remove.add_argument("-R", "--regex", "--remove", action="append", default=[], type=_pattern, metavar="REGEX",
                        help="remove every object whose whole name it matches (repeatable; ^ or $ in it: searched as "
                             "written, as a2ltool does; --remove: a2ltool's spelling)")
    remove.add_argument("--range", "--remove-range", action="append", default=[], nargs=2, type=_address,
                        metavar=("MIN", "MAX"), help="remove every object whose address lies in [MIN, MAX) "
                                                     "(repeatable; 0x hex allowed; --remove-range: a2ltool's spelling)")
    remove.add_argument("--drop-optional-references", action="store_true",
                        help="an INPUT_QUANTITY that names a removed object becomes NO_INPUT_QUANTITY, a "
                             "COMPARISON_QUANTITY is dropped (each a warning) instead of refusing the removal")
    remove.add_argument("-c", "--cleanup", action="store_true",
                        help="then also remove what nothing uses any more, as `workbench a2l cleanup` does")
    _pruning_options(remove)
    remove.set_defaults(func=_as_batch(_remove))


def _add_cleanup(commands) -> None:
    cleanup = commands.add_parser("cleanup", help="remove what nothing uses (a2ltool's --cleanup)",
                                  description="a2ltool's --cleanup, until nothing more goes: COMPU_METHODs, "
                                  "COMPU_TABs, COMPU_VTABs, COMPU_VTAB_RANGEs, RECORD_LAYOUTs and UNITs no kept block "
                                  "refers to; GROUPs without REF_CHARACTERISTIC, REF_MEASUREMENT or SUB_GROUP entries "
                                  "that no USER_RIGHTS names; FUNCTIONs without DEF_/REF_CHARACTERISTIC, "
                                  "IN_/OUT_/LOC_MEASUREMENT or SUB_FUNCTION entries that no FUNCTION_LIST names; list "
                                  "entries that name nothing. Every reference `check` knows counts (a2ltool misses an "
                                  "OVERWRITE's CONVERSION and takes an AXIS_PTS in a GROUP for a dangling entry); a "
                                  "CONVERSION that names no COMPU_METHOD is left for `check` (a2ltool writes "
                                  "NO_COMPU_METHOD). Only the removed text differs from the input. Exit codes: 0 "
                                  "written, 1 refused (changes in included files, see --update-includes), 2 bad input "
                                  "(malformed A2L).")
    cleanup.add_argument("a2l", metavar="IN.a2l")
    _pruning_options(cleanup)
    cleanup.set_defaults(func=_as_batch(_cleanup))


def _pruning_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", type=output_file, metavar="OUT.a2l",
                        help="file to write (atomically; may be IN.a2l itself); required unless --dry-run")
    parser.add_argument("--dry-run", action="store_true", help="report what would be removed; write nothing")
    _include_options(parser, "; without it or --merge-includes a removal there refuses the operation")
    _output_options(parser)


def _include_options(parser: argparse.ArgumentParser, without: str = "") -> None:
    """--update-includes | --merge-includes: what becomes of changes that fall into /include'd files."""
    includes = parser.add_mutually_exclusive_group()
    includes.add_argument("--update-includes", action="store_true",
                          help=f"also rewrite the included files that change, in place (atomically){without}")
    includes.add_argument("--merge-includes", action="store_true",
                          help="write the text of every /include inline: the output is self-contained")


def _as_batch(handler):
    """The command run as what it is: a batch that reads its files, writes its output and ends.

    - The cyclic garbage collector is off while it runs (imports included): what it leaves is freed by
      reference counting. The collector's passes over the objects numpy's import, the DWARF index and
      the token tables hold cost 2 % of an uncached update of 65,000 objects (67 of 2,972 M
      instructions) and 1 % of a cached one.
    - Memory it frees stays with the process (:func:`_keep_freed_memory`).
    - Its process ends without tearing its heap down (``batch``: see :func:`workbench.cli.entry_point`).
    """

    @functools.wraps(handler)
    def run(args: argparse.Namespace) -> int:
        _keep_freed_memory()
        enabled = gc.isenabled()
        gc.disable()
        try:
            return handler(args)
        finally:
            if enabled:
                gc.enable()

    run.batch = True
    return run


_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3  # glibc's mallopt parameters (malloc.h)


def _keep_freed_memory() -> None:
    """glibc: blocks up to 32 MiB (its most) come from the heap, and freed heap memory is kept for the next
    allocation instead of being returned to the system. numpy's temporaries over a 10 MiB file (masks,
    offsets, gathers) otherwise go back and come again as fresh pages, each first touch a page fault: a
    cached update of 65,000 objects 31,900 -> 21,600 page faults and 448 -> 416 ms, an uncached one
    582 -> 560 ms. Elsewhere (macOS, Windows, musl: no mallopt) nothing changes.

    Transparent huge pages for the heap (madvise) halve the page faults again, but on a virtual machine a
    fresh 2 MiB page can cost more than the 512 faults it saves (touching 256 MiB: 40 to 560 ms against a
    steady 115-170 ms with 4 KiB pages, here): an uncached update of 130,000 objects became slower in
    the median, so the heap keeps the kernel's default."""
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (AttributeError, OSError, TypeError):
        return
    mallopt(_M_MMAP_THRESHOLD, 32 << 20)
    mallopt(_M_TRIM_THRESHOLD, 1 << 30)


def _output_options(parser: argparse.ArgumentParser, verbose: bool = True) -> None:
    add_output_arguments(parser)
    if verbose:
        parser.add_argument("-v", "--verbose", action="store_true", help="list every finding, not only problems")


def _cache_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--cache-dir", metavar="DIR", help="folder of the ELF index cache (default: "
                        "$WORKBENCH_CACHE_DIR/elf-index when that is set, else the user's cache folder, e.g. "
                        "~/.cache/workbench/elf-index)")
    parser.add_argument("--no-cache", action="store_true", help="neither read nor write the ELF index cache")


def _merge(args: argparse.Namespace) -> int:
    from workbench.a2l.merge import MergeFailed, merge_files
    from workbench.a2l.reports import ConflictPolicy
    from workbench.cli.progressbar import ProgressBar

    try:
        with ProgressBar("merging", enabled=None if not args.json else False) as progress:
            report = merge_files(args.master, args.fragments, args.output, module=args.module,
                                 policy=ConflictPolicy(args.on_conflict),
                                 keep_includes=args.keep_includes, progress=progress)
    except MergeFailed as exc:
        _print_report(exc.report, args, summary=str(exc))
        return 1
    merged = sum(1 for f in report.findings if f.kind == "merged")
    _print_report(report, args, summary=f"merged {merged} fragment(s) into {args.output}", output=args.output)
    return 0


def _update(args: argparse.Namespace) -> int:
    from workbench.a2l.reports import IncludeMode, UpdateMode
    from workbench.a2l.update import UpdateFailed, update_file
    from workbench.cli.progressbar import ProgressBar

    mode = UpdateMode.STRICT if args.strict else UpdateMode.REMOVE_MISSING if args.remove_missing else UpdateMode.DEFAULT
    if args.drop_optional_references and not args.remove_missing:
        raise InputError("update --drop-optional-references: goes with --remove-missing (only removed objects' "
                         "references are dropped)")
    includes = (IncludeMode.UPDATE if args.update_includes else IncludeMode.MERGE if args.merge_includes
                else IncludeMode.KEEP)
    try:
        with ProgressBar("updating", enabled=None if not args.json else False) as progress:
            report = update_file(args.a2l, args.elf, args.output, mode=mode, types=args.types, epk=not args.no_epk,
                                 epk_symbol=args.epk_symbol, includes=includes, cache_dir=args.cache_dir,
                                 use_cache=not args.no_cache, validate=args.validate,
                                 report_addresses=args.verbose or args.json,
                                 drop_optional=args.drop_optional_references, progress=progress)
    except UpdateFailed as exc:
        _print_report(exc.report, args, summary=f"{exc}; nothing written")
        return 1
    _print_report(report, args, summary=report.summary(args.output), output=args.output)
    return 0 if report.ok else 1  # written, with errors (changes in included files it could not write)


def _pattern(text: str) -> str:
    """argparse type: a regular expression of --*-regex (a bad one is a usage error naming the option, exit 2)."""
    import re

    from workbench.a2l.patterns import selection_pattern

    try:
        selection_pattern(text)
    except re.error as exc:
        raise argparse.ArgumentTypeError(f"not a regular expression: {text!r} ({exc})") from None
    return text


def _address(text: str) -> int:
    """argparse type: an address of --*-range (decimal or 0x hex)."""
    return integer_within(text, "an address", 0, None, "an address is 0 or more")


def _take_files_after_create(insert: argparse.ArgumentParser) -> None:
    """``insert IN.a2l --create ELF``: argparse takes IN.a2l for the ELF and refuses ELF as 'unrecognized'; the
    words it could not place are kept for :func:`_insert` to say what --create takes (other extras stay errors)."""
    parse_known_args = insert.parse_known_args

    def parse(args=None, namespace=None):
        namespace, rest = parse_known_args(args, namespace)
        if namespace.create:
            namespace.files_after = [word for word in rest if not word.startswith("-")]
            rest = [word for word in rest if word.startswith("-")]
        return namespace, rest

    insert.parse_known_args = parse


def _insert(args: argparse.Namespace) -> int:
    from workbench.a2l.insert import Selection, insert_file
    from workbench.cli.progressbar import ProgressBar

    files = [name for name in (args.a2l, args.elf, *args.files_after) if name is not None]
    if args.create and len(files) > 1:
        raise InputError(f"insert --create ELF: --create makes a new A2L from one ELF, written to -o OUT.a2l; "
                         f"{len(files)} files given ({' '.join(files)}): without --create, insert IN.a2l ELF adds "
                         "to an existing A2L")
    if not args.create and args.a2l is None:
        raise InputError("insert: give IN.a2l and ELF (or --create ELF for a new A2L)")
    if args.output is None and not args.dry_run:
        raise InputError("insert: -o/--output OUT.a2l is required (or --dry-run)")
    selections = [Selection(tuple(getattr(args, f"{kind}_regex")), tuple(map(tuple, getattr(args, f"{kind}_range"))),
                            tuple(getattr(args, f"{kind}_paths")), tuple(getattr(args, f"{kind}_section")))
                  for kind in ("measurement", "characteristic")]
    if not any(selections):
        raise InputError("insert: nothing selected: give --measurement-regex, --characteristic-regex, a --*-range, "
                         "a --*-section or -M/-C PATH")
    output = None if args.dry_run else args.output
    options = dict(measurements=selections[0], characteristics=selections[1], target_group=args.target_group,
                   module=args.module, structures=args.structures, old_arrays=args.old_arrays, cache_dir=args.cache_dir,
                   use_cache=not args.no_cache)
    with ProgressBar("inserting", enabled=None if not args.json else False) as progress:
        if args.create:
            from workbench.a2l.create import create_file

            report = create_file(args.elf, output, progress=progress, **options)
        else:
            report = insert_file(args.a2l, args.elf, output, progress=progress, **options)
    _print_report(report, args, summary=report.summary(output), output=output)
    return 0 if report.ok else 1


def _remove(args: argparse.Namespace) -> int:
    from workbench.a2l.prune import remove_file

    if not args.regex and not args.range:
        raise InputError("remove: nothing selected: give --regex REGEX or --range MIN MAX")
    return _prune(args, lambda output, includes, progress: remove_file(
        args.a2l, output, regexes=tuple(args.regex), ranges=tuple(map(tuple, args.range)), cleanup=args.cleanup,
        drop_optional=args.drop_optional_references, includes=includes, progress=progress))


def _cleanup(args: argparse.Namespace) -> int:
    from workbench.a2l.prune import cleanup_file

    return _prune(args, lambda output, includes, progress: cleanup_file(args.a2l, output, includes=includes,
                                                                         progress=progress))


def _prune(args: argparse.Namespace, run) -> int:
    from workbench.a2l.prune import PruneFailed
    from workbench.a2l.reports import IncludeMode
    from workbench.cli.progressbar import ProgressBar

    if args.output is None and not args.dry_run:
        raise InputError(f"{args.command}: -o/--output OUT.a2l is required (or --dry-run)")
    includes = (IncludeMode.UPDATE if args.update_includes else IncludeMode.MERGE if args.merge_includes
                else IncludeMode.KEEP)
    output = None if args.dry_run else args.output
    try:
        with ProgressBar("removing" if args.command == "remove" else "cleaning up",
                         enabled=None if not args.json else False) as progress:
            report = run(output, includes, progress)
    except PruneFailed as exc:
        _print_report(exc.report, args, summary=str(exc))
        return 1
    _print_report(report, args, summary=report.summary(output), output=output)
    return 0


def _flatten(args: argparse.Namespace) -> int:
    from workbench.a2l.includes import flatten_file, flatten_summary
    from workbench.cli.progressbar import ProgressBar

    with ProgressBar("flattening", enabled=None if not args.json else False) as progress:
        report = flatten_file(args.a2l, args.output, progress=progress)
    _print_report(report, args, summary=flatten_summary(report, args.output), output=args.output)
    return 0


def _check(args: argparse.Namespace) -> int:
    from workbench.a2l.check import check_file
    from workbench.cli.progressbar import ProgressBar

    with ProgressBar("checking", enabled=None if not args.json else False) as progress:
        report = check_file(args.a2l, args.elf, image=args.image, cache_dir=args.cache_dir,
                            use_cache=not args.no_cache, progress=progress)
    print_report(report, as_json=args.json, verbose=True,
                 summary=f"{args.a2l}: " + ("clean" if report.ok else f"{len(report.problems)} problem(s)"))
    return 0 if report.ok else 1


def _diff(args: argparse.Namespace) -> int:
    from workbench.a2l.diff import diff_files

    entries = diff_files(args.a, args.b)
    if args.json:  # ok: the files do not differ (exit code 0), as in every other report's JSON
        print_json({"operation": "diff", "ok": not entries, "a": args.a, "b": args.b,
                    "differences": [entry.to_dict() for entry in entries]})
    else:
        for entry in entries:
            where = entry.new_location or entry.old_location
            print(f"{where}: {entry.status} {entry.keyword} {entry.name}")
            for change in entry.changes:
                print(f"    {change.field}: {change.old if change.old is not None else '(none)'} -> "
                      f"{change.new if change.new is not None else '(none)'}")
        counts = {status: sum(1 for e in entries if e.status == status) for status in ("added", "removed", "changed")}
        print(", ".join(f"{count} {status}" for status, count in counts.items()), file=sys.stderr)
    return 1 if entries else 0


def _print_report(report, args: argparse.Namespace, summary: str, output: str | None = None) -> None:
    print_report(report, as_json=args.json, verbose=args.verbose, summary=summary, output=output)
