"""Reading the ECU's memory for the sync: neighbouring spans merged into few UPLOADs, progress per block."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from workbench.calib.memory import Span
from workbench.progress import Progress, report
from workbench.session import Session
from workbench.session.memory import merge_spans, read_merged

__all__ = ["EcuReader"]


@dataclass
class EcuReader:
    """A :data:`~workbench.sync.values.Fetch` over the session's ECU; counts what it uploaded.

    Reads on the page XCP is on: the caller chooses it (``session.on_page``).
    """

    session: Session
    progress: Progress | None = None
    label: str = "uploading"
    bytes_read: int = 0

    def __call__(self, spans: Iterable[Span]) -> dict[Span, bytes]:
        """``{span: bytes}`` of every span, read in merged blocks.

        :raises XcpCommandError, XcpTimeoutError: the ECU refused or did not answer.
        :raises Cancelled: the progress was cancelled (between blocks).
        """
        wanted = list(dict.fromkeys(spans))
        if not wanted:
            return {}
        total = sum(block.size for block in merge_spans(wanted))
        done = 0

        def read(block: Span) -> bytes:
            nonlocal done
            report(self.progress, done, total, self.label)
            data = self.session.read_memory(block.address, block.size, block.extension)
            done += block.size
            self.bytes_read += block.size
            return data

        with self.session.lock:
            found = read_merged(wanted, read)
        report(self.progress, total, total, self.label)
        return found
