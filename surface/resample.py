"""Sampling one run of a boundary loop: now planar-and-3-D shared code in
:mod:`uniform2d.chord_sampling`, named here for the surface layer's modules."""

from uniform2d.chord_sampling import plain_run, run_counts, sample_run

__all__ = ["plain_run", "run_counts", "sample_run"]
