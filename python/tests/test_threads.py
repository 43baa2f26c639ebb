"""The GIL is released while meshing; Ctrl-C and progress callbacks."""

import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import delone
from conftest import CUBE, CUBE_QUADS, SQUARE, SQUARE_SEGS


def test_same_result_from_many_threads():
    def job(_):
        return delone.triangulate(SQUARE, SQUARE_SEGS, "pq30a0.0005").elements

    with ThreadPoolExecutor(4) as ex:
        results = list(ex.map(job, range(8)))
    assert all(np.array_equal(r, results[0]) for r in results)


def test_gil_is_released_while_meshing():
    ticks = []
    done = threading.Event()

    def ticker():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    th = threading.Thread(target=ticker)
    th.start()
    t0 = time.perf_counter()
    delone.triangulate(SQUARE, SQUARE_SEGS, "pq30a0.000005")
    t1 = time.perf_counter()
    done.set()
    th.join()
    inside = [t for t in ticks if t0 < t < t1]
    # The other thread kept running: ticks throughout the call.
    assert t1 - t0 > 0.05
    assert len(inside) > 10


def test_progress_callback_gets_reports():
    seen = []
    delone.triangulate(SQUARE, SQUARE_SEGS, "pq30a0.000005", progress=lambda *r: seen.append(r))
    assert any(r[0] == "refining" for r in seen)
    stage, done, total, unit = seen[-1]
    assert isinstance(stage, str) and isinstance(done, int) and isinstance(unit, str)
    seen3 = []
    delone.tetrahedralize(CUBE, CUBE_QUADS, "pq1.414a0.0001", progress=lambda *r: seen3.append(r[0]))
    assert "refining" in seen3


def test_progress_true_draws_a_tqdm_bar(capsys):
    pytest.importorskip("tqdm")
    delone.triangulate(SQUARE, SQUARE_SEGS, "pq30a0.000005", progress=True)
    assert "refining" in capsys.readouterr().err


def test_an_exception_in_the_callback_stops_the_run():
    class Stop(Exception):
        pass

    def cb(*_):
        raise Stop

    t = time.perf_counter()
    with pytest.raises(Stop):
        delone.triangulate(SQUARE, SQUARE_SEGS, "pq30a0.0000005", progress=cb)
    assert time.perf_counter() - t < 5
    with pytest.raises(Stop):
        delone.tetrahedralize(CUBE, CUBE_QUADS, "pq1.414a0.000001", progress=cb)


SCRIPT = """
import signal, time, delone
# Python leaves SIGINT alone when it starts with SIGINT ignored (a
# background job of a non-interactive shell, as some CI runners start it):
# install the handler that raises KeyboardInterrupt, as an interactive
# session has it.
signal.signal(signal.SIGINT, signal.default_int_handler)
print("ready", flush=True)
t = time.perf_counter()
try:
    delone.triangulate([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]], "pq30a0.00000002")
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
"""


def test_ctrl_c_interrupts_a_long_run():
    p = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(0.5)
        t = time.perf_counter()
        p.send_signal(signal.SIGINT)
        out, _ = p.communicate(timeout=60)
        assert out.strip() == "interrupted"
        assert time.perf_counter() - t < 10
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
