"""Benchmark: the first run's compile time (README command 1 with no numba cache).

Usage::

    python benchmarks/bench_compile.py [--n 400] [--top 15] [--one-cpu] [--llvm] [--trace]
                                       [--timeline]

Runs ``uniform2d mesh data/plate_bolts.json -n 400 -o plate.vtu --stats --plot
plate.png`` (README command 1) in a fresh process whose numba cache is an empty
directory (``NUMBA_CACHE_DIR``), so every kernel compiles, and prints the wall
time from the start of that process to its exit (what a user waits for), the CPU
time of the command and of the process compiling kernels beside it on a cold
cache (``uniform2d/cli/_warmer.py``), and, from numba's compile events in the
command's own process, the compile time per kernel module and the functions
that take longest.  Compile times are CPU times of the compiling thread (on a
loaded machine wall times measure the other processes too), exclusive: a
function's own compile, without the callees it compiled on the way; the wall
time the command spent in compiles is printed beside them (it includes waits
for kernels the warmer was compiling, :mod:`uniform2d.compile_claims`).  Functions compiled more than once (one
specialisation per argument types) are listed: each extra one is compile time a
caller could save.  ``--llvm`` adds LLVM's share of the command's compile
(function passes, module passes, machine-code generation: CPU seconds) and the
lines of IR its module passes optimised against the same with each function
counted once: numba links a copy of every callee into each caller's module and
optimises and generates it again there.  ``--trace`` adds, per process (the
command and its warmer), when it started and ended, its CPU and its top-level
compiles' CPU and wall (wall beyond CPU: waits for the other's claims, or for
the CPU); ``--timeline`` lists those compiles in order.  ``--one-cpu`` runs the command on one CPU, where it starts
no second process: the first run as it is without one.  The second process
starts only if a CPU is idle (``uniform2d/cli/_warmer.py``); on a shared
machine, ``nice -n -10 python benchmarks/bench_compile.py --ignore-load`` comes
near what an idle one does.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import _checkout  # noqa: F401  (measure this checkout, and so do the timed children)

ROOT = Path(__file__).resolve().parents[1]

#: Put on the command's PYTHONPATH (as ``sitecustomize``) with ``--trace``: each
#: process, the command and its warmer, appends one JSON line per top-level
#: compile (wall start and end, CPU) and one when it ends to BENCH_TRACE.
TRACER = r"""
import json, os, time
T = os.environ.get("BENCH_TRACE")
if T:
    from numba.core import event as _ev
    _role = "warmer" if os.environ.get("UNIFORM2D_COMPILE_CLAIMS") else "command"
    _stack = []

    def _write(**rec):
        with open(T, "a") as f:
            f.write(json.dumps({"pid": os.getpid(), "role": _role, **rec}) + "\n")

    _write(start=time.time(), cpu=time.process_time())

    class _Trace(_ev.Listener):
        def on_start(self, e):
            _stack.append((time.time(), time.thread_time()))
        def on_end(self, e):
            t0, c0 = _stack.pop()
            if not _stack:
                d = e.data["dispatcher"]
                _write(name=f"{d.py_func.__module__.rsplit('.', 1)[-1]}.{d.py_func.__name__}",
                       t0=t0, t1=time.time(), cpu=time.thread_time() - c0)

    _ev.register("numba:compile", _Trace())
    _exit = os._exit

    def _traced_exit(code):
        _write(end=time.time(), cpu=time.process_time())
        _exit(code)

    os._exit = _traced_exit
    import atexit
    atexit.register(lambda: _write(end=time.time(), cpu=time.process_time()))
"""

CHILD = r"""
import collections, json, os, resource, sys, time
from numba.core import event as ev

stack, own, count = [], collections.Counter(), collections.Counter()

def name_of(d):
    mod = str(getattr(d.py_func, "__module__", None) or "numba")
    return mod.rsplit(".", 1)[-1] + "." + d.py_func.__name__

wall = [0.0]

class Listener(ev.Listener):
    def on_start(self, e):
        stack.append([time.thread_time(), 0.0, time.perf_counter()])
    def on_end(self, e):
        t0, child, w0 = stack.pop()
        dt = time.thread_time() - t0
        name = name_of(e.data["dispatcher"])
        own[name] += dt - child
        count[name] += 1
        if stack:
            stack[-1][1] += dt
        else:
            wall[0] += time.perf_counter() - w0

ev.register("numba:compile", Listener())
llvm = collections.Counter()
if os.environ.get("BENCH_LLVM"):  # LLVM's share of the compile, and its work on copies
    import re
    from llvmlite.binding import newpassmanagers as npm
    from numba.core import codegen

    def timed(cls, name, key):
        f = getattr(cls, name)
        def run(self, *a, **k):
            t = time.thread_time()
            try:
                return f(self, *a, **k)
            finally:
                llvm[key] += time.thread_time() - t
        setattr(cls, name, run)

    timed(npm.FunctionPassManager, "run", "function passes")
    timed(npm.ModulePassManager, "run", "module passes")
    timed(codegen.JitEngine, "finalize_object", "machine code")
    lines, optimise = {}, codegen.CPUCodeLibrary._optimize_final_module

    def counted(self):  # a kernel's module, its callees' copies linked in
        t = time.thread_time()
        for m in re.finditer(r'^define [^@]*@"?([^"(]+)"?\(.*?^}', str(self._final_module),
                             re.S | re.M):
            n = m.group(0).count("\n")
            llvm["IR lines optimised"] += n
            lines[m.group(1)] = max(lines.get(m.group(1), 0), n)
        llvm["counting"] += time.thread_time() - t
        optimise(self)

    codegen.CPUCodeLibrary._optimize_final_module = counted
if os.environ.get("BENCH_IGNORE_LOAD"):  # measure what an idle machine's run does
    import uniform2d.cli._warmer as warmer
    warmer.busy = lambda cpus: False
from uniform2d.cli.main import main
code = main(sys.argv[1:])
if llvm:
    llvm["IR lines, each function once"] = sum(lines.values())
json.dump({"code": code, "own": own, "count": count, "compile_wall": wall[0], "llvm": llvm},
          sys.stderr)
"""


def _cpu_of_children() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _one_cpu() -> None:
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})


def first_run(n: int = 400, one_cpu: bool = False, ignore_load: bool = False,
              llvm: bool = False, trace: bool = False) -> dict | None:
    """README command 1 (``mesh -n n``) in a fresh process on an empty numba cache:
    {"wall", "cpu" (with the warmer's), "code", "own", "count", "llvm"} (own
    compile seconds and compilations per function; with ``llvm``, LLVM's CPU
    seconds by stage and the IR lines its module passes optimised; with ``trace``,
    "trace": each process's records, see :data:`TRACER`), or None (its stderr
    printed) if the command's compile record cannot be read."""
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        if trace:
            Path(out, "site").mkdir()
            Path(out, "site", "sitecustomize.py").write_text(TRACER)
            env["PYTHONPATH"] = os.pathsep.join(
                [str(Path(out, "site"))] + [p for p in [env.get("PYTHONPATH")] if p])
            env["BENCH_TRACE"] = str(Path(out, "trace.jsonl"))
        if ignore_load:
            env["BENCH_IGNORE_LOAD"] = "1"
        if llvm:
            env["BENCH_LLVM"] = "1"
        cmd = [sys.executable, "-c", CHILD, "mesh", str(ROOT / "data" / "plate_bolts.json"),
               "-n", str(n), "-o", str(Path(out) / "plate.vtu"), "--stats",
               "--plot", str(Path(out) / "plate.png")]
        cpu0, t0 = _cpu_of_children(), time.perf_counter()
        run = subprocess.run(cmd, env=env, cwd=out, capture_output=True, text=True, check=False,
                             preexec_fn=_one_cpu if one_cpu else None)
        wall, cpu = time.perf_counter() - t0, _cpu_of_children() - cpu0
        records = []
        if trace and Path(env["BENCH_TRACE"]).exists():
            records = [json.loads(line) for line in
                       Path(env["BENCH_TRACE"]).read_text().splitlines()]
    tail = run.stderr[run.stderr.rfind('{"code"'):]
    try:
        res = json.loads(tail)
    except ValueError:
        print(run.stderr, file=sys.stderr)
        return None
    return {"wall": wall, "cpu": cpu, "trace": records, **res}


def _show_trace(records: list, timeline: bool) -> None:
    """Per process (the command, its warmer): when it started and ended (s from
    the command's start), its CPU, its top-level compiles' CPU and wall (wall
    beyond CPU: waits for claimed kernels, or for the CPU)."""
    if not records:
        return
    origin = min(r["start"] for r in records if "start" in r)
    for pid in dict.fromkeys(r["pid"] for r in records):
        mine = [r for r in records if r["pid"] == pid]
        role = mine[0]["role"]
        start = next((r["start"] for r in mine if "start" in r), origin)
        end = next((r for r in mine if "end" in r), None)
        comps = [r for r in mine if "name" in r]
        ccpu = sum(r["cpu"] for r in comps)
        cwall = sum(r["t1"] - r["t0"] for r in comps)
        last = max((r["t1"] for r in comps), default=start)
        print(f"{role}: from {start - origin:.1f} s to "
              + (f"{end['end'] - origin:.1f} s, CPU {end['cpu']:.1f} s" if end else
                 f"its kill (last compile ended at {last - origin:.1f} s)")
              + f"; {len(comps)} top-level compiles: {ccpu:.1f} s CPU, {cwall:.1f} s wall"
              + (f", first at {comps[0]['t0'] - origin:.1f} s, last ended {last - origin:.1f} s"
                 if comps else ""))
        if timeline:
            for r in comps:
                print(f"    {r['t0'] - origin:6.1f} {r['t1'] - origin:6.1f}  cpu {r['cpu']:5.2f}"
                      f"  {r['name']}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--top", type=int, default=15, help="functions listed")
    ap.add_argument("--one-cpu", action="store_true",
                    help="run the command on one CPU (no second compiling process)")
    ap.add_argument("--ignore-load", action="store_true",
                    help="start the second compiling process even if the machine's load says "
                    "its CPUs are busy (e.g. under 'nice -n -10' on a shared machine)")
    ap.add_argument("--llvm", action="store_true",
                    help="also LLVM's CPU time by stage in the command's process, and how much "
                    "of the IR it optimised are copies of callees linked into their callers "
                    "(counting them adds a fraction of a second to the compile figures)")
    ap.add_argument("--trace", action="store_true",
                    help="per process (the command and its warmer): start, end, CPU, compile "
                    "CPU and wall")
    ap.add_argument("--timeline", action="store_true",
                    help="with --trace, list each process's top-level compiles in order")
    args = ap.parse_args(argv)
    if args.one_cpu and not hasattr(os, "sched_setaffinity"):
        ap.error("--one-cpu needs os.sched_setaffinity (Linux)")
    res = first_run(args.n, one_cpu=args.one_cpu, ignore_load=args.ignore_load, llvm=args.llvm,
                    trace=args.trace or args.timeline)
    if res is None:
        return 1
    wall, cpu = res["wall"], res["cpu"]
    own, count = res["own"], res["count"]
    modules: dict[str, float] = {}
    for name, t in own.items():
        modules[name.split(".")[0]] = modules.get(name.split(".")[0], 0.0) + t
    print(f"first run, mesh -n {args.n}, empty numba cache"
          + (", one CPU" if args.one_cpu else ""))
    print(f"wall {wall:.1f} s   CPU {cpu:.1f} s (with the kernel warmer, if any)   "
          f"load {os.getloadavg()[0]:.2f}")
    print(f"the command's own compile: {sum(own.values()):.1f} s CPU in {sum(count.values())} "
          f"compilations, {res['compile_wall']:.1f} s wall (with waits for kernels the warmer "
          "was compiling, and for the CPU on a loaded machine)")
    print("compile per module (s): " + ", ".join(
        f"{m} {t:.1f}" for m, t in sorted(modules.items(), key=lambda kv: -kv[1])))
    llvm = res.get("llvm") or {}
    if llvm:
        stages = ("function passes", "module passes", "machine code")
        print("LLVM in the command's process: " + ", ".join(f"{k} {llvm.get(k, 0.0):.1f} s"
                                                             for k in stages)
              + f" (CPU); counting the IR took {llvm.get('counting', 0.0):.1f} s of the compile")
        once = llvm.get("IR lines, each function once", 0)
        total = llvm.get("IR lines optimised", 0)
        print(f"IR optimised by module passes: {total:,.0f} lines, {once:,.0f} with each function "
              f"counted once ({total / max(once, 1):.1f}x: callees are linked into every caller "
              "and optimised and generated again there)")
    _show_trace(res["trace"], args.timeline)
    print("longest functions:")
    for name, t in sorted(own.items(), key=lambda kv: -kv[1])[: args.top]:
        print(f"  {t:6.2f} s  x{count[name]}  {name}")
    again = {k: v for k, v in count.items() if v > 1 and not k.startswith(("arrayobj.", "builtins.", "numba."))}
    if again:
        print("compiled more than once: " + ", ".join(f"{k} x{v}" for k, v in sorted(again.items())))
    return 0 if res["code"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
