"""A package's public names imported from its modules on first use, as python-can does with its interfaces.

``__all__, __getattr__, __dir__ = lazy_exports(__name__, {"pkg.module": ("Name", ...)})`` in a
package's ``__init__`` lets ``from pkg import Name`` work while ``import pkg`` loads none of the
modules (and none of their heavy libraries: cantools, numpy, pyelftools) until a name is used.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping

__all__ = ["lazy_exports"]


def lazy_exports(package: str, exports: Mapping[str, tuple[str, ...]]
                 ) -> tuple[list[str], Callable[[str], object], Callable[[], list[str]]]:
    """``__all__`` (sorted), a module ``__getattr__`` and ``__dir__`` for ``package``.

    :param exports: module path -> the names it gives the package.
    """
    module_of = {name: module for module, names in exports.items() for name in names}
    names = sorted(module_of)

    def __getattr__(name: str) -> object:
        module = module_of.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)  # the next lookup finds it without this function
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(names))

    return names, __getattr__, __dir__
