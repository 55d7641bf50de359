"""``workbench sim``: serve the simulated FLCU ECU until Ctrl-C (the library call is ``workbench.sim.serve_demo``)."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from contextlib import ExitStack

from workbench.bus_defaults import BusSpec
from workbench.cli.options import (
    add_bus_arguments,
    add_can2_bus_kwargs_argument,
    add_ethernet_arguments,
    add_output_arguments,
    bus_settings,
    can2_bus_spec,
    positive_float,
    print_json,
)
from workbench.errors import InputError

__all__ = ["add_subparser", "run"]

EPILOG = """\
XCP on CAN (ids, baud rate and EPK from the A2L) goes on the CAN bus the python-can options name
(default: udp_multicast 239.74.163.2); the FLCU's CAN2 messages share that bus unless
--can2-channel (or --can2-bus-kwargs, e.g. port=N) puts them on another one. With --host the ECU
serves XCP on Ethernet instead (UDP unless --protocol tcp; port and packet sizes from the A2L's
XCP_ON_UDP_IP/XCP_ON_TCP_IP, --port 0 takes any free port), and the CAN bus options, if given,
carry only the CAN2 messages.
With --bitrate on a software bus (virtual, udp_multicast) the simulator paces its frames as a
real CAN bus of that bit rate would; on hardware the bit rate goes to the interface. python-can
binds udp_multicast's port for every group: two simulators on one host need their own ports
(--bus-kwargs port=N). --pcm adds a residual-bus PCM that sends EnableFLCU and
TargetRailPressure every 100 ms, so the rail pressure rises on its own. Resources CAL/PAG, DAQ
and PGM are locked until UNLOCK with the seed & key plugin workbench.sim.seedkey:compute_key
(--unlocked serves them open). --static-daq offers four static DAQ lists (two fixed to the 4 ms and
50 ms events) instead of dynamic DAQ, as older ECUs do.

Faults (--fault, repeatable): a sensor's voltage (rail=4.9: out of its 0.5-4.5 V span), an output
driver's error (OTV1=OPEN_LOAD; OTV2, PRV, LED; SHORT_TO_GND, SHORT_TO_BAT ...), a channel id error on
an RX message (chid:PCM_TO_FLCU_001), and with --pcm a PCM message that stops (pcm-stop:PCM_TO_FLCU_002:
an RX timeout) or has another DLC (pcm-dlc:PCM_TO_FLCU_002=2). The same faults, and more, can be
injected while it runs through its control channel (127.0.0.1, a free port, shown in the banner): the
requirement tests (workbench test) find it by the bus options alone.

--profile serves the demo through another implementation of XCP's options, as other ECUs have
them (docs/slave-profiles.md; --profile list shows them). Where the profile changes what the A2L
says, --write-a2l PATH writes the A2L a master needs for it (the demo's A2L otherwise).

examples:
  workbench sim --pcm
  workbench sim --interface udp_multicast --channel 239.74.163.2 --bus-kwargs port=43200
  workbench sim --pcm --time-scale 10                     # ten simulated seconds each second
  workbench sim --interface socketcan --channel vcan0 --can2-channel vcan1
  workbench sim --host 127.0.0.1 --port 5555 --protocol tcp --pcm
  workbench sim --pcm --fault rail=4.9 --fault OTV1=OPEN_LOAD
  workbench sim --profile segments --write-a2l segments.a2l
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(
        name, help=help_text, description="Serve the simulated FLCU ECU (XCP on CAN or on Ethernet) until Ctrl-C.",
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    files = parser.add_argument_group("demo ECU files (default: the built-in demo)")
    files.add_argument("--a2l", help="A2L with IF_DATA XCP and MOD_PAR EPK/ADDR_EPK")
    files.add_argument("--elf", help="application ELF (sections, symbols)")
    files.add_argument("--s19", help="flash image (S-records or Intel HEX)")
    files.add_argument("--dbc", help="CAN2 database of the FLCU messages")
    add_bus_arguments(parser)
    add_ethernet_arguments(parser)
    can2 = parser.add_argument_group("CAN2 (FLCU messages)")
    can2.add_argument("--can2-interface", help="python-can interface of CAN2 (default: --interface)")
    can2.add_argument("--can2-channel", help="put CAN2 on its own bus with this channel (default: share CAN1)")
    add_can2_bus_kwargs_argument(can2)
    sim = parser.add_argument_group("simulation")
    sim.add_argument("--pcm", action="store_true", help="simulate the PCM: EnableFLCU=1 and the target rail pressure every 100 ms")
    sim.add_argument("--pcm-target", type=float, default=25.0, metavar="BAR", help="the PCM's TargetRailPressure in bar (default 25)")
    sim.add_argument("--time-scale", type=positive_float, default=1.0, metavar="X",
                     help="simulated seconds per real second (default 1: real time)")
    sim.add_argument("--no-app-key", action="store_true",
                     help="start with the application-valid key erased: the ECU stays in boot (programming only)")
    sim.add_argument("--unlocked", action="store_true", help="no seed & key: CAL/PAG, DAQ and PGM open at CONNECT")
    sim.add_argument("--static-daq", action="store_true",
                     help="static DAQ lists (fixed lists, ODTs and entries; no ALLOC_DAQ) instead of dynamic DAQ")
    sim.add_argument("--profile", default="demo", metavar="NAME",
                     help="serve through this slave profile ('list' lists them; default: demo)")
    sim.add_argument("--write-a2l", metavar="PATH", help="write the A2L that describes the ECU served (the profile's)")
    parser.defer(lambda: _list_profiles_in(parser))
    sim.add_argument("--duration", type=positive_float, metavar="S", help="stop by itself after S real seconds")
    sim.add_argument("--fault", action="append", default=[], metavar="FAULT",
                     help="inject a fault from the start (repeatable; see below)")
    sim.add_argument("--no-control", action="store_true",
                     help="no control channel (fault injection while it runs; a second workbench sim on this bus "
                          "then does not see this one and serves too)")
    add_output_arguments(parser)
    parser.set_defaults(func=run)


def _list_profiles_in(parser: argparse.ArgumentParser) -> None:
    """The profiles' names at the end of the help (imported only when the help is shown or sim runs)."""
    from workbench.sim.profiles import PROFILES

    parser.epilog += "\nprofiles: " + ", ".join(PROFILES) + "\n"


def _print_profiles(as_json: bool) -> int:
    from workbench.sim.profiles import PROFILES

    if as_json:
        print_json([{"name": p.name, "changes": p.changes, "exercises": p.exercises, "own_a2l": p.changes_a2l}
                    for p in PROFILES.values()])
    else:
        for p in PROFILES.values():
            print(f"{p.name:26} {p.changes}\n{'':26} exercises: {p.exercises}")
    return 0


def run(args: argparse.Namespace) -> int:
    from workbench.sim.control import ControlServer, endpoint_keys, serving_elsewhere
    from workbench.sim.demo_ecu import DemoFiles, build_demo_ecu
    from workbench.sim.eth_port import EthernetEndpoint
    from workbench.sim.inject import FlcuFaults
    from workbench.sim.profiles import profile
    from workbench.sim.serve import serve_demo

    if args.profile == "list":
        return _print_profiles(args.json)
    chosen = profile(args.profile)
    bus = bus_settings(args)
    if (args.port is not None or args.protocol is not None) and not args.host:
        raise InputError("--port and --protocol are for XCP on Ethernet: give --host too (e.g. --host 127.0.0.1)")
    if args.can2_interface and not args.can2_channel:
        raise InputError("--can2-interface needs --can2-channel (without it CAN2 shares CAN1)")
    own_can2 = args.can2_channel or args.can2_bus_kwargs
    if args.host and bus and own_can2:
        raise InputError("with --host the CAN bus options carry only CAN2: --can2-channel/--can2-bus-kwargs have "
                         "nothing to move")
    can2 = None
    if own_can2:
        can2 = can2_bus_spec(args, BusSpec.from_kwargs(bus or {})).kwargs()
    ethernet = EthernetEndpoint(args.host, args.port, args.protocol or "udp") if args.host else None
    defaults = DemoFiles.defaults()
    files = DemoFiles(
        a2l=args.a2l or defaults.a2l, elf=args.elf or defaults.elf,
        s19=args.s19 or defaults.s19, dbc=args.dbc or defaults.dbc,
    )
    demo = build_demo_ecu(files, transport=ethernet.protocol if ethernet is not None else "CAN",
                          valid_key=not args.no_app_key, unlocked=args.unlocked, static_daq=args.static_daq,
                          slave_profile=chosen)
    simulator = serve_demo(bus, ethernet=ethernet, can2=can2, demo=demo,
                           pcm_target_bar=args.pcm_target if args.pcm else None, time_scale=args.time_scale)
    other = serving_elsewhere(endpoint_keys(simulator.describe()))
    if other is not None:
        simulator.close()
        raise InputError(f"another workbench sim (pid {other[1]}) serves on "
                         f"{_bus_text(simulator.describe()['buses']['CAN1'])}: two ECUs on the same ids answer every "
                         "command twice; stop it, or serve on a port of its own (--bus-kwargs port=N)")
    if args.write_a2l:
        _write_a2l(simulator, args.write_a2l)
    stop = threading.Event()
    previous = {}
    if threading.current_thread() is threading.main_thread():  # Ctrl-C and SIGTERM stop serving, also the moment
        for number in (signal.SIGINT, signal.SIGTERM):         # the banner is out
            previous[number] = signal.signal(number, lambda *_: stop.set())
    try:
        with simulator, ExitStack() as stack:
            faults = FlcuFaults(demo, simulator.lock, simulator.pcm)
            injected = [faults.apply(spec) for spec in args.fault]
            control = None
            if not args.no_control:
                control = stack.enter_context(ControlServer(faults, endpoint_keys(simulator.describe())))
            _announce(args, simulator, files, injected, control.address if control else None)
            stop.wait(args.duration)
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
    if not args.json:
        print("workbench sim: stopped", flush=True)
    return 0


def _write_a2l(simulator, path: str) -> None:
    """The served ECU's A2L at ``path`` (atomically); the simulator is closed when that fails."""
    from workbench.fileio import write_output

    doc = simulator.a2l
    try:
        write_output(path, doc.source.file_bytes(doc.data))
    except BaseException:
        simulator.close()
        raise


def _announce(args: argparse.Namespace, simulator, files, faults: list[str], control: tuple | None) -> None:
    info = simulator.describe()
    info["files"] = {key: str(value) for key, value in vars(files).items()}
    info["a2l"] = args.write_a2l or (str(files.a2l) if simulator.a2l.path == files.a2l else None)
    info["pcm"] = {"target_bar": args.pcm_target} if args.pcm else None
    info["faults"] = faults
    info["control"] = {"host": control[0], "port": control[1]} if control else None
    if args.json:
        print_json(info)
        sys.stdout.flush()
        return
    xcp, buses = info["xcp"], info["buses"]
    if xcp["transport"] == "CAN":
        where = [f"  CAN1 (XCP)   {_bus_text(buses['CAN1'])}",
                 f"  XCP ids      master 0x{xcp['can_id_master']:X} -> ECU, ECU -> master 0x{xcp['can_id_slave']:X}"
                 + (f", GET_SLAVE_ID on 0x{xcp['can_id_broadcast']:X}" if "can_id_broadcast" in xcp else "")]
        can2 = _bus_text(buses["CAN2"]) if "CAN2" in buses else "shares CAN1"
    else:
        where = [f"  XCP          on {xcp['transport']} at {xcp['host']}:{xcp['port']} "
                 f"(MAX_CTO {xcp['max_cto']}, MAX_DTO {xcp['max_dto']})"]
        can2 = _bus_text(buses["CAN2"]) if "CAN2" in buses else "not connected (give the CAN bus options)"
    lines = [
        f"workbench sim: FLCU demo ECU, {info['state']}",
        *where,
        f"  CAN2 (FLCU)  {can2}",
        f"  EPK          {info['epk']}",
        f"  bus timing   {info['bitrate']} bit/s" if info["bitrate"] else "  bus timing   not modelled (use --bitrate)",
        f"  time scale   {info['time_scale']}x",
        f"  DAQ          {_daq_text(info['daq'], simulator.ecu.params.events)}",
        f"  PCM          TargetRailPressure {args.pcm_target} bar, EnableFLCU 1" if args.pcm else "  PCM          off (--pcm)",
        f"  profile      {info['profile']}" + ("" if info["profile"] == "demo"
                                                  else f": {_profile_changes(info['profile'])}"),
        f"  A2L          {info['a2l']}" if info["a2l"]
        else "  A2L          the profile's own: write it with --write-a2l PATH",
        "  seed & key   workbench.sim.seedkey:compute_key" + (" (not needed: --unlocked)" if args.unlocked else ""),
        *(f"  fault        {fault}" for fault in faults),
        f"  control      {control[0]}:{control[1]} (fault injection; workbench test finds it by the bus options)"
        if control else "  control      off (--no-control)",
        "serving; Ctrl-C stops",
    ]
    print("\n".join(lines), flush=True)


def _profile_changes(name: str) -> str:
    from workbench.sim.profiles import profile

    return profile(name).changes


def _daq_text(daq: dict, events) -> str:
    """``dynamic (up to 16 lists)`` or ``static, 4 lists (ODTs x entries): 8x3 on Task4ms, ...``."""
    if daq["config"] == "dynamic":
        return f"dynamic (up to {daq['max_daq']} lists)"
    names = {event.number: event.name for event in events}
    lists = [f"{shape['odts']}x{shape['entries']}"
             + (f" on {names.get(shape['fixed_event'], shape['fixed_event'])}" if shape["fixed_event"] is not None else "")
             for shape in daq["lists"]]
    return f"static, {len(lists)} lists (ODTs x entries): {', '.join(lists)}"


def _bus_text(settings: dict) -> str:
    """``interface channel (other settings)``, e.g. ``udp_multicast 239.74.163.2 (port=43200)``."""
    text = " ".join(str(settings[key]) for key in ("interface", "channel") if settings.get(key) is not None) or "bus"
    if "bus" in settings:
        return settings["bus"]
    others = [f"{key}={value}" for key, value in settings.items()
              if key not in ("interface", "channel", "receive_own_messages")]
    return f"{text} ({', '.join(others)})" if others else text
