"""``workbench scan``: which XCP on CAN slaves answer on a bus, and on which identifiers (GET_SLAVE_ID)."""

from __future__ import annotations

import argparse
import sys

from workbench.cli.options import add_bus_arguments, add_output_arguments, bus_spec, positive_float, print_json

__all__ = ["add_subparser", "can_id", "detection_lines", "run"]

EPILOG = """\
examples:
  workbench scan                                        # the demo ECU of 'workbench sim' (udp_multicast)
  workbench scan --interface socketcan --channel can0 --broadcast-id 0x100
  workbench scan --a2l out/FLCU.a2l --interface vector --channel 0 --identify --json

Only GET_SLAVE_ID is broadcast, on the one bus named (no CONNECT sweep over identifiers); --identify
then connects to each slave that answered, on the identifiers it named.
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(
        name, help=help_text, epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Send XCP on CAN's GET_SLAVE_ID (echo, then inverse echo) on the broadcast identifier and\n"
                    "list each slave that answers: the identifier it takes commands on and the one it answers on.")
    group = parser.add_argument_group("scan")
    group.add_argument("--a2l", metavar="A2L",
                       help="the A2L whose XCP_ON_CAN gives CAN_ID_BROADCAST, BAUDRATE and the ids to check "
                            "(default: the demo ECU's, unless --broadcast-id is given)")
    group.add_argument("--broadcast-id", metavar="ID", type=can_id,
                       help="the broadcast CAN identifier, e.g. 0x100 (bit 31 set, 0x80000100: extended) "
                            "(default: the A2L's CAN_ID_BROADCAST)")
    group.add_argument("--wait", metavar="SECONDS", type=positive_float, default=None,
                       help="how long each request collects answers (default: 0.2)")
    group.add_argument("--identify", action="store_true",
                       help="also connect to each slave that confirmed its ids: GET_ID (text, EPK), GET_DAQ_ID, "
                            "disconnect")
    add_bus_arguments(parser)
    add_output_arguments(parser)
    parser.set_defaults(func=run)


def can_id(text: str):
    """argparse type: a CAN identifier as the A2L writes it (bit 31: extended)."""
    from workbench.cli.options import integer_within
    from workbench.xcp_protocol import CanId

    try:
        return CanId.from_a2l(integer_within(text, "a CAN identifier", 0, 0xFFFFFFFF, "must be 0 to 0xFFFFFFFF"))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def run(args: argparse.Namespace) -> int:
    from workbench.session.detect import detect_slaves
    from workbench.xcp.detect import DEFAULT_WAIT_S

    wait_s = args.wait or DEFAULT_WAIT_S
    detection = detect_slaves(args.a2l, bus=bus_spec(args), broadcast_id=args.broadcast_id, wait_s=wait_s,
                              identify=args.identify)
    error = None if detection.slaves else f"no XCP slave answered {detection.found.sent()} within {wait_s:g} s"
    if args.json:  # a failure as every command's --json says one: error and exit_code beside the report
        print_json({"ok": error is None, **detection.to_dict(), **({"error": error, "exit_code": 1} if error else {})})
    elif detection.slaves or detection.found.refused:
        print("\n".join(detection_lines(detection)))
    if error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    return 0


def detection_lines(detection) -> list[str]:
    """One line a slave (and its identity when asked for), then the A2L's ids held against the answers."""
    count = len(detection.slaves)
    lines = [f"{detection.found.sent()}: {count} slave{'' if count == 1 else 's'} answered"]
    identities = {identity.slave: identity for identity in detection.identities}
    for number, slave in enumerate(detection.slaves, 1):
        confirmed = "" if slave.confirmed else "  (answered the echo, not the inverse echo)"
        lines.append(f"slave {number}  commands on {slave.command_id}, answers on {slave.response_id}{confirmed}")
        identity = identities.get(slave)
        if identity is None:
            continue
        if identity.error:
            lines.append(f"  not identified: {identity.error}")
            continue
        lines.append(f"  ECU         {identity.text or '-'}")
        lines.append(f"  EPK         {identity.epk or '-'}")
        lines.append(f"  DAQ ids     {'; '.join(str(ids) for ids in identity.daq_ids) or '-'}")
        lines += [f"  note        {note}" for note in identity.notes]
    for can_id, reason in detection.found.refused:
        lines.append(f"refused     an answer on {can_id}: {reason}")
    if detection.a2l_ids is not None and detection.slaves:
        master, slave = detection.a2l_ids
        verdict = ("a slave answers on them" if detection.a2l_slave is not None
                   else "no slave answered on them: correct the A2L's ids with the ones above")
        lines.append(f"A2L         CAN_ID_MASTER {master}, CAN_ID_SLAVE {slave}: {verdict}")
    return lines
