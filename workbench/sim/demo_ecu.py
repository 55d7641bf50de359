"""The FLCU demo ECU assembled from its files: ELF (layout, symbols), s19 (flash), A2L (XCP), DBC (CAN2).

From the A2L come the CAN ids, the baud rate, MAX_CTO/MAX_DTO of the transport served (XCP on
CAN or on UDP/TCP), the EPK address, the DAQ events and the BUILD_CHECKSUM type; the DAQ limits
are the simulator's own (:class:`DaqParameters`), and the A2L must state the same (a test checks it), except
with ``static_daq``: the slave then offers static DAQ lists where the A2L says DYNAMIC, as a foreign ECU whose
A2L is out of date would (a master goes by what the slave says). The s19 never holds the application-valid
key (``.app_key`` is NOLOAD): the factory programs it after the image, as a flash tool
does, unless ``valid_key=False``.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, replace
from pathlib import Path

from workbench import demo
from workbench.a2l import A2lDocument, XcpConfig, read_xcp_config
from workbench.a2l.includes import load_a2l_to_work
from workbench.can.dbc_file import DbcFile, load_dbc
from workbench.elf import ElfSymbols
from workbench.errors import InputError
from workbench.image import ChecksumType, load_image, split_by_region
from workbench.sim.bsw import Bsw
from workbench.sim.can2 import Can2Driver
from workbench.sim.ecu import SimulatedEcu
from workbench.xcp_framing import HEADER_SIZE
from workbench.sim.faults import FaultPlan
from workbench.sim.flcu import FlcuApplication
from workbench.sim.layout import ApplicationLayout
from workbench.sim.memory_map import HDS9
from workbench.sim.pcm import PcmNode
from workbench.sim.plant import FuelSystemPlant
from workbench.sim.profile_a2l import profile_document
from workbench.sim.profiles import SlaveProfile, profile
from workbench.sim.scheduler import Scheduler
from workbench.sim.xcp.parameters import DEMO_STATIC_LISTS, EventChannel, XcpParameters
from workbench.xcp_protocol import Resource

__all__ = ["DemoEcu", "DemoFiles", "build_demo_ecu", "xcp_parameters"]

ECU_NODE = "FLCU"
MAX_ETHERNET_DTO = 65507 - HEADER_SIZE  # the largest UDP payload (IPv4) less the LEN/CTR header
PLANT_STEP_S = 0.001


@dataclass
class DemoFiles:
    a2l: Path
    elf: Path
    s19: Path
    dbc: Path

    @classmethod
    def defaults(cls) -> DemoFiles:
        """The demo's files; the merged A2L when it exists, else the master A2L (same IF_DATA XCP)."""
        a2l = demo.a2l() if demo.a2l().exists() else demo.master_a2l()
        return cls(a2l, demo.elf(), demo.s19(), demo.dbc_can2())


@dataclass
class DemoEcu:
    """The assembled ECU and the parts a simulator or a test wires to it."""

    ecu: SimulatedEcu
    can2: Can2Driver
    plant: FuelSystemPlant
    a2l: A2lDocument  # what a master needs: the A2L file's, or the profile's own when it changes IF_DATA XCP
    dbc: DbcFile
    files: DemoFiles
    profile: SlaveProfile = profile("demo")

    def pcm_node(self, enable: bool = True, target_bar: float = 25.0) -> PcmNode:
        """A residual-bus PCM for this ECU's CAN2 database."""
        return PcmNode(self.dbc, enable, target_bar)


def xcp_parameters(doc: A2lDocument, config: XcpConfig, transport: str = "CAN") -> XcpParameters:
    """The slave's parameters for ``transport`` ("CAN", "UDP" or "TCP") from an A2L: ids, baud rate, EPK,
    events, checksum, and MAX_CTO/MAX_DTO from that transport's block (its own PROTOCOL_LAYER, if it has
    one, overrules the common one); the DAQ limits stay the simulator's.

    :raises InputError: the A2L lacks the transport's block or an EPK, or asks for packet sizes the
        transport cannot carry (classic CAN: 8 bytes; Ethernet: MAX_CTO 8..255, MAX_DTO 8..MAX_ETHERNET_DTO).
    """
    where = doc.path or "<A2L>"
    transport = transport.upper()
    try:
        effective = config.for_transport(transport)
    except KeyError as exc:
        raise InputError(f"{where}: IF_DATA XCP has no {exc.args[0]} block; the simulated ECU serves XCP on "
                         f"{transport} as the A2L describes it") from None
    sizes = (effective.max_cto, effective.max_dto)
    if transport == "CAN" and sizes != (8, 8):
        raise InputError(f"{where}: MAX_CTO/MAX_DTO must be 8 on classic CAN, the A2L says {sizes[0]}/{sizes[1]}")
    if transport != "CAN" and not (8 <= sizes[0] <= 0xFF and 8 <= sizes[1] <= MAX_ETHERNET_DTO):
        raise InputError(f"{where}: XCP on {transport} needs MAX_CTO 8..255 and MAX_DTO 8..{MAX_ETHERNET_DTO}, "
                         f"the A2L says {sizes[0]}/{sizes[1]}")
    epk, epk_address = doc.epk(), _get_id_epk_address(doc)
    if epk is None or epk_address is None:
        raise InputError(f"{where}: MOD_PAR needs EPK and ADDR_EPK")
    defaults = XcpParameters()
    events = defaults.events
    if effective.daq is not None and effective.daq.events:
        events = tuple(
            EventChannel(e.number, e.name, e.period_s or 0.0, e.priority) for e in effective.daq.events
        )
    checksum = next((s.checksum_type for s in config.segments if s.checksum_type), None)
    checksum_block = next((s.checksum_max_block_size for s in config.segments if s.checksum_max_block_size), None)
    if checksum is not None and checksum.removeprefix("XCP_") not in ChecksumType.__members__:
        raise InputError(f"{where}: the simulated ECU cannot compute the CHECKSUM type {checksum}")
    mode = effective.communication_mode
    ids = {}
    if config.can is not None:  # on Ethernet too: the ids stay the A2L's, unused
        can = config.can
        ids = {
            "can_id_master": can.can_id_master,
            "can_id_slave": can.can_id_slave,
            "can_id_broadcast": can.can_id_broadcast,
            "baudrate": can.baudrate or defaults.baudrate,
            "max_dlc_required": can.max_dlc_required,
        }
    return XcpParameters(
        **ids,
        max_cto=sizes[0],
        max_dto=sizes[1],
        max_bs=mode.max_bs if mode is not None and mode.max_bs else defaults.max_bs,
        checksum_type=ChecksumType[checksum.removeprefix("XCP_")] if checksum else defaults.checksum_type,
        max_checksum_block=checksum_block or defaults.max_checksum_block,
        epk_address=epk_address,
        epk_length=len(epk),
        asam_mc2_name=Path(str(doc.path)).stem if doc.path else defaults.asam_mc2_name,
        events=events,
    )


def _get_id_epk_address(doc: A2lDocument) -> int | None:
    """The ADDR_EPK whose EPK GET_ID 5 reports: the one in the calibration data (a DATA segment) where the A2L names
    one in each part of the software, whatever their order (the application header's may come first); else the first."""
    in_data = [epk.address for epk in doc.epk_addresses() if epk.segment is not None and epk.segment.prg_type == "DATA"]
    return in_data[0] if in_data else doc.addr_epk()


def build_demo_ecu(
    files: DemoFiles | None = None,
    *,
    transport: str = "CAN",
    valid_key: bool = True,
    unlocked: bool = False,
    static_daq: bool = False,
    slave_profile: SlaveProfile | str = "demo",
    scheduler: Scheduler | None = None,
    faults: FaultPlan | None = None,
    rng: random.Random | None = None,
) -> DemoEcu:
    """The FLCU ECU with its plant on one scheduler (the plant steps every millisecond), not powered yet.

    ``transport`` ("CAN", "UDP" or "TCP") picks the A2L block whose packet sizes the slave uses;
    ``slave_profile`` (a :class:`SlaveProfile` or its name, see :mod:`workbench.sim.profiles`) changes how the
    slave implements XCP's options, and :attr:`DemoEcu.a2l` then says so; ``unlocked`` serves CAL/PAG, DAQ and PGM
    without seed & key; ``static_daq`` offers the static DAQ lists
    :data:`~workbench.sim.xcp.parameters.DEMO_STATIC_LISTS` instead of dynamic DAQ (the A2L still says dynamic).

    :raises InputError: a file is missing or malformed, or no profile has that name.
    """
    files = files or DemoFiles.defaults()
    chosen = profile(slave_profile) if isinstance(slave_profile, str) else slave_profile
    doc = load_a2l_to_work(files.a2l)
    config = read_xcp_config(doc)
    params = chosen.parameters(xcp_parameters(doc, config, transport), transport)
    memory_map = chosen.memory_map(HDS9)
    if chosen.changes_a2l:
        described = {name: chosen.parameters(xcp_parameters(doc, config, name), name)
                     for name in ("CAN", "UDP", "TCP") if getattr(config, name.lower()) is not None}
        doc = profile_document(doc, described, memory_map, chosen.name,
                               {name: ms / 1000 for name, ms in chosen.timeouts_ms.items()})
    if unlocked:
        params = replace(params, protected=Resource(0))
    if static_daq:
        params = replace(params, daq=replace(params.daq, static_lists=DEMO_STATIC_LISTS))
    elf = ElfSymbols(files.elf)
    flash = load_image(files.s19)
    _, outside = split_by_region(flash, list(HDS9.flash))
    if outside:
        names = "/".join(region.name for region in HDS9.flash)
        raise InputError(f"{files.s19}: data outside the ECU's flash ({names}): {' '.join(map(str, outside))}")
    if valid_key:
        flash.add(HDS9.app_key_address, HDS9.app_key, overwrite=True)
    scheduler = scheduler or Scheduler()
    dbc = load_dbc(files.dbc)
    can2 = Can2Driver(dbc, ECU_NODE, lambda: scheduler.now_s)
    plant = FuelSystemPlant()
    scheduler.add(PLANT_STEP_S, lambda: plant.step(PLANT_STEP_S), "plant", order=-2)
    ecu = SimulatedEcu(
        flash,
        ApplicationLayout.from_elf(elf, memory_map),
        FlcuApplication,
        hardware=Bsw(plant, can2),
        params=params,
        memory_map=memory_map,
        scheduler=scheduler,
        faults=faults,
        rng=rng,
    )
    return DemoEcu(ecu, can2, plant, doc, dbc, files, chosen)
