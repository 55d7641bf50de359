"""The committed demo ECU image (assets/FLCU.elf, assets/FLCU.s19) as docs/demo-ecu.md describes it.

No compiler needed: the C sources say which variables are calibrations (``CAL_RAM``) and
which are measurements (exported globals of a model), the ELF says where they are, the s19
what the flash holds.
"""

from __future__ import annotations

import re
import struct

import bincopy
import cantools
import pytest
from elftools.elf.elffile import ELFFile

from workbench import demo
from workbench.can import naming
from workbench.elf import ElfSymbols

ECU = demo.path("assets", "ecu")
MODELS = ["PressSens", "Utils", "FuelLevel", "TankCtrl", "PRVCtrl", "ActuatorCommands", "CANRX", "CANTX"]
BOOT, APPLICATIVE, CALIB, SHARED = (0x800000, 0x840000), (0x840000, 0xFC0000), (0xFC0000, 0xFE0000), (0xFE0000, 0xFE4000)
CAL_RAM, RAM = (0x40000000, 0x40020000), (0x40020000, 0x40080000)
EPK = b"10300020250301"
LOADED_SECTIONS = (".app_header", ".text", ".rodata", ".data", ".epk", ".cal_ram", ".cal_trailer")
_DEFINITION = re.compile(r"^(CAL_RAM )?(\w+) (\w+)(\[[^=;]*\])?(?: = [^;]*)?;", re.M)


def _definitions(kind: str) -> set[str]:
    """Names the model sources define at file scope: "calibration" (CAL_RAM) or "measurement"."""
    names = set()
    for model in MODELS:
        for cal_ram, ctype, name, _dims in _DEFINITION.findall((ECU / f"{model}.c").read_text()):
            if ctype in ("static", "const", "extern", "return"):
                continue
            if bool(cal_ram) == (kind == "calibration"):
                names.add(name)
    return names


@pytest.fixture(scope="module")
def elf() -> ElfSymbols:
    return ElfSymbols(demo.elf())


@pytest.fixture(scope="module")
def s19() -> bincopy.BinFile:
    return bincopy.BinFile(str(demo.s19()))


def _inside(window: tuple[int, int], address: int, size: int) -> bool:
    return window[0] <= address and address + size <= window[1]


def _rom_address(ram_address: int) -> int:
    return ram_address - CAL_RAM[0] + CALIB[0]


def test_the_sources_define_calibrations_and_measurements():
    calibrations, measurements = _definitions("calibration"), _definitions("measurement")
    assert {"zsEWMA_ALPHA", "zvRailPConv", "xvPRV_DC_FF", "csFLCU_TO_PCM_003_En", "cfTARGETRAILPRESSURE_VALUE"} <= calibrations
    assert {"zsSensVolt", "xsDC", "CANRX_PCM_TO_FLCU_001_Pdu", "PRVCtrl_DW", "xsTankCtrlState"} <= measurements
    assert not calibrations & measurements


def test_every_calibration_lies_in_cal_ram_and_nothing_else_does(elf):
    calibrations = _definitions("calibration")
    for name in calibrations:
        symbol = elf.symbol(name)
        assert symbol.section == ".cal_ram" and _inside(CAL_RAM, symbol.address, symbol.size), name
    in_cal_ram = {s.name for s in elf.symbols.values() if s.section == ".cal_ram" and s.kind == "object"}
    assert in_cal_ram == calibrations


def test_every_measurement_lies_in_ram(elf):
    for name in _definitions("measurement"):
        symbol = elf.symbol(name)
        assert symbol.section in (".bss", ".data") and _inside(RAM, symbol.address, symbol.size), name


def test_calibration_names_follow_the_naming_rules():
    pattern = re.compile(r"^(?:(?:zs|zf|xs|xa|xv|cf)[A-Z0-9_]+|zv[A-Z][A-Za-z0-9]*|cs\w+_En)$")
    assert [n for n in _definitions("calibration") if not pattern.match(n)] == []


def test_every_name_the_contract_mentions_is_in_the_elf(elf):
    text = demo.path("docs", "demo-ecu.md").read_text()
    names = set()
    for name, both in re.findall(r"`((?:zs|zf|zv|xs|xa|xv|cf|cs|CANRX_|CANTX_)\w*[A-Za-z0-9])(/_VALUE)?`", text):
        if "_00n_" not in name:  # CANTX_FLCU_TO_PCM_00n_Pdu stands for three
            names |= {name, name.replace("_EN", "_VALUE")} if both else {name}
    assert len(names) > 70
    assert sorted(n for n in names if n not in elf.symbols) == []


def test_every_can_signal_has_its_fix_calibrations_and_every_tx_message_its_enable(elf, s19):
    database = cantools.database.load_file(str(demo.dbc_can2()))
    for message in database.messages:
        for signal in message.signals:
            enable, value = elf.symbol(naming.fix_enable_name(signal.name)), elf.symbol(naming.fix_value_name(signal.name))
            width = int(re.search(r"\d+", naming.raw_c_type(signal.length, signal.is_signed)).group()) // 8
            assert (enable.size, value.size) == (1, width), signal.name
            assert enable.section == value.section == ".cal_ram"
            assert s19[_rom_address(enable.address)] == 0  # no fix at power-on
        if "FLCU" in message.senders:
            enable = elf.symbol(naming.tx_enable_name(message.name))
            assert enable.section == ".cal_ram" and s19[_rom_address(enable.address)] == 1
        else:
            published = (naming.rx_status_name(message.name), naming.rx_bit_status_name(message.name),
                         *(naming.rx_signal_name(message.name, s.name) for s in message.signals))
            for name in published:
                assert elf.symbol(name).section == ".bss", name


def test_cal_ram_load_image_is_in_the_s19(elf, s19):
    cal_ram = elf.sections[".cal_ram"]
    assert (cal_ram.address, cal_ram.load_address) == (0x40000010, 0xFC0010)
    with open(demo.elf(), "rb") as handle:
        section_bytes = ELFFile(handle).get_section_by_name(".cal_ram").data()
    assert s19[cal_ram.load_address : cal_ram.load_address + cal_ram.size] == section_bytes


@pytest.mark.parametrize(
    "name,fmt,value",
    [
        ("zsEWMA_ALPHA", "<f", 0.2), ("zsSENS_VOLT_MIN", "<f", 0.5), ("zsSENS_VOLT_MAX", "<f", 4.5),
        ("xsDIAG_VOLT_MIN", "<f", 0.5), ("xsDIAG_VOLT_MAX", "<f", 4.5), ("xsMANIFOLD_TOL", "<f", 30.0),
        ("xsEMPTY_TANK_THR", "<f", 5.0), ("xsFULL_TANK_PRESS", "<f", 700.0), ("xsSWITCH_TANK_THR", "<f", 20.0),
        ("xsPRV_KP", "<f", 5.0), ("xsPRV_KI", "<f", 2.0), ("xsPRV_KD", "<f", 0.02), ("xsPRV_I_BAND", "<f", 5.0),
        ("xsPRV_DC_MIN", "<f", 0.0), ("xsPRV_DC_MAX", "<f", 100.0), ("xsPRV_PWM_PERIOD", "<H", 1000),
        ("zfRAILPRESSURE_EN", "<B", 0), ("zfRAILPRESSURE_VALUE", "<f", 0.0),
    ],
)
def test_documented_initial_values_are_in_cal_rom(elf, s19, name, fmt, value):
    address = _rom_address(elf.symbol(name).address)
    (stored,) = struct.unpack(fmt, s19[address : address + struct.calcsize(fmt)])
    assert stored == pytest.approx(value, rel=1e-7)


def test_s19_holds_exactly_the_loadable_sections_at_their_load_addresses(elf, s19):
    expected = []
    for name in LOADED_SECTIONS:
        section = elf.sections[name]
        if section.size:
            expected.append((section.load_address, section.load_address + section.size))
    merged: list[list[int]] = []
    for start, end in sorted(expected):
        if merged and merged[-1][1] == start:
            merged[-1][1] = end
        else:
            merged.append([start, end])
    assert [[s.minimum_address, s.maximum_address] for s in s19.segments] == merged
    for segment in s19.segments:
        start, end = segment.minimum_address, segment.maximum_address
        assert _inside(APPLICATIVE, start, end - start) or _inside(CALIB, start, end - start)


def test_calib_partial_ranges_are_epk_calibrations_and_trailer(elf, s19):
    cal_ram = elf.sections[".cal_ram"]
    calib = [(s.minimum_address, s.maximum_address) for s in s19.segments if _inside(CALIB, s.minimum_address, 1)]
    assert calib == [(0xFC0000, cal_ram.load_address + cal_ram.size), (0xFDFFF0, 0xFE0000)]
    for window in (BOOT, SHARED, CAL_RAM, RAM):
        assert not any(s.minimum_address < window[1] and window[0] < s.maximum_address for s in s19.segments)


def test_epk_header_trailer_and_key(elf, s19):
    assert s19[0xFC0000:0xFC0010] == EPK + bytes(2)
    header = s19[0x840000:0x84003C]
    magic, version = struct.unpack_from("<II", header)
    assert (magic, version) == (0x39534448, 1) and header[8:24] == EPK + bytes(2)
    assert header[24:28] == b"FLCU" and struct.unpack_from("<I", header, 56)[0] == elf.symbol("API_OS_Init").address
    trailer = struct.unpack("<4I", s19[0xFDFFF0:0xFE0000])
    cal_ram = elf.sections[".cal_ram"]
    assert trailer == (0x544C4143, 0xFC0000, cal_ram.load_address + cal_ram.size, 0xC33C5AA5)
    key = elf.symbol("AppValidKey")
    assert (key.address, key.size, elf.sections[".app_key"].loaded) == (0xFE0000, 4, False)
    assert "0x5AA5C33C" in (ECU / "boot_key.h").read_text()


def test_can_init_callback_configures_every_message_of_the_dbc():
    """api.c's generated block (figure 55): TX then RX, DBC order, mailboxes numbered per role."""
    database = cantools.database.load_file(str(demo.dbc_can2()))
    tx = [m for m in database.messages if "FLCU" in m.senders]
    rx = [m for m in database.messages if "FLCU" not in m.senders]
    expected = [""]
    for index, message in enumerate(tx):
        mailbox = f"CAN2_MSG_TX_{index:03d}"
        expected += [
            f"//callbacks automatically generated for {message.name}",
            f"API_CAN_setPduInitValues({mailbox}, DataInitPduIntel);",
            f"CanNetwork_SetTxPeriod({mailbox}, {message.cycle_time});",
            f"CanNetwork_SetTxDlc({mailbox}, {message.length});",
            f"CanNetwork_EnableDisableSendMessages({mailbox}, TRUE);",
            "",
        ]
    for index, message in enumerate(rx):
        mailbox = f"CAN2_MSG_RX_{index:03d}"
        expected += [
            f"//callbacks automatically generated for {message.name}",
            f"CanNetwork_SetRxPeriod({mailbox}, {message.cycle_time});",
            f"CanNetwork_SetRxTimeout({mailbox}, 300);",
            f"CanNetwork_SetRxDlc({mailbox}, {message.length});",
            f"CanNetwork_EnableDisableReceivedMessages({mailbox}, TRUE);",
            "",
        ]
    source = (ECU / "api.c").read_text()
    block = source.split("// <initCbk>\n", 1)[1].split("  // </initCbk>", 1)[0]
    assert [line.strip() for line in block.splitlines()] == expected
