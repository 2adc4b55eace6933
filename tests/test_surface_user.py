"""The surface layer as a new user meets it: the import without the extra, log
output left to the application, the --stats text, the --plot figure."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
PATCHES = ROOT / "data" / "patches"


def python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300, cwd=ROOT)


@pytest.mark.parametrize("module", ["igl", "pymeshlab", "trimesh"])
def test_import_without_the_extra_names_it(module):
    # sys.modules[name] = None makes `import name` fail as if it were not installed.
    run = python(f"import sys; sys.modules[{module!r}] = None\nimport surface")
    assert run.returncode != 0
    last = run.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: the surface layer needs the 'surface' extra")
    assert f"'{module}'" in last and "pip install 'uniform2d[surface]'" in last
    assert "ModuleNotFoundError" not in run.stderr


def test_remesh_command_without_the_extra_is_one_line(tmp_path):
    run = python(
        "import sys; sys.modules['igl'] = None\n"
        "from uniform2d.cli.main import main\n"
        f"sys.exit(main(['remesh', {str(PATCHES / 'cap60.obj')!r}, '-n', '50', "
        f"'-o', {str(tmp_path / 'x.obj')!r}]))"
    )
    assert run.returncode == 2
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("uniform2d: error: ")
    assert "pip install 'uniform2d[surface]'" in run.stderr
    assert list(tmp_path.iterdir()) == []


def test_library_logs_reach_no_stderr_without_logging_configured():
    # Without a handler of its own, a WARNING would go to logging's last-resort
    # handler (stderr) of an application that configured no logging.
    pytest.importorskip("igl")
    run = python(
        "import logging, uniform2d, surface\n"
        "logging.getLogger('surface.parameterize').warning('fallback note')\n"
        "logging.getLogger('uniform2d.optimize').warning('a note')\n"
        "print('done')"
    )
    assert run.returncode == 0 and run.stdout.strip() == "done"
    assert run.stderr == ""


def test_the_command_shows_surface_notes_with_v(capsys, tmp_path, monkeypatch):
    pytest.importorskip("igl")
    import logging

    import surface.plugin  # the layer the command finds through its entry point
    from uniform2d.cli.main import main

    real = surface.plugin.remesh

    def remesh(*args, **kwargs):
        logging.getLogger("surface.parameterize").info("lscm rejected; used arap")
        return real(*args, **kwargs)

    monkeypatch.setattr(surface.plugin, "remesh", remesh)
    argv = ["remesh", str(PATCHES / "plate_hole.obj"), "-n", "80", "-o", str(tmp_path / "x.obj")]
    assert main(argv) == 0
    assert "lscm rejected" not in capsys.readouterr().err
    assert main(["-v", *argv]) == 0
    assert "uniform2d: INFO: lscm rejected; used arap" in capsys.readouterr().err


@pytest.fixture(scope="module")
def plate():
    pytest.importorskip("igl")
    pytest.importorskip("pymeshlab")
    import surface

    return surface.remesh(PATCHES / "plate_hole.obj", 150, hausdorff=False)


def test_stats_of_a_flat_patch_say_there_is_no_trend(plate):
    assert np.isnan(plate.report.size_trend)  # a flat patch: the area scale is constant
    text = plate.report.summary()
    assert "nan" not in text.lower()
    assert "no size trend to measure (the area scale hardly varies)" in text
    curved = dataclasses.replace(plate.report, size_trend=-0.0123)
    assert "size trend -0.012 (compensated)" in curved.summary()


def test_remesh_figure_frames_the_patch(plate, tmp_path):
    # The drawn mesh fills most of its panel instead of sitting small in the middle.
    from PIL import Image

    from surface._figures import plot_result

    for extent in ("flat", "tall"):
        result = plate
        if extent == "tall":  # the same mesh stood on its side, three times as high
            V = plate.vertices[:, [0, 2, 1]] * [1.0, 1.0, 3.0]
            result = dataclasses.replace(plate, vertices=V)
        path = tmp_path / f"{extent}.png"
        plot_result(result, path)
        img = np.asarray(Image.open(path).convert("L"), dtype=float)
        left = img[:, : img.shape[1] * 2 // 5]  # the 3-D panel, left of its colour bar
        rows, cols = np.nonzero(left < 200)
        rows = rows[rows > 0.08 * img.shape[0]]  # below the title
        height = (rows.max() - rows.min()) / img.shape[0]
        width = (cols.max() - cols.min()) / left.shape[1]
        assert max(height, width) > 0.7, (extent, height, width)
        assert rows.max() < img.shape[0] - 2 and cols.min() > 1, "the mesh is cut off"


def test_remesh_plot_path_checked_before_remeshing(capsys, tmp_path, monkeypatch):
    pytest.importorskip("igl")
    import surface
    from uniform2d.cli.main import main

    monkeypatch.setattr(surface, "remesh", lambda *a, **k: pytest.fail("remeshed first"))
    for plot, expected in (("p.bmp", "cannot save a figure"), ("nodir/p.png", "does not exist")):
        code = main(["remesh", str(PATCHES / "cap60.obj"), "-n", "50",
                     "-o", str(tmp_path / "x.obj"), "--plot", str(tmp_path / plot)])
        err = capsys.readouterr().err
        assert code == 2 and expected in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
