"""MDF4 recording: throughput of the recording path, and a long recording at the simulated ECU's fastest rate.

1. Throughput (in this process): DAQ samples of every MEASUREMENT of the demo A2L (85 signals,
   arrays by element: 102 channels) as the DAQ stream hands them over (raw bytes), turned into
   MDF records and written by :class:`workbench.record.MdfStreamWriter` with a flush a second of
   the demo's rate (250 samples); figure: samples/s and signal values/s written, as a multiple of
   what the demo ECU's 4 ms event produces (250 samples/s), and asammdf's own writer (``MDF.append``
   of the same records, then ``save``) on the same data as the reference.
2. The long run (two processes, as a user works): ``workbench sim --pcm`` on udp_multicast (a port
   of its own), and ``workbench measure <every MEASUREMENT> --event Task4ms --record OUT.mf4 --can2
   FLCU_CAN2.dbc --raw-can --duration S`` recording every signal on the 4 ms event (the fastest the
   demo offers), the CAN2 messages decoded and every frame of the bus raw (the XCP DTOs included).
   The recording process's resident memory is sampled every second (``/proc``); at the end the file
   is read back with asammdf: samples, lost samples, timestamps rising, gaps against the 4 ms
   period, CAN2 frames, raw frames, file size.

Plain script: ``.venv/bin/python benchmarks/record_bench.py [--seconds 600] [--skip-long]``.
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from session_bench import free_port

from workbench import demo

CLI = [sys.executable, "-c", "from workbench.cli import entry_point; entry_point()"]


def throughput(seconds: int = 120) -> dict:
    """``seconds`` of the demo's 4 ms event (every MEASUREMENT) recorded as fast as this host can."""
    from asammdf import MDF, Signal

    from workbench.a2l import load_a2l
    from workbench.calib.signals import measurement_codec
    from workbench.record.daq_channels import DaqGroup
    from workbench.record.mdf_stream import MdfStreamWriter
    from workbench.xcp.daq import DaqBatch, DaqListPlan

    model = load_a2l(demo.a2l()).model()
    codecs = [measurement_codec(model, name) for name in model.names("MEASUREMENT")]
    group = DaqGroup(0, "Task4ms", 0.004, codecs)
    offsets = np.cumsum([0] + [codec.size for codec in codecs])
    positions = {codec.name: np.arange(start, start + codec.size) for codec, start in zip(codecs, offsets)}
    plan = DaqListPlan(0, 0, (), True, positions)
    per_flush = 250
    rng = np.random.default_rng(1)
    batches = []
    for flush in range(seconds):
        data = rng.integers(0, 64, (per_flush, int(offsets[-1])), dtype=np.uint8)  # below 64: floats stay finite
        time_s = (np.arange(per_flush) + flush * per_flush) * 0.004
        batches.append(DaqBatch(plan, time_s, time_s + 1.8e9, data))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "throughput.mf4"
        started = time.perf_counter()
        writer = MdfStreamWriter(path, [group.spec])
        for batch in batches:
            writer.append(0, batch.time, group.columns(batch))
            writer.flush()
        writer.close()
        ours = time.perf_counter() - started
        size = path.stat().st_size

        started = time.perf_counter()
        reference = MDF(version="4.11")
        columns = [group.columns(batch) for batch in batches]
        times = np.concatenate([batch.time for batch in batches])
        signals = [Signal(np.concatenate([c[i] for c in columns]), times, name=spec.name, unit=spec.unit,
                          conversion=spec.conversion)
                   for i, spec in enumerate(group.spec.channels)]
        reference.append(signals, common_timebase=True)
        reference.save(Path(folder) / "reference.mf4", compression=2)
        reference.close()
        theirs = time.perf_counter() - started
        reference_size = (Path(folder) / "reference.mf4").stat().st_size
    samples = seconds * per_flush
    return {"samples": samples, "signals": len(codecs), "channels": len(group.spec.channels), "seconds": ours,
            "samples_per_s": samples / ours, "values_per_s": samples * len(codecs) / ours, "bytes": size,
            "reference_seconds": theirs, "reference_bytes": reference_size}


def usage(pid: int) -> tuple[int, int, float]:
    """(resident KiB, peak resident KiB, CPU seconds) of a running process."""
    fields = {}
    with open(f"/proc/{pid}/status", encoding="ascii") as status:
        for line in status:
            key, _, value = line.partition(":")
            fields[key] = value.split()[0] if value.split() else "0"
    with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
        times = stat.read().rsplit(")", 1)[1].split()[11:13]  # utime, stime after the command's name
    return int(fields.get("VmRSS", 0)), int(fields.get("VmHWM", 0)), sum(map(int, times)) / os.sysconf("SC_CLK_TCK")


def long_run(seconds: float, out: Path) -> dict:
    from workbench.a2l import load_a2l

    names = load_a2l(demo.a2l()).model().names("MEASUREMENT")
    bus = ["--bus-kwargs", f"port={free_port(socket.SOCK_DGRAM)}"]
    sim = subprocess.Popen([*CLI, "sim", "--pcm", *bus], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in sim.stdout:
        if line.startswith("serving"):
            break
    memory = []
    simulator_cpu = 0.0
    try:
        recorder = subprocess.Popen([*CLI, "measure", *names, "--event", "Task4ms", "--record", str(out),
                                     "--overwrite", "--can2", str(demo.dbc_can2()), "--raw-can", "--json",
                                     "--duration", str(seconds), *bus],
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        started = time.monotonic()
        while recorder.poll() is None:
            try:
                memory.append((time.monotonic() - started, *usage(recorder.pid)))
                simulator_cpu = usage(sim.pid)[2]
            except (FileNotFoundError, ProcessLookupError):
                break
            time.sleep(1.0)
        output, errors = recorder.communicate()
        if recorder.returncode:
            raise SystemExit(f"the recording failed: {errors}")
    finally:
        sim.terminate()
        sim.wait(10)
    summary = json.loads(output)
    summary.update(check_file(out))
    summary["memory"] = memory
    summary["names"] = len(names)
    summary["simulator_cpu"] = simulator_cpu
    return summary


def check_file(path: Path) -> dict:
    from asammdf import MDF

    with MDF(path) as mdf:
        groups = {group.channel_group.acq_name: index for index, group in enumerate(mdf.groups)}
        times = mdf.get_master(groups["Task4ms"])
        steps = np.diff(times)
        raw_frames = mdf.groups[groups["CAN2"]].channel_group.cycles_nr
        decoded = sum(mdf.groups[index].channel_group.cycles_nr for name, index in groups.items()
                      if name.startswith(("PCM_TO", "FLCU_TO")))
    return {"file_samples": len(times), "rising": bool(np.all(steps > 0)),
            "gaps": int(np.sum(np.rint(steps / 0.004) > 1)), "missing_by_time": int(np.sum(np.rint(steps / 0.004) - 1)),
            "file_raw_frames": raw_frames, "file_can_frames": decoded, "file_bytes_read": path.stat().st_size}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=float, default=600.0, help="length of the long run (default 10 minutes)")
    parser.add_argument("--skip-long", action="store_true", help="only the throughput")
    parser.add_argument("--keep", metavar="OUT.mf4", help="keep the long run's recording here")
    args = parser.parse_args()
    result = throughput()
    print(f"throughput: {result['samples_per_s']:,.0f} samples/s = {result['values_per_s']:,.0f} signal values/s "
          f"({result['signals']} signals, {result['channels']} channels, flushed every 250 samples) = "
          f"{result['samples_per_s'] / 250:,.0f}x the demo's 4 ms event; {result['samples']:,} samples in "
          f"{result['seconds']:.2f} s, {result['bytes'] / 2**20:.1f} MiB; asammdf MDF.append + save (deflate) of the "
          f"same records {result['reference_seconds']:.2f} s, {result['reference_bytes'] / 2**20:.1f} MiB "
          f"(ours {result['seconds'] / result['reference_seconds']:.2f}x its time)")
    if args.skip_long:
        return
    with tempfile.TemporaryDirectory() as folder:
        out = Path(args.keep) if args.keep else Path(folder) / "long.mf4"
        run = long_run(args.seconds, out)
    memory = run["memory"]
    minute = next((rss for when, rss, _, _ in memory if when >= 60), memory[-1][1] if memory else 0)
    peak = max((hwm for _, _, hwm, _ in memory), default=0)
    cpu = memory[-1][3] / memory[-1][0] if memory and memory[-1][0] else 0.0
    print(f"long run: {run['seconds']:.0f} s, {run['names']} signals on Task4ms: {run['samples']:,} samples "
          f"({run['samples'] / run['seconds']:,.0f}/s, {run['values']:,} values), lost {run['lost']}, overloads "
          f"{run['overloads']}; in the file {run['file_samples']:,} samples, times rising {run['rising']}, gaps "
          f"{run['gaps']} ({run['missing_by_time']} samples); CAN2 frames decoded {run['can_frames']:,} (file "
          f"{run['file_can_frames']:,}), raw frames {run['raw_frames']:,} (file {run['file_raw_frames']:,}); file "
          f"{run['file_bytes'] / 2**20:.1f} MiB; recording process RSS {minute / 1024:.0f} MiB after a minute, "
          f"{memory[-1][1] / 1024:.0f} MiB at the end, peak {peak / 1024:.0f} MiB; CPU: recording process {cpu:.0%} "
          f"of a core, simulator {run['simulator_cpu'] / memory[-1][0]:.0%}; load average {os.getloadavg()[0]:.1f} "
          f"on {os.cpu_count()} cores")
    by_minute = {int(when // 60): rss for when, rss, _, _ in reversed(memory)}  # the first sample of each minute
    print("RSS MiB at the start of each minute: " + " ".join(f"{by_minute[m] / 1024:.0f}" for m in sorted(by_minute)))


if __name__ == "__main__":
    main()
