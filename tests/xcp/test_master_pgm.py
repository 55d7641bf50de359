"""The master's programming commands against the simulated ECU: sectors, PROGRAM in every mode, reset, resync."""

from __future__ import annotations

import dataclasses
import os

import pytest

from workbench.errors import XcpCommandError
from workbench.sim.ecu import EcuState
from workbench.xcp.info import ProgramStartInfo, SectorInfo, data_per_frame, program_block_size
from workbench.xcp_protocol import Cmd, Err

CALIB = 0xFC0000


@pytest.fixture
def programming(rig) -> ProgramStartInfo:
    start = rig.master.program_start()
    rig.master.set_mta(CALIB)
    rig.master.program_clear(0x20000)
    rig.master.set_mta(CALIB)
    return start


def test_sector_and_processor_info(rig):
    assert rig.master.get_pgm_processor_info().max_sectors == 3
    assert rig.master.get_sector_info(1) == SectorInfo(1, 2, 1, 0, 0xFC0000, 0x20000)


def test_program_start_says_how_to_program(rig):
    start = rig.master.program_start()
    assert (start.master_block_mode, start.max_cto_pgm, start.max_bs_pgm, start.min_st_pgm_s) == (True, 8, 42, 0.0)
    assert rig.master.program_block_size(start) == 252  # 42 whole frames: 1 + MAX_BS allows 43, 255 bytes 42.5
    assert rig.demo.ecu.state is EcuState.HALTED


@pytest.mark.parametrize(("max_cto", "granularity", "max_bs", "use_max", "block"), [
    (8, 1, 42, False, 252), (8, 1, None, False, 6), (8, 1, None, True, 7), (8, 1, 0, False, 6),
    (8, 4, 42, False, 172), (8, 4, None, True, 4), (64, 1, 255, False, 248), (8, 2, 200, False, 510)])
def test_one_rule_for_the_block_size(max_cto, granularity, max_bs, use_max, block):
    """The master (PROGRAM_START) and the flash plan's estimate (the A2L) share it: whole elements a frame, at most
    1 + MAX_BS_PGM frames and 255 elements a block; PROGRAM_MAX one byte (element) more than PROGRAM."""
    assert program_block_size(max_cto, granularity, max_bs=max_bs, use_max=use_max) == block
    assert block % data_per_frame(max_cto, granularity) == 0 or use_max


@pytest.mark.parametrize("master_block_mode, use_max", [(True, False), (False, True), (False, False)])
def test_program_in_blocks_in_program_max_frames_or_one_frame_a_command(rig, programming, master_block_mode, use_max):
    start = dataclasses.replace(programming, master_block_mode=master_block_mode)
    data = os.urandom(1000)
    rig.master.program(data, start, use_max=use_max)
    assert rig.demo.ecu.read(CALIB, len(data)) == data
    assert rig.master.program_block_size(start, use_max=use_max) == (252 if master_block_mode else 7 if use_max else 6)


def test_a_refused_block_is_reported_by_its_early_response(rig, programming):
    rig.master.program(b"\x01" * 300, programming)
    rig.master.set_mta(CALIB)
    with pytest.raises(XcpCommandError, match="PROGRAM(_NEXT)? failed: ERR_ACCESS_DENIED"):
        rig.master.program(b"\x02" * 252, programming)  # written flash: refused at the block's first frame


def test_resynchronize_drops_the_answers_a_broken_block_still_gets(rig, programming):
    rig.master.link.send(bytes([Cmd.PROGRAM, 252]) + b"\x00" * 6)
    for remaining in (240, 234, 228):  # a lost frame: each of these gets ERR_SEQUENCE
        rig.master.link.send(bytes([Cmd.PROGRAM_NEXT, remaining]) + b"\x00" * 6)
    rig.master.resynchronize()
    assert rig.master.link.receive(0.05) is None
    assert rig.master.get_status() is not None


def test_program_reset_ends_the_session_and_reboots(rig, programming):
    rig.master.program_reset()
    assert not rig.master.connected
    rig.master.connect(timeout="t6")
    assert rig.demo.ecu.state is EcuState.APPLICATION


def test_program_clear_outside_a_sector_is_refused(rig):
    rig.master.program_start()
    rig.master.set_mta(0x800000)
    with pytest.raises(XcpCommandError) as refused:
        rig.master.program_clear(0x40000)
    assert refused.value.code == Err.WRITE_PROTECTED
