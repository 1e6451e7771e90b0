"""Bakes release the GIL: other Python threads run meanwhile, and
concurrent bakes give the serial bytes."""

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

import micromap_index as mmi
from conftest import GRID, THORN


def test_other_threads_run_during_a_bake():
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    started = time.perf_counter()
    mmi.bake(alpha, uvs, level=9)
    alone = time.perf_counter() - started
    if alone < 0.05:
        pytest.skip(f"SKIPPED: the bake took {alone:.3f} s, too short to observe")
    ticks = 0
    worker = threading.Thread(target=mmi.bake, args=(alpha, uvs), kwargs={"level": 9})
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Holding the GIL, the bake would block this loop for its whole run.
    assert ticks >= 10, f"{ticks} ticks during a {alone:.3f} s bake"


def test_concurrent_bakes_equal_serial():
    alpha = mmi.read_alpha(THORN)
    uvs = mmi.read_triangles(GRID)
    levels = [2, 3, 4, 5]
    serial = [mmi.bake(alpha, uvs, level=l).files() for l in levels]
    with ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(lambda l: mmi.bake(alpha, uvs, level=l).files(), levels))
    assert parallel == serial
