"""``python -m workbench``: the ``workbench`` command itself (the same exit codes and exit), for a shell
whose PATH lacks the console script's folder (Windows' Scripts, a venv not activated)."""

from workbench.cli import entry_point

__all__: list[str] = []

if __name__ == "__main__":
    entry_point()
