"""``workbench sim``: serve the simulated FLCU ECU on a CAN bus until Ctrl-C."""

from __future__ import annotations

import argparse
import signal
import sys
import threading

from workbench.cli.options import add_bus_arguments, add_output_arguments, bus_config, positive_float, print_json
from workbench.errors import InputError

SOFTWARE_BUSES = ("virtual", "udp_multicast")

EPILOG = """\
CAN1 carries XCP (ids, baud rate and EPK from the A2L); the FLCU's CAN2 messages share that
bus unless --can2-channel puts them on another one. With --bitrate on a software bus
(virtual, udp_multicast) the simulator paces its frames as a real CAN bus of that bit rate
would; on hardware the bit rate goes to the interface. --pcm adds a residual-bus PCM that
sends EnableFLCU and TargetRailPressure every 100 ms, so the rail pressure rises on its own.
Resources CAL/PAG, DAQ and PGM are locked until UNLOCK with the seed & key plugin
workbench.sim.seedkey:compute_key (--unlocked serves them open).

examples:
  workbench sim --pcm
  workbench sim --interface virtual --channel demo --time-scale 10
  workbench sim --interface socketcan --channel vcan0 --can2-channel vcan1
"""


def add_subparser(subparsers, name: str, help_text: str) -> None:
    parser = subparsers.add_parser(
        name, help=help_text, description="Serve the simulated FLCU ECU (XCP on CAN slave) until Ctrl-C.",
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    files = parser.add_argument_group("demo ECU files (default: the built-in demo)")
    files.add_argument("--a2l", help="A2L with IF_DATA XCP and MOD_PAR EPK/ADDR_EPK")
    files.add_argument("--elf", help="application ELF (sections, symbols)")
    files.add_argument("--s19", help="flash image (S-records or Intel HEX)")
    files.add_argument("--dbc", help="CAN2 database of the FLCU messages")
    add_bus_arguments(parser)
    can2 = parser.add_argument_group("CAN2 (FLCU messages)")
    can2.add_argument("--can2-interface", help="python-can interface of CAN2 (default: --interface)")
    can2.add_argument("--can2-channel", help="put CAN2 on its own bus with this channel (default: share CAN1)")
    sim = parser.add_argument_group("simulation")
    sim.add_argument("--pcm", action="store_true", help="simulate the PCM: EnableFLCU=1 and the target rail pressure every 100 ms")
    sim.add_argument("--pcm-target", type=float, default=25.0, metavar="BAR", help="the PCM's TargetRailPressure in bar (default 25)")
    sim.add_argument("--time-scale", type=positive_float, default=1.0, metavar="X",
                     help="simulated seconds per real second (default 1: real time)")
    sim.add_argument("--no-app-key", action="store_true",
                     help="start with the application-valid key erased: the ECU stays in boot (programming only)")
    sim.add_argument("--unlocked", action="store_true", help="no seed & key: CAL/PAG, DAQ and PGM open at CONNECT")
    sim.add_argument("--duration", type=positive_float, metavar="S", help="stop by itself after S real seconds")
    add_output_arguments(parser)
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from workbench.sim.demo_ecu import DemoFiles, build_demo_ecu
    from workbench.sim.server import Simulator

    if args.host or args.port:
        raise InputError("the simulated ECU speaks XCP on CAN only (no --host/--port)")
    if args.can2_interface and not args.can2_channel:
        raise InputError("--can2-interface needs --can2-channel (without it CAN2 shares CAN1)")
    defaults = DemoFiles.defaults()
    files = DemoFiles(
        a2l=args.a2l or defaults.a2l, elf=args.elf or defaults.elf,
        s19=args.s19 or defaults.s19, dbc=args.dbc or defaults.dbc,
    )
    demo = build_demo_ecu(files, valid_key=not args.no_app_key, unlocked=args.unlocked)
    software = args.interface in SOFTWARE_BUSES
    can1 = bus_config(args)
    timing_bitrate = None
    if software:
        timing_bitrate = can1.pop("bitrate", None)
    elif "bitrate" not in can1:
        can1["bitrate"] = demo.ecu.params.baudrate
    can2 = None
    if args.can2_channel:
        can2 = dict(can1, interface=args.can2_interface or args.interface, channel=args.can2_channel)
    pcm = demo.pcm_node(target_bar=args.pcm_target) if args.pcm else None
    if pcm is not None:
        try:
            pcm.frames()
        except ValueError as exc:
            raise InputError(f"--pcm-target: {exc}") from None
    simulator = Simulator(
        demo.ecu, can1, can2, can2_driver=demo.can2, pcm=pcm, bitrate=timing_bitrate, time_scale=args.time_scale,
    )
    stop = threading.Event()
    previous = signal.signal(signal.SIGTERM, lambda *_: stop.set()) if threading.current_thread() is threading.main_thread() else None
    try:
        with simulator:
            _announce(args, simulator, files)
            try:
                stop.wait(args.duration)
            except KeyboardInterrupt:
                pass
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    if not args.json:
        print("workbench sim: stopped", flush=True)
    return 0


def _announce(args: argparse.Namespace, simulator, files) -> None:
    info = simulator.describe()
    info["files"] = {key: str(value) for key, value in vars(files).items()}
    info["pcm"] = {"target_bar": args.pcm_target} if args.pcm else None
    if args.json:
        print_json(info)
        sys.stdout.flush()
        return
    can1 = info["buses"]["CAN1"]
    lines = [
        f"workbench sim: FLCU demo ECU, {info['state']}",
        f"  CAN1 (XCP)   {can1.get('interface')} {can1.get('channel', '')}".rstrip(),
        f"  XCP ids      master 0x{info['can_id_master']:X} -> ECU, ECU -> master 0x{info['can_id_slave']:X}",
        f"  CAN2 (FLCU)  " + (f"{info['buses']['CAN2'].get('interface')} {info['buses']['CAN2'].get('channel')}"
                              if "CAN2" in info["buses"] else "shares CAN1"),
        f"  EPK          {info['epk']}",
        f"  bus timing   {info['bitrate']} bit/s" if info["bitrate"] else "  bus timing   not modelled (use --bitrate)",
        f"  time scale   {info['time_scale']}x",
        f"  PCM          TargetRailPressure {args.pcm_target} bar, EnableFLCU 1" if args.pcm else "  PCM          off (--pcm)",
        "  seed & key   workbench.sim.seedkey:compute_key" + (" (not needed: --unlocked)" if args.unlocked else ""),
        "serving; Ctrl-C stops",
    ]
    print("\n".join(lines), flush=True)
