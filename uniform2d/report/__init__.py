"""Comparison reports: uniform2d against the meshers people use today.

:func:`make_report` meshes every input at every n with our T+ and
:func:`uniform2d.uniform_mesh` (polygons) or :func:`surface.remesh` (patches),
and with every peer of :mod:`uniform2d.peers` tuned to the same vertex count,
then writes ``index.html`` (one self-contained page), ``report.md``,
``results.json`` (every number) and the meshes.  Cases run serially, in a local
process pool or on a Dask cluster, with the same results.

Modules: :mod:`.cases` (inputs, the case list, running one case),
:mod:`.runners` (serial / pool / Dask), :mod:`.render` (figures, HTML,
Markdown), :mod:`.build` (:func:`make_report`), :mod:`.compare` (two mesh files).
"""

from .build import make_report, strip_timings
from .cases import MEASURES, load_input, load_inputs, plan, run_case
from .compare import compare_meshes, format_comparison
from .runners import run_cases

__all__ = [
    "make_report",
    "strip_timings",
    "plan",
    "run_case",
    "run_cases",
    "load_input",
    "load_inputs",
    "compare_meshes",
    "format_comparison",
    "MEASURES",
]
