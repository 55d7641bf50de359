"""The options every command that talks to an ECU takes, and the session they open.

``--a2l`` (default: the demo ECU's merged and updated A2L), python-can's bus options
(``--interface --channel --bitrate --bus-kwargs ...``), ``--host/--port/--protocol`` for XCP on
Ethernet, ``--key-function``, ``--accept-epk-mismatch`` and ``--daq-can-id``.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from workbench.cli.options import (
    add_bus_arguments,
    add_ethernet_arguments,
    add_output_arguments,
    bus_spec,
)

if TYPE_CHECKING:
    from workbench.a2l import A2lDocument
    from workbench.can import DbcFile
    from workbench.session import Session

__all__ = ["a2l_document", "add_ecu_arguments", "can2_dbc", "open_session"]


def add_ecu_arguments(parser: argparse.ArgumentParser, *, json_output: bool = True) -> None:
    group = parser.add_argument_group("ECU")
    group.add_argument("--a2l", metavar="A2L", help="the ECU's A2L (default: the built-in demo ECU's)")
    group.add_argument("--key-function", metavar="NAME",
                       help="seed & key function: module:function, file.py:function, an installed plugin's name or a "
                            "key library with ASAM's XCP_ComputeKeyFromSeed (.dll on Windows, .so on Linux) "
                            "(default: the A2L's SEED_AND_KEY_EXTERNAL_FUNCTION)")
    group.add_argument("--accept-epk-mismatch", action="store_true",
                       help="write although the ECU's EPK differs from the A2L's (the session is read-only otherwise)")
    group.add_argument("--daq-can-id", action="append", type=_daq_can_id, metavar="LIST=ID", dest="daq_can_ids",
                       help="XCP on CAN: DAQ list LIST sends its DTOs on CAN id ID (as the A2L writes it: 0x7F4, bit "
                            "31 set for an extended id), set with SET_DAQ_ID before it starts; for lists the A2L's "
                            "DAQ_LIST_CAN_ID calls VARIABLE (default: CAN_ID_SLAVE); repeatable")
    add_bus_arguments(parser)
    add_ethernet_arguments(parser)
    if json_output:
        add_output_arguments(parser)


def _daq_can_id(text: str) -> tuple[int, int]:
    from workbench.errors import InputError
    from workbench.session.connection import parse_daq_can_ids

    try:
        ((number, can_id),) = parse_daq_can_ids(text).items()
    except (InputError, ValueError) as exc:
        raise argparse.ArgumentTypeError(str(exc) if isinstance(exc, InputError) else f"{text!r}: one LIST=ID") from None
    return number, can_id


def a2l_document(args: argparse.Namespace) -> A2lDocument:
    """The A2L of ``--a2l`` (default: the demo's), loaded before connecting so names can be checked first; an
    A2ML include that is not there is a warning on stderr (:func:`~workbench.a2l.includes.load_a2l_to_work`)."""
    import sys

    from workbench import demo
    from workbench.a2l.includes import left_out, load_a2l_to_work

    doc = load_a2l_to_work(args.a2l or demo.a2l())
    for line in left_out(doc):
        print(f"warning: {line}", file=sys.stderr)
    return doc


def can2_dbc(args: argparse.Namespace) -> DbcFile | str | None:
    """The CAN2 DBC: ``--can2 DBC`` loaded, so call this before connecting (a missing, unreadable or malformed file
    is bad input said before anything is sent); else the demo's path with the demo's A2L (loaded where a signal
    needs it); None: no DBC is known."""
    from pathlib import Path

    from workbench import demo

    if args.can2:
        from workbench.can import load_dbc

        return load_dbc(args.can2)
    if args.a2l is None or Path(args.a2l).resolve() == Path(demo.a2l()).resolve():
        return str(demo.dbc_can2())
    return None


def open_session(args: argparse.Namespace, a2l: A2lDocument | None = None, *, reading: bool = False) -> Session:
    """The session the ECU options describe (connected, EPK checked); ``a2l``: the A2L already loaded. The bus
    is built once from the options and handed over whole. Another master's traffic heard before CONNECT is a
    warning on stderr (:attr:`Session.other_master`). ``reading``: the command only reads values by
    name, so an EPK mismatch is said as a warning on stderr (a write refuses with its own error; ``info``
    shows it): the values come from the A2L's addresses, which may hold other things in the ECU's software."""
    import sys

    from workbench.session import Session

    session = Session.open(a2l or a2l_document(args), bus=bus_spec(args), host=args.host, port=args.port,
                           protocol=args.protocol, key_function=args.key_function,
                           accept_epk_mismatch=args.accept_epk_mismatch,
                           daq_can_ids=dict(getattr(args, "daq_can_ids", None) or ()))
    if session.other_master:
        print(f"warning: {session.other_master}", file=sys.stderr)
    if reading and session.epk.matches is False:
        print(f"warning: {session.epk.describe()}: the values are read at this A2L's addresses, which may not "
              "hold them in the ECU's software", file=sys.stderr)
    return session
