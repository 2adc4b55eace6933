"""uniform2d.threads: the optimiser's starts on several threads, the same bytes on any count."""

import hashlib
import os
from pathlib import Path

import pytest
from support.benchmarks import benchmark_polygons

import uniform2d
from uniform2d.errors import InvalidArgumentError
from uniform2d.optimize.seed import variants
from uniform2d.testing import check_mesh
from uniform2d.threads import ENV, get_threads, set_threads, thread_map

DATA = Path(__file__).resolve().parents[1] / "data"


def _digest(m) -> str:
    return hashlib.sha256(m.points.tobytes() + m.triangles.tobytes()).hexdigest()


@pytest.fixture
def restore_threads():
    yield
    set_threads(None)


@pytest.mark.parametrize("name, n", [("star10", 300), ("square2holes", 1200)])
def test_same_bytes_on_one_and_two_threads(name, n, restore_threads):
    p = benchmark_polygons()[name]
    assert len(variants(p, n)) > 1  # several starts: work the threads share
    digests = []
    for k in (1, 2, 1):
        set_threads(k)
        m = uniform2d.uniform_mesh(p, n)
        check_mesh(m.points, m.triangles, p)
        digests.append(_digest(m))
    assert digests[0] == digests[1] == digests[2]


def test_thread_map_keeps_the_order_and_raises(restore_threads):
    set_threads(2)
    assert thread_map(lambda x: -x, range(50)) == [-x for x in range(50)]

    def bad(x):
        if x == 3:
            raise KeyError(x)
        return x

    with pytest.raises(KeyError):
        thread_map(bad, range(6))


def test_maps_run_on_kept_threads_and_a_map_inside_a_map_ends(restore_threads):
    import threading

    set_threads(2)

    def kept():
        return {t.ident for t in threading.enumerate() if t.name.startswith("uniform2d-map")}

    names = thread_map(lambda x: threading.current_thread().name, range(8))
    assert all(name.startswith("uniform2d-map") for name in names)
    before = kept()
    assert 1 <= len(before) <= 2
    thread_map(lambda x: x, range(8))
    assert kept() == before  # the same threads, none started or ended
    # a map inside a map runs its calls on the outer map's thread, in order
    got = thread_map(lambda x: thread_map(lambda y: 10 * x + y, range(3)), range(4))
    assert got == [[10 * x + y for y in range(3)] for x in range(4)]


def _map_in_child(queue) -> None:
    queue.put(thread_map(lambda x: 2 * x, range(6)))


@pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork here")
def test_a_forked_child_maps_on_threads_of_its_own(restore_threads):
    """The kept threads are the parent's: a child forked after a map (whose
    copy of the pool has no threads) makes its own, instead of waiting."""
    import multiprocessing
    import queue as queues

    set_threads(2)
    assert thread_map(lambda x: x, range(6)) == list(range(6))  # the parent's pool
    ctx = multiprocessing.get_context("fork")
    results = ctx.Queue()
    child = ctx.Process(target=_map_in_child, args=(results,))
    child.start()
    try:
        got = results.get(timeout=60)
    except queues.Empty:
        got = None
    finally:
        child.join(5)
        if child.is_alive():
            child.kill()
    assert got == [2 * x for x in range(6)]


def test_thread_count_from_the_call_the_environment_or_the_cores(monkeypatch, restore_threads):
    monkeypatch.setenv(ENV, "3")
    assert get_threads() == 3
    set_threads(1)
    assert get_threads() == 1
    set_threads(None)
    monkeypatch.delenv(ENV)
    assert get_threads() >= 1
    for bad in (0, -2, 1.5, True, "2"):
        with pytest.raises(InvalidArgumentError, match="at least 1"):
            set_threads(bad)
    monkeypatch.setenv(ENV, "many")
    with pytest.raises(InvalidArgumentError, match=ENV):
        get_threads()


def test_in_background_gives_the_value_or_the_exception():
    from uniform2d.threads import in_background

    assert in_background(lambda: [x * x for x in range(4)]).result() == [0, 1, 4, 9]

    def bad():
        raise KeyError("seen by result()")

    with pytest.raises(KeyError, match="seen by result"):
        in_background(bad).result()


def test_angle_attempt_ahead_only_with_small_holes_and_threads(restore_threads):
    # the bolt plate's holes are small at 500 vertices (the attempt is then made
    # on a thread of its own beside the first mesh), a square's are not
    from uniform2d.io import read_polygon
    from uniform2d.optimize import pipeline
    from uniform2d.optimize.boundary import target_size

    plate = read_polygon(str(DATA / "plate_bolts.json"))
    n = 500 - len(plate.vertices)
    h = target_size(plate, n)
    assert pipeline._small_holes(plate, h)
    assert not pipeline._small_holes(plate, 0.1 * h)  # the holes' edges beside h / 20
    assert not pipeline._small_holes(benchmark_polygons()["square"], h)
    set_threads(1)
    assert pipeline._angle_attempt_ahead(plate, n, h, "balanced", {}) is None


@pytest.mark.parametrize("total", [500, 2000])
def test_bolt_plate_same_bytes_with_the_angle_attempt_ahead(total, restore_threads):
    # two threads: the angle attempt runs beside the first mesh; one: after it
    from uniform2d.io import read_polygon

    plate = read_polygon(str(DATA / "plate_bolts.json"))
    digests = []
    for k in (2, 1):
        set_threads(k)
        m = uniform2d.uniform_mesh(plate, total - len(plate.vertices))
        check_mesh(m.points, m.triangles, plate)
        assert m.info["angle_attempt"]  # the attempt's mesh is the one kept
        digests.append(_digest(m))
    assert digests[0] == digests[1]


def test_reference_ahead_only_with_threads_and_the_same_info(restore_threads):
    # T+ (the reference the mesh must beat) is made on a thread of its own
    # beside the optimisation on two threads, at once on one: the same mesh
    # and the same T+ figures either way
    from uniform2d.optimize import pipeline
    from uniform2d.optimize.schedule import LARGE

    p = benchmark_polygons()["lshape"]
    set_threads(1)
    assert pipeline._reference_ahead(p, 400, None) is None
    one = uniform2d.uniform_mesh(p, 400)
    set_threads(2)
    tp = uniform2d.tplus(p, 400)
    assert pipeline._reference_ahead(p, 400, tp) is None  # the caller's T+: nothing to make
    assert pipeline._reference_ahead(p, LARGE, None) is None  # T+ not beside a large run
    ahead = pipeline._reference_ahead(p, 400, None)
    info, q, d_n = ahead.result()
    assert (info, d_n) == (tp.info, tp.info["d_n"]) and q.min_angle == tp.quality().min_angle
    two = uniform2d.uniform_mesh(p, 400)
    check_mesh(two.points, two.triangles, p)
    assert len(two.points) == len(p.vertices) + 400
    assert _digest(one) == _digest(two)
    assert one.info["start"] == two.info["start"] and one.info["start"] is not None
