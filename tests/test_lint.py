"""The code passes ruff with the rule set pinned in pyproject.toml."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

ruff = pytest.importorskip("ruff.__main__")

ROOT = Path(__file__).resolve().parents[1]


def test_ruff_is_clean():
    done = subprocess.run(
        [ruff.find_ruff_bin(), "check", "--output-format", "concise", "--no-cache",
         "uniform2d", "surface", "tests", "benchmarks", "docs"],
        cwd=ROOT, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
