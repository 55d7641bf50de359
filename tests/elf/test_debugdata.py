"""DebugData resolves A2L symbol paths the way the compiler laid them out.

types.c stores, for the paths in EXPECTED, ``&path`` and ``sizeof(path)`` in two
arrays; the compiler is the oracle, read back through .symtab and the file bytes.
"""

import shutil
import struct
import sys
from pathlib import Path

import pytest

from workbench.elf import dwarf
from workbench.elf.debugdata import DebugData
from workbench.elf.symbols import ElfSymbols
from workbench.elf.type_resolver import TypeResolver
from workbench.errors import InputError, UnknownSymbolError

FIXTURES = Path(__file__).parent / "fixtures"
DWARF_ELFS = ["types_dwarf5.elf", "types_dwarf4.elf", "types_dwarf2.elf", "types_m32.elf",
              "types_zdebug.elf", "types_zstd.elf"]  # the last two: DWARF 5 compressed (GNU .zdebug_*, zstd)
# A2L spellings of the paths in types.c's expected_address[], in order
EXPECTED = ["zsScalar", "zvLut", "zvLut.Table[3]", "outer.b.c", "outer.arr[2].d[1]", "outer.arr._3_",
            "matrix[2][3]", "matrix._4_", "vector._7_", "bits.after", "u.bytes[2]", "state", "node.value",
            "outer.last", "hidden_counter", "csConstant"]


def compiler_truth(path):
    elf = ElfSymbols(path)
    width = 8 if elf.elfclass == 64 else 4
    addresses = elf.read(elf.symbol("expected_address").address, width * len(EXPECTED))
    sizes = elf.read(elf.symbol("expected_size").address, 4 * len(EXPECTED))
    fmt = "<" + ("Q" if width == 8 else "I") * len(EXPECTED)
    return dict(zip(EXPECTED, zip(struct.unpack(fmt, addresses), struct.unpack("<" + "I" * len(EXPECTED), sizes))))


@pytest.mark.parametrize("elf_name", DWARF_ELFS)
def test_paths_resolve_to_the_compilers_addresses_and_sizes(elf_name):
    truth = compiler_truth(FIXTURES / elf_name)
    debug = DebugData(FIXTURES / elf_name, use_cache=False)
    for path, (address, size) in truth.items():
        found = debug.resolve(path)
        assert (found.address, found.size, found.source) == (address, size, "dwarf"), path


@pytest.mark.parametrize("elf_name", DWARF_ELFS)
def test_types_through_typedefs_qualifiers_enums_and_pointers(elf_name):
    debug = DebugData(FIXTURES / elf_name, use_cache=False)
    scalar = debug.resolve("zsScalar").type
    assert (scalar.kind, scalar.encoding, scalar.size, scalar.typedef) == ("base", "float", 4, "real32_T")
    assert debug.resolve("csConstant").type.typedef == "uint8_T"
    lut = debug.resolve("zvLut").type
    assert lut.kind == "struct" and lut.typedef == "zvLut_str" and [m.name for m in lut.members] == ["BP1", "Table"]
    assert debug.resolve("matrix").type.dims == (5, 6)
    assert debug.resolve("matrix[1]").type.dims == (6,)
    state = debug.resolve("state").type
    assert state.kind == "enum" and state.size == 4 and state.typedef == "tState"
    assert debug.resolve("node").type.member("next").type.kind == "pointer"
    assert debug.resolve("u").type.kind == "union"
    assert debug.resolve("big").type.encoding == "signed"


@pytest.mark.parametrize("elf_name", DWARF_ELFS)
def test_bitfields_give_storage_unit_and_bit_position(elf_name):
    debug = DebugData(FIXTURES / elf_name, use_cache=False)
    base = debug.resolve("bits").address
    found = [(debug.resolve(f"bits.{name}").address - base, debug.resolve(f"bits.{name}").bit_size,
              debug.resolve(f"bits.{name}").bit_position) for name in ("low", "mid", "high")]
    assert found == [(0, 3, 0), (0, 5, 3), (0, 12, 8)]


class _OneStruct:
    """The DIEs of ``struct { uint32_t field : 3; }`` as a DWARF 2 producer may write them: the field counted in
    a unit of one byte (DW_AT_byte_size 1) at offset 3, 2 bits below its most significant bit."""

    def __init__(self, big_endian: bool):
        self.order = ">" if big_endian else "<"
        self.dies = {
            1: dwarf.Die(1, dwarf.TAG_STRUCT, {dwarf.AT_BYTE_SIZE: 4}, True, 2, None),
            2: dwarf.Die(2, dwarf.TAG_MEMBER, {dwarf.AT_NAME: "field", dwarf.AT_TYPE: 3, dwarf.AT_MEMBER_LOCATION: 3,
                                               dwarf.AT_BYTE_SIZE: 1, dwarf.AT_BIT_OFFSET: 2, dwarf.AT_BIT_SIZE: 3},
                         False, 3, None),
            3: dwarf.Die(3, dwarf.TAG_BASE, {dwarf.AT_NAME: "uint32_t", dwarf.AT_BYTE_SIZE: 4, dwarf.AT_ENCODING: 7},
                         False, 4, None),
        }

    def die(self, offset):
        return self.dies[offset]

    def children(self, die):
        return [self.dies[2]] if die.offset == 1 else []


@pytest.mark.parametrize("big_endian, position", [(True, 3), (False, 27)])
def test_a_dwarf2_bitfield_is_read_through_a_unit_of_its_type(big_endian, position):
    # memory bits 3..5 of byte 3: the value bits 3..5 of a big-endian uint32 at offset 0, 27..29 of a little-endian
    [field] = TypeResolver(_OneStruct(big_endian)).resolve(1).members
    assert (field.offset, field.type.size, field.bit_size, field.bit_position) == (0, 4, 3, position)


def test_bad_paths_say_why():
    debug = DebugData(FIXTURES / "types_dwarf5.elf", use_cache=False)
    with pytest.raises(UnknownSymbolError, match="has no member 'nope'"):
        debug.resolve("outer.nope")
    with pytest.raises(UnknownSymbolError, match="index 4 is outside the array of 4"):
        debug.resolve("outer.arr[4]")
    with pytest.raises(UnknownSymbolError, match="has no index"):
        debug.resolve("zsScalar[0]")
    with pytest.raises(UnknownSymbolError, match="not_there"):
        debug.resolve("not_there")
    assert debug.find("outer..b") is None


def test_symtab_fallback_without_dwarf():
    debug = DebugData(FIXTURES / "types_symtab.elf", use_cache=False)
    truth = compiler_truth(FIXTURES / "types_symtab.elf")
    assert not debug.has_dwarf
    found = debug.resolve("outer")
    assert (found.source, found.type, found.address) == ("symtab", None, compiler_truth(FIXTURES / "types_dwarf5.elf")
                                                         ["outer.b.c"][0] - 2)
    assert debug.resolve("hidden_counter").address == truth["hidden_counter"][0]
    with pytest.raises(UnknownSymbolError, match="no DWARF type"):
        debug.resolve("outer.b.c")
    with pytest.raises(UnknownSymbolError):
        debug.resolve("_start")  # a function is not a variable


def test_index_is_cached_and_a_rebuilt_elf_is_not_served_stale(tmp_path):
    elf = tmp_path / "copy.elf"
    shutil.copy(FIXTURES / "types_dwarf5.elf", elf)
    cache = tmp_path / "cache"
    with DebugData(elf, cache_dir=cache) as first:
        assert not first.from_cache
        first.resolve("outer.arr[2].d[1]")
    assert len(list(cache.iterdir())) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cache", "copy.elf"]  # nothing beside the user's file
    with DebugData(elf, cache_dir=cache) as second:
        assert second.from_cache
        assert second.resolve("outer.arr[2].d[1]") == first.resolve("outer.arr[2].d[1]")
        assert second._reader is None  # answered from the cache without reading DWARF
    shutil.copy(FIXTURES / "types_m32.elf", elf)  # "rebuilt": another size, header and mtime
    with DebugData(elf, cache_dir=cache) as third:
        assert not third.from_cache
        assert third.resolve("outer.b.c").address == compiler_truth(FIXTURES / "types_m32.elf")["outer.b.c"][0]


def test_symbols_resolved_in_earlier_runs_stay_cached_together(tmp_path):
    """Each run adds what it resolved to the entry, keeping what earlier runs resolved and it did not ask for."""
    from workbench.elf.debugdata import ResolvedSymbol

    cache = tmp_path / "cache"
    elf = FIXTURES / "types_dwarf5.elf"
    with DebugData(elf, cache_dir=cache) as first:
        scalar = first.resolve("zsScalar")
    with DebugData(elf, cache_dir=cache) as second:
        member = second.resolve("outer.arr[2].d[1]")  # new: the index is read from the cache
    with DebugData(elf, cache_dir=cache) as third:
        assert third.resolve("outer.arr[2].d[1]") == member and third.resolve("zsScalar") == scalar
        assert type(third.resolve("zsScalar")) is ResolvedSymbol
        assert third._variables is None  # both answered by the entry alone
        with pytest.raises(UnknownSymbolError):
            third.resolve("no_such_variable")
    with DebugData(elf, cache_dir=cache) as fourth:
        assert fourth.resolve_error("no_such_variable") and fourth._variables is None  # the failure is cached too


def test_unreadable_cache_is_a_miss(tmp_path):
    cache = tmp_path / "cache"
    with DebugData(FIXTURES / "types_dwarf5.elf", cache_dir=cache):
        pass
    for entry in cache.iterdir():
        entry.write_bytes(b"not a pickle")
    with DebugData(FIXTURES / "types_dwarf5.elf", cache_dir=cache) as debug:
        assert not debug.from_cache and debug.resolve("zsScalar")


def test_an_entry_of_another_elf_under_the_same_name_is_a_miss(tmp_path, monkeypatch):
    """The entry names its ELF: two ELFs whose entries had one file name never answer for each other."""
    from workbench.elf.cache import IndexCache

    monkeypatch.setattr(IndexCache, "path_for", lambda self, elf_path, identity: self.directory / "shared.pickle")
    cache = tmp_path / "cache"
    with DebugData(FIXTURES / "types_dwarf5.elf", cache_dir=cache):
        pass
    with DebugData(FIXTURES / "types_m32.elf", cache_dir=cache) as other:
        assert not other.from_cache
        assert other.resolve("outer.b.c").address == compiler_truth(FIXTURES / "types_m32.elf")["outer.b.c"][0]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the Linux rule; elsewhere platformdirs decides")
@pytest.mark.parametrize("xdg, home", [(None, "/home/u"), ("/xdg/cache", "/home/u"), ("", "/home/u"),
                                       ("relative/cache", "/home/u"), (None, None), (None, "relative")])
def test_the_default_cache_folder_is_the_one_platformdirs_names(monkeypatch, xdg, home):
    """The index cache's folder is found without importing platformdirs (5-10 ms of every cached update), by
    its rule: $XDG_CACHE_HOME when absolute, else ~/.cache (the account's home when HOME is unset or relative)."""
    import platformdirs

    from workbench.elf.cache import default_cache_dir

    monkeypatch.delenv("WORKBENCH_CACHE_DIR", raising=False)
    for name, value in (("XDG_CACHE_HOME", xdg), ("HOME", home)):
        if value is None:
            monkeypatch.delenv(name, raising=False)
        else:
            monkeypatch.setenv(name, value)
    monkeypatch.setattr(platformdirs.unix.Unix, "_optionally_create_directory", lambda *args, **kwargs: None,
                        raising=False)
    assert default_cache_dir() == Path(platformdirs.user_cache_dir("workbench")) / "elf-index"


def test_workbench_cache_dir_names_the_cache_folder(tmp_path, monkeypatch):
    """A CI job keeps the index on a volume of its own without moving every other program's cache (XDG)."""
    from workbench.elf.cache import default_cache_dir

    monkeypatch.setenv("WORKBENCH_CACHE_DIR", str(tmp_path / "ci"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_dir() == tmp_path / "ci" / "elf-index"
    DebugData(FIXTURES / "types_dwarf5.elf").save()
    assert [entry.suffix for entry in (tmp_path / "ci" / "elf-index").iterdir()] == [".pickle"]
    assert not (tmp_path / "xdg").exists()


def test_a_rebuilt_elf_replaces_its_entry_and_the_folder_keeps_the_most_recently_used(tmp_path, monkeypatch):
    """Every build's ELF added an entry for good (a few MiB for 50,000 variables): an entry of an earlier build of
    the same file goes when the new one is stored, and beyond ENTRIES the least recently used go."""
    import os

    from workbench.elf import cache

    cache_dir, elves = tmp_path / "cache", []
    for number in range(5):
        elves.append(tmp_path / f"app{number}.elf")
        shutil.copy(FIXTURES / "types_dwarf5.elf", elves[-1])
    with DebugData(elves[0], cache_dir=cache_dir):
        pass
    os.utime(elves[0], ns=(0, 10**18))  # rebuilt: another modification time, another entry
    with DebugData(elves[0], cache_dir=cache_dir) as debug:
        assert not debug.from_cache
    assert [entry.name.split(".")[0] for entry in cache_dir.iterdir()] == ["app0"]

    monkeypatch.setattr(cache, "ENTRIES", 3)
    for elf in elves[1:3]:
        with DebugData(elf, cache_dir=cache_dir):
            pass
    with DebugData(elves[0], cache_dir=cache_dir) as debug:  # used again: the last to go
        assert debug.from_cache
    for elf in elves[3:]:
        with DebugData(elf, cache_dir=cache_dir):
            pass
    assert sorted(entry.name.split(".")[0] for entry in cache_dir.iterdir()) == ["app0", "app3", "app4"]


def test_not_an_elf(tmp_path):
    bad = tmp_path / "bad.elf"
    bad.write_bytes(b"ASAP2_VERSION 1 71\n")
    with pytest.raises(InputError, match="not a readable ELF"):
        DebugData(bad, use_cache=False)
    for use_cache in (False, True):  # the cache's lookup is no different (it said FileNotFoundError)
        with pytest.raises(InputError, match=r"missing\.elf: no such file$"):
            DebugData(tmp_path / "missing.elf", cache_dir=tmp_path / "cache", use_cache=use_cache)
        with pytest.raises(InputError, match=r": is a folder, not an ELF file$"):
            DebugData(tmp_path, cache_dir=tmp_path / "cache", use_cache=use_cache)
