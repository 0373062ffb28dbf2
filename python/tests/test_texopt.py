"""texopt from Python against the texopt program: the same answers, the same cache, the same
refusals; Ctrl-C that keeps the cache whole; threads that compute side by side.

Run by `cargo test --release` (tests/python.rs builds the package into a virtual environment
and runs pytest here), or by hand after `maturin develop --release` with TEXOPT_BIN naming
the texopt program.
"""

import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import texopt

ROOT = Path(__file__).resolve().parents[2]
TEXOPT = os.environ.get("TEXOPT_BIN", str(ROOT / "target" / "release" / "texopt"))

CASE_I = dict(R=0.8, l1=0.01, per=0.06, depth=5)


def cli(*args, check=True):
    out = subprocess.run([TEXOPT, *map(str, args)], capture_output=True, text=True)
    if check:
        assert out.returncode == 0, out.stderr
    return out


def small_study(
    dir: Path, depths=(5, 10), l1=(0.02, 0.03), radii=(3.2, 5), n1=64, n2=4
) -> Path:
    """A study on a coarse mesh, its report in dir/out."""
    text = f"""
        [study]
        name = "small"
        fidelity = "draft"
        untextured = true

        [parameters]
        R = {list(radii)}
        l1 = {list(l1)}
        per = 0.06
        depth = {list(depths)}

        [numerics]
        n1 = {n1}
        n2 = {n2}
        dt = 1.6e-3
        periodic_tol = 1e-3

        [report]
        dir = "{dir / 'out'}"
    """
    path = dir / "small.toml"
    path.write_text(textwrap.dedent(text))
    return path


def test_case_I_from_python_is_the_program_s_json_to_the_bit():
    r = texopt.simulate(**CASE_I)
    flags = [f"--{k}" for k in CASE_I]
    argv = [x for k, v in zip(flags, CASE_I.values()) for x in (k, v)]
    program = json.loads(cli("simulate", *argv, "--json").stdout)
    # Every key and every number equal (JSON numbers read back to the same doubles), but
    # the wall time, which is the clock's.
    assert r.answer.pop("wall_time_s") > 0
    program.pop("wall_time_s")
    assert r.answer == program
    assert r.f_mean == program["f_mean"] and r.c_min == program["c_min"]


def test_the_last_period_and_the_film_come_back_as_arrays():
    r = texopt.simulate(**CASE_I, frames=3, progress=False)
    period = CASE_I["per"]  # u = 1: one period is per in units of L/U
    assert r.t[-1] == pytest.approx(r.t_end)
    assert r.t[-1] - r.t[0] < period <= r.t[-1] - r.t[0] + 2 * (r.t[1] - r.t[0])
    assert np.all(np.isfinite(r.z)) and np.all(np.isfinite(r.f))
    # The period's mean friction is the answer's (the run's last window is one period).
    assert np.mean(r.f) == pytest.approx(r.f_mean, rel=0.02)
    assert r.z.min() == pytest.approx(r.z_min, rel=1e-9)
    assert len(r.frames) == 3
    n1, n2 = r.answer["inputs"]["numerics"]["n1"], r.answer["inputs"]["numerics"]["n2"]
    frame = r.frames[0]
    assert frame.p.shape == frame.theta.shape == frame.h.shape == (n1 + 1, n2)
    assert frame.p.min() >= 0 and 0 <= frame.theta.min() and frame.theta.max() <= 1
    assert frame.x1[0] == 0 and frame.x1[-1] == pytest.approx(0.2)


@pytest.mark.parametrize(
    "kw, named",
    [
        (dict(R=5, depth=5, per=0.06), "l1 = missing"),
        (dict(R=5, l1="wide", per=0.06, depth=5), "l1 = 'wide': must be a number"),
        (dict(R=0.01), "R = 0.01"),
        (dict(R=5, speed=-3), "speed = -3"),
        (dict(R=5, fidelity="quick"), "fidelity = 'quick': must be one of draft, fast"),
        (dict(R=5, mesh=(700,)), "mesh = (700,)"),
        (dict(R=5, l1=0.001, per=0.06, depth=20), "allow_thick_pockets=True"),
        (dict(R=5, e_star=0.001), "contact=False runs without"),
    ],
)
def test_a_bad_argument_raises_value_error_naming_it_and_the_rule(kw, named):
    with pytest.raises(ValueError, match=named.replace("(", r"\(").replace(")", r"\)")):
        texopt.simulate(**kw)


def test_an_unknown_keyword_is_a_type_error_as_in_python():
    with pytest.raises(TypeError, match="depht"):
        texopt.simulate(R=5, depht=5)


def test_a_failed_run_raises_texopt_error_with_its_reason():
    # Far outside the validated range: the film cannot carry the load and the gap closes.
    with pytest.raises(texopt.TexoptError, match="the gap closed"):
        texopt.simulate(**CASE_I, speed=0.001, load=1e6, progress=False)


def test_the_program_s_commands_refuse_bad_input_as_value_error(tmp_path):
    with pytest.raises(ValueError, match="--depth = 20..2"):
        texopt.optimise(5, depth=(20, 2), out=tmp_path / "o", cache=tmp_path / "c.sqlite")
    with pytest.raises(ValueError, match="--bogus"):
        texopt.optimise(5, bogus=3)
    assert not (tmp_path / "o").exists() and not (tmp_path / "c.sqlite").exists()


def test_a_cache_written_from_python_is_read_by_the_program_and_back(tmp_path):
    study = small_study(tmp_path)
    cache = tmp_path / "c.sqlite"
    run = texopt.study(study, cache=cache)
    assert run.code == 0 and len(run.rows) == 10
    assert set(run.rows["status"]) == {"done"}
    out = cli("study", study, "--cache", cache, "--cached-only")
    assert "10 cases: 10 from the cache, 0 computed" in out.stdout
    # The other way round: the program fills a cache that Python reads without computing.
    other = tmp_path / "d.sqlite"
    cli("study", study, "--cache", other, "--no-report")
    again = texopt.study(study, cache=other, cached_only=True)
    assert len(again.rows) == 10 and set(again.rows["status"]) == {"done"}
    assert list(again.rows["f_mean"]) == list(run.rows["f_mean"])


def test_ctrl_c_stops_a_study_and_leaves_its_cache_consistent(tmp_path):
    # Rows enough that the study takes seconds: Ctrl-C must land while it runs.
    study = small_study(
        tmp_path, depths=(2, 4, 6, 8, 10), l1=(0.01, 0.02, 0.03), radii=(3.2, 5, 12.8), n1=200, n2=16
    )
    cache = tmp_path / "c.sqlite"
    script = (
        "import sys, texopt\n"
        "print('started', flush=True)\n"
        f"texopt.study({str(study)!r}, cache={str(cache)!r}, jobs=1)\n"
    )
    child = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert child.stdout.readline().strip() == "started"
    # Once a few cases are stored, Ctrl-C.
    deadline = time.time() + 120
    while time.time() < deadline and child.poll() is None and stored(cache) < 3:
        time.sleep(0.1)
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=120)
    assert child.returncode != 0 and "KeyboardInterrupt" in err, err
    done = stored(cache)
    total = 5 * 3 * 3 + 3
    assert 3 <= done < total, f"{done} of {total} cases stored"
    # The program reads what was stored, and the rest is computed where the run stopped.
    out = cli("study", study, "--cache", cache, "--no-report")
    assert f"{total} cases: {done} from the cache, {total - done} computed" in out.stdout


def stored(cache: Path) -> int:
    """The cases a cache holds, read by the program (0 before it exists)."""
    if not cache.exists():
        return 0
    out = cli("cache", "--cache", cache, "stats", check=False)
    for line in out.stdout.splitlines():
        if "evaluations done" in line:
            return int(line.split()[0])
    return 0


def test_two_threads_compute_side_by_side():
    """The GIL is released while Rust computes: two calls from two threads overlap in time
    (with the GIL held, the second could not even start before the first returned)."""
    spans = {}

    def one(name, R):
        start = time.perf_counter()
        texopt.simulate(R=R, l1=0.01, per=0.06, depth=5, progress=False)
        spans[name] = (start, time.perf_counter())

    with ThreadPoolExecutor(2) as pool:
        list(pool.map(one, ["a", "b"], [3.2, 5]))
    (a0, a1), (b0, b1) = spans["a"], spans["b"]
    assert max(a0, b0) < min(a1, b1), spans
    # Meanwhile the interpreter itself runs: a thread counting while a case computes.
    counted = []
    stop = threading.Event()

    def count():
        n = 0
        while not stop.is_set():
            n += 1
        counted.append(n)

    t = threading.Thread(target=count)
    t.start()
    texopt.simulate(**CASE_I, progress=False)
    stop.set()
    t.join()
    assert counted[0] > 1000


def test_optimise_gives_its_front_and_best_designs_as_tables(tmp_path):
    run = texopt.optimise(
        5,
        particles=2,
        iterations=1,
        fidelity="draft",
        mesh=(64, 4),
        dt=1.6e-3,
        per=(0.03, 0.06),
        l1=(0.005, 0.012),
        out=tmp_path / "o",
        cache=tmp_path / "c.sqlite",
    )
    assert run.code == 0
    assert len(run.front) >= 1 and {"l1", "per", "depth", "f_mean", "c_min"} <= set(run.front)
    # Either best may be the plain liner (no texture of this small space beating it).
    assert len(run.best) == 2
    assert set(run.best["label"]) <= {"best friction", "best clearance", "plain liner"}
    assert np.all(np.isfinite(run.front["f_mean"]))
    report = run.reports["R5"]
    assert report["best_friction"]["f_mean"] == run.best["f_mean"][0]


def test_cycle_gives_its_tables(tmp_path):
    engine = (ROOT / "python" / "tests" / "engine_small.toml").read_text()
    file = tmp_path / "e.toml"
    file.write_text(engine)
    run = texopt.cycle(
        file,
        quasi_steady=True,
        step=10,
        design_step=90,
        particles=2,
        iterations=1,
        mesh=(64, 4),
        dt=1.6e-3,
        out=tmp_path / "out",
        cache=tmp_path / "c.sqlite",
    )
    assert run.code == 0
    assert len(run.angles) == 72
    assert "cycle_t" in run.reports


def test_without_pandas_tables_are_lists_of_dicts(tmp_path, monkeypatch):
    study = small_study(tmp_path)
    texopt.study(study, cache=tmp_path / "c.sqlite")
    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` now fails
    run = texopt.study(study, cache=tmp_path / "c.sqlite", cached_only=True)
    assert isinstance(run.rows, list) and len(run.rows) == 10
    assert isinstance(run.rows[0]["f_mean"], float)
