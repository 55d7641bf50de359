"""The ELF matrix: every address `workbench a2l update` writes is where gdb finds the object.

tests/elf/matrix/build.sh builds C and C++ sources (anonymous unions and structs, bitfields,
function-local and file statics, namespaces, static members, inheritance, a class only
declared in a unit) with gcc and clang, DWARF 4 and 5, 32 and 64 bits, -O0 and -O2, plus
C++ with type units: 36 small ELFs, committed. wild_c.a2l and wild_cpp.a2l name their
objects the ways A2L generators do. Each ELF goes through the CLI as a user runs it
(`a2l update --types`, then `a2l check --elf`, in a temporary folder), and every address
and BIT_MASK is compared with what gdb reads from the same ELF (gdb_oracle.py, run in gdb
once for the whole matrix), the .symtab fallback too on stripped copies.

tests/elf/matrix/cross holds the same sources cross-compiled for ECU targets (build_cross.sh:
big-endian 32-bit PowerPC (gcc, clang) and m68k, bare-metal Cortex-M, DWARF 2 to 5, linked
into flash and RAM like an ECU) with ecu.c's bitfields, doubles, 64-bit integers, enum,
pointer and EPK: addresses, sizes, BIT_MASKs (in the target's byte order) and data types
against gdb-multiarch, as recorded in cross/gdb.json (CI has no gdb-multiarch; a test
compares the record with it).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from elftools.elf.elffile import ELFFile

from workbench.a2l import load_a2l
from workbench.cli import main
from workbench.elf.debugdata import DebugData
from workbench.elf.symbols import ElfSymbols

HERE = Path(__file__).parent
MATRIX = HERE / "matrix"
ELFS = sorted(path.name for path in MATRIX.glob("*.elf"))
COMBINATIONS = [f"{language}-{compiler}-dwarf{dwarf}-m{bits}-{opt}.elf" for language in ("c", "cpp")
                for compiler in ("gcc", "clang") for dwarf in (4, 5) for bits in (32, 64) for opt in ("O0", "O2")]
TYPE_UNITS = [f"cpp-{compiler}-dwarf{dwarf}-types.elf" for compiler in ("gcc", "clang") for dwarf in (4, 5)]
CROSS = MATRIX / "cross"
CROSS_ELFS = sorted(path.name for path in CROSS.glob("*.elf"))
CROSS_RECORD = CROSS / "gdb.json"
# target in the name -> (ELF machine, little-endian)
CROSS_TARGETS = {"ppc": ("EM_PPC", False), "arm": ("EM_ARM", True), "m68k": ("EM_68K", False)}

# A2L object -> the same object as a gdb expression
C_OBJECTS = {
    "ctrlReg.Value": "ctrlReg.Value", "ctrlReg.Mode": "ctrlReg.Mode", "ctrlReg.Prescaler": "ctrlReg.Prescaler",
    "variant.asFloat": "variant.asFloat", "variant.high": "variant.high", "variant.count": "variant.count",
    "variant.tail._2_": "variant.tail[2]", "sharedCounter": "sharedCounter", "bigCounter": "bigCounter",
    "signedMatrix": "signedMatrix", "signedMatrix[1][2][3]": "signedMatrix[1][2][3]",
    "tickCount": "wild_tick::tickCount", "wild_tick.history": "wild_tick::history",
    "wild_filter.state": "wild_filter::state", "LimitState": "wild_limit::state",
    "wild_c.fileLocal": "'wild.c'::fileLocal", "OtherFileLocal": "'wild_other.c'::fileLocal",
    "wild_other_step.ambiguous": "wild_other_step::ambiguous", "otherOnly": "wild_other_step::otherOnly",
    "gain": "gain", "curveValues": "curveValues", "engineMap.values": "engineMap.values",
    "valueBlock": "valueBlock", "curveAxis": "curveAxis", "engineMap.xAxis": "engineMap.xAxis",
    "engineMap.yAxis": "engineMap.yAxis", "sharedAxis": "sharedAxis",
}
CPP_OBJECTS = {
    "plainGlobal": "plainGlobal", "app.mostDerived.baseId": "app::mostDerived.baseId",
    "app.mostDerived.mixinValue": "app::mostDerived.mixinValue",
    "app.mostDerived.derivedOnly": "app::mostDerived.derivedOnly",
    "app.mostDerived.leaf._1_": "app::mostDerived.leaf[1]", "app.mostDerived.raw": "app::mostDerived.raw",
    "app.mostDerived.lowBits": "app::mostDerived.lowBits", "app.mostDerived.highBits": "app::mostDerived.highBits",
    "DerivedFlags": "app::derived.flags", "app.Controller.instances": "app::Controller::instances",
    "controller.setpoint": "app::controller.setpoint", "app.detail.nestedValue": "app::detail::nestedValue",
    "Counters12": "app::detail::counters[1][2]", "otherValue": "app::detail::otherValue",
    "calls": "'app::Controller::step'::calls", "StepCalls": "'app::Controller::step'::calls",
    "freeFunction.freeCalls": "freeFunction::freeCalls",
    "hiddenInAnonymous": "'(anonymous namespace)::hiddenInAnonymous'",
    "sensor.raw": "app::sensor.raw", "sensor.scale": "app::sensor.scale",
    "app.Controller.limits": "app::Controller::limits", "Limit2": "app::Controller::limits[2]",
}
# ecu.c's objects (ecu_c.a2l, cross-compiled ELFs only): their names are gdb's
ECU_OBJECTS = {name: name for name in (
    "status.ready", "status.level", "status.phase", "status.sector", "status.offset", "status.window", "frame.id",
    "frame.kind", "frame.value", "frame.crc", "torque", "energy", "odometer", "gear", "bufferPointer", "calibDouble",
    "calibTable")}
ECU_EPK = ("ECU-MATRIX 1.0", "epkText")
ECU_GEARS = ["-1", "GEAR_FAULT", "0", "GEAR_PARK", "1", "GEAR_REVERSE", "2", "GEAR_NEUTRAL", "3", "GEAR_DRIVE",
             "4660", "GEAR_SERVICE"]  # ecu.c's enum tGear, GEAR_SERVICE = 0x1234
# what the stripped ELFs of cross/stripped still name: ecu.c's and wild.c's globals
SYMTAB_CROSS = ["sharedCounter", "bigCounter", "signedMatrix", "tickCount", "otherOnly", "gain", "curveValues",
                "valueBlock", "curveAxis", "sharedAxis", "torque", "energy", "odometer", "gear", "bufferPointer",
                "calibDouble", "calibTable"]
# gdb's element of an object (gdb_oracle.py) -> its ASAP2 data type
A2L_DATATYPES = {"float4": "FLOAT32_IEEE", "float8": "FLOAT64_IEEE", "pointer4": "ULONG",
                 **{f"{kind}{size}": name for size, names in ((1, "SBYTE UBYTE"), (2, "SWORD UWORD"),
                                                            (4, "SLONG ULONG"), (8, "A_INT64 A_UINT64"))
                    for kind, name in zip(("signed", "unsigned"), names.split())}}
# what a stripped ELF's .symtab still names (no members without DWARF types), per compiler
SYMTAB_C = {"gcc": ["sharedCounter", "bigCounter", "signedMatrix", "tickCount", "otherOnly", "gain", "curveValues",
                    "valueBlock", "curveAxis", "sharedAxis"]}
SYMTAB_C["clang"] = SYMTAB_C["gcc"] + ["wild_tick.history", "wild_filter.state"]  # clang names them function.variable
SYMTAB_CPP = ["plainGlobal", "app.Controller.instances", "app.detail.nestedValue", "otherValue", "calls", "StepCalls",
              "freeFunction.freeCalls", "hiddenInAnonymous", "app.Controller.limits"]


def objects_of(elf_name: str) -> tuple[Path, dict[str, str], str]:
    if elf_name.startswith("cpp-"):
        return MATRIX / "wild_cpp.a2l", CPP_OBJECTS, "c++"
    return MATRIX / "wild_c.a2l", C_OBJECTS, "c"


def sources_of(elf_name: str) -> list[tuple[Path, dict[str, str]]]:
    """The A2L files an ELF is updated from and their objects: a cross-compiled C ELF has ecu.c's too."""
    source, objects, _ = objects_of(elf_name)
    ecu = [(MATRIX / "ecu_c.a2l", ECU_OBJECTS)] if elf_name in CROSS_ELFS and source.name == "wild_c.a2l" else []
    return [(source, objects)] + ecu


def run_gdb(gdb: str, folder: Path, names: list[str], work: Path) -> dict[str, dict[str, list]]:
    """ELF name -> gdb expression -> [bit address, bit size or None, byte size, element] (gdb_oracle.py),
    one gdb run for all ``names`` in ``folder``."""
    request = []
    for name in names:
        expressions = {expression for _, objects in sources_of(name) for expression in objects.values()}
        if name in CROSS_ELFS and name.startswith("c-"):
            expressions.add(ECU_EPK[1])
        request.append({"elf": str(folder / name), "language": objects_of(name)[2],
                        "expressions": sorted(expressions)})
    (work / "request.json").write_text(json.dumps(request))
    env = {**os.environ, "WB_GDB_REQUEST": str(work / "request.json"), "WB_GDB_RESULT": str(work / "result.json")}
    subprocess.run([gdb, "-batch", "-nx", "-x", str(HERE / "gdb_oracle.py")], env=env, check=True,
                   capture_output=True, timeout=300)
    return dict(zip(names, json.loads((work / "result.json").read_text())))


@pytest.fixture(scope="module")
def gdb_truth(tmp_path_factory) -> dict[str, dict[str, list]]:
    """ELF name -> gdb expression -> [bit address, bit size or None, byte size, element], gdb run once."""
    if shutil.which("gdb") is None:
        pytest.skip("gdb is needed as the independent reader of the ELF matrix")
    return run_gdb("gdb", MATRIX, ELFS, tmp_path_factory.mktemp("gdb"))


@pytest.fixture(scope="module")
def cross_truth() -> dict[str, dict[str, list]]:
    """gdb-multiarch's places of the objects of the cross-compiled ELFs, as recorded."""
    return json.loads(CROSS_RECORD.read_text())


def placements(a2l: Path) -> dict[str, tuple[int, int | None, str | None]]:
    """A2L object -> (address, BIT_MASK or None, a MEASUREMENT's data type) as the file states them."""
    doc = load_a2l(a2l)
    found = {}
    for block in doc.objects("MEASUREMENT"):
        mask = block.option("BIT_MASK")
        found[block.name] = (doc.int_value(block.option("ECU_ADDRESS")[0]),
                             doc.int_value(mask[0]) if mask else None, doc.text(block.args[2]))
    for keyword, index in (("CHARACTERISTIC", 3), ("AXIS_PTS", 2)):
        for block in doc.objects(keyword):
            found[block.name] = (doc.int_value(block.args[index]), None, None)
    return found


def assert_where_gdb_says(objects: dict[str, str], placed: dict, truth: dict, names, little_endian=True) -> None:
    for name in names:
        bit_address, bit_size, size, _ = truth[objects[name]]
        address, mask, _ = placed[name]
        if bit_size is None:
            assert (address, mask) == (bit_address // 8, None), name
            continue
        lowest, count = (mask & -mask).bit_length() - 1, bin(mask).count("1")
        assert mask >> lowest == (1 << count) - 1 and mask < 1 << 8 * size, (name, hex(mask))
        # the mask is in the value of the storage unit as the ECU reads it; gdb counts memory's bits
        # from the least significant bit of the first byte on little-endian targets, from the most
        # significant one on big-endian targets
        first = lowest if little_endian else 8 * size - lowest - count
        assert (8 * address + first, count) == (bit_address, bit_size), name


def update_and_check(elf: Path, source: Path, tmp_path: Path, capsys) -> tuple[dict, dict, dict]:
    """`a2l update --types` of ``source`` from ``elf`` into ``updated-<source>``, then `a2l check --elf` of
    the result, as a user runs them: (the objects' placements, update's report, check's report)."""
    a2l = tmp_path / source.name
    shutil.copy(source, a2l)
    out = tmp_path / f"updated-{source.name}"
    assert main(["a2l", "update", str(a2l), str(elf), "-o", str(out), "--types", "--no-cache", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    cache = ["--cache-dir", str(tmp_path / "cache")]  # its own: a stale index of the user's never meets the test
    assert main(["a2l", "check", str(out), "--elf", str(elf), "--json", *cache]) in (0, 1)
    checked = json.loads(capsys.readouterr().out)
    return placements(out), report, checked


def test_the_matrix_is_what_its_names_say():
    assert ELFS == sorted(COMBINATIONS + TYPE_UNITS)
    for name in ELFS:
        with open(MATRIX / name, "rb") as handle:
            elf = ELFFile(handle)
            units = [unit.get_top_DIE() for unit in elf.get_dwarf_info().iter_CUs()]
            compiled = [die for die in units if die.tag == "DW_TAG_compile_unit"]
            assert len(compiled) == 2, name  # two sources a program
            assert {die.cu.header.version for die in units} == {int(re.search(r"dwarf(\d)", name).group(1))}, name
            assert elf.elfclass == (32 if "-m32-" in name else 64), name
            producers = {"clang" if "clang" in die.attributes["DW_AT_producer"].value.decode() else "gcc"
                         for die in compiled}
            assert producers == {name.split("-")[1]}, name
            if name.endswith("-types.elf"):  # DWARF 4 type units in .debug_types, DWARF 5's in .debug_info
                assert (elf.get_section_by_name(".debug_types") is not None) == ("dwarf4" in name), name
                assert len(units) > 2 or "dwarf4" in name, name


@pytest.mark.parametrize("elf_name", ELFS)
def test_update_writes_where_gdb_reads(elf_name, gdb_truth, tmp_path, capsys):
    source, objects, _ = objects_of(elf_name)
    truth = gdb_truth[elf_name]
    unknown = {expression: truth[expression] for expression in objects.values() if isinstance(truth[expression], str)}
    assert not unknown, f"gdb cannot read: {unknown}"
    placed, report, checked = update_and_check(MATRIX / elf_name, source, tmp_path, capsys)
    assert_where_gdb_says(objects, placed, truth, objects)
    assert_wild_types_kept(source, placed, report)
    errors = [(f["kind"], f["name"]) for f in checked["findings"] if f["severity"] == "error"]
    assert errors == ([("symbol-not-found", "ambiguous")] if source.name == "wild_c.a2l" else [])


def assert_wild_types_kept(source: Path, placed: dict, report: dict) -> None:
    """wild_c.a2l and wild_cpp.a2l state every data type and shape right: --types changes nothing but bit masks."""
    changes = {f["kind"] for f in report["findings"]} - {"address-updated", "bit-mask-updated", "epk-not-found",
                                                         "epk-not-set",  # no MOD_PAR for ecu.c's EPK
                                                         "byte-order-mismatch"}  # MSB_LAST against big-endian ELFs
    if source.name == "wild_c.a2l":  # a static of two functions: reported, its address left alone
        assert changes == {"symbol-ambiguous"}
        [ambiguous] = [f for f in report["findings"] if f["kind"] == "symbol-ambiguous"]
        assert "wild_other_step.ambiguous" in ambiguous["message"] and "wild_tick.ambiguous" in ambiguous["message"]
        assert placed["ambiguous"][:2] == (0x4321, None)
    else:
        assert changes == set()


def test_the_cross_compiled_elfs_are_what_their_names_say():
    assert len(CROSS_ELFS) == 17
    versions = {}
    for name in CROSS_ELFS:
        language, compiler, target, dwarf, _ = name.removesuffix(".elf").split("-")
        with open(CROSS / name, "rb") as handle:
            elf = ELFFile(handle)
            assert (elf["e_machine"], elf.little_endian, elf.elfclass) == (*CROSS_TARGETS[target], 32), name
            units = [unit.get_top_DIE() for unit in elf.get_dwarf_info().iter_CUs()]
            sources = {die.attributes["DW_AT_name"].value.decode() for die in units}  # and libgcc's (arm)
            assert {"wild.c", "wild_other.c", "ecu.c"} <= sources if language == "c" else \
                {"wild.cpp", "wild_other.cpp"} <= sources, name
            own = [die for die in units if die.attributes["DW_AT_name"].value.decode() in
                   ("wild.c", "wild_other.c", "ecu.c", "wild.cpp", "wild_other.cpp")]
            assert {die.cu.header.version for die in own} == {int(dwarf[5:])}, name
            producers = {"clang" if b"clang" in die.attributes["DW_AT_producer"].value else "gcc" for die in own}
            assert producers == {compiler}, name
            versions.setdefault(f"{compiler}-{target}", set()).add(dwarf)
            ram, flash = (elf.get_section_by_name(section)["sh_addr"] for section in (".data", ".text"))
            assert ram == {"ppc": 0x4000_0000, "arm": 0x2000_0000, "m68k": 0x80_0000}[target] < ram + 0x1000, name
            assert flash == {"ppc": 0x80_0000, "arm": 0x800_0000, "m68k": 0x1_0000}[target], name
            # .data's initial values lie in flash behind the constants (its LMA, by the program headers)
            [segment] = [s for s in elf.iter_segments() if s["p_type"] == "PT_LOAD" and s["p_vaddr"] == ram]
            assert ElfSymbols(CROSS / name).sections[".data"].load_address == segment["p_paddr"] < ram, name
    assert versions["gcc-ppc"] == versions["gcc-arm"] == {"dwarf2", "dwarf3", "dwarf4", "dwarf5"}


@pytest.mark.parametrize("elf_name", CROSS_ELFS)
def test_cross_compiled_update_writes_where_gdb_reads(elf_name, cross_truth, tmp_path, capsys):
    """Big-endian and bare-metal ELFs: every address, BIT_MASK and data type as gdb-multiarch reads it, the EPK,
    and `a2l check --elf` names an A2L whose byte order is not the ELF's."""
    little_endian = CROSS_TARGETS[elf_name.split("-")[2]][1]
    truth = cross_truth[elf_name]
    for source, objects in sources_of(elf_name):
        placed, report, checked = update_and_check(CROSS / elf_name, source, tmp_path, capsys)
        assert_where_gdb_says(objects, placed, truth, objects, little_endian)
        if source.name == "ecu_c.a2l":  # every data type a placeholder UBYTE before
            datatypes = {name: placed[name][2] for name in objects if placed[name][2] is not None}
            assert datatypes == {name: A2L_DATATYPES[truth[name][3]] for name in datatypes}
            with DebugData(CROSS / elf_name, use_cache=False) as debug:  # the sizes the overlap check uses
                assert {name: debug.find(name).size for name in objects} == {name: truth[name][2] for name in objects}
            [vtab] = load_a2l(tmp_path / "updated-ecu_c.a2l").objects("COMPU_VTAB")  # the enum's, new
            assert [vtab.doc.text(token) for token in vtab.args[2:]] == ["TAB_VERB", "6", *ECU_GEARS]
            # the calibrations' RECORD_LAYOUTs and every limit were right: nothing else changed
            assert {f["kind"] for f in report["findings"]} - {"byte-order-mismatch"} == {
                "address-updated", "bit-mask-updated", "bit-mask-unrepresentable", "datatype-updated",
                "conversion-added", "conversion-updated", "epk-updated"}
            unrepresentable = {f["name"] for f in report["findings"] if f["kind"] == "bit-mask-unrepresentable"}
            assert unrepresentable == {"wide.wide"} and placed["wide.wide"][1] == 0x1  # reported, left alone
            epk = {f["name"]: f["message"] for f in report["findings"] if f["kind"] == "epk-updated"}
            epk_address = truth[ECU_EPK[1]][0] // 8
            assert epk == {"EPK": f"EPK '' -> {ECU_EPK[0]!r} (from .epk)",
                           "ADDR_EPK": f"ADDR_EPK 0x0 -> 0x{epk_address:X}"}
        else:
            assert_wild_types_kept(source, placed, report)
        # wild_*.a2l say MSB_LAST (an error on a big-endian ELF), ecu_c.a2l nothing (ASAP2's MSB_FIRST: a warning)
        states_little_endian = source.name != "ecu_c.a2l"
        problems = {(f["kind"], f["name"], f["severity"]) for f in checked["findings"]
                    if f["severity"] == "error" or f["kind"] == "byte-order-mismatch"}
        expected = {("symbol-not-found", "ambiguous", "error")} if source.name == "wild_c.a2l" else set()
        if states_little_endian != little_endian:
            expected.add(("byte-order-mismatch", "MOD_COMMON", "error" if states_little_endian else "warning"))
        assert problems == expected, source.name
        # the update says so too, as a warning (it writes the addresses either way)
        orders = {(f["kind"], f["severity"]) for f in report["findings"] if f["kind"] == "byte-order-mismatch"}
        assert orders == ({("byte-order-mismatch", "warning")} if states_little_endian != little_endian else set())


@pytest.mark.parametrize("elf_name", ["c-gcc-ppc-dwarf4-O0.elf", "c-gcc-arm-dwarf4-O2.elf"])
def test_cross_compiled_symtab_fallback(elf_name, cross_truth, tmp_path, capsys):
    """Without DWARF (objcopy --strip-debug): a big-endian .symtab, and a Thumb one with its mapping symbols."""
    for source, objects in sources_of(elf_name):
        out = tmp_path / f"updated-{source.name}"
        main(["a2l", "update", str(source), str(CROSS / "stripped" / elf_name), "-o", str(out), "--no-cache"])
        capsys.readouterr()
        named = [name for name in objects if name in SYMTAB_CROSS]
        assert_where_gdb_says(objects, placements(out), cross_truth[elf_name], named)
        assert len(named) == (10 if source.name == "wild_c.a2l" else 7)


@pytest.mark.skipif(shutil.which("gdb-multiarch") is None, reason="gdb-multiarch reads the cross-compiled ELFs")
def test_cross_record_is_what_gdb_multiarch_reads(tmp_path):
    live = run_gdb("gdb-multiarch", CROSS, CROSS_ELFS, tmp_path)
    unknown = {(name, expression): found for name, places in live.items() for expression, found in places.items()
               if isinstance(found, str)}
    assert not unknown, f"gdb-multiarch cannot read: {unknown}"
    if os.environ.get("WB_RECORD_CROSS_GDB"):  # build_cross.sh: after a rebuild, record the new truth
        CROSS_RECORD.write_text("{\n" + ",\n".join(
            f" {json.dumps(name)}: {{\n" + ",\n".join(f"  {json.dumps(expression)}: {json.dumps(found)}"
                                                       for expression, found in sorted(places.items())) + "}"
            for name, places in sorted(live.items())) + "\n}\n")
        return
    assert live == json.loads(CROSS_RECORD.read_text())


@pytest.mark.parametrize("elf_name", [name for name in COMBINATIONS if name.endswith("-m64-O2.elf")])
def test_symtab_fallback_demangles_and_knows_function_statics(elf_name, gdb_truth, tmp_path, capsys):
    if shutil.which("objcopy") is None:
        pytest.skip("objcopy is needed to strip the debug information")
    stripped = tmp_path / "stripped.elf"
    subprocess.run(["objcopy", "--strip-debug", str(MATRIX / elf_name), str(stripped)], check=True)
    source, objects, _ = objects_of(elf_name)
    out = tmp_path / "updated.a2l"
    main(["a2l", "update", str(source), str(stripped), "-o", str(out), "--no-cache"])
    capsys.readouterr()
    named = SYMTAB_CPP if source.name == "wild_cpp.a2l" else SYMTAB_C[elf_name.split("-")[1]]
    assert_where_gdb_says(objects, placements(out), gdb_truth[elf_name], named)


@pytest.mark.compilers
def test_build_script_rebuilds_the_committed_matrix(tmp_path):
    missing = [tool for tool in ("gcc", "g++", "clang", "clang++") if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"{', '.join(missing)} needed to rebuild the ELF matrix")
    subprocess.run(["sh", str(MATRIX / "build.sh"), str(tmp_path)], check=True, capture_output=True)
    assert sorted(p.name for p in tmp_path.glob("*.elf")) == ELFS
    for compiler, sample in (("gcc", "c-gcc-dwarf5-m64-O0.elf"), ("clang", "c-clang-dwarf5-m64-O0.elf")):
        if _producer(tmp_path / sample) != _producer(MATRIX / sample):
            pytest.skip(f"this {compiler} is not the one that built the committed ELFs: "
                        f"{_producer(tmp_path / sample)!r} vs {_producer(MATRIX / sample)!r}")
    different = [name for name in ELFS if (tmp_path / name).read_bytes() != (MATRIX / name).read_bytes()]
    assert different == []


@pytest.mark.compilers
def test_build_cross_rebuilds_the_committed_cross_compiled_elfs(tmp_path):
    compilers = ("powerpc-linux-gnu-gcc", "powerpc-linux-gnu-g++", "arm-none-eabi-gcc", "arm-none-eabi-g++",
                 "m68k-linux-gnu-gcc", "clang", "clang++")
    missing = [tool for tool in compilers if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"{', '.join(missing)} needed to rebuild the cross-compiled ELFs")
    subprocess.run(["sh", str(MATRIX / "build_cross.sh"), str(tmp_path)], check=True, capture_output=True)
    assert sorted(p.name for p in tmp_path.glob("*.elf")) == CROSS_ELFS
    for sample in ("c-gcc-ppc-dwarf2-O0.elf", "c-gcc-arm-dwarf3-O0.elf", "c-gcc-m68k-dwarf2-O0.elf",
                   "c-clang-ppc-dwarf5-O0.elf"):
        if _producer(tmp_path / sample) != _producer(CROSS / sample):
            pytest.skip(f"not the compiler that built the committed {sample}: {_producer(tmp_path / sample)!r}")
    built = CROSS_ELFS + [f"stripped/{path.name}" for path in (CROSS / "stripped").glob("*.elf")]
    different = [name for name in built if (tmp_path / name).read_bytes() != (CROSS / name).read_bytes()]
    assert different == []


def _producer(path: Path) -> str:
    with open(path, "rb") as handle:
        unit = next(ELFFile(handle).get_dwarf_info().iter_CUs())
        return unit.get_top_DIE().attributes["DW_AT_producer"].value.decode()
