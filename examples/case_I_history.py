"""Case I of the paper from Python: the ring's position Z(t) and the friction f(t) over the
last texture period, with the ten instants a–j marked, as the program draws them in
results/snapshots/case_I/history.png (the paper's Fig. 7). The same run as
`bash studies/snapshots.sh` makes for Case I (`texopt simulate --R 0.8 --l1 0.01 --per 0.06
--depth 5 --fidelity paper --start paper --snapshots …`), so the curves are the committed
history's to round-off; the script says how far apart they are.

    python examples/case_I_history.py      # writes results/python/case_I_history.png

Needs the package (README, "From Python") and matplotlib.
"""

import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import texopt

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "python" / "case_I_history.png"

r = texopt.simulate(
    R=0.8, l1=0.01, per=0.06, depth=5, fidelity="paper", start="paper", frames=10
)
operating = r.answer["inputs"]["operating"]
# Times are in units of L/U: L = 1 cm, so 1 ms at 10 m/s (docs/model.md §1).
ms_per_t = 10.0 / operating["speed_ms"]
t = r.t * ms_per_t
instants = [(f.t * ms_per_t, f.z, f.f) for f in r.frames]

# The committed history of the program's own run, for the comparison.
with open(ROOT / "results" / "snapshots" / "case_I" / "history.csv") as f:
    rows = list(csv.DictReader(f))
z_program = np.array([float(row["z_um"]) for row in rows])
f_program = np.array([float(row["f"]) for row in rows])
same = len(z_program) == len(r.z)
print(f"{texopt.__name__}: {r}")
if same:
    print(
        f"against results/snapshots/case_I/history.csv: max |ΔZ| = {np.abs(r.z - z_program).max():.1e} µm, "
        f"max |Δf| = {np.abs(r.f - f_program).max():.1e}"
    )
else:
    print(f"the committed history has {len(z_program)} steps, this run {len(r.z)}")

fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
top.plot(t, r.z, color="tab:blue")
bottom.plot(t, r.f, color="tab:red")
for k, (ti, zi, fi) in enumerate(instants):
    label = "abcdefghij"[k]
    top.plot(ti, zi, "ko", ms=4)
    top.annotate(label, (ti, zi), textcoords="offset points", xytext=(0, 6), ha="center")
    bottom.plot(ti, fi, "ko", ms=4)
top.set_ylabel("Z (µm)")
bottom.set_ylabel("f (eq. 11)")
bottom.set_xlabel("t (ms)")
top.set_title(
    f"Case I from Python: R = 0.8 cm, pockets 0.01 cm, 5 µm deep\n"
    f"f̄ = {r.f_mean:.5f}, C_min = {r.c_min:.3f} µm (paper numerics, the last period)"
)
fig.tight_layout()
OUT.parent.mkdir(parents=True, exist_ok=True)
fig.savefig(OUT, dpi=100)
print(f"wrote {OUT.relative_to(ROOT)}")
