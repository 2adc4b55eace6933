"""The optimiser's tuning: how long each stage runs and how far a move goes.

Each constant is a choice measured on the benchmark polygons and patches (the
measurements are in the commit history); the comments say what the constant
controls and why it has the value it has.
"""

from __future__ import annotations

from fractions import Fraction
from typing import NamedTuple


class Stage(NamedTuple):
    """One descent stage's own limits, where a schedule sets them
    (:attr:`Schedule.stages`)."""

    sweeps: int  # at most
    #: the stage ends after ``patience`` sweeps in a row none of which lowered
    #: the objective by the fraction ``gain``; None: the kernel's
    #: (:data:`uniform2d._kernel.descent.PATIENCE`, ``GAIN``)
    patience: int | None = None
    gain: float | None = None


class Schedule(NamedTuple):
    """Iteration counts of one :func:`uniform2d.optimize.improve` run."""

    spring_rounds: int  # least-squares spring rounds first
    sweeps: int  # descent sweeps per stage (at most)
    exponents: tuple  # stage k minimises the p-norm energy with p = 2**k
    spread_sweeps: int  # sweeps of the final stage that lowers the edge spread
    #: ((k, Stage), ...): the stages p = 2**k with limits of their own (the
    #: others: ``sweeps`` and the kernel's stopping rule)
    stages: tuple = ()

    def stage(self, k: int) -> Stage:
        """The limits of the stage p = 2**k."""
        return dict(self.stages).get(k, Stage(self.sweeps))


#: Meshes up to LARGE points: stages up to p = 256, which lowers the longest edge
#: and the largest perimeter further than stopping at 64; beyond 256 the gain is
#: small and the powers would overflow for edges off their target by 2x.
SCHEDULE = Schedule(60, 40, (4, 5, 6, 7, 8), 20)
#: Above LARGE points, where the work is kept near linear.
SCHEDULE_LARGE = Schedule(30, 25, (4, 5), 5)
#: With a size field (the surface layer) the stages stop at p = 64: the higher
#: ones trade the bulk of the grading for the extremes, and the surface's
#: targets are about the spread (CV) more than the extremes.  Shorter stages and
#: a longer spread stage buy the same CV for less time.
SCHEDULE_GRADED = Schedule(60, 25, (2, 3, 4, 5, 6), 30)
#: The winner of the trials (:func:`uniform2d.optimize.moves.improve_best`) in
#: meshes of more than MEDIUM points, up to SMALL: its trials ran 40 spring
#: rounds and two short descent stages already, and there a second spring
#: run of 20 rounds, stages of up to 25 sweeps and 10 spread sweeps reach what
#: 60, 40 and 20 do within 0.3 % (geometric means of every measure of
#: bench_uniform at 1000 and 10000, of bench_constrained at 1000 and
#: bench_angles at 1500 and the bolt plate at 2000 and 8000; the worst angle
#: of none lower) for a quarter less of the serial schedule's time.  Without
#: the second spring run rect4x1's edge ratio at n = 1000 is 7 % worse.
#: Smaller meshes keep SCHEDULE: their worst angle (the angle fit's start)
#: moves with the schedule.  Above SMALL points, where fewer starts are tried,
#: the shorter run lets one polygon's longest edge grow by more than 1 %, so
#: they keep SCHEDULE's stages (SCHEDULE_BIG).  5 spread sweeps instead of 10
#: leave every extreme as it was (within 0.1 %) and the edge CV up to 0.36 %
#: higher (0.2 % in the geometric means) for 5 % less CPU time at n = 1000.
#: The p = 32, 64 and 256 stages stop at 20 sweeps (p = 128 keeps 25): every
#: measure of the benchmark polygons at 1000, 1500 and 3000 points and the
#: bolt plate at 2000 and 4000 within 0.62 % (geometric means within 0.25 %),
#: 3.6 % less CPU time at n = 1000; 20 sweeps in every stage, or in the
#: first three, cost the plate's CV at 2000 3 %.
SCHEDULE_MEDIUM = Schedule(20, 25, (4, 5, 6, 7, 8), 5,
                           stages=((5, Stage(20)), (6, Stage(20)), (8, Stage(20))))
MEDIUM = 1000
#: The winner above SMALL points, up to LARGE: SCHEDULE with 5 spread sweeps
#: instead of 20, which at n = 10000 (bench_uniform) and the bolt plate at
#: 8000 points leave every extreme and the worst angle as they were (within
#: 0.03 %) and the edge CV up to 0.41 % higher (0.2 % in the geometric mean),
#: for 13 % less CPU time.  Fewer sweeps a stage (25, 32) or spring rounds
#: (30), or one stage fewer (p = 2**6 or 2**7), cost a longest edge or the
#: plate's worst angle more than 1 %.  Its stages stop after 5 sweeps without
#: gain (the kernel's PATIENCE is 6), the p = 32 and 64 ones after 5 sweeps
#: that lower the objective by less than 3e-4 each (GAIN 1e-4: slow creep
#: there is undone by the later stages anyway): every measure of the
#: benchmark polygons at 6000, 10000 and 15000 points and the bolt plate at
#: 6000, 8000 and 15000 within 0.83 % (geometric means within 0.1 %), 6 %
#: less CPU time at n = 10000.  Patience 2 in those two stages saves 13-16 %
#: but costs the plate at 6000 4.5 % of its edge ratio.
SCHEDULE_BIG = Schedule(60, 40, (4, 5, 6, 7, 8), 5,
                        stages=((4, Stage(40, 5)), (5, Stage(40, 5, 3e-4)),
                                (6, Stage(40, 5, 3e-4)), (7, Stage(40, 5)), (8, Stage(40, 5))))
#: Point counts (|V| + n) above which fewer starts are tried
#: (:func:`uniform2d.optimize.seed.variants`: above SMALL fewer, above LARGE
#: one) and, above LARGE, SCHEDULE_LARGE is used.
LARGE = 20000
SMALL = 5000

#: Quality guard of the moves: a triangle whose doubled area is below
#: FLAT * target**2 may not get flatter (an equilateral one has 0.87 * target**2).
FLAT = 0.1
#: Spring rounds (:func:`uniform2d._kernel.relax.spring`): the step (fraction of
#: the spring force applied per round), the pressure (rest lengths scaled so
#: that their root mean square is this times the edges'), the relative
#: displacement below which the rounds stop, and the cap of a move (fraction of
#: the target length).
SPRING_STEP = 0.2
SPRING_PRESSURE = 1.02
SPRING_TOL = 1e-4
SPRING_CAP = 0.3
#: First step of a descent or spread line search (fraction of the target length).
SEARCH_STEP = 0.05

#: Boundary spacings (relative to h) tried for small and medium meshes.  Above
#: SMALL points a spacing other than 1.0 never won on the benchmark and bundled
#: polygons (at 8000 and 10000 Steiner points), so medium meshes try 1.0 alone;
#: below, 0.95 and 1.05 each win on some of them.
SPACINGS = (1.0, 0.95, 1.05)
SPACINGS_MEDIUM = (1.0,)
#: Seeds tried: the plain lattice (False) and boundary rows + lattice (True).
LAYERED = (False, True)
LAYERED_MEDIUM = (True,)
LAYERED_LARGE = True
#: Meshes of more than STRIPS_MIN and up to SMALL points of a polygon without
#: holes, segments or fixed points also try *strip starts*: STRIP_DEPTHS rows
#: along every edge (each staggered from the one below,
#: :func:`uniform2d.optimize.rows.boundary_rows`), at the boundary spacings
#: STRIP_SPACINGS, after the other starts (which win ties).  They lower the
#: longest-edge and perimeter factors where the boundary's rows set them;
#: around holes they cost worst angle and CV, at n = 1000 the speed goal has no
#: room for them and below STRIPS_MIN they gain too little for their time
#: (measured in docs/strip_starts.md).
STRIPS_MIN = 1200
#: ... and only where P's edges are at least STRIP_PIECES target sizes long on
#: average: a resampled outline or a surface chart, edges of a piece or two,
#: has no strip to lay, and there the extra starts only change which of the
#: others wins (the more starts, the more go on after each trial).
STRIP_PIECES = 16
STRIP_DEPTHS = (2, 3)
STRIP_SPACINGS = (1.0,)
#: Successive halving over the starts (:func:`uniform2d.optimize.moves.improve_best`):
#: every start runs the first of these short schedules, the best KEEP of those
#: the next, and so on; the winner goes on into the full schedule from stage
#: AFTER_TRIALS (p = 2**5: after the trials' p = 8 and 32 stages a p = 16 one
#: gains nothing).  20 spring rounds, 4 sweeps a stage, or no p = 32 trial
#: pick worse starts (CV, edge ratio or min angle over 1 % worse
#: on the benchmark polygons); the winner's second spring run and the full
#: schedule's p = 32 stage are still worth their time.
TRIALS = (
    Schedule(40, 0, (), 0),
    Schedule(0, 6, (3,), 0),
    Schedule(0, 6, (5,), 0),
)
KEEP = Fraction(2, 3)  # exact: the survivors are ceil(KEEP * starts)
AFTER_TRIALS = 5
#: The first trial's spring rounds run in two parts: after PRUNE_ROUNDS rounds
#: the starts are ranked and only as many as the next trial takes, plus
#: PRUNE_SPARE, run the rest (a spring run goes on where it stopped, bit for
#: bit).  On the benchmark, bundled and constrained polygons at 200 to 2000
#: points the winner ranks at most fifth of 12 after 10 rounds in meshes of
#: more than KEEP_MAX points (6 go on after the first trial) and at most
#: eighth below (8 go on): the same winner, the same mesh, for 20-30 % fewer
#: spring rounds in the first trial.
PRUNE_ROUNDS = 10
#: Above KEEP_MAX points the split comes after PRUNE_ROUNDS_LARGE rounds: there
#: the winner ranks at most fourth of 12 after 5 rounds on the same cases (6
#: go on), and every mesh of bench_uniform, bench_constrained and
#: bench_angles is the same, bytes and all, with 5 as with 10 for every
#: size; below KEEP_MAX the margin is gone after 5 (heptagon_short's winner at
#: n = 200 ranks ninth of 12, 9 go on).
PRUNE_ROUNDS_LARGE = 5
PRUNE_SPARE = 1
#: Above KEEP_MAX points no spare: there the winner ranks at most fourth of 12
#: after PRUNE_ROUNDS_LARGE rounds on the benchmark, constrained and bolt-plate
#: polygons at 1000 to 2000 points, and the next trial takes five.  The split
#: still leaves two starts at least: with two (above SMALL points) deciding on
#: 5 rounds alone picked another start for square2holes at n = 10000.
PRUNE_SPARE_LARGE = 0
#: Above KEEP_MAX points fewer of the starts go on after each trial: the best
#: KEEP_LARGE[k] of them after trial k (ceil, at least one; the spring trial's
#: split then leaves all but those and PRUNE_SPARE out after PRUNE_ROUNDS).
#: On the benchmark, constrained and bolt-plate polygons at 1000 to 2000
#: points (21 cases) the winner ranks at most fifth of 12 after 10 spring
#: rounds, fourth of 7 after the spring trial and third of 6 after the p = 8
#: one; with the spring trial unsplit, rect4x1's at n = 1000 ranks fifth
#: after it: 12, then 6, 5 and 3 starts run the trials instead of 12, 7, 6
#: and 3, the same winner on all of them (same bytes on every case of
#: bench_uniform, bench_constrained and bench_angles).  Four after the spring
#: trial would keep those winners too but not rect4x1's unsplit one.  At
#: 10000 (two starts, one goes on) nothing changes.  In smaller meshes the
#: winner can rank lower early (the star's at n = 200 is fifth after two
#: trials): KEEP there.
KEEP_MAX = 500
KEEP_LARGE = (Fraction(5, 12), Fraction(3, 5))
#: With ``"balanced"``, the short run ranks the starts by its objective value
#: times the edge CV to this power: the start fixes the mesh's structure, and
#: with it the CV the moves can reach (on a rectangle, a lattice aligned with a
#: short side meets the long sides along a row of 5-7 pairs), which the
#: extremes alone do not see.  The weight buys a clearly lower CV for a small
#: cost in the extremes.
CV_WEIGHT = 0.5
#: Lattice seed points farther than BAND target sizes from the boundary stay put,
#: except where strip starts are tried (:func:`uniform2d.optimize.seed.stripped`).
BAND = 8.0

#: Relocation moves (:func:`uniform2d.optimize.relocate.relocate`), for meshes up
#: to RELOCATE_MAX points: tries, the radius (in target sizes) re-relaxed around
#: a move, and its schedule.  A try costs a CDT of the whole mesh and moves one
#: point, so it pays only where one point matters: in small meshes.
RELOCATE_MAX = 1000
RELOCATE_TRIES = 15
RELOCATE_RADIUS = 4.0
RELOCATE = {"spring_rounds": 20, "sweeps": 20, "exponents": (3, 4, 5, 6), "spread_sweeps": 10}


def schedule_for(n_points: int, graded: bool, winner: bool = False) -> Schedule:
    """The default schedule for a mesh of ``n_points`` points, with or without a
    size field; ``winner``: for the winner of the optimiser's trials
    (SCHEDULE_MEDIUM above MEDIUM points, up to SMALL; SCHEDULE_BIG above,
    up to LARGE)."""
    if n_points > LARGE:
        return SCHEDULE_LARGE
    if graded:
        return SCHEDULE_GRADED
    if winner and MEDIUM < n_points:
        return SCHEDULE_MEDIUM if n_points <= SMALL else SCHEDULE_BIG
    return SCHEDULE
