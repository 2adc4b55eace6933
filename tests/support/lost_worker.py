"""A part function that kills the process running it the first time (for the
lost-worker test of partitioned meshes): the marker file says it happened."""

from __future__ import annotations

import os

from uniform2d.partitioned import mesh_faces


def kill_once(marker: str, item):
    """:func:`uniform2d.partitioned.mesh_faces`, after killing this process if
    ``marker`` does not exist yet (it is created first, atomically)."""
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return mesh_faces(item)
    os.close(fd)
    os._exit(1)
