"""Which variable a name means: scopes, Vector's suffix, ambiguity, demangled .symtab names,
C++ member lookup through anonymous members and base classes; and the index cache keeps it."""

import shutil
from pathlib import Path

import pytest

from workbench.elf.ctypes_model import CMember, CType, MemberError
from workbench.elf.debugdata import AmbiguousSymbolError, DebugData
from workbench.elf.lookup import Variable, VariableTable, VectorSpec, scope_splits, split_vector_spec
from workbench.elf.paths import PathError, split_path, walk
from workbench.elf.symtab_names import split_qualified

MATRIX = Path(__file__).parent / "matrix"


def test_scope_splits_plainest_first():
    assert list(scope_splits("a.b[2]")) == [((), "a", ".b[2]"), (("a",), "b", "[2]")]
    assert list(scope_splits("app::Controller::step.calls")) == [
        (("app", "Controller"), "step", ".calls"), (("app", "Controller", "step"), "calls", "")]
    assert list(scope_splits("(anonymous namespace)::x")) == [(("(anonymous namespace)",), "x", "")]


def test_vector_suffix():
    assert split_vector_spec("x.y{Function:f}{Namespace:inner}{Namespace:outer}{CompileUnit:a_c}{Namespace:Global}") \
        == ("x.y", VectorSpec("f", ("outer", "inner"), "a_c"))
    assert split_vector_spec("x{Oops}") == ("x{Oops}", None)


def test_file_scope_wins_then_external_linkage_then_ambiguity():
    table = VariableTable([
        Variable("x", 0x10, None, (), "a_c", True), Variable("x", 0x20, None, (), "b_c", False),
        Variable("x", 0x30, None, ("f",), "a_c", False, True), Variable("y", 0x40, None, (), "a_c", False),
        Variable("y", 0x50, None, (), "b_c", False), Variable("z", 0x60, None, ("f",), "a_c", False, True),
        Variable("z", 0x70, None, ("g",), "a_c", False, True)])
    assert table.find("x.m")[0].address == 0x10  # the global, not the file static nor f's static
    assert table.find("f.x")[0].address == 0x30 and table.find("b_c.x")[0].address == 0x20
    assert table.find("x{Function:f}")[0].address == 0x30
    with pytest.raises(AmbiguousSymbolError) as info:
        table.find("y")
    assert info.value.candidates == ["a_c.y", "b_c.y"]
    with pytest.raises(AmbiguousSymbolError, match=r"f\.z, g\.z"):
        table.find("z")
    assert table.find("nothing") is None


def test_demangled_names_lose_their_parameter_lists():
    assert split_qualified("app::Controller::step(unsigned int) const::calls") == (
        ["app", "Controller", "step", "calls"], True)
    assert split_qualified("ns::Holder<std::pair<int, int> >::value") == (["ns", "Holder<std::pair<int, int> >",
                                                                           "value"], False)


def test_member_lookup_anonymous_bases_and_virtual_bases():
    u8 = CType("base", 1, "uint8_t", "unsigned")
    inner = CType("struct", 2, members=(CMember("lo", 0, u8), CMember("hi", 1, u8)))
    base = CType("struct", 4, "Base", members=(CMember("id", 0, u8), CMember("", 2, inner)))
    other = CType("struct", 2, "Other", members=(CMember("id", 1, u8),))
    derived = CType("struct", 8, "Derived", members=(CMember("own", 6, u8),),
                    bases=(CMember("Base", 0, base), CMember("Other", 4, other)))
    assert base.find_member("hi").offset == 3  # through the anonymous struct at 2
    assert walk(derived, split_path("x.Base.hi")[1])[0] == 3
    assert walk(derived, split_path("x.Other.id")[1])[0] == 5
    with pytest.raises(PathError, match="more than one base class"):
        walk(derived, split_path("x.id")[1])
    virtual = CType("struct", 8, "V", bases=(CMember("Base", None, base),))
    with pytest.raises(MemberError, match="virtual base"):
        virtual.find_member("hi")


def test_function_statics_and_ambiguity_survive_the_cache(tmp_path):
    elf = tmp_path / "wild.elf"
    shutil.copy(MATRIX / "c-clang-dwarf5-m64-O2.elf", elf)
    cache = tmp_path / "cache"
    with DebugData(elf, cache_dir=cache) as first:
        expected = [first.resolve(path).address for path in ("wild_tick.history[2]", "tickCount", "wild_c.fileLocal")]
        assert first.is_ambiguous("state") and first.is_ambiguous("fileLocal")
    with DebugData(elf, cache_dir=cache) as second:
        assert second.from_cache
        assert [second.resolve(path).address for path in ("wild_tick.history[2]", "tickCount",
                                                          "wild_c.fileLocal")] == expected
        assert second.is_ambiguous("state") and second.is_ambiguous("fileLocal")
        assert second._reader is None  # function statics and types came from the cache


def _variable_dies(elf_path: Path) -> dict[int, bool]:
    """pyelftools' variable DIEs: offset -> whether it lies inside a function (at any depth)."""
    from elftools.elf.elffile import ELFFile

    with open(elf_path, "rb") as handle:
        found = {}
        for unit in ELFFile(handle).get_dwarf_info().iter_CUs():
            for die in unit.iter_DIEs():
                if die.tag != "DW_TAG_variable":
                    continue
                parent = die.get_parent()
                while parent is not None and parent.tag not in ("DW_TAG_subprogram", "DW_TAG_inlined_subroutine"):
                    parent = parent.get_parent()
                found[die.offset] = parent is not None
    return found


@pytest.mark.parametrize("elf_name", ["c-gcc-dwarf4-m64-O0.elf", "cpp-clang-dwarf5-m64-O2.elf"])
def test_a_name_missing_at_file_scope_decodes_only_the_variables_inside_functions(elf_name, monkeypatch):
    """The function statics are read for a name the globals lack; the file-scope variables, read once
    already, are stepped over (an ELF of 50,000 globals decoded them all a second time)."""
    from workbench.elf import die_readers, dwarf

    debug = DebugData(MATRIX / elf_name, use_cache=False)
    decoded = []
    make_reader = die_readers.variable_reader

    def recording_reader(*args):
        read = make_reader(*args)

        def recording(data, position, unit):
            decoded.append(position - 1)  # the DIE's offset: its abbreviation code is one byte here
            return read(data, position, unit)

        return recording

    monkeypatch.setattr(die_readers, "variable_reader", recording_reader)
    debug._dwarf()._plan_cache.clear()  # the readers are made again, recording
    decode = dwarf.DwarfReader._decode

    def decoding(self, plan, position, unit, wanted):
        if wanted is dwarf.VARIABLE_ATTRS:
            decoded.append(position - 1)
        return decode(self, plan, position, unit, wanted)

    monkeypatch.setattr(dwarf.DwarfReader, "_decode", decoding)
    assert debug.find("no_such_variable") is None
    variables = _variable_dies(MATRIX / elf_name)
    decoded_variables = [offset for offset in decoded if offset in variables]
    inside = sorted(offset for offset, in_function in variables.items() if in_function)
    assert sorted(decoded_variables) == inside and inside
    assert len(variables) > len(inside)  # there were file-scope variables to step over


def test_paths_of_unique_names_need_no_scoped_lookup():
    """``x``, ``x.member`` and ``x[2]`` of a name that designates one variable are one dict lookup: neither
    the scoped table of every variable nor the .symtab table is built (nor for a name no symbol has)."""
    debug = DebugData(MATRIX / "c-gcc-dwarf4-m64-O0.elf", use_cache=False)
    table = VariableTable(debug._variables)
    for path in ("wild_tick.history[2]", "wild_c.fileLocal", "tickCount", "wild_filter.state"):
        assert debug.resolve(path).address == DebugData(MATRIX / "c-gcc-dwarf4-m64-O0.elf", use_cache=False) \
            .resolve(path).address
    plain = [name for name, variables in table.by_name.items() if len(variables) == 1]
    fresh = DebugData(MATRIX / "c-gcc-dwarf4-m64-O0.elf", use_cache=False)
    for name in plain:
        assert fresh.resolve(name).address == table.find(name)[0].address
    assert fresh.find("no_such_variable") is None
    assert fresh._globals is None and fresh._symtab is None
