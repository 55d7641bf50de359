"""Import an A2L into pya2ldb and keep what its C++ parser reported.

pya2ldb's parser logs syntax errors from C++ straight to the process's stdout and
carries on, so the only way to see them is to capture file descriptors 1 and 2
around the import.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import re
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from pya2l import import_a2l

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
    with _fd_output() as output:
        session = import_a2l(str(path), in_memory=True, encoding="utf-8", progress_bar=False, loglevel="ERROR")
    return ImportedA2l(path, session, output)


@contextlib.contextmanager
def _fd_output():
    lines: list[str] = []
    with tempfile.TemporaryFile() as sink:
        sys.stdout.flush()
        sys.stderr.flush()
        saved = [os.dup(1), os.dup(2)]
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        try:
            yield lines
        finally:
            ctypes.CDLL(None).fflush(None)  # C stdio buffers of the parser's logger
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            lines.extend(sink.read().decode("utf-8", "replace").splitlines())
