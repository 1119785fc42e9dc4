"""paper-thermal against the paper rig and against energy: with its
temperature laws switched off a blow is the paper rig's blow (the heat does
not act back), at its defaults it differs only by what the blow's own heat
does to the oil; over a blow the energy the mechanics lose is the heat the
capacitors store plus what the room takes; a warmer oil softens the column
and thins the seal's friction; and the network alone, linear, carries the
heat of one blow to the next as a matrix exponential."""
import numpy as np
import pytest
from scipy.linalg import expm

from pdbfs.models import RIGS, PaperThermalNetwork, paper_rig, paper_thermal_rig

RIG = paper_thermal_rig()
PAPER = paper_rig()
OFF = {"oil.alpha_T": 0.0, "seal.B": 0.0}
FIGURES = ("peak_pressure", "time_of_peak", "pulse_duration")
CAPACITORS = {"oil_heat": 2.80e4, "piston_heat": 1.112e5, "breech_heat": 2.30e5}
MASSES = {"hammer": 2948.4, "piston": 241.7, "breech": 500.0}
ROOM = 293.15


def test_it_is_a_rig_of_the_command_line():
    assert type(RIGS["paper-thermal"]()) is type(RIG)
    names = {p.name for p in RIG.parameters()}
    assert {"oil.alpha_T", "seal.B", "oil_heat.C", "room.T"} <= names
    assert {p.name for p in PAPER.parameters()} <= names


@pytest.mark.parametrize("backend,tol", [("c", 1e-9), ("casadi", 1e-7)])
def test_with_the_laws_off_a_blow_is_the_paper_rigs(backend, tol):
    """The mechanics are the paper rig's; only the added states change the
    integrator's steps (measured at rtol 1e-10: 1e-13 compiled, 8e-9 IDAS)."""
    a = RIG.simulate(0.02, backend=backend, params=OFF, rtol=1e-10).summary()
    b = PAPER.simulate(0.02, backend=backend, rtol=1e-10).summary()
    for k in FIGURES:
        assert a[k] == pytest.approx(b[k], rel=tol), k


@pytest.mark.parametrize("backend,tol,rtol", [("c", 1e-12, None), ("casadi", 1e-8, 1e-10)])
def test_with_the_laws_off_a_blow_does_not_depend_on_the_temperatures(backend, tol, rtol):
    """What a campaign with its laws off relies on: every blow is the first
    (measured from 40 K warmer, uneven starts: 4e-15 compiled at its default
    tolerance; IDAS, whose steps the temperatures' size moves, 3e-8 at its
    default rtol 1e-8 and 4e-10 at 1e-10)."""
    first = RIG.simulate(0.02, backend=backend, params=OFF, rtol=rtol).summary()
    start = {"oil_heat.T": ROOM + 40.0, "piston_heat.T": ROOM + 41.0, "breech_heat.T": ROOM + 38.0}
    later = RIG.simulate(0.02, backend=backend, params=OFF, start=start, rtol=rtol).summary()
    for k in FIGURES:
        assert later[k] == pytest.approx(first[k], rel=tol), k


def test_at_its_defaults_a_blow_differs_only_by_its_own_heat():
    """The oil warms during the blow, softening the column and thinning the
    seal: the pulse moves by no more than its coefficients do."""
    res = RIG.simulate(0.02, rtol=1e-10)
    a, b = res.summary(), PAPER.simulate(0.02, rtol=1e-10).summary()
    warming = res["oil_heat.T"][-1] - ROOM
    assert 0.01 < warming < 0.2                              # K: a blow's ~1.6 kJ in 28 kJ/K
    drift = max(abs(res["oil.k_T"][-1] / 2.228e8 - 1), abs(res["seal.c_T"][-1] / 2.556e4 - 1))
    assert drift < 3e-3
    for k in FIGURES:
        assert 1e-9 < abs(a[k] / b[k] - 1) < drift, k
    assert a["peak_pressure"] < b["peak_pressure"]           # the softer oil


def _mechanical_energy(res, i):
    e = sum(0.5 * m * res[f"{n}.v"][i] ** 2 for n, m in MASSES.items())
    e += 5.958e10 * max(res["contact.d"][i], 0.0) ** 2.5 / 2.5
    e += 0.5 * 2.228e8 * max(res["oil.d"][i], 0.0) ** 2
    return e + 0.5 * 2.5e10 * res["breech.s"][i] ** 2


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_over_a_blow_the_lost_energy_is_the_stored_heat_and_the_rooms(backend):
    """Capacitors 20 K above the room, so that the room takes heat during the
    blow; laws off, so that the oil's spring energy is k d^2 / 2 (measured:
    3e-10 compiled, 3e-9 IDAS at rtol 1e-10)."""
    start = {f"{n}.T0": ROOM + 20.0 for n in CAPACITORS}
    res = RIG.simulate(0.02, n_out=4001, backend=backend, params={**OFF, **start}, rtol=1e-10)
    lost = _mechanical_energy(res, 0) - _mechanical_energy(res, -1)
    stored = sum(c * (res[f"{n}.T"][-1] - (ROOM + 20.0)) for n, c in CAPACITORS.items())
    to_room = np.trapezoid(res["piston_room.Q_flow"] + res["breech_room.Q_flow"], res.t)
    assert lost > 1000.0 and to_room > 5.0                  # J
    assert lost == pytest.approx(stored + to_room, rel=1e-8)


def _figures(**params):
    return RIG.simulate(0.025, params=params).summary()


def test_a_warmer_oil_softens_the_pulse_and_a_thinner_seal_raises_it():
    """10 K warmer: the column's stiffness falls by 1 - exp(-0.04) = 3.9 %, so
    the peak falls and the pulse lengthens by about half that (a spring-mass
    would give exactly half); the seal's friction falls by 28 % (Andrade),
    which raises the peak (less of the blow goes into the seal)."""
    cold, warm = _figures(), {"oil_heat.T0": ROOM + 10.0}
    soft = _figures(**warm, **{"seal.B": 0.0})
    fall = 1 - np.exp(-0.04)
    for k, sign in (("peak_pressure", -1), ("pulse_duration", 1)):
        change = sign * (soft[k] / cold[k] - 1)
        assert 0.3 * fall < change < 0.8 * fall, k
    thin = _figures(**warm, **{"oil.alpha_T": 0.0})
    assert thin["peak_pressure"] > cold["peak_pressure"]


def test_the_network_alone_has_the_rigs_names_and_values():
    net = {p.name: p.value for p in PaperThermalNetwork().parameters()}
    full = {p.name: p.value for p in RIG.parameters()}
    assert net and all(full[n] == v for n, v in net.items())
    assert sorted(PaperThermalNetwork().compile().x_names) == \
        sorted(f"{n}.T" for n in CAPACITORS)


def test_the_network_carries_a_blows_heat_as_a_matrix_exponential():
    """Between blows the network is linear: from the temperatures a blow
    leaves, T(t) = T_room + expm(A t) (T_end - T_room), A from linearize."""
    blow = RIG.simulate(0.02, params={"oil_heat.T0": ROOM + 5.0})
    net = PaperThermalNetwork()
    lin = net.linearize()
    end = np.array([blow[s][-1] for s in lin.states])
    start = {s: v for s, v in zip(lin.states, end)}
    res = net.simulate(3600.0, n_out=7, start=start, rtol=1e-10)
    for i, t in enumerate(res.t):
        want = ROOM + expm(lin.A * t) @ (end - ROOM)
        got = np.array([res[s][i] for s in lin.states])
        assert np.max(np.abs(got - want)) < 1e-8 * 5.0, t
    # heat flows from the oil into the steel and the room: the oil cools first
    assert res["oil_heat.T"][-1] < end[lin.states.index("oil_heat.T")]
