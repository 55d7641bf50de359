"""Seed & key functions as Python plugins, never DLLs (vendor key DLLs do not load on Linux).

A key function is ``f(seed: bytes, resource: int) -> bytes`` (resource: 0x01 CAL/PAG, 0x04 DAQ,
0x08 STIM, 0x10 PGM). It is named the way the A2L's SEED_AND_KEY_EXTERNAL_FUNCTION or the user
names it:

* ``package.module:function`` — an importable module (the demo: ``workbench.sim.seedkey:compute_key``);
* ``path/to/keys.py:function`` — a Python file (relative paths from the A2L's folder, then the
  working folder);
* ``entry-point-name`` — a plugin installed under the ``workbench.seed_key`` entry point group.

A DLL name (``SeedNKey.dll``) is refused with a message that says what to give instead.
"""

from __future__ import annotations

import importlib
import importlib.util
from importlib.metadata import entry_points
from pathlib import Path

from workbench.errors import InputError
from workbench.xcp.master import KeyFunction

__all__ = ["ENTRY_POINT_GROUP", "load_key_function"]

ENTRY_POINT_GROUP = "workbench.seed_key"


def load_key_function(name: str, base: Path | None = None) -> KeyFunction:
    """The key function ``name`` refers to (see the module docstring for the forms).

    :param base: the folder relative file paths are looked up in first (the A2L's).
    :raises InputError: a DLL, a missing module/file/function, or something that is not callable.
    """
    spec = name.strip()
    if spec.lower().endswith((".dll", ".so", ".dylib")):
        raise InputError(f"the seed & key function {spec!r} is a native library; workbench loads Python key "
                         "functions only: give 'module:function' or 'file.py:function'")
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


def _module_from_file(path_text: str, base: Path | None):
    candidates = [Path(path_text)] if Path(path_text).is_absolute() else [
        *([base / path_text] if base is not None else []), Path.cwd() / path_text]
    path = next((candidate for candidate in candidates if candidate.is_file()), None)
    if path is None:
        raise InputError(f"seed & key file {path_text!r} not found (looked in {', '.join(str(c.parent) for c in candidates)})")
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
