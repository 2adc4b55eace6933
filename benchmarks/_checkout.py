"""Make ``python benchmarks/x.py`` measure this checkout, not an installed copy.

Python puts ``benchmarks/`` first on ``sys.path`` and the installed packages
(site-packages, or another checkout's editable install) after it, so without
this a benchmark run from a second checkout or worktree measures whatever is
installed.  Importing this module puts the checkout's root after the
``PYTHONPATH`` entries, so that ``PYTHONPATH=/other/checkout`` still measures
that one (as ``bench_angles.py --before`` does), and before everything else.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _after_pythonpath() -> int:
    """Index in ``sys.path`` just after the script's directory and PYTHONPATH
    (the script's directory may stand there twice: a benchmark that imports
    another puts ``benchmarks/`` first itself)."""
    env = {os.path.abspath(p) for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p}
    env.add(str(ROOT / "benchmarks"))
    i = 1
    while i < len(sys.path) and os.path.abspath(sys.path[i]) in env:
        i += 1
    return i


if str(ROOT) not in sys.path:
    sys.path.insert(_after_pythonpath(), str(ROOT))
    # child processes (``python -c`` timings, workers) measure the same checkout
    _env = os.environ.get("PYTHONPATH", "")
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (_env, str(ROOT)) if p)
