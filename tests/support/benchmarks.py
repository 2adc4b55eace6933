"""The repository's benchmark polygons (``data/benchmarks/*.json``)."""

from __future__ import annotations

import json
from pathlib import Path

from uniform2d import Polygon

__all__ = ["benchmark_dir", "benchmark_polygons"]

_REPO = Path(__file__).resolve().parents[2]


def benchmark_dir() -> Path:
    """``data/benchmarks`` in the repository if present, else ``../shared/benchmarks/polygons``."""
    local = _REPO / "data" / "benchmarks"
    if local.is_dir() and any(local.rglob("*.json")):
        return local
    return Path(__file__).resolve().parents[3] / "shared" / "benchmarks" / "polygons"


def benchmark_polygons() -> dict[str, Polygon]:
    """name -> Polygon for every benchmark JSON file ({"outer": [...], "holes": [...]})."""
    out: dict[str, Polygon] = {}
    root = benchmark_dir()
    for path in sorted(root.rglob("*.json")):
        data = json.loads(path.read_text())
        if not isinstance(data, dict) or "outer" not in data:
            continue
        out[path.stem] = Polygon(data["outer"], data.get("holes", []))
    if not out:
        raise FileNotFoundError(f"no benchmark polygons found in {root}")
    return out
