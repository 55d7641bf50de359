"""Generate the large A2L benchmark case: C sources with ~50,000 variables, their ELF, and A2Ls.

Writes into a work folder:
  src/unit_NN.c        scalars, structs (with a nested struct) and arrays; built with ``gcc -g``
  big.elf              the linked program (nobody runs it)
  big.a2l              one A2L describing the variables (addresses 0: what ``update`` fills in)
  master.a2l           PROJECT/MODULE/MOD_PAR/MOD_COMMON/shared COMPU_METHODs and RECORD_LAYOUTs
  fragments/unit_NN.a2l  one fragment per C file (what ``merge`` puts into the master)
The content is deterministic for given sizes.
"""

from __future__ import annotations

import argparse
import random
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

C_TYPES = [("float", "FLOAT32_IEEE", "Scalar_FLOAT32"), ("unsigned short", "UWORD", "Scalar_UWORD"),
           ("unsigned char", "UBYTE", "Scalar_UBYTE"), ("int", "SLONG", "Scalar_SLONG")]
HEADER = """ASAP2_VERSION 1 71
/begin PROJECT Bench "generated benchmark"
  /begin HEADER "large generated case" VERSION "1.0" /end HEADER
  /begin MODULE Bench "all units"
"""
SHARED = """    /begin MOD_PAR "benchmark ECU"
      EPK "BENCH_EPK"
      ADDR_EPK 0x0
      /begin MEMORY_SEGMENT Ram "all data" DATA RAM INTERN 0x0 0xFFFFFFFF -1 -1 -1 -1 -1 /end MEMORY_SEGMENT
    /end MOD_PAR
    /begin MOD_COMMON "" BYTE_ORDER MSB_LAST ALIGNMENT_BYTE 1 ALIGNMENT_WORD 2 ALIGNMENT_LONG 4 /end MOD_COMMON
    /begin COMPU_METHOD CM_Identity "identity" IDENTICAL "%10.3" "" /end COMPU_METHOD
    /begin COMPU_METHOD CM_Linear "phys = 0.1 * raw" LINEAR "%8.1" "bar" COEFFS_LINEAR 0.1 0 /end COMPU_METHOD
""" + "".join(f"    /begin RECORD_LAYOUT {layout} FNC_VALUES 1 {datatype} ROW_DIR DIRECT /end RECORD_LAYOUT\n"
              for _, datatype, layout in C_TYPES)
FOOTER = "  /end MODULE\n/end PROJECT\n"


def generate(workdir: Path, units: int = 50, scalars: int = 700, structs: int = 200, arrays: int = 100,
             seed: int = 1) -> Path:
    """Write the case into ``workdir`` (skipping what is already there) and return it."""
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "src").mkdir(exist_ok=True)
    (workdir / "fragments").mkdir(exist_ok=True)
    rng = random.Random(seed)
    bodies = []
    for unit in range(units):
        c_text, a2l_text = _unit(unit, scalars, structs, arrays, rng)
        (workdir / "src" / f"unit_{unit:02d}.c").write_text(c_text)
        (workdir / "fragments" / f"unit_{unit:02d}.a2l").write_text(
            HEADER.replace("Bench", f"Unit{unit:02d}") + a2l_text + FOOTER)
        bodies.append(a2l_text)
    (workdir / "src" / "main.c").write_text('const char EPK[16] __attribute__((used)) = "BENCH_2024_0001";\n'
                                            "void _start(void) { for (;;) {} }\n")
    (workdir / "master.a2l").write_text(HEADER + SHARED + FOOTER)
    (workdir / "big.a2l").write_text(HEADER + SHARED + "".join(bodies) + FOOTER)
    _build(workdir)
    return workdir


def _unit(unit: int, scalars: int, structs: int, arrays: int, rng: random.Random) -> tuple[str, str]:
    c = [f"/* generated unit {unit} */", "typedef struct { unsigned short raw; float phys; } tSignal;",
         "typedef struct { tSignal in; unsigned char status; int counter; float gain[4]; } tChannel;"]
    a2l = [f"    /* ---------------- unit {unit} ---------------- */"]
    for index in range(scalars):
        c_type, datatype, layout = C_TYPES[rng.randrange(len(C_TYPES))]
        name = f"u{unit:02d}_var{index:04d}"
        c.append(f"{c_type} {name};")
        if index % 5 == 0:  # every fifth scalar is a calibration
            a2l.append(f'    /begin CHARACTERISTIC {name} "calibration {index} of unit {unit}" VALUE 0x00000000 '
                       f'{layout} 0 CM_Identity 0 100\n      FORMAT "%8.3"\n    /end CHARACTERISTIC')
        else:
            a2l.append(_measurement(name, f"signal {index} of unit {unit}", datatype))
    for index in range(structs):
        name = f"u{unit:02d}_chan{index:03d}"
        c.append(f"tChannel {name};")
        a2l.append(_measurement(f"{name}.in.phys", f"channel {index}: physical input", "FLOAT32_IEEE"))
        a2l.append(_measurement(f"{name}.counter", f"channel {index}: counter", "SLONG"))
    for index in range(arrays):
        name = f"u{unit:02d}_arr{index:03d}"
        c.append(f"unsigned short {name}[8];")
        a2l.append(_measurement(name, f"array {index}", "UWORD", extra="\n      MATRIX_DIM 8"))
        a2l.append(_measurement(f"{name}[{index % 8}]", f"array {index}: element {index % 8}", "UWORD"))
    return "\n".join(c) + "\n", "\n".join(a2l) + "\n"


def _measurement(name: str, text: str, datatype: str, extra: str = "") -> str:
    return (f'    /begin MEASUREMENT {name} "{text}" {datatype} CM_Identity 1 0 -1000 1000\n'
            f'      ECU_ADDRESS 0x00000000{extra}\n'
            f'      FORMAT "%10.3"\n    /end MEASUREMENT')


def _build(workdir: Path) -> None:
    sources = sorted((workdir / "src").glob("*.c"))
    objects = [source.with_suffix(".o") for source in sources]
    with ThreadPoolExecutor() as pool:
        list(pool.map(lambda pair: subprocess.run(
            ["gcc", "-g", "-O0", "-fno-pie", "-fno-common", "-c", str(pair[0]), "-o", str(pair[1])], check=True),
            zip(sources, objects)))
    subprocess.run(["gcc", "-nostdlib", "-static", "-no-pie", "-Wl,-e,_start", "-o", str(workdir / "big.elf"),
                    *map(str, objects)], check=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("workdir", type=Path)
    parser.add_argument("--units", type=int, default=50)
    args = parser.parse_args()
    generate(args.workdir, units=args.units)


if __name__ == "__main__":
    main()
