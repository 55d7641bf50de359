"""The package as a user meets it: the command, its groups, the import boundary."""

import ast
import importlib
import json
import pkgutil
import subprocess
import sys
import types
from pathlib import Path

import pytest

import workbench
from workbench.cli import GROUPS, main


def test_help_lists_every_group(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for group in ("a2l", "sim", "measure", "cal", "flash", "dbc", "gui", "demo", "info"):
        assert f"    {group} " in out


def test_unknown_group_is_a_usage_error(capsys):
    assert main(["frobnicate"]) == 2
    assert "invalid choice" in capsys.readouterr().err


@pytest.mark.parametrize("group", [g for g, _ in GROUPS])
def test_every_group_answers_help(group, capsys):
    code = main([group, "--help"])
    out, err = capsys.readouterr()
    assert code == 0 and group in out


def test_import_workbench_loads_no_qt():
    code = "import sys, workbench, workbench.cli; sys.exit(any(m.startswith(('PySide6', 'pyqtgraph')) for m in sys.modules))"
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0


def test_python_dash_m_workbench_is_the_command(tmp_path):
    """``python -m workbench`` (a PATH without the console script's folder) answers as ``workbench`` does."""
    def run(*args):
        return subprocess.run([sys.executable, "-m", "workbench", *args], capture_output=True, text=True, cwd=tmp_path,
                              check=False)

    version = run("--version")
    assert (version.returncode, version.stdout) == (0, "workbench 0.1.0\n")
    missing = run("a2l", "check", "missing.a2l")
    assert missing.returncode == 2 and missing.stderr.splitlines() == ["error: missing.a2l: no such file"]
    (tmp_path / "bad.a2l").write_text('/begin PROJECT p ""\n /begin MODULE m ""\n  /begin MEASUREMENT x "" UBYTE cm 0 0 0 1\n'
                                      '   ECU_ADDRESS 0x1000\n  /end MEASUREMENT\n /end MODULE\n/end PROJECT\n')
    failed = run("a2l", "check", "bad.a2l")  # COMPU_METHOD cm is not defined
    assert failed.returncode == 1 and "bad.a2l:3:" in failed.stdout


def test_a_closed_pipe_ends_quietly(tmp_path):
    script = tmp_path / "flood.py"
    script.write_text(
        "import sys, argparse, workbench.cli as cli\n"
        "def flood(args):\n"
        "    for n in range(200000):\n"
        "        print('line', n)\n"
        "parser = argparse.ArgumentParser()\n"
        "parser.add_argument('--debug', action='store_true')\n"
        "parser.set_defaults(func=flood, group='flood')\n"
        "cli.build_parser = lambda *only: parser\n"
        "sys.exit(cli.main([]))\n"
    )
    proc = subprocess.run(f"{sys.executable} {script} | head -1", shell=True, capture_output=True, text=True)
    assert proc.stdout == "line 0\n"
    assert proc.stderr == ""


@pytest.mark.parametrize("package", ["workbench.a2l", "workbench.can", "workbench.elf", "workbench.image", "workbench.sim",
                                     "workbench.calib", "workbench.calib.dataset", "workbench.flash", "workbench.sync",
                                     "workbench.record", "workbench.testbench"])
def test_every_export_resolves_and_no_submodule_shadows_it(package):
    module = importlib.import_module(package)
    for info in pkgutil.iter_modules(module.__path__):  # a submodule's first import sets it on its package
        importlib.import_module(f"{package}.{info.name}")
    exported = {name: getattr(module, name, None) for name in module.__all__}
    assert [name for name, value in exported.items() if value is None or isinstance(value, types.ModuleType)] == []


def _bound_at_top(body: list[ast.stmt]) -> set[str]:
    """The names a module's top level binds (defs, classes, assignments, imports; inside top-level if/try too)."""
    names = set()
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                names.update(n.id for n in ast.walk(target) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store))
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
        elif isinstance(node, ast.If) and "TYPE_CHECKING" not in ast.unparse(node.test):
            names |= _bound_at_top(node.body) | _bound_at_top(node.orelse)
        elif isinstance(node, ast.Try):
            names |= _bound_at_top(node.body) | _bound_at_top(node.orelse)
    return names


def test_every_module_has_an_all_of_names_it_defines():
    """STYLE: ``__all__`` per module, naming what it binds. Read from the source (no module imported): left out only
    a module that binds no name (a package's docstring) and the FLCU requirement tests, which pytest collects."""
    found = {}
    for path in sorted(Path(workbench.__file__).parent.rglob("*.py")):
        if "flcu_suite" in path.parts:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        bound = _bound_at_top(tree.body)
        listed = [node.value for node in tree.body if isinstance(node, (ast.Assign, ast.AnnAssign))
                  and "__all__" in _bound_at_top([node])]
        name = str(path.relative_to(Path(workbench.__file__).parent.parent))
        if not listed:
            if bound - {"annotations"}:  # ``from __future__ import annotations`` alone binds nothing of its own
                found[name] = "no __all__"
        elif isinstance(listed[0], ast.List):  # a lazy package computes its own (checked by the test above)
            missing = [n.value for n in listed[0].elts if isinstance(n, ast.Constant) and n.value not in bound]
            if missing:
                found[name] = missing
    assert found == {}


def test_a_command_that_names_no_python_can_option_loads_no_python_can():
    # import can loads asammdf and pandas (0.3-0.5 s): XCP on Ethernet and a flash image need none of it
    s19 = Path(workbench.__file__).parents[1] / "assets" / "FLCU.s19"
    code = ("import json, sys; from workbench.cli import build_parser, main;"
            "ethernet = build_parser('info').parse_args(['info', '--host', '127.0.0.1', '--port', '5555']);"
            f"code = main(['cal', 'get', 'xsPRV_PWM_PERIOD', '--image', {str(s19)!r}]);"
            "before = 'can' in sys.modules;"
            "can = build_parser('info').parse_args(['info', '--inter', 'virtual', '-c', 'x']);"
            "print(json.dumps([code, ethernet.host, before, can.interface, can.channel, 'can' in sys.modules]))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(run.stdout.splitlines()[-1]) == [0, "127.0.0.1", False, "virtual", "x", True]


def test_the_lazy_packages_load_no_heavy_library_until_a_name_is_used():
    code = ("import json, sys, workbench, workbench.a2l, workbench.can, workbench.calib.dataset, workbench.flash, "
            "workbench.sync, workbench.record, workbench.cli;"
            "print(json.dumps(sorted({m.split('.')[0] for m in sys.modules} & "
            "{'numpy', 'cantools', 'can', 'elftools', 'pyxcp', 'asammdf', 'pya2l', 'rich', 'bincopy', 'lxml'})))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(run.stdout) == []
