"""Seed & key functions: Python plugins, or native key libraries with ASAM's interface.

A key function is ``f(seed: bytes, resource: int) -> bytes`` (resource: 0x01 CAL/PAG, 0x04 DAQ,
0x08 STIM, 0x10 PGM). It is named the way the A2L's SEED_AND_KEY_EXTERNAL_FUNCTION or the user
names it:

* ``package.module:function`` — an importable module (the demo: ``workbench.sim.seedkey:compute_key``);
* ``path/to/keys.py:function`` — a Python file;
* ``entry-point-name`` — a plugin installed under the ``workbench.seed_key`` entry point group;
* ``SeedNKey.dll``, ``libseednkey.so`` — a key library exporting ASAM's ``XCP_ComputeKeyFromSeed``
  (cdecl), as CANape and INCA load them. It must be built for this Python's system, processor and
  bitness (a Windows DLL loads only in a Windows Python; a 32-bit one only in a 32-bit Python): the file's
  header is read first, and a library that cannot load here is refused saying what it was built for.

Relative file paths are looked up in the A2L's folder, then in the working folder.
"""

from __future__ import annotations

import ctypes
import importlib
import importlib.util
import platform
import struct
import sys
from importlib.metadata import entry_points
from pathlib import Path

from workbench.errors import InputError
from workbench.xcp.master import KeyFunction

__all__ = ["ENTRY_POINT_GROUP", "library_key_function", "load_key_function"]

ENTRY_POINT_GROUP = "workbench.seed_key"


def load_key_function(name: str, base: Path | None = None) -> KeyFunction:
    """The key function ``name`` refers to (see the module docstring for the forms).

    :param base: the folder relative file paths are looked up in first (the A2L's).
    :raises InputError: a missing module/file/function, something that is not callable, or a key library that
        cannot load in this Python.
    """
    spec = name.strip()
    if _is_library(spec):
        return library_key_function(_file(spec, base, "seed & key library"))
    if ":" not in spec:
        return _from_entry_point(spec)
    module_part, _, function_name = spec.rpartition(":")
    if module_part.endswith(".py") or "/" in module_part or "\\" in module_part:
        module = _module_from_file(module_part, base)
    else:
        try:
            module = importlib.import_module(module_part)
        except ImportError as exc:
            raise InputError(f"seed & key function {spec!r}: cannot import {module_part!r} ({exc})") from None
    function = getattr(module, function_name, None)
    if not callable(function):
        raise InputError(f"seed & key function {spec!r}: {module_part!r} has no function {function_name!r}")
    return function


def _file(path_text: str, base: Path | None, what: str) -> Path:
    candidates = [Path(path_text)] if Path(path_text).is_absolute() else [
        *([base / path_text] if base is not None else []), Path.cwd() / path_text]
    path = next((candidate for candidate in candidates if candidate.is_file()), None)
    if path is None:
        raise InputError(f"{what} {path_text!r} not found (looked in {', '.join(str(c.parent) for c in candidates)})")
    return path


def _module_from_file(path_text: str, base: Path | None):
    path = _file(path_text, base, "seed & key file")
    spec = importlib.util.spec_from_file_location(f"workbench_seed_key_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as exc:  # the user's file: say what went wrong, in one line
        raise InputError(f"seed & key file {path}: {type(exc).__name__}: {exc}") from None
    return module


def _from_entry_point(name: str) -> KeyFunction:
    found = [ep for ep in entry_points(group=ENTRY_POINT_GROUP) if ep.name == name]
    if not found:
        raise InputError(f"seed & key function {name!r}: give 'module:function' or 'file.py:function', or install a "
                         f"plugin under the entry point group {ENTRY_POINT_GROUP!r}")
    try:
        function = found[0].load()
    except Exception as exc:
        raise InputError(f"seed & key plugin {name!r}: {type(exc).__name__}: {exc}") from None
    if not callable(function):
        raise InputError(f"seed & key plugin {name!r} is not a function")
    return function


# ASAM's return codes of XCP_ComputeKeyFromSeed
_LIBRARY_ERRORS = {1: "the privilege (resource) is not available", 2: "invalid seed length",
                   3: "the key buffer is too short"}
_KEY_BUFFER = 255  # the interface's key length is a byte


def _is_library(spec: str) -> bool:
    name = spec.lower()
    return name.endswith((".dll", ".so", ".dylib")) or ".so." in Path(name).name  # libkey.so.1


def library_key_function(path: Path):
    """The key function of a native key library: ASAM's
    ``uint32 XCP_ComputeKeyFromSeed(uint8 resource, uint8 seedLength, uint8 *seed, uint8 *keyLength, uint8 *key)``
    (``keyLength`` in: the buffer's size, out: the key's), 0 for success.

    :raises InputError: the library is built for another system, processor or bitness, does not load, or
        does not export the function.
    """
    built_for, here = _built_for(path), _this_python()
    if built_for is None:
        raise InputError(f"seed & key library {path}: not a library (neither a Windows DLL, an ELF nor a Mach-O file)")
    if built_for != here:
        advice = ("a 32-bit Python loads it" if built_for[0] == here[0] and built_for[1:] == ("x86", 32) else
                  "give the key algorithm as a Python function ('module:function' or 'file.py:function'), or a "
                  "build of the library for this computer")
        raise InputError(f"seed & key library {path} is built for {_describe(built_for)}; this Python runs on "
                         f"{_describe(here)}: {advice}")
    try:
        library = ctypes.CDLL(str(path))
    except OSError as exc:
        raise InputError(f"seed & key library {path}: cannot load it ({exc})") from None
    try:
        compute = library.XCP_ComputeKeyFromSeed
    except AttributeError:
        raise InputError(f"seed & key library {path}: it exports no XCP_ComputeKeyFromSeed (ASAM's key library "
                         "interface)") from None
    byte_pointer = ctypes.POINTER(ctypes.c_uint8)
    compute.argtypes = [ctypes.c_uint8, ctypes.c_uint8, byte_pointer, byte_pointer, byte_pointer]
    compute.restype = ctypes.c_uint32

    def compute_key(seed: bytes, resource: int) -> bytes:
        if len(seed) > _KEY_BUFFER:
            raise ValueError(f"a seed of {len(seed)} bytes: the library interface takes 255 at most")
        seed_buffer = (ctypes.c_uint8 * max(len(seed), 1)).from_buffer_copy(seed.ljust(1, b"\0"))
        key, key_length = (ctypes.c_uint8 * _KEY_BUFFER)(), ctypes.c_uint8(_KEY_BUFFER)
        status = compute(resource, len(seed), seed_buffer, ctypes.byref(key_length), key)
        if status:
            raise ValueError(f"XCP_ComputeKeyFromSeed returned {status} ({_LIBRARY_ERRORS.get(status, 'an error')})")
        return bytes(key[:key_length.value])

    compute_key.__name__ = f"{path.name}:XCP_ComputeKeyFromSeed"
    return compute_key


# (system, processor, bits): what a library is built for and what this Python is
_PE_MACHINES = {0x14C: ("x86", 32), 0x8664: ("x86-64", 64), 0xAA64: ("ARM64", 64), 0x1C4: ("ARM", 32)}
_ELF_MACHINES = {3: "x86", 62: "x86-64", 40: "ARM", 183: "ARM64"}
_MACHO_CPUS = {7: ("x86", 32), 0x01000007: ("x86-64", 64), 12: ("ARM", 32), 0x0100000C: ("ARM64", 64)}
_PYTHON_MACHINES = {"x86_64": "x86-64", "amd64": "x86-64", "i386": "x86", "i686": "x86", "x86": "x86",
                    "aarch64": "ARM64", "arm64": "ARM64", "armv7l": "ARM"}


def _built_for(path: Path) -> tuple[str, str, int] | None:
    """(system, processor, bits) from the file's header; None for a file that is no library of a known kind."""
    try:
        with open(path, "rb") as file:
            head = file.read(4096)
    except OSError as exc:
        raise InputError(f"seed & key library {path}: cannot read it ({exc.strerror})") from None
    if head[:4] == b"\x7fELF" and len(head) >= 20:
        bits = 64 if head[4] == 2 else 32
        machine = struct.unpack_from("<H" if head[5] == 1 else ">H", head, 18)[0]
        return "Linux", _ELF_MACHINES.get(machine, f"machine {machine}"), bits
    if head[:2] == b"MZ" and len(head) >= 64:
        pe = struct.unpack_from("<I", head, 0x3C)[0]
        if head[pe:pe + 4] == b"PE\0\0":
            machine = struct.unpack_from("<H", head, pe + 4)[0]
            processor, bits = _PE_MACHINES.get(machine, (f"machine 0x{machine:X}", 0))
            return "Windows", processor, bits
    if head[:4] in (b"\xcf\xfa\xed\xfe", b"\xce\xfa\xed\xfe"):  # Mach-O, little-endian
        processor, bits = _MACHO_CPUS.get(struct.unpack_from("<I", head, 4)[0], ("another processor", 0))
        return "macOS", processor, bits
    return None


def _this_python() -> tuple[str, str, int]:
    system = {"win32": "Windows", "darwin": "macOS"}.get(sys.platform, "Linux")
    bits = struct.calcsize("P") * 8
    machine = _PYTHON_MACHINES.get(platform.machine().lower(), platform.machine())
    if machine == "x86-64" and bits == 32:  # a 32-bit Python on a 64-bit Windows
        machine = "x86"
    return system, machine, bits


def _describe(built_for: tuple[str, str, int]) -> str:
    system, processor, bits = built_for
    return f"{system} on {processor} ({bits}-bit)" if bits else f"{system} on {processor}"
