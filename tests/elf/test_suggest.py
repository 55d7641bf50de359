"""Did-you-mean for symbols an ELF lacks: the narrowed search finds what difflib over every name finds."""

import difflib
import random

from workbench.elf.suggest import NameIndex


def test_short_names_case_and_strangers():
    index = NameIndex(["x", "y1", "fooBar_Ctr", "fooBar_Cnt2", "EPK"])
    assert index.closest("X") == ["x"] and index.closest("Y1") == ["y1"]  # names of one or two letters have trigrams
    assert index.closest("FOOBAR_CTR") == ["fooBar_Ctr"]  # the case alone differs: first
    assert index.closest("fooBar_Cnt") == ["fooBar_Cnt2"]
    assert index.closest("fooBar_Ctr", count=2) == ["fooBar_Ctr", "fooBar_Cnt2"]
    assert index.closest("rail_pressure") == [] and NameIndex([]).closest("x") == []


def test_the_narrowed_search_is_as_good_as_difflib_over_every_name():
    """20,000 names that share unit prefixes and words (as an ECU's do); renamed ones are found as well as by a
    difflib over all names, which is the slow way (seconds for a hundred)."""
    rng = random.Random(7)
    words = ["Rail", "Press", "Tank", "Level", "Valve", "Pump", "Ctr", "Cnt", "Filt", "Raw", "Diag", "Stat"]
    names = list(dict.fromkeys(f"{rng.choice(['zs', 'xs', 'cf'])}{rng.choice(words)}{rng.choice(words)}_{n % 997}"
                               for n in range(20000)))
    index = NameIndex(names)
    folded = [name.lower() for name in names]
    for name in rng.sample(names, 5):
        cut = rng.randrange(2, len(name) - 1)
        renamed = name[:cut] + "x" + name[cut + 1:]
        (found,) = index.closest(renamed)
        best = difflib.get_close_matches(renamed.lower(), folded, 1, 0.75)[0]
        ratio = difflib.SequenceMatcher(None, renamed.lower(), best).ratio()
        assert difflib.SequenceMatcher(None, renamed.lower(), found.lower()).ratio() == ratio, (renamed, found, best)

