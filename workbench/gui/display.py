"""Whether Qt can open a window here, asked without importing Qt (Qt aborts the process when it cannot):
``workbench gui``/``demo`` say why in one line, the test suite falls back to the offscreen platform."""

from __future__ import annotations

import ctypes.util
import importlib.util
import os
import re
import socket
import sys
from pathlib import Path

__all__ = ["display_problem"]


def display_problem() -> str | None:
    """Why Qt could not open a window here (Linux without a display, or without the library Qt's X11
    platform needs since Qt 6.5), or None; an explicit QT_QPA_PLATFORM is the user's choice."""
    if not sys.platform.startswith("linux") or os.environ.get("QT_QPA_PLATFORM") or os.environ.get("WAYLAND_DISPLAY"):
        return None
    if not os.environ.get("DISPLAY"):
        return ("no display to open the window on (neither DISPLAY nor WAYLAND_DISPLAY is set): run it in a desktop "
                "session or over ssh -X, or add --screenshot PNG to render the window to a file")
    display = os.environ["DISPLAY"]
    if not _x_server_answers(display):
        return f"no X server answers on the display {display}: start one, or fix DISPLAY"
    if ctypes.util.find_library("xcb-cursor") is None:
        return "Qt's X11 platform needs libxcb-cursor0: install it (Debian/Ubuntu: sudo apt install libxcb-cursor0)"
    return _x11_plugin_problem()


def _x11_plugin_problem() -> str | None:
    """Why Qt's X11 platform plugin cannot be loaded (a system library it links is missing: Qt would abort the
    process), or None. Loading it is the one sure test; it loads the Qt libraries PySide6 loads anyway."""
    plugin = _x11_plugin()
    if plugin is None or not plugin.exists():
        return None  # no PySide6: require_gui names the package
    try:
        ctypes.CDLL(str(plugin))
    except OSError as exc:
        return (f"Qt's X11 platform cannot load: {exc}; install Qt's X11 libraries (Debian/Ubuntu: sudo apt install "
                "libxcb-cursor0 libxcb-icccm4 libxcb-keysyms1 libxcb-image0 libxcb-render-util0 libxkbcommon-x11-0)")
    return None


def _x11_plugin() -> Path | None:
    """PySide6's X11 platform plugin, found without importing Qt."""
    spec = importlib.util.find_spec("PySide6")
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(next(iter(spec.submodule_search_locations))) / "Qt" / "plugins" / "platforms" / "libqxcb.so"


def _x_server_answers(display: str) -> bool:
    """A local display (``:N``) has a socket an X server listens on; a remote one is not checked."""
    local = re.fullmatch(r"(?:unix)?:(\d+)(?:\.\d+)?", display)
    if local is None:
        return True
    path = f"/tmp/.X11-unix/X{local.group(1)}"
    for address in ("\0" + path, path):  # Linux's abstract socket first, as Xlib tries it
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
            try:
                probe.connect(address)
                return True
            except OSError:
                continue
    return False
