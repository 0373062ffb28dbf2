"""The cost of the boundary: Case I through `texopt.simulate` against the program's
`texopt simulate … --json`, run alternately on an idle machine, best and median of N; and
two cases from two threads against the same two one after the other.

    python python/bench.py [N]    # writes results/python/boundary.json and boundary.md

The program's time includes starting its process and printing the JSON; Python's includes
reading the keywords, releasing the GIL and building the result's arrays.
"""

import json
import platform
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import texopt

ROOT = Path(__file__).resolve().parents[1]
BIN = ROOT / "target" / "release" / "texopt"
CASE = dict(R=0.8, l1=0.01, per=0.06, depth=5)
N = int(sys.argv[1]) if len(sys.argv) > 1 else 9


def program() -> float:
    argv = [str(BIN), "simulate", "--json"]
    for k, v in CASE.items():
        argv += [f"--{k}", str(v)]
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, capture_output=True)
    return time.perf_counter() - t0


def python() -> float:
    t0 = time.perf_counter()
    texopt.simulate(**CASE, progress=False)
    return time.perf_counter() - t0


def pair(threads: int) -> float:
    """Case I and Case III from `threads` threads (1: one after the other)."""
    cases = [CASE, dict(R=3.2, l1=0.03, per=0.06, depth=10)]
    t0 = time.perf_counter()
    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(lambda c: texopt.simulate(**c, progress=False), cases))
    return time.perf_counter() - t0


program(), python()  # warm the caches of both
times = {"program": [], "python": []}
for _ in range(N):
    times["program"].append(program())
    times["python"].append(python())
pairs = {"one_thread": [], "two_threads": []}
for _ in range(max(3, N // 3)):
    pairs["one_thread"].append(pair(1))
    pairs["two_threads"].append(pair(2))
summary = {
    name: {"best_s": min(t), "median_s": statistics.median(t), "runs": t}
    for name, t in times.items()
}
ratio_best = summary["python"]["best_s"] / summary["program"]["best_s"] - 1
ratio_median = summary["python"]["median_s"] / summary["program"]["median_s"] - 1
out = ROOT / "results" / "python"
out.mkdir(parents=True, exist_ok=True)
report = {
    "case": CASE,
    "fidelity": "fast",
    "host": platform.node(),
    "python": platform.python_version(),
    "n": N,
    "timings": summary,
    "python_over_program_best": ratio_best,
    "python_over_program_median": ratio_median,
    "two_cases": {k: {"best_s": min(v), "runs": v} for k, v in pairs.items()},
}
(out / "boundary.json").write_text(json.dumps(report, indent=2) + "\n")
md = f"""# The cost of the Python boundary

`python python/bench.py {N}` (an idle machine; ≈ {2 * N + 2} s): Case I (R = 0.8 cm, pockets
0.01 cm, per 0.06 cm, 5 µm deep, `fast`) through `texopt.simulate` and through the program's
`texopt simulate … --json`, alternately, {N} times each.

| | best (s) | median (s) |
|---|---|---|
| the program | {summary['program']['best_s']:.3f} | {summary['program']['median_s']:.3f} |
| Python | {summary['python']['best_s']:.3f} | {summary['python']['median_s']:.3f} |
| Python against the program | {100 * ratio_best:+.1f} % | {100 * ratio_median:+.1f} % |

The program's time includes starting its process and printing its JSON; Python's includes
reading the keywords, releasing the GIL and building the result's arrays.

Two cases (Case I and Case III at `fast`) from a pool of two threads take
{min(pairs['two_threads']):.2f} s against {min(pairs['one_thread']):.2f} s one after the other (best of
{len(pairs['one_thread'])}): the GIL is released while Rust computes, so on two cores the pair takes
about the longer case's time.
"""
(out / "boundary.md").write_text(md)
print(md)
