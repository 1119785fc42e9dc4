"""Start-up: what a user waits for before the first number, each measured in
new processes against its target (CPU seconds, the process's own and its
children's: the compiler's), in one run:

* import      ``import pdbfs`` (median of ``--rounds`` processes): its
              names are imported on first use; beside it, for scale,
              the API of a run at hand (``from pdbfs import Rig,
              simulate``: numpy, CasADi, the modelling and simulation
              layers) and numpy with CasADi alone;
* command line ``import pdbfs.cli``: what every command pays before it
              reads its options (``--help``, a refused option);
* sweep       the first sweep's overhead in a process: a one-point sweep
              of the paper rig (its DAE and library cached) less a second
              one in the same process (median);
* new rig     the first simulate of a rig never built before, with the
              per-machine parts cached: a fresh class of the paper rig with
              one more mass (another structure: its library is not in the
              cache), once with a state count never compiled before (the
              explicit method's arithmetic compiled for it) and once with
              one compiled before (median of each);
* new machine the first simulate with an empty cache folder (zig's own
              cache too), CVODE's sources at hand offline
              (``PDBFS_SUNDIALS_SDIST``): the default method, and ``bdf``
              (CVODE compiled too);
* scipy       (``--versus-scipy``) a one-shot ``pdbfs simulate --json``
              writing its CSV and plot, against the same done by a script
              with scipy and matplotlib (wall time, interleaved rounds).

Each target is printed with its figure and their ratio; the exit status is
1 when one is missed.

    python scripts/bench_startup.py [--rounds 7] [--only import,sweep,new-rig,new-machine]
    python scripts/bench_startup.py --versus-scipy [--args "--backend c"]

Bytecode is compiled once into a temporary folder first (as an installed
wheel has it), so no import pays for compiling Python.
"""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: targets, CPU seconds
TARGETS = {"import": 0.150, "command line": 0.150, "sweep": 0.2, "new rig": 2.0, "new rig, known state count": 2.0,
           "new machine": 15.0, "new machine, bdf": 15.0}

#: a child's measurement: CPU seconds of ``code`` (after ``setup``), its own and its
#: children's, printed as JSON with whatever ``code`` put in ``out``
CHILD = '''
import resource, time
out = {{}}
{setup}
def cpu():
    c = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + c.ru_utime + c.ru_stime
t0 = cpu()
{code}
out["cpu"] = cpu() - t0
import json
print(json.dumps(out))
'''

#: the paper rig with one more mass (a sensor on the breech, through a stiff
#: spring): a structure of its own, under a name never used before
NEW_RIG = '''
import uuid
from pdbfs.components import Mass, Spring
from pdbfs.models import PaperRig
from pdbfs.simulation.run import compiled_build

class NewRig(PaperRig):
    name = "pdbfs_bench_" + uuid.uuid4().hex[:12]
    extra = {extra}

    def declare(self):
        super().declare()
        last = self.breech.flange_b
        for k in range(self.extra):
            setattr(self, f"link{{k}}", Spring(k=1e9))
            setattr(self, f"sensor{{k}}", Mass(m=1.0))
            self.connect(last, getattr(self, f"link{{k}}").flange_a)
            self.connect(getattr(self, f"link{{k}}").flange_b, getattr(self, f"sensor{{k}}").flange_a)
            last = getattr(self, f"sensor{{k}}").flange_b
rig = NewRig()
'''


def child_env(pycache: str, **extra) -> dict:
    """This environment with bytecode kept in ``pycache`` (written, then read)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(PYTHONPYCACHEPREFIX=pycache, **extra)
    return env


def measure(code: str, env: dict, setup: str = "", cwd: str | None = None) -> dict:
    """Run CHILD with ``code`` in a new process: its JSON (``cpu`` and more)."""
    r = subprocess.run([sys.executable, "-c", CHILD.format(setup=setup, code=code)], env=env,
                       capture_output=True, text=True, cwd=cwd)
    if r.returncode != 0:
        raise SystemExit(f"bench_startup: a measurement failed:\n{r.stderr[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def bench_import(env, rounds):
    """``import pdbfs`` and ``import pdbfs.cli``, with the API of a run and
    numpy with CasADi (which that imports) in turns beside them."""
    codes = {"import": "import pdbfs", "command line": "import pdbfs.cli",
             "api": "from pdbfs import Rig, simulate", "base": "import numpy, casadi"}
    times = {k: [] for k in codes}
    for _ in range(rounds):
        for k, code in codes.items():
            times[k].append(measure(code, env)["cpu"])
    m = {k: statistics.median(v) for k, v in times.items()}
    return {"import": (m["import"], f"the API of a run at hand {m['api'] * 1e3:.0f} ms, of which "
                                    f"numpy + CasADi {m['base'] * 1e3:.0f} ms"),
            "command line": (m["command line"], "before a command reads its options")}


SWEEP_SETUP = '''
import pdbfs
from pdbfs.models import paper_rig
rig = paper_rig()
rig.simulate()          # the rig's DAE and library at hand: the sweep's own start-up is measured
'''
SWEEP = '''
pdbfs.sweep(rig, {"hammer.v0": [2.5]}, progress=False)
out["first"] = cpu() - t0
pdbfs.sweep(rig, {"hammer.v0": [2.6]}, progress=False)
out["second"] = cpu() - t0 - out["first"]
'''


def bench_sweep(env, rounds):
    runs = [measure(SWEEP, env, SWEEP_SETUP) for _ in range(rounds)]
    over = statistics.median(r["first"] - r["second"] for r in runs)
    second = statistics.median(r["second"] for r in runs)
    return {"sweep": (over, f"a second sweep in the process {second * 1e3:.0f} ms")}


SIMULATE = '''
r = rig.simulate({kw})
out["peak"] = r.summary()["peak_pressure"]
out["states"] = rig.compile().x.numel()
out["driver builds"] = compiled_build.DRIVER_BUILDS
'''


def bench_new_rig(env, rounds, cache):
    """In a cache folder of its own (``cache``: CVODE linked in from the real
    one, zig's cache shared), after one new rig has built the per-machine
    parts: new rigs of state counts not compiled yet (the paper rig with
    2, 3, ... more masses), and of the count compiled (one more mass)."""
    env = dict(env, XDG_CACHE_HOME=str(cache))
    measure(SIMULATE.format(kw=""), env, NEW_RIG.format(extra=1))       # the per-machine parts
    fresh = [measure(SIMULATE.format(kw=""), env, NEW_RIG.format(extra=2 + k)) for k in range(rounds)]
    known = [measure(SIMULATE.format(kw=""), env, NEW_RIG.format(extra=1)) for _ in range(rounds)]
    if any(r["driver builds"] for r in fresh + known):
        raise SystemExit("bench_startup: a new rig compiled the drivers again")
    return {"new rig": (statistics.median(r["cpu"] for r in fresh),
                        f"{fresh[0]['states']} to {fresh[-1]['states']} states, each count new"),
            "new rig, known state count": (statistics.median(r["cpu"] for r in known),
                                           f"{known[0]['states']} states")}


def bench_new_machine(env, cache):
    """The first simulate of the paper rig with nothing in the cache folder
    ``cache`` (nor zig's cache), CVODE's sources from the kept sdist."""
    env = {k: v for k, v in env.items() if not k.startswith("ZIG_")}
    from pdbfs.native.sundials import sdist_path
    if sdist_path().is_file():
        env["PDBFS_SUNDIALS_SDIST"] = str(sdist_path())
    setup = "from pdbfs.models import paper_rig\nfrom pdbfs.simulation.run import compiled_build\n" \
        "rig = paper_rig()"
    out = {}
    for name, kw in (("new machine", ""), ("new machine, bdf", 'method="bdf"')):
        folder = Path(tempfile.mkdtemp(dir=cache))
        env["XDG_CACHE_HOME"] = str(folder)
        r = measure(SIMULATE.format(kw=kw), env, setup)
        out[name] = (r["cpu"], "CVODE compiled too" if kw else "the default method")
    return out


def link_cvode(cache: Path) -> None:
    """The real cache's CVODE (sources and archives) in the cache folder ``cache``."""
    from pdbfs.files import cache_folder
    real = cache_folder()
    (cache / "pdbfs").mkdir(parents=True, exist_ok=True)
    for d in real.glob("*-7.*"):       # sundials-<version>, cvode-<version>
        os.symlink(d, cache / "pdbfs" / d.name)


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


def timed(cmd, env) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    return time.perf_counter() - t


def versus_scipy(env, rounds, args):
    """The one-shot ``pdbfs simulate --json`` against the scipy script, wall times."""
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "scipy_rig.py"
        script.write_text(SCIPY.format(tests=str(ROOT / "tests")))
        pdbfs = [sys.executable, "-m", "pdbfs.cli", "simulate", "--json", "--out", tmp, *shlex.split(args)]
        scipy = [sys.executable, str(script), tmp]
        timed(pdbfs, env)                  # the cache filled, as after a first run
        timed(scipy, env)
        times = {"pdbfs simulate --json": [], "scipy + matplotlib": []}
        for _ in range(rounds):
            times["pdbfs simulate --json"].append(timed(pdbfs, env))
            times["scipy + matplotlib"].append(timed(scipy, env))
    for name, ts in times.items():
        print(f"{name:24s} median {statistics.median(ts):.3f} s  "
              f"(min {min(ts):.3f}, max {max(ts):.3f}, {len(ts)} runs)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--only", default="import,sweep,new-rig,new-machine",
                    help="the measurements to make, comma separated")
    ap.add_argument("--versus-scipy", action="store_true", help="the one-shot against scipy instead")
    ap.add_argument("--args", default="", help="more options of pdbfs simulate (--versus-scipy)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="pdbfs-bench-startup-") as tmp:
        tmp = Path(tmp)
        env = child_env(str(tmp / "pycache"))
        # the bytecode of everything measured written (and each kind of run made once)
        measure(SWEEP + "import pdbfs.cli, pdbfs.studies, pdbfs.components, numpy, casadi", env,
                SWEEP_SETUP)
        if a.versus_scipy:
            return versus_scipy(env, a.rounds, a.args)
        from pdbfs.files import cache_folder
        env.setdefault("ZIG_GLOBAL_CACHE_DIR", str(cache_folder() / "zig"))
        only = a.only.split(",")
        got = {}
        if "import" in only:
            got.update(bench_import(env, a.rounds))
        if "sweep" in only:
            got.update(bench_sweep(env, max(3, a.rounds // 2)))
        if "new-rig" in only:
            link_cvode(tmp / "rigs")
            got.update(bench_new_rig(env, max(3, a.rounds // 2), tmp / "rigs"))
        if "new-machine" in only:
            (tmp / "machine").mkdir()
            got.update(bench_new_machine(env, tmp / "machine"))
    missed = []
    print(f"{'target':28s} {'measured':>10s} {'target':>9s} {'ratio':>6s}")
    for name, (value, note) in got.items():
        ratio = value / TARGETS[name]
        flag = "" if ratio <= 1 else "  MISSED"
        if ratio > 1:
            missed.append(name)
        print(f"{name:28s} {value:9.3f}s {TARGETS[name]:8.3f}s {ratio:6.2f}  ({note}){flag}")
    if missed:
        print(f"missed: {', '.join(missed)}")
        sys.exit(1)


if __name__ == "__main__":
    main()
