"""Time the A2L object model and the measurement decoder; print figures and ratios, assert nothing.

    python benchmarks/model_bench.py [--workdir benchmarks/build/a2l] [--repeat 5] [--samples 1000000]

The model half uses the large generated case of ``a2l_generate.py`` (10.4 MiB, 65,000 objects;
generated on first use, needs gcc): loading (with and without the full grammar check), indexing
the names, one lookup, a listing of every object from token columns, and building every object.
The reference is the reader's own load in the same run (the model's index costs this much more).
The decoder half turns ``--samples`` raw values per signal into physical values as the DAQ
decoder does, per conversion kind; the reference is numpy merely reading the same bytes
(``frombuffer`` + ``astype``), the least any decoder must do.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from a2l_generate import generate  # noqa: E402

from workbench.a2l import load_a2l, load_a2l_string  # noqa: E402
from workbench.calib import measurement_codec  # noqa: E402

HERE = Path(__file__).resolve().parent


def best(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def fresh(path: Path, repeat: int, work) -> float:
    """Best time of ``work(model)`` on a model just opened (its objects not built yet)."""
    times = []
    for _ in range(repeat):
        model = load_a2l(path, validate=False).model()
        start = time.perf_counter()
        work(model)
        times.append(time.perf_counter() - start)
    return min(times)


def model_figures(path: Path, repeat: int) -> None:
    size = path.stat().st_size / 2**20
    load = best(lambda: load_a2l(path, validate=False), repeat)
    load_model = best(lambda: load_a2l(path, validate=False).model(), repeat)
    validated = best(lambda: load_a2l(path).model(), max(1, repeat // 2))
    model = load_a2l(path, validate=False).model()
    names = model.names("CHARACTERISTIC")
    middle = names[len(names) // 2]
    count = len(model)
    lookup = fresh(path, repeat, lambda m: m.characteristic(middle))
    summaries = fresh(path, repeat, lambda m: m.summaries())
    pattern = fresh(path, repeat, lambda m: m.find("u2?_var00*", kind="MEASUREMENT"))
    everything = fresh(path, 1, list)
    print(f"A2L object model: {path.name}, {size:.1f} MiB, {count} objects (best of {repeat})")
    print(f"  reader load (reference)            {load:7.3f} s")
    print(f"  load + model index                 {load_model:7.3f} s   {load_model / load:5.2f}x the load")
    print(f"  load (full grammar check) + index  {validated:7.3f} s")
    print(f"  first characteristic() lookup      {lookup * 1000:7.2f} ms")
    print(f"  summaries(): name/kind/unit/conv.  {summaries:7.3f} s   {count / summaries:9.0f} objects/s")
    print(f"  find('u2?_var00*') measurements    {pattern * 1000:7.2f} ms")
    print(f"  every object built (list(model))   {everything:7.3f} s   {count / everything:9.0f} objects/s")
    demo = HERE.parent / "assets" / "FLCU.a2l"
    demo_time = best(lambda: load_a2l(demo).characteristic("xsSWITCH_TANK_THR"), repeat)
    print(f"  demo A2L: load + characteristic()  {demo_time * 1000:7.2f} ms")


_SIGNALS = """/begin PROJECT P "" /begin MODULE M ""
/begin MOD_COMMON "" BYTE_ORDER MSB_LAST /end MOD_COMMON
/begin COMPU_METHOD Lin "" LINEAR "%6.2" "bar" COEFFS_LINEAR 0.01 -50 /end COMPU_METHOD
/begin COMPU_METHOD Rat "" RAT_FUNC "%6.2" "bar" COEFFS 0 100 0 0 0 1 /end COMPU_METHOD
/begin COMPU_METHOD Tab "" TAB_INTP "%6.2" "V" COMPU_TAB_REF T /end COMPU_METHOD
/begin COMPU_METHOD Verb "" TAB_VERB "%3.0" "" COMPU_TAB_REF V /end COMPU_METHOD
/begin COMPU_METHOD Form "" FORM "%6.2" "degC" /begin FORMULA "X1 * 0.1 - 40" /end FORMULA /end COMPU_METHOD
/begin COMPU_TAB T "" TAB_INTP 4 0 0 1000 1 30000 3 65535 5 /end COMPU_TAB
/begin COMPU_VTAB V "" TAB_VERB 3 0 "OFF" 1 "TANK1_ON" 2 "TANK2_ON" /end COMPU_VTAB
/begin MEASUREMENT identity_f32 "" FLOAT32_IEEE NO_COMPU_METHOD 0 0 -1e9 1e9 ECU_ADDRESS 0 /end MEASUREMENT
/begin MEASUREMENT linear_s16 "" SWORD Lin 0 0 -400 400 ECU_ADDRESS 0 /end MEASUREMENT
/begin MEASUREMENT rat_func_u32 "" ULONG Rat 0 0 0 1e7 ECU_ADDRESS 0 /end MEASUREMENT
/begin MEASUREMENT table_u16 "" UWORD Tab 0 0 0 5 ECU_ADDRESS 0 /end MEASUREMENT
/begin MEASUREMENT formula_u16 "" UWORD Form 0 0 -40 6000 ECU_ADDRESS 0 /end MEASUREMENT
/begin MEASUREMENT bitfield_u16 "" UWORD NO_COMPU_METHOD 0 0 0 15 ECU_ADDRESS 0 BIT_MASK 0x0F0 /end MEASUREMENT
/begin MEASUREMENT enum_u8 "" UBYTE Verb 0 0 0 2 ECU_ADDRESS 0 /end MEASUREMENT
/end MODULE /end PROJECT"""


def decoder_figures(samples: int, repeat: int) -> None:
    model = load_a2l_string(_SIGNALS).model()
    rng = np.random.default_rng(1)
    print(f"Measurement decoding: {samples} samples per signal (best of {repeat}); reference: numpy reading the bytes")
    print(f"  {'signal':14s} {'to_physical':>14s} {'from bytes':>14s} {'reference':>14s}  ratio")
    for name in model.names("MEASUREMENT"):
        codec = measurement_codec(model, name)
        high = 3 if name.startswith("enum") else 2 ** (8 * codec.element_size - 1) - 1
        raw = rng.integers(0, high, samples).astype(codec.dtype) if codec.dtype.kind != "f" else \
            rng.normal(0, 1e3, samples).astype(codec.dtype)
        data = raw.tobytes()
        values = raw.astype(np.int64 if codec.dtype.kind in "iu" else np.float64)
        physical = best(lambda: codec.to_physical(values), repeat)
        from_bytes = best(lambda: codec.decode_samples(data, samples), repeat)
        reference = best(lambda: np.frombuffer(data, codec.dtype).astype(np.float64), repeat)
        shown = f"{samples / physical / 1e6:10.1f} M/s" if physical > 1e-5 else "  (no work)   "
        print(f"  {name:14s} {shown} {samples / from_bytes / 1e6:10.1f} M/s "
              f"{samples / reference / 1e6:10.1f} M/s  {from_bytes / reference:5.1f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--workdir", type=Path, default=HERE / "build" / "a2l")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--samples", type=int, default=1_000_000)
    args = parser.parse_args()
    big = args.workdir / "big.a2l"
    if not big.exists():
        generate(args.workdir)
    model_figures(big, args.repeat)
    decoder_figures(args.samples, args.repeat)


if __name__ == "__main__":
    main()
