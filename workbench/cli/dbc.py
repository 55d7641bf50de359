"""``workbench dbc``: the thesis's CAN library (chapter 6.3) on cantools, without MATLAB.

* ``table`` — the message table with the thesis's Message/SignalOfMsg properties;
* ``fixcal`` — the fix calibrations as a C header/source pair and an A2L fragment;
* ``callbacks`` — the CAN driver configuration between the ``// <initCbk>`` markers of api.c;
* ``check`` — DBC problems (exit 1 when there are warnings or errors).

Every command loads through :func:`workbench.can.dbc_file.load_dbc`, so they agree on what a
file holds; the problems the load reads past are warnings (``file:line: warning: ...``) on
stderr, and findings of ``check``.
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter

from workbench.cli.options import add_output_arguments, print_json, print_report
from workbench.findings import Severity

__all__ = ["MAILBOX_ORDERS", "add_subparser"]

_GROUP_DESCRIPTION = """\
The thesis's CAN library (chapter 6.3) from a DBC, without MATLAB:
  table      the message table with the thesis's Message/SignalOfMsg properties
  fixcal     the fix calibrations as a C header/source pair and an A2L fragment
  callbacks  the CAN driver configuration between the // <initCbk> markers of api.c
  check      DBC problems (exit 1 when there are warnings or errors)
What CANdb++ reads loads: problems it reads past (an id above 0x7FF without the extended
flag, names that start with a digit, comments without text, references to signals that do not
exist ...) are warnings naming file:line, on stderr and in `check`.
Exit codes: 0 success, 1 problems (check) or a failed write (disk full), 2 bad input (a file
that cannot be read or parsed, a place that cannot be written, a bad option)."""
_NETWORK_HELP = ("CAN1..CAN4 for every DBC given (default: the CANn in each file name, "
                 "e.g. FLCU_CAN2.dbc is on CAN2)")
_TABLE_NETWORK_HELP = ("CAN1..CAN4 for every DBC given (default: the CANn in each file name, e.g. FLCU_CAN2.dbc "
                       "is on CAN2; a file whose name says none is assumed on CAN2, the vehicle bus, and a note "
                       "says so)")
_ROLE_HELP = ("the ECU node the roles are relative to: a message it sends is TX, one whose signals it "
              "receives is RX, any other is not in its table")
# workbench.can.mailboxes.MailboxOrder's values, spelled here so that --help needs no cantools
MAILBOX_ORDERS = ("file", "reverse", "id", "name")
_ORDER_HELP = (
    "order in which a DBC's messages take the mailboxes of their network and role: "
    "file (default: the first TX message of the file is CAN2_MSG_TX_000), reverse (the thesis's "
    "figures: FLCU_TO_PCM_003 = CAN2_MSG_TX_000), id, name. A further DBC on the same network "
    "takes the next free mailboxes (the thesis's canMap)"
)
_QUALIFIED_HELP = ("message-qualified names cf<MESSAGE>_<SIGNAL>_EN/_VALUE (e.g. cfC3RXAAA_SGN1_EN), for DBCs "
                   "whose messages share signal names")
_TIMEOUT_NOTE = ("Periods and timeouts come from GenMsgCycleTime/GenMsgTimeoutTime (ms); a message "
                 "without a timeout gets 3 x its period, as the thesis's import does.")


def add_subparser(subparsers: argparse._SubParsersAction, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, description=_GROUP_DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(title="commands", dest="command", metavar="COMMAND", required=True)

    table = commands.add_parser(
        "table", help="message table: Name, ID, DLC, Period, Timeout, Role, MboxId and the signals",
        description="The message table of one or more DBCs. " + _TIMEOUT_NOTE,
    )
    _add_table_arguments(table, node_help=_ROLE_HELP + " (without it: no roles and no mailboxes)", node_required=False,
                         network_help=_TABLE_NETWORK_HELP)
    output = table.add_mutually_exclusive_group()
    output.add_argument("--csv", action="store_true", help="one CSV row per signal")
    output.add_argument("--json", action="store_true", help="messages with their signals as JSON")
    table.set_defaults(func=_table)

    fixcal = commands.add_parser(
        "fixcal", help="cf<SIGNAL>_EN/_VALUE and cs<Message>_En calibrations as C and A2L",
        description=(
            "Fix calibrations of every signal the node sends or receives: cf<SIGNAL>_EN (uint8 0/1, "
            "initially 0) and cf<SIGNAL>_VALUE (the raw value in the integer type of the signal's width, "
            "shown in physical units through a COMPU_METHOD from factor/offset, limits from the DBC "
            "min/max), and cs<Message>_En (uint8 0/1, initially 1) for every message it sends. Writes "
            "<dbc>_fixcal.h/.c (definitions in .cal_ram through the CAL_RAM macro, rtwtypes types) and "
            "<dbc>_fixcal.a2l (a complete small A2L whose CHARACTERISTICs wait for `workbench a2l update`)."
        ),
    )
    fixcal.add_argument("dbc", metavar="FILE.dbc")
    fixcal.add_argument("--node", required=True, help=_ROLE_HELP)
    fixcal.add_argument("--qualified", action="store_true", help=_QUALIFIED_HELP)
    fixcal.add_argument("-o", "--output", default=".", metavar="DIR", help="folder for the files (default: .)")
    fixcal.add_argument("--master", metavar="A2L", default=None,
                        help="master A2L whose MOD_COMMON (byte order, alignments) the fragment repeats "
                             "(default: the demo project's a2l/FLCU_master.a2l)")
    fixcal.add_argument("--measurements", metavar="CSV", default=None,
                        help="rows 'signal,measurement' (first row just that): the MEASUREMENT that shows each "
                             "signal's live value (a sent signal's source variable, a received signal's published "
                             "value), written as its _VALUE's COMPARISON_QUANTITY so tools find it by the link; "
                             "a signal by its name or as Message.Signal")
    parts = fixcal.add_mutually_exclusive_group()
    parts.add_argument("--a2l-only", action="store_true", help="write only the A2L fragment")
    parts.add_argument("--c-only", action="store_true",
                       help="write only the C header and source (not with --master or --measurements: A2L only)")
    fixcal.set_defaults(func=_fixcal)

    callbacks = commands.add_parser(
        "callbacks", help="regenerate the CAN driver configuration between the // <initCbk> markers of api.c",
        description=(
            "Regenerate the driver configuration calls (API_CAN_setPduInitValues, CanNetwork_SetTxPeriod/"
            "SetTxDlc/EnableDisableSendMessages, SetRxPeriod/SetRxTimeout/SetRxDlc/"
            "EnableDisableReceivedMessages) of the node's messages, TX then RX in mailbox order, between the "
            "lines '// <initCbk>' and '// </initCbk>' of api.c (exactly one of each, start first). Everything "
            "outside the markers stays byte for byte; the file is written atomically and only when it "
            "changes. " + _TIMEOUT_NOTE
        ),
    )
    _add_table_arguments(callbacks, node_help=_ROLE_HELP, node_required=True, network_help=_NETWORK_HELP)
    callbacks.add_argument("--api", required=True, metavar="api.c", help="the C file with the markers")
    callbacks.set_defaults(func=_callbacks)

    check = commands.add_parser(
        "check", help="report DBC problems (exit 1 when there are any)",
        description=(
            "Report what the load read past (an id above 0x7FF without the extended flag, names that start "
            "with a digit, comments without text, references to missing signals ...), overlapping signals, "
            "signals beyond the DLC, duplicate ids and names (across the DBCs of one network), missing "
            "GenMsgCycleTime/GenMsgTimeoutTime, a VFrameFormat that disagrees with the id, and, as one hint, "
            "fix calibration names `dbc fixcal` would define twice. Exit 0: no warnings or errors (hints "
            "may remain); 1: warnings or errors; 2: a file cannot be read."
        ),
    )
    check.add_argument("dbc", nargs="+", metavar="FILE.dbc")
    check.add_argument("--network", help="CAN1..CAN4 for every DBC given (default: from the file name; "
                                         "DBCs without one are compared with themselves only)")
    check.add_argument("--node", help="look for fix-calibration collisions among this node's messages only")
    check.add_argument("--qualified", action="store_true",
                       help="look for collisions of the message-qualified fix-calibration names")
    add_output_arguments(check)
    check.set_defaults(func=_check)


def _add_table_arguments(parser: argparse.ArgumentParser, *, node_help: str, node_required: bool,
                         network_help: str) -> None:
    """The DBCs, their network, the node and the mailbox order: what a node's message table needs."""
    parser.add_argument("dbc", nargs="+", metavar="FILE.dbc")
    parser.add_argument("--network", help=network_help)
    parser.add_argument("--node", required=node_required, help=node_help)
    parser.add_argument("--order", choices=MAILBOX_ORDERS, default="file", help=_ORDER_HELP)


def _table(args: argparse.Namespace) -> int:
    from workbench.can.mailboxes import MailboxOrder
    from workbench.can.table import ASSUMED_NETWORK, build_table, guess_network, load_networks
    from workbench.can.table_export import table_csv, table_text

    dbcs = load_networks(args.dbc, args.network, assume=ASSUMED_NETWORK)
    assumed = [dbc for dbc, _ in dbcs if args.network is None and guess_network(dbc.path) is None]
    table = build_table(dbcs, args.node, MailboxOrder(args.order))
    _print_load_warnings(dbc for dbc, _ in dbcs)
    for dbc in assumed:
        print(f"{dbc.path}: note: no CAN1..CAN4 in the file name: assumed on {ASSUMED_NETWORK} "
              f"(--network chooses)", file=sys.stderr)
    if args.json:
        data = table.to_dict()
        data["networks"] = [{"file": str(dbc.path), "network": network, "assumed": dbc in assumed}
                            for dbc, network in dbcs]
        data["warnings"] = [warning.to_dict() for dbc, _ in dbcs for warning in dbc.warnings]
        print_json(data)
    else:
        sys.stdout.write(table_csv(table) if args.csv else table_text(table))
    return 0


def _print_load_warnings(dbcs) -> None:
    """What the loads read past, one ``file:line: warning: ...`` line each, on stderr."""
    for dbc in dbcs:
        for warning in dbc.warnings:
            print(warning, file=sys.stderr)


def _fixcal(args: argparse.Namespace) -> int:
    from workbench import demo
    from workbench.can.dbc_file import load_dbc
    from workbench.can.fixcal_output import fixcal_files, read_signal_measurements
    from workbench.errors import InputError

    unused = [option for option, given in (("--master", args.master), ("--measurements", args.measurements)) if given]
    if args.c_only and unused:  # both go into the A2L fragment only
        raise InputError(f"{' and '.join(unused)} shape{'s' if len(unused) == 1 else ''} the A2L fragment, which "
                         "--c-only does not write: leave out one or the other")
    master = args.master if args.master is not None else demo.master_a2l()
    measurements = read_signal_measurements(args.measurements) if args.measurements else None
    dbc = load_dbc(args.dbc)
    _print_load_warnings([dbc])
    files = fixcal_files(dbc, args.node, c=not args.a2l_only, a2l=not args.c_only, master_a2l=master,
                         qualified=args.qualified, measurements=measurements)
    for path in files.write(args.output):
        print(path)
    print(f"{len(files.calibrations)} calibrations for {args.node}", file=sys.stderr)
    return 0


def _callbacks(args: argparse.Namespace) -> int:
    from workbench.can.callbacks import write_callbacks
    from workbench.can.mailboxes import MailboxOrder
    from workbench.can.table import build_table, load_networks

    dbcs = load_networks(args.dbc, args.network)
    table = build_table(dbcs, args.node, MailboxOrder(args.order))
    _print_load_warnings(dbc for dbc, _ in dbcs)
    changed = write_callbacks(args.api, table.messages)
    print(f"{args.api}: {'regenerated' if changed else 'unchanged'} "
          f"({len(table.messages)} messages of {args.node})")
    return 0


def _check(args: argparse.Namespace) -> int:
    from workbench.can.dbc_file import load_dbc
    from workbench.can.table import guess_network, network_of
    from workbench.can.validation import check_dbcs

    dbcs = [(load_dbc(path), network_of(path, args.network) if args.network else guess_network(path))
            for path in args.dbc]
    report = check_dbcs(dbcs, args.node, qualified=args.qualified)
    print_report(report, as_json=args.json, verbose=True, summary=_check_summary(report, len(dbcs)))
    return 0 if report.ok else 1


def _check_summary(report, files: int) -> str:
    """``3 warnings, 1 hint in 2 files`` (``no problems in 1 file``)."""
    counts = Counter(finding.severity for finding in report.findings)
    parts = [f"{counts[severity]} {word}{'s' if counts[severity] != 1 else ''}"
             for severity, word in ((Severity.ERROR, "error"), (Severity.WARNING, "warning"), (Severity.INFO, "hint"))
             if counts[severity]]
    return f"{', '.join(parts) or 'no problems'} in {files} file{'s' if files != 1 else ''}"
