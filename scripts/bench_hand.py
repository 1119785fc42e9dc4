"""The hand-written C baseline of the speed targets (hand_dop853.c: the paper
rig's three equations and a DOP853 with dense output, the peak located on
it), compiled -O2 when first asked for (gcc with OpenMP where present, else
zig cc and a pthreads loop) into a temporary folder and loaded by ctypes.

    hand = bench_hand.load()
    hand.single(TABLE1)()               # one run: its peak pressure, Pa
    hand.sweep(TABLE1, V, K)()          # the peaks of the points (V[i], K[i])

``python scripts/bench_hand.py`` prints the compiler, its peak against the
tight reference and its steps.
"""
from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SOURCE = Path(__file__).with_name("hand_dop853.c")
#: the order of hand_dop853.c's parameter vector
P_NAMES = ("m1", "m2", "m3", "k1", "D", "k2", "k3", "c2", "A")
CORES = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
#: pdbfs's default tolerances of its explicit method (rtol 5e-8, atol 1e-10)
RTOL, ATOL = 5e-8, 1e-10


def compile_command(out: Path) -> list[str]:
    """gcc -O2 -fopenmp where gcc is found, else zig cc -O2 (no OpenMP: pthreads)."""
    gcc = shutil.which("gcc")
    if gcc:
        return [gcc, "-O2", "-fopenmp", "-fPIC", "-shared", str(SOURCE), "-o", str(out), "-lm"]
    zig = shutil.which("zig") or str(Path(sys.executable).with_name("zig"))
    return [zig, "cc", "-O2", "-fPIC", "-shared", str(SOURCE), "-o", str(out), "-lm",
            "-lpthread"]


class Hand:
    """The compiled baseline: ``single`` and ``sweep`` give functions to time."""

    def __init__(self):
        self._dir = tempfile.TemporaryDirectory(prefix="pdbfs-hand-")
        out = Path(self._dir.name) / "hand.so"
        # OpenMP's threads sleep when idle: spinning, they would count in the CPU
        # time of whatever is timed after the loop
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
        self.command = compile_command(out)
        subprocess.run(self.command, check=True, capture_output=True, text=True)
        lib = ctypes.CDLL(str(out))
        vp, d = ctypes.c_void_p, ctypes.c_double
        lib.hand_peak.argtypes = [vp, d, d, d, d, vp]
        lib.hand_peak.restype = ctypes.c_int
        lib.hand_sweep.argtypes = [ctypes.c_long, vp, vp, vp, d, d, d, vp, ctypes.c_int]
        lib.hand_sweep.restype = None
        lib.hand_openmp.restype = ctypes.c_int
        self.lib = lib
        self.openmp = bool(lib.hand_openmp())

    @staticmethod
    def _p(p) -> np.ndarray:
        return np.array([p[k] for k in P_NAMES], dtype=float)

    def run(self, p, v0=None, rtol=RTOL, atol=ATOL, t_end=0.02) -> dict:
        """One run: peak pressure (Pa), its time (s), steps, evaluations."""
        q, out = self._p(p), np.zeros(4)
        rc = self.lib.hand_peak(q.ctypes.data, float(p["v0"] if v0 is None else v0), rtol, atol,
                                t_end, out.ctypes.data)
        if rc:
            raise RuntimeError("the hand-written DOP853 failed")
        return {"peak": out[0], "t_peak": out[1], "steps": int(out[2]), "evals": int(out[3])}

    def single(self, p, rtol=RTOL, atol=ATOL, t_end=0.02):
        """A function of no argument running one simulation, returning its peak pressure."""
        q, out, v0 = self._p(p), np.zeros(4), float(p["v0"])
        f, qa, oa = self.lib.hand_peak, q.ctypes.data, out.ctypes.data

        def run(q=q):                  # (q held: qa is its address)
            if f(qa, v0, rtol, atol, t_end, oa):
                raise RuntimeError("the hand-written DOP853 failed")
            return out[0]
        return run

    def sweep(self, p, V, K, rtol=RTOL, atol=ATOL, t_end=0.02, threads=CORES):
        """A function of no argument running the points (V[i], K[i]) in the
        parallel loop (``threads`` threads), returning their peaks."""
        q = self._p(p)
        V, K = np.ascontiguousarray(V, float), np.ascontiguousarray(K, float)

        def run():
            out = np.empty(V.size)
            self.lib.hand_sweep(V.size, V.ctypes.data, K.ctypes.data, q.ctypes.data, rtol, atol,
                                t_end, out.ctypes.data, threads)
            return out
        return run


#: the hand-written C's tolerances tried for its accuracy, loosest first
LADDER = (1e-7, 5e-8, 2e-8, 1e-8, 5e-9, 2e-9, 1e-9, 5e-10, 2e-10, 1e-10)


def sweep_points(n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """(hammer speeds, oil stiffnesses) of the peers' sweep: [1.5, 5.5] m/s x [1e8, 5e8] N/m."""
    rng = np.random.default_rng(seed)
    return rng.uniform(1.5, 5.5, n), rng.uniform(1e8, 5e8, n)


def tight_peaks(p, V, K) -> tuple[np.ndarray, str]:
    """Peaks of the points (V[i], K[i]) to 1e-10 and which solver gave them:
    numbalsoda's DOP853 at rtol 1e-13 on a 1 us grid, Hermite-refined (an
    independent program) where it is installed, else this C at rtol 1e-13."""
    import bench_peers as bp
    tight = bp.numbalsoda_sweep(np.linspace(0.0, 0.02, 20001), p, V, K, rtol=1e-13, atol=1e-16)
    if tight is not None:
        return tight(), "numbalsoda DOP853 rtol 1e-13"
    return load().sweep(p, V, K, rtol=1e-13, atol=1e-17)(), "hand-written C DOP853 rtol 1e-13"


def matched_rtol(p, pdbfs_peaks, V, K, ref) -> tuple[float, float, float]:
    """The loosest tolerance of LADDER at which the hand-written C's median
    peak error over the points is no larger than pdbfs's (``pdbfs_peaks`` of
    the same points; ``ref`` the tight peaks): (rtol, its median error,
    pdbfs's median error)."""
    want = float(np.median(np.abs(pdbfs_peaks - ref) / ref))
    hand = load()
    for rtol in LADDER:
        err = float(np.median(np.abs(hand.sweep(p, V, K, rtol=rtol)() - ref) / ref))
        if err <= want:
            return rtol, err, want
    return LADDER[-1], err, want


def check_targets(targets) -> int:
    """Print each target (name, measured ratio, limit) and whether it is met;
    1 if one is missed (the script's exit status), else 0."""
    print("targets:")
    missed = 0
    for name, ratio, limit in targets:
        if ratio is None:
            print(f"  {name}: not measurable here (a peer is missing): NOT MET")
            missed = 1
            continue
        ok = ratio <= limit
        missed |= not ok
        print(f"  {name}: {ratio:.2f} (target <= {limit:g}): {'met' if ok else 'MISSED'}")
    return int(missed)


_HAND = []


def load() -> Hand:
    """The baseline, compiled once per process."""
    if not _HAND:
        _HAND.append(Hand())
    return _HAND[0]


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    from paper_equations import TABLE1  # noqa: E402
    from bench_simulate import tight_peak  # noqa: E402
    hand = load()
    r = hand.run(TABLE1)
    ref = tight_peak()
    print(" ".join(hand.command))
    print(f"OpenMP: {hand.openmp}; peak {r['peak'] / 1e6:.9f} MPa at {r['t_peak'] * 1e3:.6f} ms, "
          f"error {abs(r['peak'] - ref) / ref:.1e}; {r['steps']} steps, {r['evals']} evaluations")
