"""The measuring code of benchmarks/bench_models.py gives known answers."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("igl")
pytest.importorskip("pymeshlab")
pytest.importorskip("trimesh")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_models as bench  # noqa: E402


def test_a_model_measured_against_itself():
    model = bench.prepare("box")
    m = bench.measure(model, model["V"], model["F"], len(model["V"]))
    assert m["exact"] and m["topology"] == "kept"
    assert m["crease"] == pytest.approx(0.0, abs=1e-12)
    assert m["h_in_out"] < 1e-12 and m["h_out_in"] < 1e-12
    assert m["ratio"] == pytest.approx(np.sqrt(2.0)) and m["angle"] == pytest.approx(45.0)
    assert bench.prepare("sphere")["creases"] is None


def test_changes_are_seen():
    model = bench.prepare("pierced_sphere")
    V, F = bench.MODELS["sphere"]()
    m = bench.measure(model, V * 1.01, F, 2000)
    assert not m["exact"] and m["topology"] == "chi 1->2, loops 1->0"
    assert m["h_in_out"] == pytest.approx(0.01 / np.sqrt(12.0), rel=1e-3)  # radius / diagonal


def test_missing_and_failing_meshers_are_rows(monkeypatch):
    model = bench.prepare("torus")
    monkeypatch.setitem(bench.MESHERS, "cgal", ("no_such_module_here", bench.run_cgal))
    assert bench.run_one("cgal", model, 500, None)["status"] == "not installed"

    def boom(model, n):
        raise RuntimeError("peer crashed")

    monkeypatch.setitem(bench.MESHERS, "pyacvd", (None, boom))
    assert bench.run_one("pyacvd", model, 500, None)["status"].startswith("failed: RuntimeError")


def test_verdict():
    ours = {"status": "ok", "n": 10000, "exact": True, "topology": "kept", "ratio": 1.5,
            "cv": 0.05, "angle": 40.0, "crease": 0.01, "h_in_out": 1e-16, "h_out_in": 1e-16,
            "time": 1.0}  # fmt: skip
    meshlab = {"status": "ok", "h_in_out": 3e-17, "h_out_in": 3e-17, "time": 0.6}
    assert bench.verdict(ours, meshlab) == "meets the goal"
    worse = {**ours, "cv": 0.1, "h_out_in": 1e-4, "time": 1.5}
    assert bench.verdict(worse, meshlab) == "misses: CV, Hausdorff, time"
    assert bench.verdict({"status": "refused: closed"}, meshlab) == "refused"
