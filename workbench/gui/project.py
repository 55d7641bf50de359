"""The project file: which ECU files, which connection, which windows with which signals.

A project is plain TOML (``.toml``) or JSON (``.json``, or any other name) that a person can read
and edit::

    a2l = "FLCU.a2l"                 # paths relative to the project file
    elf = "FLCU.elf"
    s19 = "FLCU.s19"
    dbcs = ["FLCU_CAN2.dbc"]

    [connection]                     # python-can's names, or host/port/protocol for Ethernet
    interface = "udp_multicast"
    channel = "239.74.163.2"

    [[plots]]
    title = "Rail pressure"
    signals = ["zsRailPressure", "csPCM_TO_FLCU_002_TargetRailPressure"]
    span_s = 10.0

    [[editors]]
    name = "xsSWITCH_TANK_THR"

    [columns]                        # column widths of the window's tables, as the user left them
    fixes = [180, 90, 90, 34, 60]

This module holds no Qt: it reads and writes files (atomically) and keeps the list of recent
projects in the user's config folder (platformdirs).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from workbench import demo
from workbench.errors import InputError
from workbench.fileio import atomic_write_text, read_text_input

__all__ = ["Connection", "PlotSpec", "Project", "demo_project", "load_project", "recent_projects",
           "remember_project", "save_project"]

_FILE_KEYS = ("a2l", "elf", "s19")
_RECENT = 10


@dataclass
class Connection:
    """How to reach the ECU; None: as the A2L's IF_DATA says."""

    interface: str | None = None
    channel: str | None = None
    bitrate: int | None = None
    bus_kwargs: dict[str, Any] = field(default_factory=dict)
    host: str | None = None
    port: int | None = None
    protocol: str | None = None  # "udp" / "tcp"
    key_function: str | None = None  # seed & key as Session.open takes its name (a key library's path ...)
    daq_can_ids: dict[int, int] = field(default_factory=dict)  # XCP on CAN: DAQ list -> CAN id set with SET_DAQ_ID

    def __post_init__(self) -> None:
        self.daq_can_ids = {int(number): int(can_id) for number, can_id in self.daq_can_ids.items()}  # JSON: str keys

    def session_options(self) -> dict[str, Any]:
        """The keyword arguments of ``Session.open`` for this connection."""
        return {"interface": self.interface, "channel": self.channel, "bitrate": self.bitrate,
                "bus_kwargs": dict(self.bus_kwargs), "host": self.host, "port": self.port, "protocol": self.protocol,
                "key_function": self.key_function, "daq_can_ids": dict(self.daq_can_ids)}

    def describe(self) -> str:
        if self.host or self.port or self.protocol:
            return f"XCP on {(self.protocol or 'udp').upper()} {self.host or '?'}:{self.port or '(A2L)'}"
        extra = "".join(f" {k}={v}" for k, v in self.bus_kwargs.items())
        return f"XCP on CAN {self.interface or '(default)'} {self.channel or ''}{extra}".rstrip()


@dataclass
class PlotSpec:
    title: str = "Measurement"
    signals: list[str] = field(default_factory=list)
    span_s: float = 10.0  # seconds of history shown while following the newest samples


@dataclass
class Project:
    """What a workbench window shows and where its ECU is. Paths are absolute in memory."""

    a2l: Path | None = None
    elf: Path | None = None
    s19: Path | None = None
    dbcs: list[Path] = field(default_factory=list)
    connection: Connection = field(default_factory=Connection)
    plots: list[PlotSpec] = field(default_factory=list)
    tables: list[list[str]] = field(default_factory=list)  # numeric views: their signals
    editors: list[str] = field(default_factory=list)  # calibration editors open, by name
    columns: dict[str, list[int]] = field(default_factory=dict)  # a table's column widths, by the table's name
    layout: str | None = None  # the window's dock layout (Qt's saveState, base64)
    path: Path | None = None  # where it was loaded from / saved to

    @property
    def name(self) -> str:
        return self.path.stem if self.path else "untitled"

    def to_dict(self) -> dict[str, Any]:
        """The file's content, paths relative to ``base`` (the project file's folder)."""
        base = self.path.parent if self.path else None
        data: dict[str, Any] = {}
        for key in _FILE_KEYS:
            if getattr(self, key) is not None:
                data[key] = _relative(getattr(self, key), base)
        if self.dbcs:
            data["dbcs"] = [_relative(p, base) for p in self.dbcs]
        connection = {k: v for k, v in asdict(self.connection).items() if v not in (None, {})}
        if connection:
            data["connection"] = connection
        if self.plots:
            data["plots"] = [asdict(plot) for plot in self.plots]
        if self.tables:
            data["tables"] = [{"signals": list(signals)} for signals in self.tables]
        if self.editors:
            data["editors"] = [{"name": name} for name in self.editors]
        if self.columns:
            data["columns"] = {name: list(widths) for name, widths in self.columns.items()}
        if self.layout:
            data["layout"] = self.layout
        return data


def _relative(path: Path, base: Path | None) -> str:
    if base is not None:
        try:
            return path.resolve().relative_to(base.resolve()).as_posix()
        except ValueError:
            pass
    return str(path)


def load_project(path: str | Path) -> Project:
    """Read a project file (TOML by the ``.toml`` extension, else JSON).

    :raises InputError: missing or malformed file, or a value of the wrong kind (named with its key).
    """
    path = Path(path)
    text = read_text_input(path, "a project file")
    try:
        if path.suffix.lower() == ".toml":
            import tomllib

            data = tomllib.loads(text)
        else:
            data = json.loads(text)
    except (ValueError, UnicodeDecodeError) as exc:  # tomllib.TOMLDecodeError and JSONDecodeError are ValueErrors
        raise InputError(f"{path}: not a project file: {exc}") from None
    if not isinstance(data, dict):
        raise InputError(f"{path}: a project file holds a table of settings, not {type(data).__name__}")
    return project_from_dict(data, path)


def project_from_dict(data: dict[str, Any], path: Path | None = None) -> Project:
    base = path.parent if path else Path.cwd()
    where = str(path) if path else "project"

    def expect(value, kind, key):
        if not isinstance(value, kind):
            raise InputError(f"{where}: '{key}' must be {getattr(kind, '__name__', kind)}, not {type(value).__name__}")
        return value

    def file(value, key) -> Path:
        return (base / expect(value, str, key)).resolve()

    project = Project(path=path)
    for key in _FILE_KEYS:
        if key in data:
            setattr(project, key, file(data[key], key))
    project.dbcs = [file(p, "dbcs") for p in expect(data.get("dbcs", []), list, "dbcs")]
    connection = expect(data.get("connection", {}), dict, "connection")
    known = set(Connection.__dataclass_fields__)
    unknown = set(connection) - known
    if unknown:
        raise InputError(f"{where}: unknown connection setting(s) {', '.join(sorted(unknown))}; "
                         f"known: {', '.join(sorted(known))}")
    project.connection = Connection(**connection)
    for plot in expect(data.get("plots", []), list, "plots"):
        plot = expect(plot, dict, "plots")
        project.plots.append(PlotSpec(str(plot.get("title", "Measurement")),
                                      [str(s) for s in expect(plot.get("signals", []), list, "plots.signals")],
                                      float(plot.get("span_s", 10.0))))
    for table in expect(data.get("tables", []), list, "tables"):
        project.tables.append([str(s) for s in expect(expect(table, dict, "tables").get("signals", []), list,
                                                      "tables.signals")])
    for editor in expect(data.get("editors", []), list, "editors"):
        project.editors.append(str(expect(editor, dict, "editors").get("name", "")))
    for name, widths in expect(data.get("columns", {}), dict, "columns").items():
        project.columns[str(name)] = [int(w) for w in expect(widths, list, f"columns.{name}") if isinstance(w, int)]
    if "layout" in data:
        project.layout = expect(data["layout"], str, "layout")
    return project


def save_project(project: Project, path: str | Path) -> None:
    """Write ``project`` to ``path`` (TOML for ``.toml``, else JSON), atomically; ``project.path`` becomes ``path``.

    :raises InputError: the place cannot be written.
    """
    path = Path(path)
    project.path = path
    data = project.to_dict()
    if path.suffix.lower() == ".toml":
        import tomli_w

        text = tomli_w.dumps(data)
    else:
        text = json.dumps(data, indent=2) + "\n"
    atomic_write_text(path, text)


def demo_project() -> Project:
    """The built-in demo ECU with the windows a new user should see first."""
    return Project(
        a2l=demo.a2l(), elf=demo.elf(), s19=demo.s19(), dbcs=[demo.dbc_can2()],
        plots=[
            PlotSpec("Rail pressure control", ["zsRailPressure", "csPCM_TO_FLCU_002_TargetRailPressure", "xsDC"]),
            PlotSpec("Tanks and valves", ["zsTank1Pressure", "zsTank2Pressure", "zsManifoldPressure",
                                          "xsValve1State", "xsValve2State"]),
        ],
        tables=[["zsRailPressure", "xsRailPressureErr", "xsPidP", "xsPidI", "xsPidFF", "xsFuelLevel",
                 "xsTankCtrlState", "xsLEDEn", "FLCU_TO_PCM_002.RailPressure"]],
        editors=["xsSWITCH_TANK_THR", "xvPRV_DC_FF"],
    )


# --- recent projects --------------------------------------------------------------------------

def _recent_file() -> Path:
    import platformdirs

    return Path(platformdirs.user_config_dir("workbench", appauthor=False)) / "recent-projects.json"


def recent_projects() -> list[Path]:
    """The projects opened last, newest first (those that still exist)."""
    try:
        paths = json.loads(_recent_file().read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    return [Path(p) for p in paths if isinstance(p, str) and Path(p).is_file()]


def remember_project(path: Path) -> None:
    """Put ``path`` first in the recent projects (a failure to write the list is not the user's problem)."""
    paths = [str(path.resolve())] + [str(p) for p in recent_projects() if p.resolve() != path.resolve()]
    try:
        file = _recent_file()
        file.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(file, json.dumps(paths[:_RECENT], indent=1))
    except (OSError, InputError):
        pass
