"""The demo ECU's A2L files agree with its ELF, its DBC and docs/demo-ecu.md.

The A2L side is read with pya2ldb, the ELF side with pyelftools (``dwarf_lookup``):
neither goes through the workbench's own A2L or ELF code.
"""

from __future__ import annotations

import re
import threading
from collections import Counter

import cantools
import pya2l.model as model
import pytest
from a2l_import import ImportedA2l, import_file
from dwarf_lookup import CType, DwarfLookup
from pya2l.api.validate import Level, Validator

from workbench import demo
from workbench.can import naming
from workbench.sim.can_port import CanXcpPort
from workbench.sim.demo_ecu import build_demo_ecu
from workbench.xcp_protocol import PID_ERR, SLAVE_ID_ECHO, CanCmd, Cmd, Err

MASTER = demo.master_a2l()
FRAGMENTS = demo.fragment_a2ls()
MODULES = ["ActuatorCommands", "CANRX", "CANTX", "FuelLevel", "PRVCtrl", "PressSens", "TankCtrl", "Utils"]

# ASAP2 data type -> (size in bytes, encoding class of the C type)
A2L_TYPES = {
    "UBYTE": (1, "unsigned"),
    "SBYTE": (1, "signed"),
    "UWORD": (2, "unsigned"),
    "SWORD": (2, "signed"),
    "ULONG": (4, "unsigned"),
    "SLONG": (4, "signed"),
    "A_UINT64": (8, "unsigned"),
    "A_INT64": (8, "signed"),
    "FLOAT32_IEEE": (4, "float"),
    "FLOAT64_IEEE": (8, "float"),
}
MANDATORY_COMMANDS = {"CONNECT", "DISCONNECT", "GET_STATUS", "SYNCH"}  # no OPTIONAL_CMD names them
C_RAW_TYPES = {"uint8_T": "UBYTE", "uint16_T": "UWORD", "uint32_T": "ULONG", "int8_T": "SBYTE", "int16_T": "SWORD", "int32_T": "SLONG"}


@pytest.fixture(scope="module")
def a2l() -> dict[str, ImportedA2l]:
    files = {path.stem: import_file(path) for path in [MASTER, *FRAGMENTS]}
    yield files
    for imported in files.values():
        imported.session.close()


@pytest.fixture(scope="module")
def elf() -> DwarfLookup:
    lookup = DwarfLookup(demo.elf())
    yield lookup
    lookup.close()


def _module(imported: ImportedA2l):
    return imported.session.query(model.Module).one()


def _segments(a2l) -> dict[str, tuple[int, int]]:
    return {s.name: (s.address, s.size) for s in _module(a2l["FLCU_master"]).mod_par.memory_segment}


def _xcp(a2l, if_data) -> dict:
    """An IF_DATA XCP block parsed by pya2ldb against the master's A2ML, as one dict."""
    merged: dict = {}
    for part in a2l["FLCU_master"].session.parse_ifdata(if_data)[0]["XCP"]:
        merged.update(part)
    return merged


# ---------------------------------------------------------------- the files parse


def test_fragments_are_the_eight_modules():
    assert [path.stem for path in FRAGMENTS] == MODULES


@pytest.mark.parametrize("name", ["FLCU_master", *MODULES])
def test_pya2ldb_imports_the_file_without_errors(a2l, name):
    imported = a2l[name]
    assert imported.parser_errors == []
    diagnostics = Validator(imported.session)()
    assert [d.text for d in diagnostics if d.type >= Level.ERROR] == []
    # nothing skipped: pya2ldb holds as many objects as the text defines
    text = imported.text_without_comments()
    module = _module(imported)
    for keyword, objects in (
        ("MEASUREMENT", module.measurement),
        ("CHARACTERISTIC", module.characteristic),
        ("AXIS_PTS", module.axis_pts),
        ("COMPU_METHOD", module.compu_method),
        ("COMPU_VTAB", module.compu_vtab),
        ("RECORD_LAYOUT", module.record_layout),
        ("FUNCTION", module.function),
    ):
        assert len(objects) == len(re.findall(rf"/begin\s+{keyword}\b", text)), keyword


def test_files_are_utf8(a2l):
    for path in [MASTER, MASTER.parent / "XCP.aml", *FRAGMENTS]:
        path.read_bytes().decode("utf-8")  # raises on anything else
    units = {m.name: m.unit for m in _module(a2l["FLCU_master"]).compu_method}
    assert units["CM_us"] == "µs"


def test_identically_named_definitions_are_identical(a2l):
    """A merge folds a COMPU_METHOD, COMPU_VTAB or RECORD_LAYOUT defined in several files only if they agree."""
    seen: dict[tuple[str, str], dict[str, str]] = {}
    for name, imported in a2l.items():
        text = imported.text_without_comments()
        for keyword in ("COMPU_METHOD", "COMPU_VTAB", "RECORD_LAYOUT"):
            for match in re.finditer(rf"/begin\s+{keyword}\s+(\S+)(.*?)/end\s+{keyword}", text, re.S):
                tokens = " ".join(match.group(2).split())
                seen.setdefault((keyword, match.group(1)), {})[name] = tokens
    differing = {key: files for key, files in seen.items() if len(set(files.values())) > 1}
    assert differing == {}
    shared_by_master_and_a_fragment = [key for key, files in seen.items() if "FLCU_master" in files and len(files) > 1]
    assert len(shared_by_master_and_a_fragment) >= 10


def test_master_functions_list_exactly_each_fragments_objects(a2l):
    functions = {f.name: f for f in _module(a2l["FLCU_master"]).function}
    assert sorted(functions["FLCU"].sub_function.identifier) == sorted(MODULES)
    for name in MODULES:
        module = _module(a2l[name])
        function = functions[name]
        listed_characteristics = function.def_characteristic.identifier if function.def_characteristic else []
        listed_measurements = [
            *(function.out_measurement.identifier if function.out_measurement else []),
            *(function.loc_measurement.identifier if function.loc_measurement else []),
        ]
        defined_characteristics = [c.name for c in module.characteristic] + [a.name for a in module.axis_pts]
        assert Counter(listed_characteristics) == Counter(defined_characteristics), name
        assert Counter(listed_measurements) == Counter(m.name for m in module.measurement), name


def test_names_with_a_path_carry_a_symbol_link_to_that_path(a2l):
    for name in MODULES:
        module = _module(a2l[name])
        for obj in [*module.measurement, *module.characteristic, *module.axis_pts]:
            is_path = bool(re.search(r"[.\[]", obj.name))
            link = obj.symbol_link
            assert (link is not None) == is_path, obj.name
            if link is not None:
                assert (link.symbolName, link.offset) == (obj.name, 0)


# ---------------------------------------------------------------- against the ELF


def _resolve(elf: DwarfLookup, obj):
    return elf.resolve(obj.symbol_link.symbolName if obj.symbol_link else obj.name)


def _type_problem(ctype: CType, datatype: str, dims: tuple[int, ...]) -> str | None:
    """Why ``ctype`` is not ``datatype`` with array dimensions ``dims`` (None: it is)."""
    if dims:
        if ctype.kind != "array" or ctype.dims != dims:
            return f"is {ctype.name} (size {ctype.size}), the A2L says {datatype}{list(dims)}"
        ctype = ctype.scalar_element()
    size, encoding = A2L_TYPES[datatype]
    if ctype.kind != "scalar" or (ctype.size, ctype.encoding) != (size, encoding):
        return f"is {ctype.name} ({ctype.size} bytes, {ctype.encoding or ctype.kind}), the A2L says {datatype}"
    return None


def _characteristic_problem(characteristic, layouts, ctype: CType) -> str | None:
    layout = layouts[characteristic.deposit]
    fnc = layout.fnc_values.datatype
    axes = [axis.maxAxisPoints for axis in characteristic.axis_descr]
    if characteristic.type == "VALUE":
        return _type_problem(ctype, fnc, ())
    if characteristic.type == "CURVE" and layout.axis_pts_x is not None:
        # the LUT struct: its members in the record layout's order, each an array of the axis length
        parts = sorted([(layout.axis_pts_x.position, layout.axis_pts_x.datatype), (layout.fnc_values.position, fnc)])
        if ctype.kind != "struct" or len(ctype.members) != len(parts):
            return f"is {ctype.name}, the record layout {layout.name} describes a struct of {len(parts)} arrays"
        members = sorted(ctype.members, key=lambda m: m.offset)
        offset = 0
        for member, (_, datatype) in zip(members, parts):
            if member.offset != offset:
                return f"member {member.name} at offset {member.offset}, the record layout puts it at {offset}"
            problem = _type_problem(member.type, datatype, (axes[0],))
            if problem:
                return f"member {member.name} {problem}"
            offset += member.type.size
        return None if offset == ctype.size else f"{ctype.name} has {ctype.size - offset} bytes the record layout does not describe"
    if characteristic.type == "MAP":
        x_points, y_points = axes
        # COLUMN_DIR: x varies fastest, i.e. the C array is [y][x]
        dims = (y_points, x_points) if layout.fnc_values.indexMode == "COLUMN_DIR" else (x_points, y_points)
        return _type_problem(ctype, fnc, dims)
    return _type_problem(ctype, fnc, tuple(axes))


@pytest.mark.parametrize("name", MODULES)
def test_every_fragment_object_is_a_c_object_of_the_a2l_type(a2l, elf, name):
    module = _module(a2l[name])
    layouts = {layout.name: layout for layout in module.record_layout}
    problems = []
    for obj in [*module.measurement, *module.characteristic, *module.axis_pts]:
        try:
            ctype = _resolve(elf, obj).type
        except KeyError as missing:
            problems.append(f"{obj.name}: {missing}")
            continue
        if isinstance(obj, model.Measurement):
            dims = tuple(obj.matrix_dim.numbers) if obj.matrix_dim else ()
            problem = _type_problem(ctype, obj.datatype, dims)
        elif isinstance(obj, model.AxisPts):
            problem = _type_problem(ctype, layouts[obj.depositAttr].axis_pts_x.datatype, (obj.maxAxisPoints,))
        else:
            problem = _characteristic_problem(obj, layouts, ctype)
        if problem:
            problems.append(f"{obj.name}: {problem}")
    assert problems == []


@pytest.mark.parametrize("name", MODULES)
def test_every_calibration_lies_in_cal_ram(a2l, elf, name):
    calram = _segments(a2l)["CALRAM"]
    module = _module(a2l[name])
    for obj in [*module.characteristic, *module.axis_pts]:
        resolved = _resolve(elf, obj)
        section = elf.section_of(resolved.address, resolved.type.size)
        assert section is not None and section.name == ".cal_ram", obj.name
        assert calram[0] <= resolved.address and resolved.address + resolved.type.size <= sum(calram), obj.name


@pytest.mark.parametrize("name", MODULES)
def test_every_measurement_lies_in_ram(a2l, elf, name):
    ram = _segments(a2l)["RAM_DATA"]
    for obj in _module(a2l[name]).measurement:
        resolved = _resolve(elf, obj)
        section = elf.section_of(resolved.address, resolved.type.size)
        assert section is not None and section.writable and section.name != ".cal_ram", obj.name
        assert ram[0] <= resolved.address and resolved.address + resolved.type.size <= sum(ram), obj.name


def test_every_calibration_and_application_variable_is_described(a2l, elf):
    """Nothing the application keeps in CAL RAM or RAM is missing from the fragments.

    Left out on purpose: the BSW stubs' tables (``API_*``, ``CanNetwork_*``), which are not
    application data.
    """
    described = set()
    for name in MODULES:
        module = _module(a2l[name])
        for obj in [*module.measurement, *module.characteristic, *module.axis_pts]:
            described.add(re.split(r"[.\[]", obj.name)[0])
    undescribed = []
    for symbol, (address, size) in elf.symbols.items():
        section = elf.section_of(address, max(size, 1))
        if section is None or section.name not in (".cal_ram", ".data", ".bss"):
            continue
        if symbol not in described and not symbol.startswith(("API_", "CanNetwork_")):
            undescribed.append(f"{symbol} ({section.name})")
    assert undescribed == []


def test_fragments_share_the_masters_byte_order_and_alignments(a2l, elf):
    def layout(name):
        common = _module(a2l[name]).mod_common
        return (common.byte_order.byteOrder, common.alignment_byte.alignmentBorder, common.alignment_word.alignmentBorder,
                common.alignment_long.alignmentBorder, common.alignment_int64.alignmentBorder,
                common.alignment_float32_ieee.alignmentBorder, common.alignment_float64_ieee.alignmentBorder)

    master = layout("FLCU_master")
    assert master[0] == ("MSB_LAST" if elf.little_endian else "MSB_FIRST")
    assert {name: layout(name) for name in MODULES} == dict.fromkeys(MODULES, master)


def test_master_epk_is_the_elfs_epk(a2l, elf):
    mod_par = _module(a2l["FLCU_master"]).mod_par
    address, size = elf.symbols["EPK"]
    assert mod_par.addr_epk[0].address == address == 0xFC0000
    assert elf.section_of(address, size).name == ".epk"
    assert mod_par.epk.identifier == elf.read(address, size).rstrip(b"\0").decode("ascii")


def test_memory_segments_hold_the_elf_sections(a2l, elf):
    segments = _segments(a2l)
    assert segments == {
        "BOOT": (0x800000, 0x40000),
        "APPLICATIVE": (0x840000, 0x780000),
        "CALIB": (0xFC0000, 0x20000),
        "SHARED": (0xFE0000, 0x4000),
        "CALRAM": (0x40000000, 0x20000),
        "RAM_DATA": (0x40020000, 0x60000),
    }

    def inside(segment, address, size):
        start, length = segments[segment]
        return start <= address and address + size <= start + length

    sections = {s.name: s for s in elf.sections}
    cal_ram = sections[".cal_ram"]
    assert inside("CALRAM", cal_ram.address, cal_ram.size)
    assert inside("CALIB", cal_ram.load_address, cal_ram.size)
    # CAL RAM mirrors CAL ROM at the same offset
    assert cal_ram.address - segments["CALRAM"][0] == cal_ram.load_address - segments["CALIB"][0]
    assert inside("CALIB", sections[".epk"].address, sections[".epk"].size)
    for name in (".data", ".bss"):
        if sections.get(name) and sections[name].size:
            assert inside("RAM_DATA", sections[name].address, sections[name].size), name
    assert inside("APPLICATIVE", sections[".text"].address, sections[".text"].size)


# ---------------------------------------------------------------- XCP parameters


def _commands_the_simulator_answers() -> set[str]:
    """Every XCP command the simulated demo ECU answers otherwise than ERR_CMD_UNKNOWN, each sent to it after a
    CONNECT of its own (with a payload of zeros: a refusal of the payload still says the command is there)."""
    ecu = build_demo_ecu().ecu
    ecu.power_on()
    answered = set()
    for command in Cmd:
        ecu.handle_cto(bytes((Cmd.CONNECT, 0)))
        if ecu.handle_cto(bytes((command,)).ljust(8, b"\0"))[-1:] != [bytes((PID_ERR, Err.CMD_UNKNOWN))]:
            answered.add(command.name)
    return answered


def _sub_commands_the_can_port_answers() -> set[str]:
    """The TRANSPORT_LAYER_CMD sub-commands (XCP on CAN's own) the simulated demo ECU's CAN port answers otherwise
    than ERR_CMD_UNKNOWN, each after a CONNECT of its own (GET_SLAVE_ID with its 'XCP' echo pattern)."""
    ecu = build_demo_ecu().ecu
    ecu.power_on()
    port = CanXcpPort(ecu, threading.Lock(), buses=None)  # the answers only: nothing is sent
    answered = set()
    for sub in CanCmd:
        ecu.handle_cto(bytes((Cmd.CONNECT, 0)))
        payload = SLAVE_ID_ECHO if sub is CanCmd.GET_SLAVE_ID else b""
        answer = port._command_answer(bytes((Cmd.TRANSPORT_LAYER_CMD, sub)) + payload.ljust(6, b"\0"))
        if answer and answer[-1][:2] != bytes((PID_ERR, Err.CMD_UNKNOWN)):
            answered.add(sub.name)
    return answered


def test_master_xcp_states_the_documented_parameters(a2l):
    xcp = _xcp(a2l, _module(a2l["FLCU_master"]).if_data)
    protocol = xcp["PROTOCOL_LAYER"]
    assert protocol[8:12] == [8, 8, "BYTE_ORDER_MSB_LAST", "ADDRESS_GRANULARITY_BYTE"]  # MAX_CTO, MAX_DTO
    assert protocol[12]["SEED_AND_KEY_EXTERNAL_FUNCTION"] == "workbench.sim.seedkey:compute_key"
    # TRANSPORT_LAYER_CMD is the CAN port's (the protocol layer answers a bare 0xF2 with ERR_CMD_UNKNOWN), so the
    # common list (CAN's) names it and the Ethernet transports' lists do not; XCP_ON_CAN names its sub-commands
    sub_commands = _sub_commands_the_can_port_answers()
    assert sub_commands >= {"GET_SLAVE_ID", "GET_DAQ_ID"}
    assert sorted(protocol[12]["OPTIONAL_CMD"]) == sorted(_commands_the_simulator_answers() - MANDATORY_COMMANDS
                                                          | {"TRANSPORT_LAYER_CMD"})

    can = xcp["XCP_ON_CAN"][0][1]
    assert (can["CAN_ID_MASTER"], can["CAN_ID_SLAVE"], can["BAUDRATE"]) == (0x7F0, 0x7F1, 1_000_000)
    assert sorted(can["OPTIONAL_TL_SUBCMD"]) == sorted(sub_commands)

    for transport in ("XCP_ON_UDP_IP", "XCP_ON_TCP_IP"):  # XCP on Ethernet: larger packets, all else as on CAN
        (version, port, address), overrides = xcp[transport]
        assert (version, port, address) == (0x0100, 5555, {"ADDRESS": "127.0.0.1"})
        ethernet_protocol = overrides["PROTOCOL_LAYER"]
        assert ethernet_protocol[8:10] == [255, 1024]  # MAX_CTO, MAX_DTO
        assert ethernet_protocol[:8] + ethernet_protocol[10:12] == protocol[:8] + protocol[10:12]
        assert {**ethernet_protocol[12], "OPTIONAL_CMD": None} == {**protocol[12], "OPTIONAL_CMD": None}
        assert ethernet_protocol[12]["OPTIONAL_CMD"] == [command for command in protocol[12]["OPTIONAL_CMD"]
                                                         if command != "TRANSPORT_LAYER_CMD"]
        assert overrides["PGM"][2] == 255 and overrides["PGM"][:2] + overrides["PGM"][3:] == xcp["PGM"][:2] + xcp["PGM"][3:]
        assert set(overrides) == {"PROTOCOL_LAYER", "PGM"}

    daq = xcp["DAQ"]
    assert daq[0] == "DYNAMIC"
    assert daq[6:10] == ["IDENTIFICATION_FIELD_TYPE_ABSOLUTE", "GRANULARITY_ODT_ENTRY_SIZE_DAQ_BYTE", 4, "NO_OVERLOAD_INDICATION"]
    assert daq[10]["TIMESTAMP_SUPPORTED"] == [1, "SIZE_DWORD", "UNIT_10US"]
    events = [(name, number, cycle, unit) for name, _, number, _, _, cycle, unit, _ in daq[10]["EVENT"]]
    assert events == [("Task4ms", 0, 4, 6), ("Task50ms", 1, 50, 6), ("Task100ms", 2, 100, 6)]  # unit 6: 1 ms
    assert daq[2] == len(events)  # MAX_EVENT_CHANNEL


def test_master_xcp_pages_and_sectors_match_the_memory_map(a2l):
    segments = _segments(a2l)
    calram = next(s for s in _module(a2l["FLCU_master"]).mod_par.memory_segment if s.name == "CALRAM")
    number, pages, *_, options = _xcp(a2l, calram.if_data)["SEGMENT"]
    assert (number, pages) == (0, 2)
    assert [page[0] for page in options["PAGE"]] == [0, 1]
    assert options["PAGE"][1][3] == "XCP_WRITE_ACCESS_NOT_ALLOWED"  # the reference page is flash
    assert options["ADDRESS_MAPPING"] == [[*segments["CALRAM"][:1], segments["CALIB"][0], segments["CALRAM"][1]]]

    pgm = _xcp(a2l, _module(a2l["FLCU_master"]).if_data)["PGM"]
    sectors = {name: (address, length) for name, _, address, length, *_ in pgm[3]["SECTOR"]}
    assert sectors == {name: segments[name] for name in ("APPLICATIVE", "CALIB", "SHARED")}


# ---------------------------------------------------------------- against the DBC


def _can2():
    return cantools.database.load_file(str(demo.dbc_can2()), strict=True)


def test_can_fix_calibrations_follow_the_dbc(a2l):
    objects = {}
    conversions = {}
    for name in ("CANRX", "CANTX"):
        module = _module(a2l[name])
        objects.update({c.name: (name, c) for c in module.characteristic})
        objects.update({m.name: (name, m) for m in module.measurement})
        conversions.update({c.name: (c, module) for c in module.compu_method})
    for message in _can2().messages:
        home = "CANTX" if "FLCU" in message.senders else "CANRX"
        if home == "CANTX":
            assert objects[naming.tx_enable_name(message.name)][0] == "CANTX"
        else:
            for status in (naming.rx_status_name(message.name), naming.rx_bit_status_name(message.name)):
                assert objects[status][0] == "CANRX"
        for signal in message.signals:
            if home == "CANRX":
                assert objects[naming.rx_signal_name(message.name, signal.name)][0] == "CANRX"
            enable_home, enable = objects[naming.fix_enable_name(signal.name)]
            value_home, value = objects[naming.fix_value_name(signal.name)]
            assert enable_home == value_home == home, signal.name
            assert (enable.conversion, enable.lowerLimit, enable.upperLimit) == ("CM_OnOff", 0, 1)
            layouts = {layout.name: layout for layout in _module(a2l[home]).record_layout}
            assert layouts[value.deposit].fnc_values.datatype == C_RAW_TYPES[naming.raw_c_type(signal.length, signal.is_signed)]
            assert (value.lowerLimit, value.upperLimit) == (signal.minimum, signal.maximum), signal.name
            assert f": {signal.comment} (" in value.longIdentifier, signal.name  # the DBC comment describes it
            conversion, module = conversions[value.conversion]
            if signal.choices:
                table = next(t for t in module.compu_vtab if t.name == conversion.compu_tab_ref.conversionTable)
                assert {int(p.inVal): p.outVal for p in table.pairs} == {k: str(v) for k, v in signal.choices.items()}
            else:
                assert conversion.conversionType == "LINEAR"
                assert (conversion.coeffs_linear.a, conversion.coeffs_linear.b) == (signal.scale, signal.offset)
                assert conversion.unit == (signal.unit or "")


def test_enumerations_match_the_c_enums(a2l):
    """Each enum's COMPU_VTAB states the values that the C sources #define for it."""
    defines = re.findall(r"#define\s+(\w+)\s+\(\((\w+)\)(\d+)U\)", demo.path("assets", "ecu", "flcu_types.h").read_text())
    c_enums: dict[str, dict[int, str]] = {}
    for name, ctype, value in defines:
        c_enums.setdefault(ctype, {})[int(value)] = name
    tables = {t.name: {int(p.inVal): p.outVal for p in t.pairs} for t in _module(a2l["FLCU_master"]).compu_vtab}
    for enum in ("tTankCtrlState", "tCANRxStatus", "Std_eDiagStatusT"):
        assert tables[f"VTAB_{enum}"] == c_enums[enum], enum
