"""Where the built-in demo ECU (the thesis's FLCU) lives.

In a source checkout the files are the repository's ``a2l/``, ``dbc/`` and
``assets/``; in an installed wheel they are packaged as ``workbench/_demo/``.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["a2l", "dbc_can2", "dbc_can3", "elf", "fragment_a2ls", "master_a2l", "path", "root", "s19"]

_PACKAGED = Path(__file__).resolve().parent / "_demo"
_CHECKOUT = Path(__file__).resolve().parent.parent


def root() -> Path:
    """The folder that holds the demo's ``a2l/``, ``dbc/`` and ``assets/``."""
    return _PACKAGED if _PACKAGED.is_dir() else _CHECKOUT


def path(*parts: str) -> Path:
    """A path inside the demo folder, e.g. ``path("assets", "FLCU.elf")``."""
    return root().joinpath(*parts)


def master_a2l() -> Path:
    """The master (header) A2L: PROJECT/MODULE, MOD_PAR, MOD_COMMON, IF_DATA XCP."""
    return path("a2l", "FLCU_master.a2l")


def fragment_a2ls() -> list[Path]:
    """The module fragments (one per application module), in a stable order."""
    return sorted(path("a2l", "modules").glob("*.a2l"))


def elf() -> Path:
    return path("assets", "FLCU.elf")


def s19() -> Path:
    return path("assets", "FLCU.s19")


def a2l() -> Path:
    """The merged A2L with every address updated from :func:`elf` (the project's A2L)."""
    return path("assets", "FLCU.a2l")


def dbc_can2() -> Path:
    """The FLCU's J1939-style vehicle bus (CAN2) database."""
    return path("dbc", "FLCU_CAN2.dbc")


def dbc_can3() -> Path:
    """The CAN3 validation database of thesis chapter 6.4."""
    return path("dbc", "CAN3_validation.dbc")
