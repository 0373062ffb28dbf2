"""texopt from Python: the same engine as the ``texopt`` program, driven from a notebook.

    >>> import texopt
    >>> r = texopt.simulate(R=0.8, l1=0.01, per=0.06, depth=5)     # Case I of the paper
    >>> r.f_mean, r.c_min                                           # eq. 11, µm
    >>> r.t, r.z, r.f                                               # the last period (numpy)

``simulate`` runs one case in this process and answers as ``texopt simulate --json`` does, to
the bit; ``study``, ``optimise`` and ``cycle`` run the program's own commands in this process
(same checks, same cache, same files) and read back what they wrote as tables: pandas
DataFrames when pandas is installed, else lists of dicts. Inputs carry the program's units
(R, l1, per in cm, depth in µm, speed in m/s, load in N/m, viscosity in Pa·s; docs/model.md).

Errors: an input a rule refuses raises ``ValueError`` naming the input and the rule; a run that
fails raises ``TexoptError`` with the reason. The GIL is released while Rust computes, so
threads run cases side by side; Ctrl-C stops a study, the optimiser or a cycle as it stops the
program (no new case starts, the running ones finish and are stored in the cache), then
raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import csv
import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np

from . import _texopt
from ._texopt import TexoptError

__all__ = [
    "simulate",
    "study",
    "optimise",
    "cycle",
    "table",
    "Result",
    "Frame",
    "TexoptError",
    "TexoptWarning",
]


class TexoptWarning(UserWarning):
    """An answer texopt gives with a reservation (the periodic regime not reached)."""


def table(rows: Union[str, Path, Sequence[dict]]):
    """Rows (a CSV file's or a list of dicts) as a pandas DataFrame, or as a list of dicts
    with numbers read as numbers when pandas is not installed."""
    if isinstance(rows, (str, Path)):
        with open(rows, newline="") as f:
            rows = [{k: _number(v) for k, v in r.items()} for r in csv.DictReader(f)]
    try:
        import pandas as pd
    except ImportError:
        return list(rows)
    return pd.DataFrame(list(rows))


def _flat(rows: Sequence[dict]) -> list:
    """Design rows with their texture's fields (l1, l2, per, width, depth, phase) as
    columns of their own."""
    out = []
    for r in rows:
        r = dict(r)
        texture = r.pop("texture", None) or {}
        out.append({**texture, **r})
    return out


def _number(v: str):
    try:
        return float(v)
    except ValueError:
        return v


def _member(obj, mapping: str, name: str):
    """`obj.<mapping>[name]` read as an attribute, or an AttributeError saying what there is."""
    held = obj.__dict__.get(mapping, {})
    if name in held:
        return held[name]
    raise AttributeError(f"no {name!r} here; the {mapping} hold {sorted(held)}")


@dataclass
class Frame:
    """One instant of the film over the last period: time t and phase (units of L/U), ring
    position z (µm), load w_h and friction f, and the node fields p (units of 6μUL/H²),
    theta and h (µm) as arrays of shape (N1 + 1, N2) over the node coordinates x1, x2 (cm)."""

    t: float
    phase: float
    z: float
    w_h: float
    f: float
    p: np.ndarray
    theta: np.ndarray
    h: np.ndarray
    x1: np.ndarray
    x2: np.ndarray


@dataclass
class Result:
    """One run's answer.

    ``answer`` is the JSON object ``texopt simulate --json`` prints (inputs, physical values,
    validity, error, every outcome); its keys are also attributes (``r.f_mean``, ``r.c_min``,
    ``r.converged``, ``r.outside_model``, ``r.error``). ``series`` holds the last period's
    columns (t, z, w_h, w_a, f and the friction terms) as numpy arrays, ``t``, ``z`` and ``f``
    among them; ``frames`` the film's instants when asked for."""

    answer: dict
    series: dict = field(repr=False)
    frames: list = field(default_factory=list, repr=False)

    def __getattr__(self, name: str) -> Any:
        return _member(self, "answer", name)

    @property
    def t(self) -> np.ndarray:
        return self.series["t"]

    @property
    def z(self) -> np.ndarray:
        return self.series["z"]

    @property
    def f(self) -> np.ndarray:
        return self.series["f"]

    def __repr__(self) -> str:
        a = self.answer
        return (
            f"texopt.Result(f_mean={a['f_mean']:.5f}, c_min={a['c_min']:.4f} µm, "
            f"z_mean={a['z_mean']:.4f} µm, converged={a['converged']})"
        )


def simulate(
    R: float,
    *,
    l1: Optional[float] = None,
    l2: Optional[float] = None,
    per: Optional[float] = None,
    width: Optional[float] = None,
    depth: Optional[float] = None,
    phase: Optional[float] = None,
    theta_s: Optional[float] = None,
    speed: Optional[float] = None,
    load: Optional[float] = None,
    viscosity: Optional[float] = None,
    ring_width: Optional[float] = None,
    ring_mass: Optional[float] = None,
    d_oil: Optional[float] = None,
    roughness: Optional[float] = None,
    contact: bool = True,
    eta_beta_sigma: Optional[float] = None,
    sigma_over_beta: Optional[float] = None,
    e_star: Optional[float] = None,
    tau0: Optional[float] = None,
    varsigma: Optional[float] = None,
    fidelity: Optional[str] = None,
    mesh: Optional[tuple] = None,
    dt: Optional[float] = None,
    time_scheme: Optional[str] = None,
    periodic_tol: Optional[float] = None,
    t_max: Optional[float] = None,
    start: Optional[str] = None,
    accelerate: Optional[bool] = None,
    allow_thick_pockets: bool = False,
    transient: bool = False,
    frames: Optional[int] = None,
    progress: bool = True,
) -> Result:
    """One case to its periodic regime, as ``texopt simulate`` runs it (its flags are these
    keywords: ``--d-oil`` is ``d_oil``, ``--no-contact`` is ``contact=False``,
    ``--mesh 700x8`` is ``mesh=(700, 8)``); an input left at None takes the program's
    default (``fidelity="fast"``, ``theta_s=0.95``, ``t_max=30``, …). ``frames=N`` keeps N
    instants of the film over the last period (``Result.frames``); ``progress`` prints a line
    on stderr every 10 s of a long run."""
    kw = {k: v for k, v in locals().items() if k not in ("frames", "progress")}
    text, series, raw_frames = _texopt.simulate(kw, frames, progress)
    answer = json.loads(text)
    result = Result(
        answer=answer,
        series={k: np.asarray(v, dtype=float) for k, v in series.items()},
        frames=[_frame(f) for f in raw_frames or []],
    )
    if not answer["converged"]:
        # An error that could not be estimated (one window only) is null in the JSON.
        err = answer.get("periodic_error")
        err = "not yet estimated" if err is None else f"{err:.1e}"
        warnings.warn(
            f"the periodic regime was not reached by t = {answer['t_end']:g} (estimated error "
            f"{err}); the numbers are not final: raise t_max or loosen periodic_tol",
            TexoptWarning,
            stacklevel=2,
        )
    return result


def _frame(f: dict) -> Frame:
    shape = tuple(f["shape"])
    grid = {k: np.asarray(f[k], dtype=float).reshape(shape) for k in ("p", "theta", "h")}
    return Frame(
        t=f["t"],
        phase=f["phase"],
        z=f["z"],
        w_h=f["w_h"],
        f=f["f"],
        x1=np.asarray(f["x1"]),
        x2=np.asarray(f["x2"]),
        **grid,
    )


def _flags(options: dict) -> list:
    """Keywords as the program's flags: ``jobs=2`` → ``--jobs 2``, ``cached_only=True`` →
    ``--cached-only``, ``l1=(0.0025, 0.03)`` → ``--l1 0.0025..0.03``, ``mesh=(64, 4)`` →
    ``--mesh 64x4``, a list → commas."""
    argv = []
    for name, value in options.items():
        if value is None or value is False:
            continue
        flag = "--R" if name == "R" else "--" + name.replace("_", "-")
        if value is True:
            argv.append(flag)
        elif name == "mesh" and isinstance(value, tuple):
            argv += [flag, "x".join(str(int(n)) for n in value)]
        elif isinstance(value, tuple):
            lo, hi = value
            argv += [flag, f"{_text(lo)}..{_text(hi)}"]
        elif isinstance(value, (list, np.ndarray)):
            argv += [flag, ",".join(_text(v) for v in value)]
        else:
            argv += [flag, _text(value)]
    return argv


def _text(v) -> str:
    if isinstance(v, float):
        return "inf" if math.isinf(v) else repr(v)
    return str(v)


def _run(argv: list) -> tuple:
    code, files = _texopt.cli(["texopt", *argv])
    return code, [Path(f) for f in files]


@dataclass
class Run:
    """A command's run: its exit code (0: all done, 1: some cases failed), the files it wrote
    and the tables it answers with (``tables``: name → table)."""

    code: int
    files: list
    tables: dict = field(default_factory=dict)
    reports: dict = field(default_factory=dict, repr=False)

    def __getattr__(self, name: str) -> Any:
        return _member(self, "tables", name)


def study(
    file: Union[str, Path],
    *,
    cache: Optional[Union[str, Path]] = None,
    jobs: Optional[int] = None,
    cached_only: bool = False,
    retry_failed: bool = False,
    report: bool = True,
    replace_report: bool = False,
) -> Run:
    """``texopt study FILE``: the study's cases through the cache (the program's, or
    ``cache``), and its report. ``Run.rows`` is the study's table, one row a case."""
    argv = ["study", str(file)] + _flags(
        dict(
            cache=cache,
            jobs=jobs,
            cached_only=cached_only,
            retry_failed=retry_failed,
            no_report=not report,
            replace_report=replace_report,
        )
    )
    code, files = _run(argv)
    path = Path(_texopt.study_table(str(file)))
    tables = {"rows": table(path)} if path in files else {}
    return Run(code, files, tables)


def optimise(R: Union[float, Sequence[float], tuple], **options) -> Run:
    """``texopt optimise --R R``: the design search, its front and best designs (one radius,
    a list of radii, or a range ``(lo, hi)`` for robust designs). Options are the program's
    flags as keywords (``depth=(2, 20)``, ``fidelity="draft"``, ``jobs=2``, ``out="dir"``).
    Per radius r the run's tables are ``front_R<r>``, ``evaluated_R<r>`` and its report
    ``reports["R<r>"]`` (with ``best_friction`` and ``best_clearance``); with one radius also
    ``front``, ``evaluated`` and ``best``."""
    code, files = _run(["optimise"] + _flags(dict(R=R, **options)))
    run = Run(code, files)
    for path in files:
        if path.suffix == ".json" and path.name.startswith("optimise_R") and not path.stem.endswith("_series"):
            report = json.loads(path.read_text())
            key = path.stem[len("optimise_") :]
            run.reports[key] = report
            run.tables[f"front_{key}"] = table(_flat(report["front"]))
            run.tables[f"evaluated_{key}"] = table(_flat(report["evaluated"]))
        elif path.suffix == ".csv" and path.name.startswith("robust_"):
            run.tables["robust"] = table(path)
    if len(run.reports) == 1:
        (key, report), = run.reports.items()
        run.tables["front"] = run.tables[f"front_{key}"]
        run.tables["evaluated"] = run.tables[f"evaluated_{key}"]
        run.tables["best"] = table(_flat([report["best_friction"], report["best_clearance"]]))
    return run


def cycle(file: Union[str, Path], **options) -> Run:
    """``texopt cycle FILE``: an engine cycle's liner designs (the program's flags as
    keywords: ``quasi_steady=True``, ``bands=True``, ``fidelity="draft"``, ``out="dir"``).
    Tables: ``steps`` (one row a crank step), ``cycles`` (one row a cycle), ``oil`` and
    ``front`` where the mode writes them, ``angles`` (the angle-by-angle evaluation of
    ``quasi_steady=True``); ``reports`` holds its JSON report."""
    code, files = _run(["cycle", str(file)] + _flags(options))
    run = Run(code, files)
    for path in files:
        if path.suffix == ".json":
            run.reports[path.stem] = json.loads(path.read_text())
        elif path.suffix == ".csv":
            for part in ("steps", "cycles", "oil", "front"):
                if path.stem.endswith("_" + part):
                    run.tables[part] = table(path)
            if path.with_suffix(".json") in files:
                run.tables["angles"] = table(path)
    return run
