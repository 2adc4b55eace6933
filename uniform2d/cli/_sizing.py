"""The size-field options of ``mesh`` and ``info``: ``--refine near:ratio[:rate]``
(repeatable) and ``--size-field FILE``, combined into one field (the smallest
size wins)."""

from __future__ import annotations


def add_size_options(p) -> None:
    from ..refine import NEAR

    p.add_argument("--refine", action="append", default=[], metavar="NEAR:RATIO[:RATE]",
                   help=f"graded mesh: size RATIO times the coarse size near NEAR ({', '.join(NEAR)}),"
                   " growing at slope RATE (default 0.3) away from it; repeatable (the smallest "
                   "size wins). The coarse size is --size H, else only the shape matters (-n)")
    p.add_argument("--size-field", metavar="FILE",
                   help="graded mesh: sizes from FILE, a grid (.npz or .json with x, y, values) "
                   "or a background mesh with point data 'size' (any format meshio reads)")


def has_field(args) -> bool:
    return bool(args.refine) or args.size_field is not None


def field_from_args(polygon, args):
    """The size field the options ask for, or None (a uniform mesh)."""
    if not has_field(args):
        return None
    from ..io.size_file import read_size_field
    from ..refine import minimum, parse_refine, refine

    fields = [refine(polygon, **parse_refine(text), size=args.size) for text in args.refine]
    if args.size_field is not None:
        fields.append(read_size_field(args.size_field))
    return minimum(polygon, *fields)
