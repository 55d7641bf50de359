"""The ECU's memory for the sync: a page of every calibration segment, read in merged UPLOADs with progress."""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass

from workbench.calib.memory import Span
from workbench.errors import InputError
from workbench.progress import Progress, report
from workbench.session import Session
from workbench.session.memory import merge_spans, read_merged

__all__ = ["EcuReader", "on_pages"]


@dataclass
class EcuReader:
    """A :data:`~workbench.sync.values.Fetch` over the session's ECU; counts what it uploaded.

    Reads on the page XCP is on: the caller chooses it (``session.on_page``). What it reads the session
    knows from then on (:meth:`Session.remember <workbench.session.Session.remember>`), so a write of
    those objects after it reads nothing again.
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

        blocks: dict[Span, bytes] = {}

        def read(block: Span) -> bytes:
            nonlocal done
            report(self.progress, done, total, self.label)
            data = blocks[block] = self.session.read_memory(block.address, block.size, block.extension)
            done += block.size
            self.bytes_read += block.size
            return data

        with self.session.lock:
            found = read_merged(wanted, read)
            self.session.remember(blocks)
        report(self.progress, total, total, self.label)
        return found


@contextmanager
def on_pages(session: Session, page: str | int | None = "working") -> Iterator[None]:
    """A context in which XCP reads and writes ``page`` ("working", "reference") of every calibration segment
    with pages (None: leave them as they are). Without XCP SEGMENTs there is one page: "working" is it.

    :raises InputError: "reference" (or a number) asked of an A2L that describes no calibration pages.
    """
    numbers = list(dict.fromkeys(segment.number for segment in session.config.segments))
    if not numbers and page not in (None, "working"):
        raise InputError(f"the A2L describes no calibration pages (XCP SEGMENT): there is no {page} page to read")
    with ExitStack() as stack:
        for number in numbers if page is not None else ():
            stack.enter_context(session.on_page(page, number))
        yield
