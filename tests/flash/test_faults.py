"""An APPLICATIVE flash under faults: the power cut at random PROGRAM frames, frames lost or doubled at random.

Every power cut must leave the ECU in boot (the key cleared first), reachable, and a second flash must finish
it: 0 bricks. A lost or doubled frame must end in a repaired, verified flash or a clean error, never in a
flash that differs from the image. ``WORKBENCH_FLASH_POWER_CUTS`` and ``WORKBENCH_FLASH_FAULT_RUNS`` set how many.

Each fault costs the master timeouts (a power cut several: the PROGRAM, its SYNCH, the reset after the
failure), a hundred times. On a virtual bus they had to be short for speed (T1 50 ms), and a loaded machine
then stalled the simulator past them: faults the test did not inject. The bench here is on a lockstep wire
(:mod:`lockstep_bus`): a timeout ends at once when the simulator has nothing left to answer, and never while it
has, so the faults are exactly the injected ones and the tests take what the code takes, whatever the load.
"""

from __future__ import annotations

import os
import random
import threading
import time
from dataclasses import replace

import pytest
from flash_images import APPLICATIVE, application_image, open_bench

from workbench.errors import EcuSilentError
from workbench.flash import FlashError, flash_ecu, plan_flash
from workbench.sim.ecu import EcuState
from workbench.xcp_protocol import Cmd, Resource

CUTS = int(os.environ.get("WORKBENCH_FLASH_POWER_CUTS", "100"))  # in four tests of a quarter each
RUNS = int(os.environ.get("WORKBENCH_FLASH_FAULT_RUNS", "25"))  # per kind and direction: 100 frames in all
IMAGE_BYTES = 16 * 1024  # with the demo application 3,900 PROGRAM frames to cut at; 64 KiB cost twice the CPU

pytestmark = pytest.mark.slow


@pytest.fixture
def bench():
    """The flash tests' bench, on a lockstep wire."""
    with open_bench(lockstep=True) as bench:
        yield bench


def test_the_bench_waits_for_a_stalled_simulator_and_not_for_a_silent_one(bench):
    """What the tests below stand on: a simulator held up 300 times T1 is answered to, not repeated to; an ECU
    that is off is found silent even with T1 an hour (the test would hang, not pass, if it waited for it)."""
    master, faults = bench.session.master, bench.ecu.faults
    master.timeouts = replace(master.timeouts, t1=0.001)
    held = threading.Event()

    def stall() -> None:  # the simulator's receive thread waits for its lock, as for a CPU on a loaded machine
        with bench.simulator.lock:
            held.set()
            time.sleep(0.3)

    staller = threading.Thread(target=stall)
    staller.start()
    held.wait()
    commands = faults.commands_seen()
    master.command(Cmd.GET_STATUS)
    staller.join()
    assert faults.commands_seen() == commands + 1  # no SYNCH, no repetition
    master.timeouts = replace(master.timeouts, t1=3600.0)
    bench.simulator.power_off()
    with pytest.raises(EcuSilentError):
        master.command(Cmd.GET_STATUS)


@pytest.fixture
def plan(bench):
    return plan_flash(application_image(IMAGE_BYTES), bench.layout, ["APPLICATIVE"], source="app.s19")


def program_frames(plan) -> int:
    """PROGRAM and PROGRAM_NEXT frames of a clean flash of ``plan`` (the 4 key bytes are one more)."""
    return sum(-(-r.size // 6) for r in plan.image.ranges) + 1


def xcp_frames(plan, direction: str) -> int:
    """About the XCP frames of a clean flash in one direction: the PROGRAM frames (or their responses, one a
    block) and the commands around them."""
    blocks = sum(-(-r.size // 252) for r in plan.image.ranges)
    return (program_frames(plan) if direction == "rx" else blocks) + 60


def assert_flashed(bench, plan) -> None:
    expected = plan.sector_content(plan.sectors[0])
    assert bench.flash_content(APPLICATIVE) == expected
    assert bench.session.master.connect_info.resources & Resource.DAQ  # the application runs


@pytest.mark.parametrize("quarter", range(4))
def test_a_power_cut_at_any_program_frame_leaves_the_ecu_in_boot_and_a_second_flash_finishes(bench, plan, quarter):
    frames = program_frames(plan)
    cuts = sorted(random.Random(20250301).sample(range(1, frames + 1), min(CUTS, frames)))[quarter::4]
    bricks = []
    for cut in cuts:
        bench.ecu.faults.power_loss_at_program(cut)
        with pytest.raises(FlashError, match="application key is cleared") as failure:
            flash_ecu(bench.session, plan)
        assert "does not answer" in str(failure.value)
        assert bench.ecu.faults.fired[-1].startswith("power loss")
        assert bench.ecu.state is EcuState.OFF
        if bench.simulator.power_on() is not EcuState.BOOT:
            bricks.append(cut)  # it started an application from a half-written flash
            continue
        bench.session.connect()
        assert not bench.session.master.connect_info.resources & Resource.DAQ  # boot: programming only
        flash_ecu(bench.session, plan)
        assert_flashed(bench, plan)
    assert bricks == []


@pytest.mark.parametrize("action", ["drop", "duplicate"])
@pytest.mark.parametrize("direction", ["rx", "tx"])
def test_a_lost_or_doubled_frame_is_repaired_or_reported_never_flashed_wrong(bench, plan, action, direction):
    rng = random.Random(f"{action}-{direction}")
    frames = xcp_frames(plan, direction)
    outcomes = {"repaired": 0, "failed": 0, "untouched": 0}
    for _ in range(RUNS):
        before = len(bench.ecu.faults.fired)
        getattr(bench.ecu.faults, f"{action}_frame")(rng.randint(1, frames), direction)
        try:
            result = flash_ecu(bench.session, plan)
        except FlashError:
            outcomes["failed"] += 1
            bench.ecu.faults.clear()
            if bench.ecu.state is EcuState.OFF:
                bench.simulator.power_on()
            bench.session.connect()
            flash_ecu(bench.session, plan)  # a clean error: the next flash finishes it
        else:
            outcomes["repaired" if len(bench.ecu.faults.fired) > before else "untouched"] += 1
            assert result.application_running
        bench.ecu.faults.clear()
        assert_flashed(bench, plan)
    print(action, direction, outcomes)
    assert outcomes["failed"] <= RUNS // 10  # nearly every fault is repaired in the flash it hits
