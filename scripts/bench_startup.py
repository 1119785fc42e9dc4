"""A one-shot ``pdbfs simulate --json`` (results.csv and results.png written)
against the same rig written by hand with scipy's solve_ivp and matplotlib,
doing the same: new processes, interleaved rounds, wall times and medians.

    python scripts/bench_startup.py [--rounds 6] [--args "--backend c"]

The compiled library and the rig's DAE are in pdbfs's cache (one warm-up
run first), as they are for anyone who has simulated the rig before.
"""
import argparse
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the paper rig's equations (tests/paper_equations.py), a 2001-point run,
#: its CSV, a plot, the peak pressure as JSON: what `pdbfs simulate --json` does
SCIPY = '''
import json, sys
import numpy as np
from scipy.integrate import solve_ivp
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
sys.path.insert(0, {tests!r})
from paper_equations import TABLE1, make_rhs, pressure
rhs, _, _ = make_rhs(**TABLE1)
t = np.linspace(0.0, 0.02, 2001)
s = solve_ivp(rhs, (0.0, 0.02), [0, TABLE1["v0"], 0, 0, 0, 0], method="DOP853", t_eval=t,
              rtol=1e-8, atol=1e-10)
p = pressure(s.y, TABLE1)
out = sys.argv[1]
np.savetxt(out + "/results.csv", np.vstack([t, s.y, p]).T, delimiter=",",
           header="time [s],x1,v1,x2,v2,x3,v3,p [Pa]")
fig, ax = plt.subplots(2, 1, sharex=True)
ax[0].plot(t * 1e3, p)
ax[1].plot(t * 1e3, s.y[0::2].T)
fig.savefig(out + "/results.png", dpi=100)
print(json.dumps({{"peak_pressure": float(p.max())}}))
'''


def timed(cmd) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("--args", default="", help="more options of pdbfs simulate")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "scipy_rig.py"
        script.write_text(SCIPY.format(tests=str(ROOT / "tests")))
        pdbfs = [sys.executable, "-m", "pdbfs.cli", "simulate", "--json", "--out", tmp,
                 *shlex.split(a.args)]
        scipy = [sys.executable, str(script), tmp]
        timed(pdbfs)                       # the cache filled, as after a first run
        timed(scipy)
        times = {"pdbfs simulate --json": [], "scipy + matplotlib": []}
        for _ in range(a.rounds):
            times["pdbfs simulate --json"].append(timed(pdbfs))
            times["scipy + matplotlib"].append(timed(scipy))
    for name, ts in times.items():
        print(f"{name:24s} median {statistics.median(ts):.3f} s  "
              f"(min {min(ts):.3f}, max {max(ts):.3f}, {len(ts)} runs)")


if __name__ == "__main__":
    main()
