import json
from pathlib import Path

import pytest

from workbench import demo
from workbench.errors import InputError
from workbench.gui.project import (
    Connection,
    PlotSpec,
    Project,
    demo_project,
    load_project,
    recent_projects,
    remember_project,
    save_project,
)


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_a_project_survives_a_round_trip_with_paths_relative_to_its_file(tmp_path, suffix):
    (tmp_path / "ecu.a2l").write_text("")
    project = Project(a2l=tmp_path / "ecu.a2l", dbcs=[demo.dbc_can2()],
                      connection=Connection("udp_multicast", "239.74.163.2", None, {"port": 43210}),
                      plots=[PlotSpec("Rail", ["zsRailPressure", "FLCU_TO_PCM_002.RailPressure"], 30.0)],
                      tables=[["xsDC"]], editors=["xsSWITCH_TANK_THR"], layout="AAAA")
    path = tmp_path / f"bench{suffix}"
    save_project(project, path)
    text = path.read_text()
    assert str(tmp_path) not in text  # relative paths: the folder can move
    loaded = load_project(path)
    assert loaded.a2l == (tmp_path / "ecu.a2l").resolve()
    assert loaded.dbcs == [demo.dbc_can2().resolve()]
    assert loaded.connection == project.connection
    assert loaded.plots == project.plots and loaded.tables == project.tables and loaded.editors == project.editors
    assert loaded.layout == "AAAA" and loaded.path == path


def test_the_demo_project_names_files_that_exist():
    project = demo_project()
    assert all(Path(p).is_file() for p in (project.a2l, project.elf, project.s19, *project.dbcs))
    assert "zsRailPressure" in project.plots[0].signals and "xsSWITCH_TANK_THR" in project.editors


@pytest.mark.parametrize("content, message", [
    ("{not json", "not a project file"),
    ("[1, 2]", "a table of settings, not list"),
    ('{"plots": {"title": "x"}}', "'plots' must be list, not dict"),
    ('{"connection": {"iface": "x"}}', r"unknown connection setting\(s\) iface"),
    ('{"a2l": 5}', "'a2l' must be str, not int"),
])
def test_a_bad_project_file_is_one_line_naming_the_file_and_the_key(tmp_path, content, message):
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(InputError, match=message) as caught:
        load_project(path)
    assert str(path) in str(caught.value) and "\n" not in str(caught.value)


def test_a_missing_project_file_is_named(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_project(tmp_path / "missing.toml")


def test_recent_projects_come_newest_first_without_duplicates_or_vanished_files(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    first, second = tmp_path / "a.toml", tmp_path / "b.toml"
    for path in (first, second):
        save_project(Project(), path)
    remember_project(first)
    remember_project(second)
    remember_project(first)
    assert recent_projects() == [first.resolve(), second.resolve()]
    second.unlink()
    assert recent_projects() == [first.resolve()]
    stored = json.loads((tmp_path / "config" / "workbench" / "recent-projects.json").read_text())
    assert len(stored) == 2
