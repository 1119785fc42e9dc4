"""Linearizing where a one-sided law sits exactly at its kink says so: the
paper rig's start has the oil column at zero compression, linearized on its
slack side (no oil stiffness in A, checked by hand), while a hair later the
loaded side has it; the Linearization and `pdbfs modes` name the law and
the side. An undamped mode's damping is 0, never -0."""
import json
import math
import subprocess
import sys

import pytest

from pdbfs.components import Fixed, Mass, Spring
from pdbfs.models import drop_rig, paper_rig
from pdbfs.rig import Rig


def params(rig):
    return {p.name: p.value for p in rig.compile().params}


def test_the_paper_rigs_start_names_the_oil_column_at_its_kink_and_the_side_taken():
    rig = paper_rig()
    P = params(rig)
    lin = rig.linearize("start")
    kinks = {k.law: k for k in lin.kinks}
    assert set(kinks) == {"oil.compression", "contact.hertz.indentation"}
    oil = kinks["oil.compression"]
    assert oil.value == 0.0 and oil.side == "< 0" and oil.branch == "unloaded" and oil.differs
    # the Hertz law's slope n k d^(n-1) is 0 on both sides of d = 0
    contact = kinks["contact.hertz.indentation"]
    assert not contact.differs and contact.side is None
    # the side taken: no oil stiffness between piston and breech, the mount alone
    i = {n: k for k, n in enumerate(lin.states)}
    assert lin.A[i["piston.v"], i["piston.s"]] == 0.0
    assert lin.A[i["breech.v"], i["piston.s"]] == 0.0
    assert lin.A[i["breech.v"], i["breech.s"]] == pytest.approx(-P["mount.k"] / P["breech.m"],
                                                                rel=1e-12)
    # the other side, a hair later (a nanosecond, the shortest run there is: the
    # piston pressed by 4e-24 m): the oil's k2
    later = rig.linearize(1e-9)
    assert later.kinks == []
    assert later.A[i["breech.v"], i["piston.s"]] == pytest.approx(P["oil.k"] / P["breech.m"],
                                                                  rel=1e-8)
    for text in (str(lin), repr(lin)):
        assert "oil.compression" in text and "unloaded" in text
    assert "linearized on its unloaded side (oil.compression < 0); its loaded side differs" \
        in str(lin)


def test_a_point_with_every_law_engaged_has_no_kink():
    lin = drop_rig(rest=True).linearize("start")
    assert lin.kinks == [] and "kink" not in str(lin)


class Touching(Rig):
    """A body just touching a compression-only spring."""

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=2.0, v0=1.0)
        self.spring = Spring(k=1e4, compression_only=True)
        self.connect(self.body.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.frame.flange)


def test_a_linearization_between_the_two_sides_is_called_so():
    lin = Touching().linearize("start")
    (kink,) = lin.kinks
    assert kink.law == "spring.stretch" and kink.differs and kink.branch == "neither"
    # the spring's slope at its kink is half its k: neither 0 (slack) nor k (pressed)
    assert lin.A[1, 0] == pytest.approx(-0.5 * 1e4 / 2.0, rel=1e-12)
    pressed = Touching().linearize("start", params={"body.s0": 1e-6})
    assert pressed.kinks == [] and pressed.A[1, 0] == pytest.approx(-1e4 / 2.0, rel=1e-12)


def test_an_undamped_mode_has_damping_zero():
    modes = paper_rig().linearize("start").modes()
    breech = max(modes, key=lambda m: m.omega)        # on the mount alone: undamped
    assert breech.damping == 0.0 and math.copysign(1.0, breech.damping) == 1.0


def test_cli_modes_names_the_laws_at_their_kink(tmp_path):
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "modes", "--rig", "paper"],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "oil.compression = 0" in r.stdout and "unloaded side" in r.stdout
    damping = [line.split()[3] for line in r.stdout.splitlines()
               if line.split() and line.split()[0].isdigit()]
    assert damping and "-0" not in damping and "0" in damping
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "modes", "--rig", "paper", "--json"],
                       capture_output=True, text=True, cwd=tmp_path)
    data = json.loads(r.stdout)
    oil = next(k for k in data["kinks"] if k["law"] == "oil.compression")
    assert oil["side"] == "< 0" and oil["branch"] == "unloaded" and oil["differs"] is True
    assert "-0.0" not in r.stdout
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "modes", "--rig", "drop-rest"],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 0 and "kink" not in r.stdout
