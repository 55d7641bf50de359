"""Native key libraries with ASAM's interface (XCP_ComputeKeyFromSeed), as CANape and INCA load them: one built
with gcc from the demo ECU's algorithm unlocks the simulated ECU; libraries built for another system or bitness
are refused from their header, before anything loads."""

from __future__ import annotations

import ctypes
import platform
import shutil
import struct
import subprocess
import sys

import pytest
from cli_helpers import run

from workbench.errors import InputError
from workbench.sim import serve_demo
from workbench.sim.seedkey import compute_key
from workbench.xcp.seedkey import load_key_function

# the demo's algorithm (workbench.sim.seedkey) in C, behind ASAM's interface; resource 0x08 (STIM) is "not available"
KEY_LIBRARY_C = r"""
#include <stdint.h>
uint32_t calls;  /* read by the tests: the key came from here */
uint32_t XCP_ComputeKeyFromSeed(uint8_t resource, uint8_t seed_length, uint8_t *seed, uint8_t *key_length,
                                uint8_t *key)
{
    calls++;
    if (resource == 0x08) return 1;
    if (seed_length < 4) return 2;
    if (*key_length < seed_length) return 3;
    for (int start = 0; start < seed_length; start += 4) {
        uint32_t word = 0;
        for (int i = 0; i < 4; i++) word = (word << 8) | (start + i < seed_length ? seed[start + i] : 0);
        word ^= 0x464C4355u ^ (resource * 0x01010101u);
        word = (word << 5) | (word >> 27);
        for (int i = 0; i < 4 && start + i < seed_length; i++) key[start + i] = (uint8_t)(word >> (24 - 8 * i));
    }
    *key_length = seed_length;
    return 0;
}
"""

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs a host gcc")


@pytest.fixture(scope="module")
def key_library(tmp_path_factory):
    folder = tmp_path_factory.mktemp("keylib")
    (folder / "seednkey.c").write_text(KEY_LIBRARY_C)
    subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-o", str(folder / "libseednkey.so"), str(folder / "seednkey.c")],
                   check=True)
    return folder / "libseednkey.so"


@pytest.mark.gcc
@needs_gcc
@pytest.mark.parametrize("seed", [bytes([1, 2, 3, 4]), bytes(range(20)), bytes([0xFF] * 7)])
@pytest.mark.parametrize("resource", [0x01, 0x04, 0x10])
def test_the_library_computes_the_demo_key(key_library, seed, resource):
    key_function = load_key_function(str(key_library))
    assert key_function(seed, resource) == compute_key(seed, resource)
    assert key_function.__name__ == "libseednkey.so:XCP_ComputeKeyFromSeed"


@pytest.mark.gcc
@needs_gcc
def test_an_error_of_the_library_is_named(key_library):
    key_function = load_key_function(key_library.name, base=key_library.parent)  # found beside the A2L
    with pytest.raises(ValueError, match=r"returned 1 \(the privilege \(resource\) is not available\)"):
        key_function(bytes(4), 0x08)
    with pytest.raises(ValueError, match="returned 2 .invalid seed length"):
        key_function(bytes(2), 0x01)


@pytest.mark.gcc
@needs_gcc
def test_a_library_without_the_interface_is_refused(tmp_path):
    (tmp_path / "other.c").write_text("int something_else(void) { return 0; }\n")
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", str(tmp_path / "other.so"), str(tmp_path / "other.c")], check=True)
    with pytest.raises(InputError, match="exports no XCP_ComputeKeyFromSeed"):
        load_key_function(str(tmp_path / "other.so"))


def _windows_dll(machine: int) -> bytes:
    """The headers of a Windows DLL (MZ, then the PE signature and its COFF machine field)."""
    head = bytearray(b"MZ" + bytes(0x3A) + struct.pack("<I", 0x80))
    head += bytes(0x80 - len(head)) + b"PE\0\0" + struct.pack("<H", machine) + bytes(64)
    return bytes(head)


@pytest.mark.parametrize(("machine", "built_for"), [(0x14C, "Windows on x86 (32-bit)"),
                                                      (0x8664, "Windows on x86-64 (64-bit)")])
def test_a_windows_dll_is_refused_on_linux_saying_what_it_is(tmp_path, machine, built_for):
    (tmp_path / "SeedNKeyXcp.dll").write_bytes(_windows_dll(machine))
    with pytest.raises(InputError) as refused:
        load_key_function("SeedNKeyXcp.dll", base=tmp_path)
    message = str(refused.value)
    assert f"is built for {built_for}; this Python runs on Linux" in message
    assert "'module:function'" in message


@pytest.mark.skipif(platform.machine() != "x86_64" or sys.platform != "linux", reason="says what an x86-64 Linux is")
def test_a_library_of_the_other_bitness_is_refused(tmp_path):
    elf32 = b"\x7fELF" + bytes([1, 1, 1]) + bytes(11) + struct.pack("<HH", 3, 3) + bytes(44)  # ELFCLASS32, EM_386
    (tmp_path / "libkey32.so").write_bytes(elf32)
    with pytest.raises(InputError, match=r"is built for Linux on x86 \(32-bit\); this Python runs on Linux on x86-64 "
                                         r"\(64-bit\): a 32-bit Python loads it"):
        load_key_function(str(tmp_path / "libkey32.so"))


def test_a_file_that_is_no_library(tmp_path):
    (tmp_path / "keys.dll").write_text("not a library")
    with pytest.raises(InputError, match="not a library"):
        load_key_function(str(tmp_path / "keys.dll"))
    with pytest.raises(InputError, match="seed & key library 'missing.so' not found"):
        load_key_function("missing.so", base=tmp_path)


@pytest.mark.gcc
@needs_gcc
def test_the_library_unlocks_the_ecu_from_the_command_line(key_library, free_udp_port, capsys):
    with serve_demo({"interface": "udp_multicast", "port": free_udp_port}):
        bus = ["--bus-kwargs", f"port={free_udp_port}", "--key-function", key_library]
        calls = ctypes.c_uint32.in_dll(ctypes.CDLL(str(key_library)), "calls")  # the library the command loads
        before = calls.value
        code, _, err = run(capsys, "cal", "set", "xsSWITCH_TANK_THR", "30", *bus)
        assert (code, err) == (0, ""), err
        assert calls.value > before  # CAL/PAG unlocked with the library's key, not the A2L's Python function
        assert run(capsys, "cal", "get", "xsSWITCH_TANK_THR", *bus)[1].strip() == "xsSWITCH_TANK_THR = 30.00 bar"
