"""ChecksumVerifier against the simulated ECU: the largest BUILD_CHECKSUM block as the ECU's refusal names it."""

from __future__ import annotations

from dataclasses import replace

from flash_images import CALIB

from workbench.flash.checksums import ChecksumVerifier


def test_the_largest_block_is_the_one_the_ecus_refusal_names(bench):
    """ERR_OUT_OF_RANGE of a BUILD_CHECKSUM over more than the ECU takes carries the largest block it does (0x6000
    here, no power of two, so halving would not find it): the verifier goes on in blocks of that size."""
    slave = bench.ecu.slave
    slave.params = replace(slave.params, max_checksum_block=0x6000)
    verifier = ChecksumVerifier(bench.session.master)
    assert verifier.differing(CALIB.start, bench.ecu.read(CALIB.start, CALIB.size)) == []
    assert (verifier.max_block, verifier.commands) == (0x6000, 6)  # 128 KiB in 5 blocks of 24 KiB and one of 8
