"""``workbench info``: who the ECU is, whether its EPK matches the A2L, what it can do."""

from __future__ import annotations

import argparse

from workbench.cli.ecu_options import add_ecu_arguments, open_session
from workbench.cli.flash import add_app_key_arguments, app_key
from workbench.cli.options import print_json

__all__ = ["add_subparser", "info_lines", "run"]

EPILOG = """\
examples:
  workbench info                                  # the demo ECU of 'workbench sim' (udp_multicast)
  workbench info --a2l out/FLCU.a2l --interface socketcan --channel can0
  workbench info --host 127.0.0.1 --protocol tcp --json
  workbench info --host 127.0.0.1 --port 5555 --save-a2l ecu.a2l   # XCPlite: its own A2L (GET_ID 4)
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(name, help=help_text, epilog=EPILOG,
                                   description="Connect, show the ECU's identity, EPK check, protection, "
                                               "packet sizes, DAQ processor and calibration pages, disconnect.",
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    add_app_key_arguments(parser.add_argument_group("boot"))
    parser.add_argument("--save-a2l", metavar="PATH",
                        help="also upload the A2L the ECU holds itself (GET_ID 4: XCPlite's) and write it to PATH")
    add_ecu_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workbench.flash import app_key_state

    key = app_key(args)
    with open_session(args) as session:
        info = session.info()
        if not args.app_key and key is not None and not _has_a_place_for(session, key):
            key = None  # the demo ECU's key, on an ECU whose flash has no sector there: no claim about it
        key_state = app_key_state(session, key) if key is not None else None
        if args.save_a2l:
            from workbench.fileio import write_output

            write_output(args.save_a2l, session.ecu_a2l())
    if args.json:
        print_json({**info.to_dict(), "app_key": key_state.value if key_state else None,
                    "state": _state(info, key_state, key), **({"saved_a2l": args.save_a2l} if args.save_a2l else {})})
        return 0
    print("\n".join(info_lines(info, _state(info, key_state, key))))
    if args.save_a2l:
        print(f"A2L           the ECU's own written to {args.save_a2l}")
    return 0


def _has_a_place_for(session, key) -> bool:
    """Whether the A2L's flash layout has a sector holding ``key`` (as a flash needs one): another ECU's bytes at
    the demo's key address would otherwise read as "a flash did not finish"."""
    from workbench.flash import FlashLayout

    return FlashLayout.from_a2l(session.doc, session.config, session.module).sector_of(key.address) is not None


def _state(info, key_state, key) -> str:
    """The state line: the boot loader or the application, and an unfinished flash the cleared key shows."""
    from workbench.flash import KeyState

    cleared = key_state is KeyState.CLEARED
    if info.boot:
        return "boot loader (programming only)" + (f"; {key_state.describe(key)}" if cleared else "")
    if cleared:  # PROGRAM_START stopped the application; the boot will not start it again
        return f"programming, the application stopped; {key_state.describe(key)}"
    return "application running"


def info_lines(info, state: str) -> list[str]:
    differing = "/".join(p["segment"] for p in info.epk_parts if p["matches"] is False)
    epk = ("match" if info.epk_match else f"MISMATCH (read-only){f' in {differing}' if differing else ''}"
           if info.epk_match is False else "not checked")
    lines = [
        f"ECU           {info.identification or '(no identification)'}",
        f"link          {info.link}",
        f"A2L name      {info.a2l_name or '-'}",
        f"EPK           ECU {_epk(info.epk_ecu)}, A2L {_epk(info.epk_a2l)}: {epk}",
        *(_epk_part(part) for part in info.epk_parts),
        f"state         {state}",
        f"resources     {', '.join(info.resources) or '-'}; locked: {', '.join(info.protected) or 'none'}",
        f"packets       MAX_CTO {info.max_cto}, MAX_DTO {info.max_dto}, {info.byte_order}, "
        f"address granularity {info.address_granularity} byte(s)",
        f"block modes   slave {'yes' if info.slave_block_mode else 'no'}, master "
        + (f"yes (MAX_BS {info.max_bs})" if info.master_block_mode else "no"),
        f"XCP versions  protocol {info.protocol_version}, transport {info.transport_version}",
    ]
    if info.daq is not None:
        daq = info.daq
        resolution = info.daq_resolution
        stamp = (_timestamps(resolution.timestamp_size, resolution.timestamp_resolution_s)
                 if resolution and resolution.timestamp_size else "no timestamps")
        lines.append(f"DAQ           {'dynamic' if daq.dynamic else 'static'}, {daq.max_daq} lists, "
                     f"{daq.identification_field.lower().replace('_', ' ')} ids, {stamp}, max ODT entry "
                     f"{resolution.max_entry_size if resolution else '?'} bytes, overload indication {daq.overload_indication}")
        for event in info.events:
            period = f"{event.period_s * 1000:g} ms" if event.period_s else "not cyclic"
            lines.append(f"  event {event.number:<3}  {event.name or '?':<16} {period}, priority {event.priority}, "
                         f"consistency {event.consistency}")
        if info.daq_can_ids:
            lines.append(f"DAQ CAN ids   {', '.join(map(str, info.daq_can_ids))}")
    for page in info.pages:
        lines.append(f"page          segment {page.segment}: ECU on {page.name(page.ecu_page)}, "
                     f"XCP on {page.name(page.xcp_page)}")
    return lines


def _epk_part(part: dict) -> str:
    """``  in CALIB       FC0000h: ECU '…', A2L '…': match`` (a part of the software with its own ADDR_EPK)."""
    verdict = {True: "match", False: "MISMATCH", None: "not read"}[part["matches"]]
    return (f"  in {part['segment']:<11} {part['address']:06X}h: ECU {_epk(part['ecu'])}, A2L {_epk(part['a2l'])}: "
            f"{verdict}")


def _epk(text: str | None) -> str:
    from workbench.errors import epk_text

    return "-" if text is None else epk_text(text)


def _timestamps(size: int, tick_s: float) -> str:
    """'4-byte timestamps of 1 ns (they wrap every 4.3 s)': the tick in the unit that reads best, and the wrap."""
    tick = f"{tick_s * 1e9:g} ns" if tick_s < 1e-6 else f"{tick_s * 1e6:g} µs" if tick_s < 1e-3 else f"{tick_s * 1e3:g} ms"
    wrap_s = tick_s * 256**size
    wrap = f"{wrap_s * 1e3:.3g} ms" if wrap_s < 1 else f"{wrap_s:.3g} s" if wrap_s < 3600 else f"{wrap_s / 3600:.3g} h"
    return f"{size}-byte timestamps of {tick} (they wrap every {wrap})"
