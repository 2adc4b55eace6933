"""Conforming meshes of constrained polygons made by Triangle (an independent
mesher), for tests of regions, files and plots that need a mesh whatever
uniform2d's own meshers can do.

Triangle keeps the input vertices first and in order, so ``points[:|V|]`` is
``polygon.vertices`` as every uniform2d mesh; its regional attributes (switch
``A``) give each triangle's region independently of :mod:`uniform2d.regions`.
"""

import numpy as np
import shapely

triangle = __import__("pytest").importorskip("triangle")


def triangle_mesh(polygon, *, max_area=None, attributes=False):
    """(points, triangles[, attribute per triangle]) of a conforming Delaunay mesh.

    With ``attributes``, every region gets attribute ``r + 1`` from a seed inside
    region r (``polygon.regions``' representative points)."""
    data = {"vertices": np.array(polygon.vertices), "segments": polygon.constraint_edges}
    if polygon.n_holes:
        data["holes"] = np.array([shapely.Polygon(h).point_on_surface().coords[0]
                                  for h in polygon.holes])
    sw = "pQ"
    if max_area is not None:
        sw += f"qa{max_area!r}"
    if attributes:
        faces = polygon.regions.faces
        seeds = [f.representative_point().coords[0] for f in faces]
        data["regions"] = np.array([[x, y, r + 1, 0] for r, (x, y) in enumerate(seeds)])
        sw += "A"
    out = triangle.triangulate(data, sw)
    pts, tri = out["vertices"], out["triangles"].astype(np.int64)
    # counter-clockwise, as uniform2d's meshes
    p = pts[tri]
    cw = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) < (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    tri[cw] = tri[cw][:, ::-1]
    assert np.array_equal(pts[:len(polygon.vertices)], polygon.vertices)
    if attributes:
        return pts, tri, out["triangle_attributes"][:, 0].astype(np.int64) - 1
    return pts, tri
