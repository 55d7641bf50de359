"""One view of an ELF's debug information, whichever source answers (a2ltool's ``DebugData``).

:class:`DebugData` resolves A2L symbol paths (``a.b[2].c``, ``ns::obj.member``,
``function.static``: see :mod:`workbench.elf.lookup` for the names it reads) to
address, size and C type: from DWARF when the ELF has it, from ``.symtab`` otherwise
(C++ names demangled; no members). The ELF's section headers, its DWARF variables, and
every type and symbol path resolved are cached on disk, so a second run against the
same ELF reads no DWARF and answers most paths with one dict lookup.
"""

from __future__ import annotations

import pickle
import re
import struct
import sys
import threading
from itertools import repeat
from pathlib import Path
from typing import TYPE_CHECKING, Callable, NamedTuple, TypeVar

import numpy as np

from workbench.elf.cache import IndexCache
from workbench.elf.lookup import AmbiguousSymbolError, Variable, VariableTable, scope_splits, split_vector_spec
from workbench.elf.symbols import ElfSymbols
from workbench.errors import InputError, UnknownSymbolError
from workbench.progress import Progress, report

# The DWARF decoder, the C type model and the .symtab names are imported where DWARF is read, a type
# resolved or the symbol table searched: an update that its cached index answers needs none of them.
if TYPE_CHECKING:
    from workbench.elf import dwarf
    from workbench.elf.ctypes_model import CType
    from workbench.elf.dwarf_index import DwarfIndex
    from workbench.elf.paths import PathError
    from workbench.elf.type_resolver import TypeResolver

T = TypeVar("T")

__all__ = ["AmbiguousSymbolError", "DebugData", "ResolvedSymbol", "read_beside"]

_HEAD = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]*")  # the variable name a member/element path starts with
_HEAD_AND_SUFFIX = re.compile(r"^([A-Za-z_$][A-Za-z0-9_$]*|)(.*)$", re.M)  # one line: head, member suffix
_DWARF_SECTIONS = (".debug_info", ".debug_types", ".debug_abbrev", ".debug_str", ".debug_line_str",
                   ".debug_str_offsets", ".debug_addr")


class ResolvedSymbol(NamedTuple):
    """Where a symbol path lives: ``address`` and ``size`` in bytes."""

    path: str
    address: int
    size: int
    type: CType | None  # None when only .symtab knew the symbol
    source: str  # "dwarf" or "symtab"
    bit_size: int | None = None  # bitfield members
    bit_position: int | None = None  # lowest bit of a bitfield in its storage unit


class DebugData:
    """Symbols and types of one ELF file.

    ``cache_dir``: folder of the index cache (None: the user's cache folder);
    ``use_cache=False`` neither reads nor writes it. Raises :class:`InputError` for a
    file that is not an ELF.
    """

    def __init__(self, elf_path: str | Path, *, cache_dir: str | Path | None = None, use_cache: bool = True,
                 progress: Progress | None = None):
        self.path = Path(elf_path)
        self._cache = IndexCache(cache_dir) if use_cache else None
        self._reader: dwarf.DwarfReader | None = None
        self._index: DwarfIndex | None = None
        # symbol path -> what resolve() answered for it: a ResolvedSymbol, or why not (see _failure)
        self._found: dict[str, ResolvedSymbol | tuple] = {}
        # the cache's resolved symbols as plain tuples without their types, taken into _found when asked for
        # (65,000 unpickle in 14 ms so, in 38 ms as ResolvedSymbols, which an address update never needs); their
        # types wait pickled in _cached_types, so that reading the EPK loads none
        self._cached_symbols: dict[str, tuple] = {}  # path -> (path, address, size, source, bit_size, bit_position)
        self._cached_types: bytes | dict[str, CType] = {}
        self._stored_index: bytes | None = None  # the cache's variables and types, unpickled when needed
        cached = self._cache.load(self.path) if self._cache is not None else None
        self.from_cache = cached is not None and self._take_cached(cached)
        if not self.from_cache:
            self.elf = ElfSymbols(self.path)
            # the variables at file scope and in namespaces; those inside functions are read when needed
            self._variables: list[tuple] | None = self._read_variables(progress) if self.elf.has_dwarf else []
            self._statics: list[tuple] | None = None  # Variable fields
            # symbol path -> address: the names that designate one variable, then every path resolved since
            self._addresses = _unique_addresses(self._variables)
            self._types = {}
            self._has_variables = bool(self._variables)
        self._first: dict[str, tuple] | None = None  # name -> the first variable of that name (Variable fields)
        self._globals: VariableTable | None = None
        self._static_table: VariableTable | None = None
        self._symtab: tuple[VariableTable, dict[int, int]] | None = None
        self._resolver: TypeResolver | None = None
        self._walks: dict[tuple, tuple | PathError] = {}
        self._stored = self._index_size() if self.from_cache else None

    def _take_cached(self, cached: dict) -> bool:
        """Use a cache entry; False (a miss) when it does not have the expected shape."""
        try:
            self.elf = ElfSymbols.from_facts(self.path, cached["elf"])
            self._addresses: dict[str, int] = cached["addresses"]
            self._found = cached["failures"]
            self._cached_symbols = cached["symbols"]
            self._cached_types = cached["symbol_types"]
            self._has_variables = cached["has_variables"]
            # variables and types: most runs never need them (the paths they resolve are in _addresses)
            self._stored_index = cached["index"]
        except (KeyError, TypeError, ValueError):
            return False
        self._variables = self._statics = self._types = None
        return isinstance(self._addresses, dict) and isinstance(self._found, dict) \
            and isinstance(self._cached_symbols, dict) and isinstance(self._cached_types, bytes) \
            and isinstance(self._stored_index, bytes)

    def _load_index(self) -> None:
        """Unpickle the cached variables and types (a damaged entry is an InputError naming the cache)."""
        if self._variables is not None:
            return
        self._variables, self._statics, self._types = self._unpickled(self._stored_index)
        if self._stored is not None:  # what the cache holds: loading it adds nothing to store
            self._stored = (*self._stored[:2], len(self._types), self._statics is not None)

    def _unpickled(self, data: bytes):
        try:
            return pickle.loads(data)
        except Exception as exc:  # the entry's outer pickle was fine: this one is damaged or foreign
            raise InputError(f"{self.path}: the ELF index cache is damaged ({exc}); remove it or use --no-cache") \
                from None

    def _symbol_types(self) -> dict[str, CType]:
        """The types of the cache's resolved symbols, unpickled on first need."""
        if self._cached_types.__class__ is bytes:
            self._cached_types = self._unpickled(self._cached_types)
        return self._cached_types

    def __enter__(self) -> "DebugData":
        return self

    def __exit__(self, *exc) -> None:
        self.save()

    @property
    def has_dwarf(self) -> bool:
        return self._has_variables

    def resolve(self, path: str) -> ResolvedSymbol:
        """Address, size and type of an A2L symbol path; raises :class:`UnknownSymbolError`
        (with the reason) when the ELF does not have it. The answer is remembered (and cached
        with the index)."""
        found = self._remembered(path)
        if found is None:
            found = self._lookup(path)
            self._found[path] = found
        if found.__class__ is tuple:
            raise _failure(path, found)
        return found

    def _remembered(self, path: str) -> ResolvedSymbol | tuple | None:
        """What :meth:`resolve` answered for ``path`` in this run or a cached one, or None."""
        found = self._found.get(path)
        if found is None and (fields := self._cached_symbols.pop(path, None)) is not None:
            name, address, size, source, bit_size, bit_position = fields
            found = self._found[path] = ResolvedSymbol(name, address, size, self._symbol_types()[path], source,
                                                       bit_size, bit_position)
        return found

    def extent(self, path: str) -> tuple[int, int] | None:
        """``(address, size)`` of ``path``, None when the ELF does not have it: :meth:`find` without the type
        (a cached update reads its EPK so, loading no type)."""
        fields = self._cached_symbols.get(path)
        if fields is not None:
            return fields[1], fields[2]
        found = self.find(path)
        return None if found is None else (found.address, found.size)

    def variables(self) -> list[Variable]:
        """The DWARF variables at file scope and in namespaces, then the functions' statics, each in the order
        the ELF declares them (``insert``)."""
        if not self._has_variables:
            return []
        self._load_index()
        if self._statics is None:
            self._statics = self._read_function_statics()
        return [Variable._make(fields) for fields in (*self._variables, *self._statics)]

    def type_of(self, variable: Variable) -> CType:
        """The C type of a variable :meth:`variables` gave."""
        return self._type(variable.type_offset)

    def _lookup(self, path: str) -> ResolvedSymbol | tuple:
        """:meth:`resolve`'s answer, not remembered: the symbol, or why not (see :func:`_failure`). The
        address is remembered for :meth:`addresses`."""
        try:
            found = self._resolve(path)
        except AmbiguousSymbolError as exc:
            return ("ambiguous", tuple(exc.candidates))
        except UnknownSymbolError as exc:
            return ("unknown", exc.where)
        self._addresses[path] = found.address
        return found

    def _resolve(self, path: str) -> ResolvedSymbol:
        found = self._dwarf_variable(path)
        if found is not None:
            variable, suffix = found
            address = variable.address
            if address is None:  # DWARF without a location: the symbol table may still know it
                known = self._symtab_find(variable.qualified_name if variable.scope else variable.name)
                if known is None:
                    raise UnknownSymbolError(path, "the variable has no static address (optimised out?)")
                address = known[0].address
            offset, reached, bit_size, bit_position = self._walk(path, variable.type_offset, suffix)
            return ResolvedSymbol(path, address + offset, reached.size, reached, "dwarf", bit_size, bit_position)
        known = self._symtab_find(path)
        if known is None:
            raise UnknownSymbolError(path, self.path.name)
        (variable, suffix), sizes = known
        if suffix:
            raise UnknownSymbolError(path, f"{self.path.name} has no DWARF type of {variable.name!r} to find members in")
        return ResolvedSymbol(path, variable.address, sizes.get(variable.address, 0), None, "symtab")

    def _dwarf_variable(self, path: str) -> tuple[Variable, str] | None:
        """The DWARF variable ``path`` starts with: at file scope or in a namespace first, else a
        function's static. Raises :class:`AmbiguousSymbolError`."""
        if not self._has_variables:
            return None
        self._load_index()
        plain = self._plain_variable(path)
        if plain is not None:
            return Variable._make(plain[0]), plain[1]
        found = None
        if any(name in self._first_of_name() for name in _variable_names(path)):  # else no global can fit
            if self._globals is None:
                self._globals = VariableTable(self._variables)
            found = self._globals.find(path)
        if found is None:
            if self._static_table is None:
                if self._statics is None:
                    self._statics = self._read_function_statics()
                self._static_table = VariableTable(self._statics)
            found = self._static_table.find(path)
        return found

    def _plain_variable(self, path: str) -> tuple[tuple, str] | None:
        """The variable (its fields) and member suffix of a path that starts with a plain name which designates
        one variable at file scope (``x``, ``x.in.phys``, ``x[3]``: most paths of an A2L): what the scoped
        lookup would answer, for a dict lookup; None for other paths."""
        if not self._has_variables:
            return None
        self._load_index()
        name, suffix = _head_and_suffix(path)
        variable = self._first_of_name().get(name)
        # a unique name's address is in _addresses; the first variable of that name lives there
        if variable is None or variable[1] is None or self._addresses.get(name) != variable[1]:
            return None
        return variable, suffix

    def _member_addresses(self, paths: list[str], rows: list[int]) -> tuple[list[int], list[int], list[int]]:
        """The rows whose path is a member or element of a variable :meth:`_plain_variable` finds (``x.in.phys``,
        ``x[3]``: most paths an update has to resolve) and whose walk succeeds, with their addresses (remembered),
        and the other rows. Done for all at once: one regular expression splits every path into its head and
        member suffix, and a loop without calls takes what it can from the walks of earlier paths."""
        if not rows or not self._has_variables:
            return [], [], rows
        self._load_index()
        texts = [paths[row] for row in rows]
        joined = "\n".join(texts)
        splits = _HEAD_AND_SUFFIX.findall(joined)
        if "::" in joined or "{" in joined or len(splits) != len(rows):  # scoped, Vector's or odd names among them
            splits = [_head_and_suffix(path) for path in texts]
        first, known, walks = self._first_of_name(), self._addresses, self._walks
        members, addresses, others = [], [], []
        for row, path, (name, suffix), variable in zip(rows, texts, splits, map(first.get, (h for h, _ in splits))):
            if variable is not None and variable[1] is not None and known.get(name) == variable[1]:
                walked = walks.get((variable[2], suffix))
                if walked is None:
                    try:
                        walked = self._walk(path, variable[2], suffix)
                    except UnknownSymbolError:
                        pass
                if walked.__class__ is tuple:
                    known[path] = variable[1] + walked[0]
                    members.append(row)
                    addresses.append(variable[1] + walked[0])
                    continue
            others.append(row)
        return members, addresses, others

    def _first_of_name(self) -> dict[str, tuple]:
        """Name -> the first variable at file scope or in a namespace of that name (Variable fields)."""
        if self._first is None:
            self._first = dict(zip((variable[0] for variable in reversed(self._variables)), reversed(self._variables)))
        return self._first

    def _symtab_find(self, path: str) -> tuple[tuple[Variable, str], dict[int, int]] | None:
        """The ``.symtab`` variable ``path`` names (demangled C++ names, gcc's and clang's names of function
        statics) with the member suffix, and the symbol sizes by address."""
        names_text = self.elf.names_text()
        if not any(name.encode() in names_text for name in _variable_names(path)):
            return None  # no symbol's name has it: the symbol table need not be read
        if self._symtab is None:
            from workbench.elf.symtab_names import symtab_variables

            variables, sizes = symtab_variables(self.elf.symbol_list)
            self._symtab = VariableTable(variables), sizes
        table, sizes = self._symtab
        found = table.find(path)
        return None if found is None else (found, sizes)

    def _walk(self, path: str, type_offset: int | None, suffix: str) -> tuple[int, CType, int | None, int | None]:
        """The member/element ``suffix`` (".b[2].c") of a variable of this type, memoised: many
        variables share a type, so ``x.in.phys`` is worked out once for all of them."""
        key = (type_offset, suffix)
        found = self._walks.get(key)
        if found is None:
            from workbench.elf.paths import PathError, split_path, walk

            ctype = self._type(type_offset)
            try:
                _, steps = split_path("x" + suffix)
                found = walk(ctype, steps)
            except PathError as exc:
                found = exc
            self._walks[key] = found
        if found.__class__ is not tuple:  # the PathError that says why
            raise UnknownSymbolError(path, str(found))
        return found

    def addresses(self, paths: list[str], progress: Progress | None = None) -> np.ndarray:
        """The address of every symbol path as an int64 array: -1 where the ELF does not have it, -2 where
        the address does not fit 63 bits (:meth:`find` has it). The hot path of an address update: plain
        names and paths resolved before cost one dict lookup each."""
        get = self._addresses.get
        try:
            found = np.fromiter(map(get, paths, repeat(-1)), np.int64, len(paths))
        except OverflowError:  # an address beyond 2**63 (none fits an A2L): one at a time
            found = np.array([_int64_or_unknown(get(path, -1)) for path in paths], np.int64)
        unknown = np.flatnonzero(found < 0).tolist()
        looked_up = self._found
        members, addresses, others = self._member_addresses(paths, [row for row in unknown if paths[row] not in looked_up])
        others += [row for row in unknown if paths[row] in looked_up]
        report(progress, len(members), len(unknown), "resolving symbol paths")
        try:
            found[members] = addresses
        except OverflowError:  # beyond 63 bits
            found[members] = list(map(_int64_or_unknown, addresses))
        for row in others:  # paths looked up before (one the ELF lacks, say), scoped names, .symtab ...
            path = paths[row]
            symbol = looked_up.get(path)
            if symbol is None:
                symbol = self._lookup(path)
                if symbol.__class__ is tuple:  # remembered: the update asks why next
                    looked_up[path] = symbol
            if symbol.__class__ is not tuple:
                found[row] = _int64_or_unknown(symbol.address)
        return found

    def symbols(self, paths: list[str]) -> list[ResolvedSymbol | None]:
        """:meth:`find` of many paths (None where the ELF does not have one), remembering only the
        addresses (an update with ``--types`` looks up every object)."""
        found: list[ResolvedSymbol | None] = []
        for path in paths:
            symbol = self._remembered(path) or self._lookup(path)
            found.append(None if symbol.__class__ is tuple else symbol)
        return found

    def find(self, path: str) -> ResolvedSymbol | None:
        try:
            return self.resolve(path)
        except UnknownSymbolError:
            return None

    def resolve_error(self, path: str) -> str:
        """Why ``path`` cannot be resolved ("" when it can)."""
        try:
            self.resolve(path)
        except UnknownSymbolError as exc:
            return f"not in {exc.where}" if exc.where == self.path.name else exc.where
        return ""

    def is_ambiguous(self, path: str) -> bool:
        """Whether ``path`` fits several variables equally (see :class:`AmbiguousSymbolError`)."""
        try:
            self.resolve(path)
        except AmbiguousSymbolError:
            return True
        except UnknownSymbolError:
            return False
        return False

    def variable_names(self) -> list[str]:
        """The names that designate one variable (DWARF; without it the symbol table's data objects): where
        :mod:`workbench.elf.suggest` looks for a name like a missing one. (The index need not be loaded for them.)"""
        if self._has_variables:  # those names, and the paths resolved since: their members left out
            return [name for name in self._addresses if name.isidentifier()]
        return [symbol.name for symbol in self.elf.symbol_list if symbol.kind == "object"]

    def save(self) -> None:
        """Write the index cache if this run added to it (an ELF without DWARF is not cached)."""
        if self._cache is None or not self._has_variables or self._index_size() == self._stored:
            return
        index = self._stored_index
        if self._variables is not None:
            statics = None if self._statics is None else list(map(tuple, self._statics))
            index = pickle.dumps((list(map(tuple, self._variables)), statics, self._types), protocol=5)
        failures, symbols, types = {}, dict(self._cached_symbols), {}
        for path, found in self._found.items():
            if found.__class__ is tuple:
                failures[path] = found
            else:
                symbols[path] = (found.path, found.address, found.size, found.source, found.bit_size,
                                 found.bit_position)
                types[path] = found.type
        symbol_types = self._cached_types
        if types or symbol_types.__class__ is not bytes:
            symbol_types = pickle.dumps({**self._symbol_types(), **types}, protocol=5)
        self._cache.store(self.path, {"elf": self.elf.facts(), "addresses": self._addresses, "failures": failures,
                                      "symbols": symbols, "symbol_types": symbol_types,
                                      "has_variables": self._has_variables, "index": index})
        self._stored = self._index_size()

    def _index_size(self) -> tuple[int, int, int, bool]:
        loaded = self._variables is not None
        return (len(self._addresses), len(self._found) + len(self._cached_symbols), len(self._types) if loaded else -1,
                loaded and self._statics is not None)

    # -- DWARF ------------------------------------------------------------------------------
    def _dwarf(self) -> dwarf.DwarfReader:
        if self._reader is None:
            try:
                sections = {name: data for name in _DWARF_SECTIONS if (data := self.elf.section_bytes(name)) is not None}
            except OSError as exc:
                raise InputError(f"{self.path}: cannot read ({exc.strerror})") from None
            except (ValueError, struct.error) as exc:  # e.g. a compressed section that does not decompress
                raise InputError(f"{self.path}: unreadable DWARF section ({exc})") from None
            from workbench.elf import dwarf

            try:
                self._reader = dwarf.DwarfReader(sections, self.elf.little_endian)
            except _damaged_dwarf() as exc:
                raise InputError(f"{self.path}: unreadable DWARF ({exc})") from None
        return self._reader

    def _dwarf_index(self) -> DwarfIndex:
        if self._index is None:
            from workbench.elf.dwarf_index import DwarfIndex

            self._index = DwarfIndex(self._dwarf())
        return self._index

    def _read_variables(self, progress: Progress | None) -> list[tuple]:
        try:
            return self._dwarf_index().global_variables(progress)
        except _damaged_dwarf() as exc:
            raise InputError(f"{self.path}: unreadable DWARF ({exc})") from None

    def _read_function_statics(self) -> list[tuple]:
        try:
            return self._dwarf_index().function_statics()
        except _damaged_dwarf() as exc:
            raise InputError(f"{self.path}: unreadable DWARF ({exc})") from None

    def _type(self, offset: int | None) -> CType:
        self._load_index()
        if offset is not None and offset in self._types:
            return self._types[offset]
        if self._resolver is None:
            from workbench.elf.type_resolver import TypeResolver

            self._resolver = TypeResolver(self._dwarf(), self._types, self._dwarf_index().definition_of)
        try:
            return self._resolver.resolve(offset)
        except _damaged_dwarf() as exc:
            raise InputError(f"{self.path}: unreadable DWARF type at 0x{offset or 0:x} ({exc})") from None


def _damaged_dwarf() -> tuple[type[Exception], ...]:
    """What decoding damaged DWARF raises: reads past a section's end, unknown codes, bad struct reads."""
    from workbench.elf import dwarf

    return dwarf.DwarfError, IndexError, ValueError, KeyError, struct.error


def _failure(path: str, why: tuple) -> UnknownSymbolError:
    """The error a remembered failure stands for: ("ambiguous", candidates) or ("unknown", where)."""
    kind, detail = why
    return AmbiguousSymbolError(path, list(detail)) if kind == "ambiguous" else UnknownSymbolError(path, detail)


def _int64_or_unknown(address: int) -> int:
    """``address`` as :meth:`DebugData.addresses` gives it (-1: unknown, -2: beyond 63 bits)."""
    return address if 0 <= address < 2**63 else -2 if address >= 2**63 else -1


def _head_and_suffix(path: str) -> tuple[str, str]:
    """A path's variable name and member suffix, ("", "") for a scoped or Vector name (see _plain_variable)."""
    head = None if "::" in path or "{" in path else _HEAD.match(path)
    return (head.group(), path[head.end():]) if head is not None else ("", "")


def _variable_names(path: str) -> list[str]:
    """The names a variable that ``path`` designates may have (see :func:`scope_splits`)."""
    return [name for _, name, _ in scope_splits(split_vector_spec(path)[0])]


def _unique_addresses(variables: list[tuple]) -> dict[str, int]:
    """name -> address of the names that designate one variable (every definition at one address)."""
    names, places = [variable[0] for variable in variables], [variable[1] for variable in variables]
    addresses = dict(zip(names, places))
    if len(addresses) == len(names) and None not in addresses.values():  # most ELFs: no name twice
        return addresses
    addresses = {}
    repeated: set[str] = set()
    for name, address, *_ in variables:
        known = addresses.get(name)
        if address is None or (known is not None and known != address):
            repeated.add(name)
        elif known is None:
            addresses[name] = address
    for name in repeated:
        addresses.pop(name, None)
    return addresses


_SWITCH_INTERVAL = 0.0002  # seconds: while the ELF is read beside other work


def read_beside(work: Callable[[], T], elf_path: str | Path, *, cache_dir: str | Path | None = None,
                use_cache: bool = True, progress: Progress | None = None) -> tuple[T, DebugData]:
    """``work()``'s result and the :class:`DebugData` of ``elf_path``, read on a second thread while
    ``work`` runs (``progress`` hears of it from that thread).

    Reading an A2L is mostly numpy passes over its bytes, which let the other thread run. Meanwhile the
    interpreter hands over every 0.2 ms instead of 5, so ``work``, back from numpy, waits that long at most
    for its turn (an uncached update of 130,000 objects: 1,042 ms with 5, 932 ms with 0.2, medians;
    benchmarks/README.md has the rest). What ``work`` raises comes first, as when the two ran in turn;
    then what reading the ELF raised.
    """
    interval = sys.getswitchinterval()
    sys.setswitchinterval(_SWITCH_INTERVAL)
    try:
        elf_read = _Background(lambda: DebugData(elf_path, cache_dir=cache_dir, use_cache=use_cache,
                                                 progress=progress))
        try:
            result = work()
        except Exception:
            elf_read.join()
            raise
    finally:
        sys.setswitchinterval(interval)
    return result, elf_read.result()


class _Background(threading.Thread):
    """``function()`` on a thread of its own; :meth:`result` waits for its value or raises what it raised."""

    def __init__(self, function: Callable[[], T]):
        super().__init__(name="workbench-elf", daemon=True)
        self._function = function
        self._value = self._error = None
        self.start()

    def run(self) -> None:
        try:
            self._value = self._function()
        except BaseException as exc:  # noqa: BLE001 - handed to the caller, raised there
            self._error = exc

    def result(self):
        self.join()
        if self._error is not None:
            raise self._error
        return self._value
