"""Running the ``workbench`` command in-process, as the CLI tests do."""

from __future__ import annotations

from workbench.cli import main

__all__ = ["run"]


def run(capsys, *argv) -> tuple[int, str, str]:
    """``workbench ARGV...`` (each argument as text: paths may be given as they are): exit code, stdout, stderr."""
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err
