"""A project's files read before any ECU is there: the A2L (document, typed model, XCP settings),
the DBCs, and the variable browser's rows. Plain Python, run in a worker when a project opens."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from workbench.gui.models.variables import Variable, variables_of_a2l, variables_of_dbc
from workbench.gui.project import Project
from workbench.gui.signal_hub import SignalInfo

__all__ = ["Workspace", "load_workspace"]


@dataclass
class Workspace:
    project: Project
    doc: Any = None  # A2lDocument
    model: Any = None  # A2lModel
    config: Any = None  # XcpConfig; None: the A2L has none (an A2L for offline work), ``no_xcp`` says why
    no_xcp: str | None = None
    left_out: list[str] = field(default_factory=list)  # the A2L's /includes not found, each where and why
    file_values: Any = None  # FileValues of the project's s19/hex: the editors' values offline (None: no file)
    dbcs: list = field(default_factory=list)  # DbcFile
    variables: list[Variable] = field(default_factory=list)

    def dbc_signals(self):
        """Every signal of the DBCs as the CAN monitor names them (``Message.Signal``)."""
        from workbench.gui.can_monitor import dbc_signals

        return dbc_signals(dbc.database for dbc in self.dbcs)

    def can2_infos(self) -> list[SignalInfo]:
        """The DBCs' signals as the views describe them: unit, comment, range, value table, and the decimals of
        one raw step (as their fix calibrations and recordings show them)."""
        from workbench.can.model import step_decimals

        signals = {f"{message.name}.{signal.name}": signal
                   for dbc in self.dbcs for message in dbc.database.messages for signal in message.signals}
        infos = []
        for s in self.dbc_signals():
            signal = signals.get(s.name)
            states = tuple((float(raw), str(text)) for raw, text in (signal.choices or {}).items()) if signal else ()
            decimals = None if signal is None or states or signal.is_float else step_decimals(signal.scale, signal.offset)
            infos.append(SignalInfo(s.name, "CAN2", s.unit, s.comment, s.minimum, s.maximum, states, decimals))
        return infos


def load_workspace(project: Project) -> Workspace:
    """Read the project's A2L and DBCs. An A2L without IF_DATA XCP (a supplier's, one written by a2ltool from
    C sources) still opens: its objects are browsed, edited against datasets and compared offline. So does one whose
    ``/include`` names a file that is not there (XCPlite's ``XCP_104.aml`` beside an A2L sent on its own): the rest
    is read, :attr:`Workspace.left_out` says which.

    :raises InputError: a file that is missing or cannot be read (the message names it and where).
    """
    from workbench import demo
    from workbench.a2l import A2lDocument, read_xcp_config
    from workbench.a2l.includes import left_out
    from workbench.a2l.source import read_source
    from workbench.can import load_dbc
    from workbench.errors import A2lParseError

    workspace = Workspace(project)
    workspace.doc = A2lDocument.from_source(read_source(project.a2l or demo.a2l()), missing_ok=True)
    workspace.left_out += left_out(workspace.doc)
    workspace.model = workspace.doc.model()
    try:
        workspace.config = read_xcp_config(workspace.doc)
    except A2lParseError as exc:  # only a connection needs it: said when one is asked for
        workspace.no_xcp = str(exc)
    workspace.dbcs = [load_dbc(path) for path in project.dbcs]
    if project.s19 is not None:
        from workbench.gui.file_values import FileValues

        workspace.file_values = FileValues(workspace.model, project.s19)
    workspace.variables = variables_of_a2l(workspace.model) + variables_of_dbc(workspace.dbc_signals())
    return workspace
