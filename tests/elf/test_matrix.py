"""The ELF matrix: every address `workbench a2l update` writes is where gdb finds the object.

tests/elf/matrix/build.sh builds C and C++ sources (anonymous unions and structs, bitfields,
function-local and file statics, namespaces, static members, inheritance, a class only
declared in a unit) with gcc and clang, DWARF 4 and 5, 32 and 64 bits, -O0 and -O2, plus
C++ with type units: 36 small ELFs, committed. wild_c.a2l and wild_cpp.a2l name their
objects the ways A2L generators do. Each ELF goes through the CLI as a user runs it
(`a2l update --types`, then `a2l check --elf`, in a temporary folder), and every address
and BIT_MASK is compared with what gdb reads from the same ELF (gdb_oracle.py, run in gdb
once for the whole matrix), the .symtab fallback too on stripped copies.
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

HERE = Path(__file__).parent
MATRIX = HERE / "matrix"
ELFS = sorted(path.name for path in MATRIX.glob("*.elf"))
COMBINATIONS = [f"{language}-{compiler}-dwarf{dwarf}-m{bits}-{opt}.elf" for language in ("c", "cpp")
                for compiler in ("gcc", "clang") for dwarf in (4, 5) for bits in (32, 64) for opt in ("O0", "O2")]
TYPE_UNITS = [f"cpp-{compiler}-dwarf{dwarf}-types.elf" for compiler in ("gcc", "clang") for dwarf in (4, 5)]

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


@pytest.fixture(scope="module")
def gdb_truth(tmp_path_factory) -> dict[str, dict[str, list]]:
    """ELF name -> gdb expression -> [bit address, bit size or None, byte size], gdb run once."""
    if shutil.which("gdb") is None:
        pytest.skip("gdb is needed as the independent reader of the ELF matrix")
    work = tmp_path_factory.mktemp("gdb")
    request = []
    for name in ELFS:
        _, objects, language = objects_of(name)
        request.append({"elf": str(MATRIX / name), "language": language, "expressions": sorted(set(objects.values()))})
    (work / "request.json").write_text(json.dumps(request))
    env = {**os.environ, "WB_GDB_REQUEST": str(work / "request.json"), "WB_GDB_RESULT": str(work / "result.json")}
    subprocess.run(["gdb", "-batch", "-nx", "-x", str(HERE / "gdb_oracle.py")], env=env, check=True,
                   capture_output=True, timeout=300)
    results = json.loads((work / "result.json").read_text())
    return dict(zip(ELFS, results))


def placements(a2l: Path) -> dict[str, tuple[int, int | None]]:
    """A2L object -> (address, BIT_MASK or None) as the file states them."""
    doc = load_a2l(a2l)
    found = {}
    for block in doc.objects("MEASUREMENT"):
        mask = block.option("BIT_MASK")
        found[block.name] = (doc.int_value(block.option("ECU_ADDRESS")[0]),
                             doc.int_value(mask[0]) if mask else None)
    for keyword, index in (("CHARACTERISTIC", 3), ("AXIS_PTS", 2)):
        for block in doc.objects(keyword):
            found[block.name] = (doc.int_value(block.args[index]), None)
    return found


def assert_where_gdb_says(elf_name: str, placed: dict, truth: dict, names) -> None:
    _, objects, _ = objects_of(elf_name)
    for name in names:
        bit_address, bit_size, _ = truth[objects[name]]
        address, mask = placed[name]
        if bit_size is None:
            assert (address, mask) == (bit_address // 8, None), name
        else:  # little-endian targets: bit n of the storage unit is bit 8 * address + n of memory
            lowest = (mask & -mask).bit_length() - 1
            assert (8 * address + lowest, bin(mask).count("1")) == (bit_address, bit_size), name


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
    a2l = tmp_path / source.name
    shutil.copy(source, a2l)
    out = tmp_path / "updated.a2l"
    assert main(["a2l", "update", str(a2l), str(MATRIX / elf_name), "-o", str(out), "--types", "--no-cache",
                 "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    truth = gdb_truth[elf_name]
    unknown = {expression: truth[expression] for expression in objects.values() if isinstance(truth[expression], str)}
    assert not unknown, f"gdb cannot read: {unknown}"
    placed = placements(out)
    assert_where_gdb_says(elf_name, placed, truth, objects)
    # --types found every data type and shape right: it changed nothing but bit masks
    changes = {f["kind"] for f in report["findings"]} - {"address-updated", "bit-mask-updated", "epk-not-found"}
    if source.name == "wild_c.a2l":  # a static of two functions: reported, its address left alone
        assert changes == {"symbol-ambiguous"}
        [ambiguous] = [f for f in report["findings"] if f["kind"] == "symbol-ambiguous"]
        assert "wild_other_step.ambiguous" in ambiguous["message"] and "wild_tick.ambiguous" in ambiguous["message"]
        assert placed["ambiguous"] == (0x4321, None)
    else:
        assert changes == set()
    assert main(["a2l", "check", str(out), "--elf", str(MATRIX / elf_name), "--json"]) in (0, 1)
    checked = json.loads(capsys.readouterr().out)
    errors = [(f["kind"], f["name"]) for f in checked["findings"] if f["severity"] == "error"]
    assert errors == ([("symbol-not-found", "ambiguous")] if source.name == "wild_c.a2l" else [])


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
    assert_where_gdb_says(elf_name, placements(out), gdb_truth[elf_name], named)


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


def _producer(path: Path) -> str:
    with open(path, "rb") as handle:
        unit = next(ELFFile(handle).get_dwarf_info().iter_CUs())
        return unit.get_top_DIE().attributes["DW_AT_producer"].value.decode()
