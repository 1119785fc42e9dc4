"""The drop rig's start against free fall: the hammer falls h to the contact
whatever the contact's clearance (gap) and wherever the frame and the mount
put the stack, and the drop-rest rig offers no setting that does nothing.

Free fall from rest: the contact closes after t = sqrt(2 h / g) at
v = sqrt(2 g h). The contact's indentation is hammer.s - piston.s - gap
(positions positive down), so a hammer released h above the point where
it closes starts at piston.s + gap - h. The hammer once started at
piston.s - gap - h: it fell h + 2 gap (0.2856 s instead of 0.2784 s at
gap = 1 cm).
"""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from pdbfs.errors import ParameterError, PdbfsError
from pdbfs.models import drop_rig
from pdbfs.studies import design_map

G = 9.80665
# runs stopped just after the contact closes: their pulse is cut off, and said so
pytestmark = pytest.mark.filterwarnings("ignore::pdbfs.PulseIncompleteWarning")


def cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=300, cwd=cwd)


def one_line(r, *words):
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdbfs: error: "), r.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def first_contact(backend, params, h):
    """(time, hammer speed) where the contact first closes, located on the
    solution: 11 output points, the contact closing between the last two."""
    # 0.2 ms into the blow: the light piston leaps ahead and is struck again
    # about 1 ms later (a second closing of the contact)
    t_end = math.sqrt(2.0 * h / G) + 2e-4
    res = drop_rig().simulate(t_end, n_out=11, params={"h": h, **params}, backend=backend)
    d = res["contact.d"]
    assert d[-2] < 0 < d[-1]                       # the grid only brackets it
    t = res.crossings("contact.d")[0]
    return t, res.value_at("hammer.v", t), res


@pytest.mark.parametrize("backend", ["c", "casadi"])
@pytest.mark.parametrize("h, gap", [(0.38, 0.01), (0.38, 1e-3), (0.38, -0.005),
                                    (0.05, 0.02), (1.2, 5e-4), (0.2, 0.0)])
def test_the_hammer_falls_h_to_the_contact_whatever_the_gap(backend, h, gap):
    t, v, res = first_contact(backend, {"contact.gap": gap}, h)
    assert t == pytest.approx(math.sqrt(2.0 * h / G), rel=1e-7)
    assert v == pytest.approx(math.sqrt(2.0 * G * h), rel=1e-7)
    # the summary's first blow is the same instant
    assert res.summary()["impact_times"][0] == pytest.approx(t, rel=1e-7)


@pytest.mark.parametrize("backend", ["c", "casadi"])
@pytest.mark.parametrize("offset", [{"mount.s_rel0": 1e-3}, {"frame.s0": -2e-3},
                                    {"mount.n": 1.5, "mount.k": 1e12, "mount.s_rel0": -1e-4}])
def test_the_stack_waits_at_rest_wherever_the_frame_and_the_mount_put_it(backend, offset):
    """The piston and the breech start in static equilibrium, measured from the
    mount's unstretched position frame.s0 - mount.s_rel0: nothing moves until
    the hammer arrives (it once started them ringing by s_rel0)."""
    h = 0.1
    t, v, res = first_contact(backend, offset, h)
    assert t == pytest.approx(math.sqrt(2.0 * h / G), rel=1e-7)
    before = res.t < t
    for body in ("piston", "breech"):
        # at rest to the solvers' drift (1.5e-8 m/s with the explicit method); a
        # start 1 mm off its rest rings at about 7000 rad/s: 7 m/s
        assert np.max(np.abs(res[f"{body}.v"][before])) < 1e-6, body
        assert np.ptp(res[f"{body}.s"][before]) < 1e-8, body
    P = {**{p.name: p.value for p in drop_rig().compile().params}, **offset}
    w = (P["piston.m"] + P["breech.m"]) * G
    rest = P["frame.s0"] - P["mount.s_rel0"] + (w / P["mount.k"]) ** (1 / P["mount.n"])
    assert res["breech.s"][0] == pytest.approx(rest, rel=1e-12, abs=1e-15)


def test_the_command_line_gives_the_free_fall_impact(tmp_path):
    r = cli("simulate", "--rig", "drop", "--set", "contact.gap=0.01", "--t-end", "0.5",
            "--json", "--out", "o", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    t = json.loads(r.stdout)["impact_times"][0]
    assert t == pytest.approx(math.sqrt(2 * 0.38 / G), rel=1e-6)       # 0.2783854 s


@pytest.mark.parametrize("params", [{"contact.gap": 1e-3}, {"contact.gap": -2e-4},
                                    {"mount.s_rel0": 1e-3, "frame.s0": 5e-4}])
def test_the_resting_hammer_sits_on_the_contact_whatever_the_gap(params):
    """Solved start against statics by hand; a gap above half the hammer's
    sink (3.1e-5 m) once put the guess outside the contact and the start
    was refused as singular."""
    from test_initialization import statics
    rig = drop_rig(rest=True)
    res = rig.simulate(0.001, n_out=3, params=params, rtol=1e-10, atol=1e-12)
    hand = statics(rig, params)
    for name, value in hand.items():
        assert res.initial[name] == pytest.approx(value, rel=1e-10, abs=1e-15), name
    P = {p.name: p.value for p in rig.compile().params}
    assert res["contact.fc"][0] == pytest.approx(P["hammer.m"] * G, rel=1e-9)


def test_drop_rest_offers_no_drop_height_and_no_start_speed(tmp_path):
    rig = drop_rig(rest=True)
    names = rig.compile().p_names
    assert "h" not in names and "g" in names
    with pytest.raises(ParameterError, match="unknown parameter 'h'"):
        rig.simulate(0.001, params={"h": 0.5})
    with pytest.raises(ParameterError, match="hammer.v0 is fixed by rig pdbfs_drop_rest at 0"):
        rig.simulate(0.001, params={"hammer.v0": 1.0})
    r = cli("params", "--rig", "drop-rest", cwd=tmp_path)
    assert r.returncode == 0 and not any(line.split()[0] == "h"
                                         for line in r.stdout.splitlines()[1:])
    one_line(cli("simulate", "--rig", "drop-rest", "--set", "h=0", "--out", "o", cwd=tmp_path),
             "unknown parameter 'h'")
    one_line(cli("simulate", "--rig", "drop-rest", "--set", "piston.v0=1", "--out", "o",
                 cwd=tmp_path), "piston.v0", "fixed")
    assert not (tmp_path / "o").exists()
    # the drop rig keeps both: its hammer may be thrown (v0) from h
    assert {"h", "hammer.v0"} <= set(drop_rig().compile().p_names)
    from pdbfs.models import DropRig
    with pytest.raises(ParameterError, match="DropRestRig"):
        DropRig(rest=True)


def test_a_design_map_with_no_pulse_anywhere_is_refused(tmp_path):
    r = cli("design-map", "--rig", "drop-rest", "--x", "oil.k=1e8:3e8", "--y",
            "hammer.m=1000:3000", "--n", "2", "--out", "M", cwd=tmp_path)
    one_line(r, "pdbfs_drop_rest", "no point of the 2 x 2 grid gives a pulse",
             "4 of 4 points gave no complete pulse")
    assert not (tmp_path / "M").exists() and "Traceback" not in r.stderr
    with pytest.raises(PdbfsError, match="no point of the 2 x 2 grid"):
        design_map(drop_rig(rest=True), ("oil.k", 1e8, 3e8), ("g", 5.0, 10.0), n=2)


def test_a_design_map_says_how_many_points_it_left_blank(tmp_path):
    """h = 0.5 m strikes at 0.32 s, after t_end = 0.1 s: no pulse there."""
    with pytest.warns(UserWarning, match="2 of 4 points gave no complete pulse"):
        m = design_map(drop_rig(), ("h", 0.001, 0.5), ("oil.k", 2e8, 3e8), n=2, t_end=0.1)
    assert m.failed == 0 and m.no_pulse == 2
    assert np.isnan(m.values["peak_pressure"][:, 1]).all()
    assert np.isfinite(m.values["peak_pressure"][:, 0]).all()
    r = cli("design-map", "--rig", "drop", "--x", "h=0.001:0.5", "--y", "oil.k=2e8:3e8",
            "--n", "2", "--t-end", "0.1", "--out", "M", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert doc["failed"] == 0 and doc["no_pulse"] == 2
    assert "left blank" in r.stderr
