"""The cost model of ``method="auto"``, one rule for every path: the compiled
and CasADi backends (pdbfs.simulation.run.stiffness, which computes the modes)
and the FMU's co-simulation (its C, native/c/fmu/stiffness.c, decides with these
numbers, written into pdbfs_model.h).

A run's cost is estimated per method as (steps it needs) x (cost of a step).
The steps come from the modes of d(ode)/dx at the start: the explicit method
must resolve the oscillating modes as accuracy asks (ERK_STEPS_*) and may not
step beyond its stability region (ERK_STABLE); CVODE's Adams needs about
ADAMS_STEPS times its steps where accuracy sets them, and is held by its own
small stability region on fast modes (ADAMS_STABLE_*); BDF is stable on any
decaying mode and needs about BDF_STEPS times the explicit method's accurate
steps. A step costs its right-hand side evaluations (EVAL_NS per instruction
of the generated right-hand side) and the method's own work per step and per
state (STEP_COST). Measured on this project's rigs (split piston and elastic
bar at N = 2 ... 32, the paper, drop and valve rigs; a benchmark checks the
choice against the methods' measured times).
"""

#: above this many states, only the eigenvalues of largest modulus
DENSE_UP_TO = 400

#: |h lambda| the explicit 8(5,3) pair stays stable to: its stability
#: region's boundary is at 5.96 on the imaginary axis and 6.4 on the negative
#: real axis (computed from its coefficients); its step control held h
#: |lambda| at 5.7 (a mode at rest, drop-rest rig) and 6.3 (a decaying one,
#: hydraulic-pulse rig)
ERK_STABLE = 6.0

#: the explicit method's steps where accuracy sets them: ERK_STEPS_BASE +
#: ERK_STEPS_COEF * t_end * w**ERK_STEPS_EXP for the fastest oscillating mode w
#: (rad/s): a fitted law (paper rig, 7,070 rad/s: 1.35 steps a radian, its
#: breech ringing; split piston N = 32, 243,000 rad/s: 0.39, its fastest
#: modes barely excited; valve rig, no oscillating mode: 53 steps a pulse)
ERK_STEPS_BASE = 50.0
ERK_STEPS_COEF = 30.0
ERK_STEPS_EXP = 0.65

#: CVODE's steps against the explicit method's where accuracy sets both
#: (measured 5.4-7.7 for Adams, 6.4-10.4 for BDF on every rig and size here)
ADAMS_STEPS = 6.5
BDF_STEPS = 8.5

#: |h lambda| CVODE's Adams was held to: an oscillating mode at rest (drop-rest
#: rig, 0.53) and a decaying one (valve rig, 0.12)
ADAMS_STABLE_OSC = 0.5
ADAMS_STABLE_DECAY = 0.12

#: ns of a right-hand side evaluation per instruction of the generated code
EVAL_NS = 0.35

#: per method: (evaluations per step, ns per step, ns per step and state);
#: Adams iterates to a fixed point below NEWTON_FROM states, with Newton on a
#: band or dense LU from there (PDBFS_NEWTON_FROM of pdbfs_cvode.h), as BDF
#: always does
STEP_COST = {"erk": (13.0, 150.0, 25.0), "adams": (1.85, 450.0, 10.0),
             "adams-newton": (1.06, 300.0, 45.0), "bdf": (1.1, 350.0, 35.0)}
NEWTON_FROM = 40

#: co-simulation (the FMU) switches between the explicit method and BDF while
#: it runs, judging steps h by the start's fastest mode lambda: to BDF once
#: SWITCH_STEPS steps in a row of the explicit method had h lambda >=
#: SWITCH_TO_BDF (held by stability: it stays at 5.7-6.3 there, and 0.4-2.6
#: where it resolves the modes), back at an event (a kink: a blow begins) or
#: once as many BDF steps in a row, over a period of that mode at least, had h
#: lambda < SWITCH_TO_ERK
SWITCH_STEPS = 15
SWITCH_TO_BDF = 4.5
SWITCH_TO_ERK = 0.5


def ode_instructions(dae) -> int:
    """Instructions of the rig's right-hand side (the cost of an evaluation),
    cached on the DAE."""
    return dae.cached("ode_instructions", lambda: int(dae.function("ode").n_instructions()))


def run_costs(fastest: float, rate: float, osc: float, n: int, instructions: float,
              t_end: float) -> dict:
    """The estimated cost (ns) of a run of ``t_end`` s with each method ("erk",
    "adams", "bdf"); an infinite ``t_end`` (a run of unknown length): per
    second of a long run.

    fastest   the largest modulus of an eigenvalue of d(ode)/dx, 1/s
    rate      the fastest decay of a mode that does not oscillate, 1/s
    osc       the largest modulus of a mode that oscillates (|Im| >= |Re|), 1/s
    n         states; instructions: of the generated right-hand side
    (native/c/fmu/stiffness.c computes the same)."""
    long_run = t_end == float("inf")
    span = 1.0 if long_run else t_end
    accurate = (0.0 if long_run else ERK_STEPS_BASE) + ERK_STEPS_COEF * span * osc ** ERK_STEPS_EXP
    steps = {"erk": max(accurate, fastest * span / ERK_STABLE),
             "adams": max(ADAMS_STEPS * accurate, osc * span / ADAMS_STABLE_OSC,
                          rate * span / ADAMS_STABLE_DECAY),
             "bdf": BDF_STEPS * accurate}
    evaluation = EVAL_NS * instructions
    out = {}
    for method, count in steps.items():
        key = "adams-newton" if method == "adams" and n >= NEWTON_FROM else method
        evals, per_step, per_state = STEP_COST[key]
        out[method] = count * (evals * evaluation + per_step + per_state * n)
    return out


def c_defines() -> list[str]:
    """The model's numbers as C #define lines, PDBFS_AUTO_<NAME> (the FMU's
    pdbfs_model.h)."""
    names = ["DENSE_UP_TO", "ERK_STABLE", "ERK_STEPS_BASE", "ERK_STEPS_COEF", "ERK_STEPS_EXP",
             "ADAMS_STEPS", "BDF_STEPS", "ADAMS_STABLE_OSC", "ADAMS_STABLE_DECAY", "EVAL_NS",
             "NEWTON_FROM", "SWITCH_STEPS", "SWITCH_TO_BDF", "SWITCH_TO_ERK"]
    lines = [f"#define PDBFS_AUTO_{k} {globals()[k]!r}" for k in names]
    for key, (evals, per_step, per_state) in STEP_COST.items():
        tag = key.upper().replace("-", "_")
        lines += [f"#define PDBFS_AUTO_{tag}_EVALS {evals!r}",
                  f"#define PDBFS_AUTO_{tag}_STEP_NS {per_step!r}",
                  f"#define PDBFS_AUTO_{tag}_STATE_NS {per_state!r}"]
    return lines
