"""What a cache sync costs against uploading the calibration memory, with the simulator's CAN bus timing model.

The demo ECU is served on a python-can ``virtual`` bus whose timing model runs at 1 Mbit/s (every frame occupies
the bus for its exact bit count, stuff bits included); a Session connects to it. The references, measured in the
same run:

- full upload of the calibration segment: the whole working page (CAL RAM, 128 KiB) read with UPLOAD, what a
  tool without checksums must do to know what the ECU holds;
- full upload of the objects: every calibration object read by name (read_dataset: 58 objects, 436 bytes in
  merged UPLOADs), what a tool that knows the A2L but uses no checksum does.

The cache sync (sync_compare, the s19 loaded once) runs on an unchanged ECU, after one object was written and
after three (a scalar, a curve, a map value), in two layouts of the segment:

- "demo": the demo as built, 452 bytes of EPK and calibrations at the start of CAL RAM and the 16-byte trailer;
- "full": every byte of the 128 KiB segment held by the reference (pseudo-random bytes after the calibrations,
  poked into the simulator's CAL RAM and into the image alike), as an ECU whose calibrations fill the segment.

Printed per case: the best wall time of ``--repeat`` runs, the bits the timing model carried in that run, and
both as ratios to the full upload of the segment (and the time to the upload of the objects). The timing model
lets a sender run up to 10 ms ahead of the modelled bus, so short cases finish before their bits would on a real
bus: the bit ratio is the one to trust for them. Plain script:
``.venv/bin/python benchmarks/sync_bench.py [--bitrate N] [--repeat N]``.
"""

from __future__ import annotations

import argparse
import logging
import random
import time

from workbench import Session, demo
from workbench.image import load_image
from workbench.sim import serve_demo
from workbench.sync import ImageReference, read_dataset, sync_compare

CAL_RAM, CAL_ROM, CAL_SIZE = 0x40000000, 0xFC0000, 0x20000
CAL_IMAGE_END, TRAILER = 0x1C4, 0x1FFF0  # offsets: end of the .cal_ram load image, the CalTrailer


def _timed(simulator, action, repeat: int):
    """(best wall time s, bus bits of that run, its result) of ``repeat`` runs."""
    best = None
    for _ in range(repeat):
        clock = simulator.bus_clock()
        bits = clock.bits
        began = time.perf_counter()
        result = action()
        elapsed = time.perf_counter() - began
        if best is None or elapsed < best[0]:
            best = (elapsed, clock.bits - bits, result)
    return best


def _full_segment(simulator, reference: ImageReference) -> ImageReference:
    """The reference and the ECU's CAL RAM with pseudo-random bytes between the calibrations and the trailer."""
    filler = random.Random(7).randbytes(TRAILER - CAL_IMAGE_END)
    simulator.ecu.memory.write(CAL_RAM + CAL_IMAGE_END, filler)
    image = load_image(demo.s19())
    image.add(CAL_ROM + CAL_IMAGE_END, filler)
    return ImageReference(reference.path, image)


def _change(ecu, count: int) -> None:
    ecu.write("xsSWITCH_TANK_THR", 25.0)
    if count > 1:
        ecu.write("zvTankPConv", ecu.read("zvTankPConv") * 0.5)
        table = ecu.read("xvPRV_DC_FF")
        table[3, 2] = 50.0
        ecu.write("xvPRV_DC_FF", table)


def _restore(ecu, reference: ImageReference) -> None:
    ecu.master.write(CAL_RAM + 0x10, reference.image.read(CAL_ROM + 0x10, CAL_IMAGE_END - 0x10))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bitrate", type=int, default=1_000_000, help="bit rate of the timing model (default 1 Mbit/s)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per case, the best counts (default 5)")
    args = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    channel = "sync-bench"
    bus = {"interface": "virtual", "channel": channel, "bitrate": args.bitrate}
    demo_reference = ImageReference(demo.s19(), load_image(demo.s19()))
    rows = []
    with serve_demo(bus) as simulator, Session.open(interface="virtual", channel=channel) as ecu:
        def segment():
            with ecu.on_page("working"):
                return ecu.read_memory(CAL_RAM, CAL_SIZE)

        rows.append(("full upload of the calibration segment", *_timed(simulator, segment, args.repeat)))
        rows.append(("full upload of every calibration object",
                     *_timed(simulator, lambda: read_dataset(ecu), args.repeat)))
        for layout in ("demo", "full"):
            reference = demo_reference if layout == "demo" else _full_segment(simulator, demo_reference)
            for count in (0, 1, 3):
                _restore(ecu, reference)
                if count:
                    _change(ecu, count)
                label = f"cache sync, {layout}, " + (f"{count} changed" if count else "unchanged")
                rows.append((label, *_timed(simulator, lambda: sync_compare(ecu, reference), args.repeat)))
    (_, segment_s, segment_bits, _), (_, objects_s, _, _) = rows[0], rows[1]
    print(f"at {args.bitrate / 1000:g} kbit/s, best of {args.repeat}:")
    print(f"{'case':40} {'time':>9} {'bus bits':>9} {'time/segment':>12} {'bits/segment':>12} {'time/objects':>12}  "
          "what it did")
    for name, seconds, bits, result in rows:
        if hasattr(result, "checksums"):
            did = (f"{result.checksums} BUILD_CHECKSUM, {result.bytes_uploaded} bytes uploaded, "
                   f"{len(result.changed)} objects differ")
        elif isinstance(result, bytes):
            did = f"{len(result)} bytes uploaded"
        else:
            did = f"{len(result)} objects read"
        print(f"{name:40} {seconds * 1000:6.1f} ms {bits:9d} {seconds / segment_s:12.2%} {bits / segment_bits:12.2%} "
              f"{seconds / objects_s:12.0%}  {did}")


if __name__ == "__main__":
    main()
