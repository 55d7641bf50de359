import threading

import numpy as np
import pytest

from workbench.gui.ringbuffer import RingBuffer


def test_keeps_the_newest_samples_contiguous_past_its_capacity():
    buffer = RingBuffer(100)
    for start in range(0, 1000, 30):
        t = np.arange(start, start + 30, dtype=float)
        buffer.append(t, t * 2)
    assert len(buffer) == 100
    assert buffer.total == 1020
    assert buffer.span() == (920.0, 1019.0)
    t, v = buffer.window(-np.inf, np.inf)
    assert np.array_equal(t, np.arange(920, 1020)) and np.array_equal(v, t * 2)


def test_a_window_takes_one_sample_beyond_each_edge_so_lines_reach_the_border():
    buffer = RingBuffer(50)
    buffer.append(np.arange(10.0), np.arange(10.0))
    t, _ = buffer.window(3.5, 6.5)
    assert list(t) == [3.0, 4.0, 5.0, 6.0, 7.0]
    assert buffer.at(4.9) == 4.0 and buffer.at(-1) is None
    assert buffer.last() == (9.0, 9.0)


def test_a_batch_bigger_than_the_capacity_keeps_its_end():
    buffer = RingBuffer(10)
    buffer.append(np.arange(25.0), np.arange(25.0))
    assert buffer.span() == (15.0, 24.0)


def test_mismatched_lengths_are_refused():
    with pytest.raises(ValueError, match="3 times for 2 values"):
        RingBuffer(10).append([1, 2, 3], [1, 2])


def test_a_reader_never_sees_a_torn_window_while_a_writer_appends():
    buffer = RingBuffer(1000)
    stop = threading.Event()

    def write():
        n = 0
        while not stop.is_set():
            t = np.arange(n, n + 7, dtype=float)
            buffer.append(t, t)
            n += 7

    writer = threading.Thread(target=write)
    writer.start()
    try:
        for _ in range(2000):
            t, v = buffer.window(-np.inf, np.inf)
            assert np.array_equal(t, v) and np.all(np.diff(t) == 1)
    finally:
        stop.set()
        writer.join()


def test_a_pause_is_a_nan_between_the_samples_either_side_and_no_value_is_held_across_it():
    buffer = RingBuffer(100)
    buffer.append(np.array([0.0, 1.0, 2.0]), np.array([10.0, 11.0, 12.0]))
    buffer.mark_gap()
    buffer.mark_gap()  # twice at one place: one gap
    buffer.append(np.array([40.0, 41.0]), np.array([20.0, 21.0]))
    t, v = buffer.window(-np.inf, np.inf, gaps=True)
    assert t.tolist() == [0.0, 1.0, 2.0, 2.0, 40.0, 41.0]
    assert np.isnan(v[3]) and not np.isnan(np.delete(v, 3)).any()
    assert len(buffer.window(-np.inf, np.inf)[0]) == 5  # without gaps: the samples only
    assert buffer.at(2.0) == 12.0 and buffer.at(20.0) is None and buffer.at(40.5) == 20.0
    buffer.append(np.arange(100, 200, dtype=float), np.zeros(100))  # the pause falls out of the buffer
    assert buffer.gaps == []
