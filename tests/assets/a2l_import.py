"""Import an A2L into pya2ldb and keep what its C++ parser reported.

pya2ldb's parser logs syntax errors from C++ straight to the process's stdout and carries on; the
import runs once per distinct file with that output kept (:mod:`pya2ldb_cache`), and this process
opens the database it left.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from pya2ldb_cache import import_once

_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)


@dataclass
class ImportedA2l:
    path: Path
    session: object  # pya2l.model.SessionProxy
    parser_output: list[str] = field(default_factory=list)

    @property
    def parser_errors(self) -> list[str]:
        return [line for line in self.parser_output if "[error]" in line.lower()]

    def text_without_comments(self) -> str:
        return _COMMENT.sub(" ", self.path.read_text(encoding="utf-8"))


def import_file(path: Path) -> ImportedA2l:
    imported = import_once(path)
    assert imported.returncode == 0, f"pya2ldb failed on {path}:\n" + "\n".join(imported.output[-40:])
    return ImportedA2l(path, imported.session(), list(imported.output))
