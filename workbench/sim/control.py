"""The simulator's control channel: fault injection into a ``workbench sim`` running in another process.

``workbench sim`` serves :class:`~workbench.sim.inject.FlcuFaults` on a TCP socket of the local host
(127.0.0.1, a free port) and registers it under the endpoint it serves XCP on (its CAN bus, or its
Ethernet address) in a folder of the user's runtime directory. A test bench given the same bus
options finds it there (:func:`find_control`), so the requirement tests inject faults into a
simulator in another process with nothing but the bus options; a real ECU has no registration,
and the bench says that fault injection is not available there.

The protocol is one JSON object a line each way: ``{"call": "sensor_voltage", "args": ["rail", 4.9]}``
answered by ``{"ok": true, "result": "rail sensor (ANIN_CH_ID_003) at 4.9 V"}`` or
``{"ok": false, "error": "..."}``. Only the calls of :data:`CALLS` are served.
"""

from __future__ import annotations

import getpass
import hashlib
import json
import os
import socket
import socketserver
import tempfile
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from workbench.errors import InputError, WorkbenchError
from workbench.logs import logger

__all__ = ["CALLS", "ControlClient", "ControlServer", "endpoint_key", "endpoint_keys", "find_control",
           "serving_elsewhere"]

log = logger(__name__)

CALLS = frozenset({"sensor_voltage", "plant", "actuator_error", "channel_id_error", "pcm_message", "clear", "apply"})
HELLO = "hello"
TIMEOUT_S = 5.0


def endpoint_key(bus: Mapping[str, Any] | None = None, *, host: str | None = None, port: int | None = None,
                 protocol: str | None = None) -> str:
    """What identifies the ECU a master reaches: its CAN bus (interface, channel, udp_multicast's port)
    or its Ethernet endpoint (protocol, host, port)."""
    if bus is not None:
        return "can|{}|{}|{}".format(bus.get("interface", ""), bus.get("channel", ""), bus.get("port", ""))
    return f"{(protocol or 'udp').lower()}|{host}|{port}"


def endpoint_keys(served: Mapping[str, Any]) -> list[str]:
    """The keys a simulator registers its control channel under, from its :meth:`Simulator.describe
    <workbench.sim.server.Simulator.describe>`: the XCP endpoint, and the CAN bus it serves on."""
    xcp, buses = served.get("xcp") or {}, served.get("buses") or {}
    keys = []
    if xcp.get("transport") in ("UDP", "TCP"):
        keys.append(endpoint_key(host=xcp.get("host"), port=xcp.get("port"), protocol=xcp["transport"]))
    if isinstance(buses.get("CAN1"), Mapping) and "interface" in buses["CAN1"]:
        keys.append(endpoint_key(buses["CAN1"]))
    return keys


def _registry() -> Path:
    try:
        user = getpass.getuser()
    except (KeyError, OSError):  # no user name in this environment
        user = str(os.getuid()) if hasattr(os, "getuid") else "user"
    return Path(os.environ.get("XDG_RUNTIME_DIR") or tempfile.gettempdir()) / f"workbench-{user}" / "sim-control"


def _alive(pid) -> bool:
    if not isinstance(pid, int) or pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process (PermissionError), or no signals on this OS: maybe alive
        return True
    return True


def _entry(key: str) -> Path:
    return _registry() / (hashlib.sha1(key.encode()).hexdigest()[:16] + ".json")


class _Handler(socketserver.StreamRequestHandler):
    def handle(self) -> None:
        faults = self.server.faults
        for line in self.rfile:
            try:
                request = json.loads(line)
                call = request.get("call")
                if call == HELLO:
                    result = self.server.hello
                elif call in CALLS:
                    result = getattr(faults, call)(*request.get("args", ()), **request.get("kwargs", {}))
                else:
                    raise InputError(f"the simulator's control channel has no call {call!r}")
                answer = {"ok": True, "result": result}
            except (WorkbenchError, TypeError, ValueError, AttributeError) as exc:
                answer = {"ok": False, "error": str(exc)}
            log.info("control: %s -> %s", line.decode(errors="replace").strip(), answer)
            self.wfile.write(json.dumps(answer).encode() + b"\n")


class _Server(socketserver.ThreadingTCPServer):
    daemon_threads = True
    allow_reuse_address = True


class ControlServer:
    """Serves ``faults`` on 127.0.0.1 (``port`` 0: any free one) and registers it under ``keys``
    (:func:`endpoint_key` of the endpoints the simulator serves); a context manager."""

    def __init__(self, faults, keys: list[str], *, port: int = 0, hello: dict[str, Any] | None = None):
        self.faults = faults
        self.keys = keys
        self._server = _Server(("127.0.0.1", port), _Handler)
        self._server.faults = faults
        self._server.hello = dict(hello or {}, pid=os.getpid())
        self.address = self._server.server_address
        self._thread = threading.Thread(target=self._server.serve_forever, name="sim-control", daemon=True)
        self._registered: list[Path] = []

    def start(self) -> ControlServer:
        self._thread.start()
        record = {"host": self.address[0], "port": self.address[1], "pid": os.getpid()}
        for key in self.keys:
            path = _entry(key)
            try:
                path.parent.mkdir(parents=True, exist_ok=True)
                temporary = path.with_suffix(f".{os.getpid()}.tmp")
                temporary.write_text(json.dumps(dict(record, key=key)), encoding="utf-8")
                os.replace(temporary, path)
                self._registered.append(path)
            except OSError as exc:  # the channel still works for whoever is told its address
                log.warning("cannot register the control channel in %s: %s", path.parent, exc)
        return self

    def close(self) -> None:
        for path in self._registered:
            try:
                if json.loads(path.read_text(encoding="utf-8")).get("pid") == os.getpid():
                    path.unlink()
            except (OSError, ValueError):
                pass
        self._registered.clear()
        self._server.shutdown()
        self._server.server_close()

    def __enter__(self) -> ControlServer:
        return self.start()

    def __exit__(self, *exc_info) -> None:
        self.close()


class ControlClient:
    """A connection to a simulator's control channel; :meth:`call` raises :class:`InputError` with the
    simulator's answer when it refuses, :class:`WorkbenchError` when the channel is gone."""

    def __init__(self, host: str, port: int):
        self.address = (host, port)
        try:
            self._socket = socket.create_connection(self.address, timeout=TIMEOUT_S)
        except OSError as exc:
            raise WorkbenchError(f"the simulator's control channel at {host}:{port} does not answer: {exc}") from None
        self._file = self._socket.makefile("rwb")
        self.hello = self.call(HELLO)

    def call(self, name: str, *args, **kwargs) -> Any:
        request = json.dumps({"call": name, "args": args, "kwargs": kwargs}).encode() + b"\n"
        try:
            self._file.write(request)
            self._file.flush()
            line = self._file.readline()
        except OSError as exc:
            raise WorkbenchError(f"the simulator's control channel at {self.address[0]}:{self.address[1]}: {exc}") from None
        if not line:
            raise WorkbenchError(f"the simulator's control channel at {self.address[0]}:{self.address[1]} closed")
        answer = json.loads(line)
        if not answer.get("ok"):
            raise InputError(f"the simulator refused {name}: {answer.get('error')}")
        return answer.get("result")

    def close(self) -> None:
        self._file.close()
        self._socket.close()


def find_control(key: str) -> ControlClient | None:
    """The control channel of the simulator registered under ``key``, connected; None when no running
    simulator registered one (a real ECU, or a simulator on another host). A registration its simulator
    left behind (killed) is removed."""
    path = _entry(key)
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if record.get("key") != key:
        return None
    if not _alive(record.get("pid")):
        path.unlink(missing_ok=True)
        return None
    try:
        return ControlClient(record["host"], int(record["port"]))
    except (WorkbenchError, KeyError, ValueError):
        return None  # a registration left behind by a simulator that was killed


def serving_elsewhere(keys: list[str]) -> tuple[str, int] | None:
    """A running simulator of another process registered under one of the CAN ``keys`` (the same bus, so the same
    CAN ids): (its key, its pid). Two of them answer every command twice, in two byte orders if their profiles
    differ; None when there is none (on Ethernet the port's bind already refuses a second one; a virtual bus is
    a process's own)."""
    for key in keys:
        if not key.startswith("can|") or key.startswith("can|virtual|") or (client := find_control(key)) is None:
            continue
        try:
            pid = int(client.hello.get("pid", 0)) if isinstance(client.hello, dict) else 0
        finally:
            client.close()
        if pid and pid != os.getpid():
            return key, pid
    return None
