"""DESIGN.md's dependency direction, checked on the imports of every module.

gui -> session (the ECU by name) -> (xcp, calib, can) -> (a2l, elf, image); record and flash
stand on the session, sync (datasets and images with the ECU, cache sync) on the session and
flash; sim uses image/a2l/can/elf but never xcp; only the CLI and the GUI sit on top. The ``workbench`` package itself exports Session lazily. A module may always use the shared
foundation (errors, progress, fileio, demo, findings, lazy_exports, logs) and what the simulated
slave and the master share: xcp_protocol (the XCP names), xcp_framing (XCP on Ethernet's header) and
bus_defaults (the default bus, opening a bus);
they import nothing of the workbench but the errors, so sim stays free of xcp.
"""

import ast
from pathlib import Path

import pytest

import workbench

PACKAGE = Path(workbench.__file__).parent
FOUNDATION = {"errors", "progress", "fileio", "demo", "findings", "lazy_exports", "logs", "xcp_protocol", "xcp_framing",
              "bus_defaults"}
ALLOWED = {
    "elf": set(),
    "image": set(),
    "a2l": {"elf", "image"},
    "can": {"a2l"},
    "sim": {"a2l", "can", "elf", "image"},
    "xcp": {"a2l", "elf", "image"},
    "calib": {"a2l", "elf", "image", "xcp", "can"},
    "session": {"a2l", "elf", "image", "xcp", "calib", "can"},
    "record": {"a2l", "xcp", "calib", "can", "session"},
    "flash": {"a2l", "elf", "image", "xcp", "session"},
    "sync": {"a2l", "image", "xcp", "calib", "session", "flash"},
    "testbench": {"a2l", "calib", "can", "record", "session", "sim"},
    "gui": {"a2l", "elf", "image", "xcp", "calib", "record", "can", "sim", "session", "flash", "sync", "testbench"},
    "cli": {"a2l", "elf", "image", "xcp", "calib", "record", "can", "sim", "gui", "session", "flash", "sync",
            "testbench"},
}


def _imported_subpackages(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
    return {n.split(".")[1] for n in names if n.startswith("workbench.") and n.count(".") >= 1}


@pytest.mark.parametrize("package", sorted(ALLOWED))
def test_a_package_imports_only_what_it_stands_on(package):
    offenders = []
    for path in sorted((PACKAGE / package).rglob("*.py")):
        for used in _imported_subpackages(path) - FOUNDATION - ALLOWED[package] - {package}:
            offenders.append(f"{path.relative_to(PACKAGE.parent)} imports workbench.{used}")
    assert offenders == []


def test_no_core_module_imports_qt():
    for path in sorted(PACKAGE.rglob("*.py")):
        if "gui" in path.relative_to(PACKAGE).parts:
            continue
        source = path.read_text(encoding="utf-8")
        assert "PySide6" not in source and "pyqtgraph" not in source, path


@pytest.mark.parametrize("module", ["xcp_protocol.py", "xcp_framing.py", "bus_defaults.py"])
def test_the_neutral_ground_of_master_and_simulator_stands_on_nothing(module):
    assert _imported_subpackages(PACKAGE / module) <= {"errors"}
