"""A compiled run keeps a record of every step for its summary
(c/pdbfs_record.c): the record grows only within the memory the machine
has available. `pdbfs simulate --t-end 1e4` took 154 million steps; with
method erk or adams its record outgrew a 23 GB machine and the kernel killed
the process (allocations succeed on credit, so no allocation ever failed).
Here the memory available is made small (what psutil reports, as on a
machine whose memory is mostly taken) under a 3 GB address-space limit as a
safety net: the run must stop at what is available, in one line naming the
time reached, not grow on to the limit."""
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from pdbfs.models import paper_rig

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="RLIMIT_AS and VmHWM as Linux has them")

#: the memory the child is told is available, bytes
AVAILABLE = 4e8

CHILD = textwrap.dedent("""
    import resource, sys
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))   # the safety net
    import pdbfs.simulation.setup.memory as memory
    memory.available = lambda: {available!r}
    from pdbfs.cli import main
    try:
        code = main({argv!r})
    finally:
        # the child's peak resident memory, kB: VmHWM, its own since exec (ru_maxrss
        # also holds the parent's at the fork: a test worker's gigabyte)
        with open("/proc/self/status") as st, open({rss!r}, "w") as fh:
            fh.write(next(ln.split()[1] for ln in st if ln.startswith("VmHWM:")))
    sys.exit(code)
""")


def _simulate(tmp_path, method):
    rss = tmp_path / "rss"
    argv = ["simulate", "--t-end", "1e4", "--method", method, "--json"]
    r = subprocess.run([sys.executable, "-c", CHILD.format(available=AVAILABLE, argv=argv,
                                                          rss=str(rss))],
                       capture_output=True, text=True, timeout=600, cwd=tmp_path)
    return r, 1e3 * float(rss.read_text())


@pytest.mark.parametrize("method", ["erk", "adams"])
def test_a_long_run_stops_within_the_memory_available(tmp_path, method):
    r, peak = _simulate(tmp_path, method)
    assert r.returncode == 2, r.stderr[-2000:]
    line = r.stderr.strip()
    m = re.fullmatch(r"pdbfs: error: rig pdbfs_paper: the run ran out of memory after "
                     r"t = ([0-9.e+-]+) s \(of 10000 s, (\d+) steps\): .*shorter t_end", line)
    assert m and 0.02 < float(m.group(1)) < 1e4, line
    assert r.stdout == ""
    # the record stopped within the share of what is available (a record of 0.8 x
    # 400 MB, and the process's own ~300 MB); it grew on to 3 GB before
    assert peak < 0.8 * AVAILABLE + 5e8, peak


def test_a_record_that_fits_keeps_its_numbers(monkeypatch):
    """The probe is asked as a long run's record grows, and stops nothing that
    fits: the numbers are those of a run it is not asked in."""
    from pdbfs.simulation.setup import memory
    rig = paper_rig()
    asked = []
    monkeypatch.setattr(memory, "headroom", lambda: asked.append(1) or 1e15)
    a = rig.simulate(30.0, method="erk", backend="c")
    assert asked and a.stats["steps"] > 131072     # a record past RECORD_ASK (64 MB)
    monkeypatch.setattr(memory, "headroom", lambda: -1.0)      # unknown: never stops
    b = rig.simulate(30.0, method="erk", backend="c", params={"hammer.v0": 2.73})
    assert np.array_equal(a["oil.pressure"], b["oil.pressure"])
    assert a.summary() == b.summary()


def test_a_ctrl_c_in_the_probe_is_raised_when_the_compiled_call_returns(monkeypatch):
    """Python's SIGINT handler runs at the first Python the main thread runs,
    in a long compiled run the record's probe: there ctypes printed the
    KeyboardInterrupt as an ignored exception, with its traceback, and the run
    went on. The probe keeps it; the call raises it once back in Python."""
    import pdbfs.simulation.setup.memory as memory

    def interrupted_here():
        raise KeyboardInterrupt
    monkeypatch.setattr(memory, "headroom", interrupted_here)
    assert memory.PROBE() == -1.0              # through ctypes, as the C calls it
    with pytest.raises(KeyboardInterrupt):
        memory.interrupted()
    memory.interrupted()                       # raised once: nothing kept after


def test_a_ctrl_c_at_the_probes_first_line_is_kept_by_the_cli(monkeypatch):
    """The handler can run before the probe's ``try`` (at the function's entry,
    where Python checks for signals): the CLI's handler keeps it there too,
    and raises everywhere else (test_cli_stops caught the entry once)."""
    import signal

    import pdbfs.simulation.setup.memory as memory
    from pdbfs.cli import interrupt

    frames = []
    monkeypatch.setattr(memory, "headroom", lambda: frames.append(sys._getframe(1)) or 1.0)
    assert memory.PROBE() == 1.0
    assert frames[0].f_code is memory._probe.__code__
    assert interrupt._handler(signal.SIGINT, frames[0]) is None     # kept, not raised
    with pytest.raises(KeyboardInterrupt):
        memory.interrupted()
    memory.interrupted()
    with pytest.raises(KeyboardInterrupt):
        interrupt._handler(signal.SIGINT, sys._getframe())
    memory.interrupted()                       # nothing kept by a raise elsewhere


def _minor_faults():
    import resource
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def test_the_next_run_writes_into_the_record_the_run_before_released():
    """A run's record (about 40 MB for 5 s of the paper rig: past glibc's mmap
    threshold) goes back to the library when its Result goes, and the next
    run of the rig records into it: it takes no fresh pages (each page of a
    fresh mapping is a page fault), where a record freed at every run took
    one per page."""
    rig = paper_rig()
    first = rig.simulate(5.0)
    pages = 8 * 100 * first.stats["steps"] / 4096          # a step's record: 100+ doubles
    assert pages > 8000, first.stats                        # past 32 MB
    del first
    faults = []
    for _ in range(3):
        before = _minor_faults()
        res = rig.simulate(5.0)
        assert res.summary()["peak_pressure"] > 0
        del res
        faults.append(_minor_faults() - before)
    assert max(faults) < 0.1 * pages, (faults, pages)


def test_the_records_kept_for_unread_states_are_bounded(monkeypatch):
    """Results whose states were never read keep their runs' records, up to
    KEPT_BYTES for a library: past it the oldest have their states made (the
    numbers they would have made when read) and their records freed."""
    from pdbfs.simulation import Simulator
    from pdbfs.simulation.run import kept
    rig = paper_rig()
    one = rig.simulate()
    lib = Simulator.of(rig).compiled()
    monkeypatch.setattr(kept, "KEPT_BYTES", 2e6)
    results = [rig.simulate() for _ in range(40)]           # ~0.2 MB each
    unread = [r for r in (w() for w in lib.kept.runs) if r is not None and r._made is None]
    size = max(r.nbytes for r in unread)
    assert 2 <= len(unread) and sum(r.nbytes for r in unread) <= 2e6 + size
    assert len(unread) < 20                                  # the others' states made
    for r in results[:3] + results[-3:]:                     # made then, and made now
        assert np.array_equal(r["oil.pressure"], one["oil.pressure"])
