"""The commands and examples of README.md and docs/*.md run as written, in a fresh
copy of the repository's data and docs, so they cannot drift from the code.

* every line of a ```bash block is run with bash (continuation lines joined);
  environment set-up (``python3 -m venv``, ``pip install``) and the test suite
  itself are left to CI (``.ci/run`` does exactly those), and a ``.venv/bin/``
  prefix means the environment running these tests;
* every ```python block of a file is run, in order, in one interpreter;
* what the guide shows of real output (the CSV file, the error line) is compared
  with the real output.

A few commands are long or heavy (the surface benchmark, a report at n = 1000,
a local Dask cluster); they run only with ``UNIFORM2D_SLOW_DOCS=1``.  One needs a
Dask scheduler at a given address, which a test cannot assume.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SLOW = os.environ.get("UNIFORM2D_SLOW_DOCS") == "1"

#: Steps of a command that set an environment up rather than use it.
SETUP = ("python3 -m venv", "pip install")

#: Commands never run here, and why.
NOT_HERE = {
    "-m pytest": "the test suite itself (CI runs it)",
    "--scheduler tcp://": "needs a Dask scheduler running at that address",
}

#: Commands too long or heavy for every run: run with UNIFORM2D_SLOW_DOCS=1.
EXPENSIVE = {
    "-n 200 -n 1000": "a report of 7 polygons at two sizes with every peer (half a minute or more)",
    "bench_surface.py": "the surface benchmark (half a minute or more, timing runs)",
    "LocalCluster": "starts a local Dask cluster of 2 worker processes",
}


def _blocks(path: Path, lang: str) -> list[str]:
    return re.findall(rf"^```{lang}\n(.*?)^```", path.read_text(), flags=re.M | re.S)


def _commands(text: str) -> list[str]:
    joined = re.sub(r"\\\n\s*", " ", text)
    lines = [line.strip() for line in joined.splitlines()]
    return [line for line in lines if line and not line.startswith("#")]


def _runnable(command: str) -> str:
    """The command without its set-up steps, using the environment running the tests."""
    steps = [s.strip() for s in command.split("&&")]
    steps = [s for s in steps if not any(k in s for k in SETUP)]
    return " && ".join(s.replace(".venv/bin/", "") for s in steps)


SHELL = [(doc.name, cmd)
         for doc in DOCS for block in _blocks(doc, "bash") for cmd in _commands(block)]
PYTHON = [doc for doc in DOCS if _blocks(doc, "python")]


#: Modules a documented example may use that are not dependencies of uniform2d.
OPTIONAL = ("pyproj",)


def _skip_reason(text: str) -> str | None:
    import importlib.util

    for mod in OPTIONAL:
        if f"import {mod}" in text and importlib.util.find_spec(mod) is None:
            return f"needs {mod}, which is not installed (not a dependency)"
    for key, why in NOT_HERE.items():
        if key in text:
            return why
    for key, why in EXPENSIVE.items():
        if key in text and not SLOW:
            return why + "; set UNIFORM2D_SLOW_DOCS=1 to run it"
    return None


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> Path:
    """A copy of what a fresh clone has besides the packages (those come from the
    environment, as after ``pip install .``)."""
    root = tmp_path_factory.mktemp("clone")
    for name in ("data", "docs", "benchmarks"):
        shutil.copytree(ROOT / name, root / name)
    shutil.copy(ROOT / "README.md", root)
    return root


def _env() -> dict:
    """The environment running these tests: its ``bin`` directory first on PATH, and the
    uniform2d it imports (the installed one, or the source tree) first on PYTHONPATH."""
    import uniform2d

    bindir = str(Path(sys.executable).parent)
    path = os.pathsep.join(p for p in [bindir, os.environ.get("PATH", "")] if p)
    here = str(Path(uniform2d.__file__).resolve().parents[1])
    pythonpath = os.pathsep.join(p for p in [here, os.environ.get("PYTHONPATH", "")] if p)
    return dict(os.environ, PATH=path, PYTHONPATH=pythonpath, MPLBACKEND="Agg",
                PYTHONWARNINGS="ignore")


def test_docs_have_commands_and_examples():
    assert len(SHELL) >= 15 and {d for d, _ in SHELL} >= {"README.md", "guide.md", "report.md"}
    assert {d.name for d in PYTHON} >= {"README.md", "guide.md", "surface.md"}


@pytest.mark.parametrize("doc, command", SHELL, ids=[f"{d}:{c[:60]}" for d, c in SHELL])
def test_documented_command_runs(fresh, doc, command):
    runnable = _runnable(command)
    if not runnable:
        pytest.skip("only sets up an environment (CI's .ci/run does it)")
    reason = _skip_reason(runnable)
    if reason:
        pytest.skip(reason)
    if "surface" in runnable or "remesh" in runnable or "patches/" in runnable:
        pytest.importorskip("igl")
    if shutil.which("uniform2d", path=_env()["PATH"]) is None and "uniform2d " in runnable:
        pytest.skip("the uniform2d command is not installed in this environment")
    run = subprocess.run(["bash", "-c", "set -euo pipefail; " + runnable], cwd=fresh, env=_env(),
                         capture_output=True, text=True, timeout=1800)
    assert run.returncode == 0, f"{doc}: {command}\n{run.stderr[-2000:]}"


@pytest.mark.parametrize("doc", PYTHON, ids=[d.name for d in PYTHON])
def test_documented_python_runs(fresh, doc, tmp_path):
    blocks = _blocks(doc, "python")
    kept = [b for b in blocks if _skip_reason(b) is None]
    if "import surface" in "".join(kept):
        pytest.importorskip("igl")
    script = tmp_path / f"{doc.stem}_example.py"  # a script file, as a user pastes it
    script.write_text("\n".join(kept))
    run = subprocess.run([sys.executable, str(script)], cwd=fresh, env=_env(),
                         capture_output=True, text=True, timeout=1800)
    assert run.returncode == 0, f"{doc.name}:\n{run.stderr[-2000:]}"


def _shown(doc: str, after: str) -> list[str]:
    """The lines of the first plain ``` block after the text ``after`` in ``doc``."""
    text = (ROOT / "docs" / doc).read_text()
    start = text.index(after)
    block = re.search(r"^```\n(.*?)^```", text[start:], flags=re.M | re.S).group(1)
    return block.splitlines()


def test_guide_csv_example_is_the_real_output(fresh, tmp_path):
    command = "uniform2d mesh data/benchmarks/square.json -n 3 -o square.csv"
    assert f"(`{command}`)" in (ROOT / "docs" / "guide.md").read_text()
    out = tmp_path / "square.csv"
    run = subprocess.run(command.replace("square.csv", str(out)).split(), cwd=fresh, env=_env(),
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    real = out.read_text().splitlines()
    shown = _shown("guide.md", command)
    at = 0
    for line in shown:  # every line shown is a real line, in the same order; "..." skips
        if line == "...":
            continue
        assert line in real[at:], f"the guide shows {line!r}, which the real file lacks"
        at = real.index(line, at) + 1
    assert shown[-1] == real[-1]


def test_guide_stats_example_is_the_real_output(fresh, tmp_path):
    command = "uniform2d mesh data/l_bracket.json --size 4 --method paper --stats"
    assert f"(`{command}`)" in (ROOT / "docs" / "guide.md").read_text()
    run = subprocess.run([*command.split(), "-o", str(tmp_path / "b.vtu")], cwd=fresh,
                         env=_env(), capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    real = run.stdout.splitlines()
    for line in _shown("guide.md", command):
        start = line.split("...")[0].rstrip()
        if "..." in line:  # an elided line: what it shows before "..." is real
            assert not start or any(r.startswith(start) for r in real), line
        elif line.strip():
            assert line in real, f"the guide shows {line!r}; the command prints otherwise"


def test_guide_error_example_is_the_real_message(tmp_path):
    shown = _shown("guide.md", "## 11. Errors")
    command, message = shown[0], shown[1]
    assert command == "$ uniform2d mesh bowtie.json -n 50 -o bowtie.vtu"
    (tmp_path / "bowtie.json").write_text('{"outer": [[0, 0], [2, 2], [2, 0], [0, 1]]}')
    run = subprocess.run(command[2:].split(), cwd=tmp_path, env=_env(), capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 2 and shown[2:] == ["$ echo $?", "2"]
    assert run.stderr.strip() == message
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bowtie.json"]
