"""Helpers of uniform2d's own tests that users have no use for: an independent
reference INSERT and its dense check, Triangle's meshes of constrained polygons,
and the repository's benchmark polygons.  The mesh checker and the random
polygons are public: :mod:`uniform2d.testing`."""
