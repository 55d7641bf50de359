"""README.md as a contract: every code block runs as copied, in a fresh copy of the repository's files.

Shell blocks run line by line through bash with the installed ``workbench`` first on PATH; a ``workbench sim``
line is a server (the README says it serves until stopped): it runs beside the lines after it and stops on
Ctrl-C. Python blocks run as ``python -c``; a block that opens a Session gets the demo ECU (with the PCM)
on the default bus. The default bus is the test's own: python-can takes the ``CAN_CONFIG`` environment
variable's ``port`` for a udp_multicast bus that names none, in the README's commands and in the ECU alike.
The first block (install, open the demo window, run this suite) is what ``.ci/run`` does.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from workbench.sim import serve_demo

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
CLONE_DIRS = ("a2l", "assets", "dbc", "examples")  # what the blocks read; they write beside them
BLOCK = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)
TIMEOUT_S = 120


def code_blocks() -> list[tuple[int, str, str]]:
    """``(line, language, code)`` of every fenced block of the README."""
    text = README.read_text(encoding="utf-8")
    return [(text.count("\n", 0, match.start()) + 1, match.group(1), match.group(2)) for match in BLOCK.finditer(text)]


BLOCKS = code_blocks()
RUNNABLE = [block for block in BLOCKS[1:] if block[1]]  # untagged blocks are text (the layout tree)


def test_the_first_block_is_what_ci_runs():
    """Install, the demo window, the test command: .ci/run installs the same way and calls the same command."""
    line, language, code = BLOCKS[0]
    assert (line, language) == (1, "sh")
    install, test_command = code.splitlines()
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert "python3 -m venv .venv" in install and "python3 -m venv .venv" in ci
    assert 'pip install -e ".[dev]"' in install and 'pip install --quiet -e ".[dev]"' in ci
    assert install.endswith(".venv/bin/workbench demo")  # tests/gui/test_gui_cli.py runs the demo window
    assert test_command in ci.splitlines()


def test_every_block_is_a_kind_this_test_runs():
    assert {language for _, language, _ in RUNNABLE} <= {"sh", "python"}
    assert len(RUNNABLE) >= 5


@pytest.fixture
def clone(tmp_path, free_udp_port):
    """A fresh copy of the files the README's blocks use, and the environment they run in."""
    for name in CLONE_DIRS:
        shutil.copytree(ROOT / name, tmp_path / name)
    env = {**os.environ, "CAN_CONFIG": json.dumps({"port": free_udp_port}),
           "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    return tmp_path, env, free_udp_port


@pytest.mark.parametrize("line, language, code", RUNNABLE, ids=[f"line-{line}" for line, _, _ in RUNNABLE])
def test_the_block_runs_as_copied(clone, line, language, code):
    where, env, port = clone
    if language == "python":
        run_python(code, where, env, port)
    else:
        run_shell(code, where, env)


def run_python(code: str, where: Path, env: dict, port: int) -> None:
    if "Session.open" in code:
        with serve_demo({"interface": "udp_multicast", "port": port}, pcm_target_bar=25.0):
            result = subprocess.run([sys.executable, "-c", code], cwd=where, env=env, capture_output=True, text=True,
                                    timeout=TIMEOUT_S)
    else:
        result = subprocess.run([sys.executable, "-c", code], cwd=where, env=env, capture_output=True, text=True,
                                timeout=TIMEOUT_S)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr


def run_shell(code: str, where: Path, env: dict) -> None:
    servers: list[subprocess.Popen] = []
    try:
        for command in (line for line in code.splitlines() if line.split("#")[0].strip()):
            if command.startswith("workbench sim"):
                servers.append(start_server(command, where, env))
                continue
            result = subprocess.run(["bash", "-c", command], cwd=where, env=env, capture_output=True, text=True,
                                    timeout=TIMEOUT_S)
            assert result.returncode == 0, f"{command}\n{result.stdout}{result.stderr}"
            assert "Traceback" not in result.stderr, result.stderr
        for server in servers:  # Ctrl-C, as the banner says
            server.send_signal(signal.SIGINT)
            out, err = server.communicate(timeout=30)
            assert server.returncode == 0 and out.endswith("workbench sim: stopped\n"), err
    finally:
        for server in servers:
            if server.poll() is None:
                server.kill()
                server.wait()


def start_server(command: str, where: Path, env: dict) -> subprocess.Popen:
    """``workbench sim ...`` started as bash would (the comment dropped), once it says it serves."""
    server = subprocess.Popen(["bash", "-c", f"exec {command.split('#')[0]}"], cwd=where, env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    serving = threading.Event()

    def watch() -> None:
        for line in server.stdout:
            if line.startswith("serving"):
                serving.set()
                return

    threading.Thread(target=watch, daemon=True).start()
    if not serving.wait(60):
        server.kill()
        pytest.fail(f"{command}: no 'serving' banner: {server.communicate()[1]}")
    return server
