"""What each layer keeps of a compiled rig is its own and lives with the
rig's DAE (DAE.companions): the simulation layer's RigState (state.py), the
rig layer's output checks. One rule when a rig changes: it compiles a new
DAE, which starts afresh, and the old state goes with the old DAE."""
import gc
import weakref

from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.state import RigState


def test_a_changed_rig_starts_afresh_and_its_old_state_goes_with_its_old_dae():
    """What the simulation layer keeps of a rig (its RigState: the Simulator,
    the compiled library, what its runs' settings decided) and the rig layer's
    output checks are the compiled DAE's companions: a rig that changes
    compiles a new DAE, which starts with none, and the old state is freed
    with the old DAE (nothing outside holds it: no registry keyed by DAEs)."""
    r = paper_rig()
    first = r.simulate().summary()
    old = r.compile()
    state = old.companions[RigState]
    assert state.simulator is Simulator.of(r) and state.compiled is not None and state.runs
    gone = [weakref.ref(o) for o in (old, state.simulator, state.compiled)]
    del state
    r.hammer.check_output = lambda dt, params: None    # a new component method: seen once compiled again
    r._changed()                                       # as connect() leaves a changed rig
    again = r.simulate().summary()
    new = r.compile()
    assert new is not old and new.companions[RigState].simulator is Simulator.of(r)
    assert new.companions[RigState].simulator.dae is new and len(r._output_checks()) == 1
    assert again == first                              # the same rig, the same numbers
    del old
    gc.collect()
    assert [ref() for ref in gone] == [None] * 3


def test_a_pickled_dae_carries_no_state():
    """A DAE sent to another process (a sweep's worker, the disk cache)
    arrives without what this process made of it, and makes its own there."""
    import pickle

    import casadi as ca
    r = paper_rig()
    own = r.simulate().summary()
    assert r.compile().companions
    with ca.global_pickle_context():
        data = pickle.dumps(r.compile())
    with ca.global_unpickle_context():
        dae = pickle.loads(data)
    assert dae.companions == {}
    assert Simulator.of(dae).run().summary() == own and RigState in dae.companions
