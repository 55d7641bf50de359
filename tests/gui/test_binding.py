"""The Qt binding itself: PySide6 6.12.0 drops a reference to True on every Signal.emit(), and
Python 3.10/3.11 (where True is mortal) then aborts at exit ("bool_dealloc"). pyproject.toml
excludes that release; this test fails on any binding that does the same."""

import sys

from PySide6.QtCore import QObject, Signal


class _Emitter(QObject):
    fired = Signal(object)


def test_emitting_a_signal_keeps_the_reference_counts_of_true_and_false(qapp):
    emitter = _Emitter()
    emitter.fired.connect(lambda value: None)
    before = sys.getrefcount(True), sys.getrefcount(False)
    for _ in range(1000):
        emitter.fired.emit(1)
    assert (sys.getrefcount(True), sys.getrefcount(False)) == before
