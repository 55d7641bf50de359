"""Variables of ``.symtab`` by the names C and C++ give them: demangled, with their scopes.

The fallback for an ELF without DWARF (or a symbol DWARF lacks) sees linker names:
``_ZN3app6detail11nestedValueE`` for ``app::detail::nestedValue``,
``_ZZN3app10Controller4stepEjE5calls`` for the static ``calls`` of
``app::Controller::step(unsigned int)``, gcc's ``tickCount.4`` and clang's
``wild_tick.tickCount`` for a C function's static. They become
:class:`~workbench.elf.lookup.Variable` records with the same scopes DWARF gives, so
one lookup (:class:`~workbench.elf.lookup.VariableTable`) serves both.

C++ names are demangled by the C++ runtime's own ``__cxa_demangle`` (libstdc++ or
libc++, through the ``cxxfilt`` package: what c++filt and gdb print). Where no C++
runtime library is found (Windows without one), mangled names stay as they are and the
first such name logs a warning.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from workbench.elf.lookup import Variable
from workbench.elf.symbols import Symbol

__all__ = ["split_qualified", "symtab_variables"]

_GCC_LOCAL = re.compile(r"([A-Za-z_$][\w$]*)\.\d+")  # gcc: a function's static "name.N"
_CLANG_LOCAL = re.compile(r"([A-Za-z_$][\w$]*)\.([A-Za-z_$][\w$]*)")  # clang: "function.name"
# demangled names that are not variables of the program: vtables, typeinfo, guard variables ...
_SPECIAL = ("vtable for ", "typeinfo for ", "typeinfo name for ", "VTT for ", "construction vtable for ",
            "guard variable for ", "reference temporary ", "TLS init function for ", "TLS wrapper function for ",
            "non-virtual thunk to ", "virtual thunk to ", "covariant return thunk to ", "transaction clone for ")


def symtab_variables(symbols: Iterable[Symbol]) -> tuple[list[Variable], dict[int, int]]:
    """The data symbols as variables, and the size of the symbol at each of their addresses."""
    variables: list[Variable] = []
    sizes: dict[int, int] = {}
    demangle = _Demangler()
    for symbol in symbols:
        if symbol.kind == "function":
            continue
        variable = _variable(symbol, demangle)
        if variable is not None:
            variables.append(variable)
            sizes.setdefault(symbol.address, symbol.size)
    return variables, sizes


def _variable(symbol: Symbol, demangle: "_Demangler") -> Variable | None:
    name, address, external = symbol.name, symbol.address, symbol.external
    if name.startswith("_Z"):
        demangled = demangle(name)
        if demangled is None:
            return Variable(name, address, None, external=external)
        if demangled.startswith(_SPECIAL):
            return None
        scopes, in_function = split_qualified(demangled)
        if not scopes:
            return None
        return Variable(scopes[-1], address, None, tuple(scopes[:-1]), external=external and not in_function,
                        function=in_function)
    if not external:
        local = _GCC_LOCAL.fullmatch(name)
        if local:
            return Variable(local.group(1), address, None, external=False)
        local = _CLANG_LOCAL.fullmatch(name)
        if local:
            return Variable(local.group(2), address, None, (local.group(1),), external=False, function=True)
    return Variable(name, address, None, external=external)


def split_qualified(demangled: str) -> tuple[list[str], bool]:
    """``"app::Controller::step(unsigned int)::calls"`` -> ``(["app", "Controller", "step", "calls"], True)``:
    the scopes without parameter lists, and whether the last one before the name is a function."""
    parts: list[str] = []
    depth = start = position = 0
    in_function = current_is_function = False
    text = demangled
    while position < len(text):
        char = text[position]
        if char in "<(":
            if char == "(" and depth == 0 and not text.startswith("(anonymous", position):
                current_is_function = True
                after = text.find("::", _matching(text, position))  # drop the parameters and " const" after them
                text = text[:position] + (text[after:] if after >= 0 else "")
                continue
            depth += 1
        elif char in ">)":
            depth -= 1
        elif depth == 0 and text.startswith("::", position):
            parts.append(text[start:position].strip())
            in_function = current_is_function
            current_is_function = False
            position += 2
            start = position
            continue
        position += 1
    parts.append(text[start:].strip())
    return [part for part in parts if part], in_function


def _matching(text: str, opening: int) -> int:
    depth = 0
    for position in range(opening, len(text)):
        if text[position] in "(<":
            depth += 1
        elif text[position] in ")>":
            depth -= 1
            if depth == 0:
                return position
    return len(text) - 1


class _Demangler:
    """``__cxa_demangle`` through cxxfilt, loaded on the first mangled name."""

    def __init__(self):
        self._demangler = None
        self._unavailable = False

    def __call__(self, name: str) -> str | None:
        if self._unavailable:
            return None
        import cxxfilt  # here: finding the C++ runtime runs ldconfig, and only C++ ELFs need it

        if self._demangler is None:
            self._demangler = cxxfilt.default_demangler
        try:
            return self._demangler.demangle(name)
        except cxxfilt.LibraryNotFound as exc:
            from workbench.logs import logger  # here: a batch a2l command never imports logging

            logger(__name__).warning("C++ names in .symtab stay mangled: %s", exc)
            self._unavailable = True
        except cxxfilt.Error:
            pass
        return None
