"""Every argument of the Python API's entry points, given the wrong type, is
the API's own ParameterError naming that argument: never an AttributeError,
a TypeError from numpy, or a value silently read some other way."""
import numpy as np
import pytest

from pdbfs.errors import ParameterError, PdbfsError
from pdbfs.models import paper_rig
from pdbfs.studies import calibrate, design, design_map, sensitivity, sweep

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
TRACE = str(ROOT / "docs" / "data" / "kistler_synthetic.csv")
RIG = paper_rig()

SIMULATE = {
    "t_end": ["0.02", None, [0.02], True, 1j],
    "n_out": ["11", 11.5, None, [3], True],
    "t_out": ["abc", 5, [[0.0, 0.001]], {"a": 1}],
    "params": [[("hammer.v0", 3.0)], "hammer.v0", 3, {3: 1.0}],
    "start": [[("hammer.s", 0.0)], "x", 3],
    "rtol": ["1e-6", [1e-6], True],          # None: the method's default (1e-8; erk 1e-9)
    "atol": ["1e-8", [1e-8], False],          # None: 1e-10, or 1e-2 rtol below rtol 1e-8
    "method": [3, None, ["bdf"]],
    "max_step": ["1e-4", [1e-4], True],
    "max_num_steps": ["100", 10.5, None],
    "backend": [3, None, ["c"]],
}


@pytest.mark.parametrize("arg,value", [(a, v) for a, vs in SIMULATE.items() for v in vs],
                         ids=lambda x: repr(x)[:20])
def test_simulate_refuses_a_wrong_type_naming_the_argument(arg, value):
    kwargs = {"n_out": 11} if arg not in ("n_out", "t_out") else {}
    with pytest.raises(ParameterError) as err:
        if arg == "t_end":
            RIG.simulate(value, **kwargs)
        else:
            RIG.simulate(0.001, **kwargs, **{arg: value})
    assert arg in str(err.value) or arg.replace("_", " ") in str(err.value), str(err.value)


def test_numpy_scalars_are_numbers():
    res = RIG.simulate(np.array(0.001), n_out=np.int64(5), rtol=np.float32(1e-7),
                       params={"hammer.v0": np.float64(3.0)})
    assert res.t.size == 5 and res.t[-1] == pytest.approx(0.001)


STUDIES = {
    "sweep rig": (lambda: sweep(3, {"hammer.v0": [3.0]}), "rig"),
    "sweep t_end": (lambda: sweep(RIG, {"hammer.v0": [3.0]}, t_end="0.02"), "t_end"),
    "sweep n_out": (lambda: sweep(RIG, {"hammer.v0": [3.0]}, n_out="11"), "n_out"),
    "sweep params": (lambda: sweep(RIG, {"hammer.v0": [3.0]}, params=[("oil.k", 1e8)]), "params"),
    "sweep start": (lambda: sweep(RIG, {"hammer.v0": [3.0]}, start=[1]), "start"),
    "sweep rtol": (lambda: sweep(RIG, {"hammer.v0": [3.0]}, rtol="1e-6"), "rtol"),
    "sweep workers": (lambda: sweep(RIG, {"hammer.v0": [3.0]}, workers="2"), "workers"),
    "calibrate free": (lambda: calibrate(RIG, TRACE, 3), "free"),
    "calibrate bounds": (lambda: calibrate(RIG, TRACE, "oil.k", bounds=[1, 2]), "bounds"),
    "calibrate starts": (lambda: calibrate(RIG, TRACE, "oil.k", starts="3"), "starts"),
    "calibrate seed": (lambda: calibrate(RIG, TRACE, "oil.k", seed="x"), "seed"),
    "calibrate t_end": (lambda: calibrate(RIG, TRACE, "oil.k", t_end="0.02"), "t_end"),
    "calibrate params": (lambda: calibrate(RIG, TRACE, "oil.k", params=[("seal.c", 1.0)]),
                         "params"),
    "calibrate start": (lambda: calibrate(RIG, TRACE, "oil.k", start=[1]), "start"),
    "calibrate signal": (lambda: calibrate(RIG, TRACE, "oil.k", signal=3), "signal"),
    "calibrate trace": (lambda: calibrate(RIG, 3, "oil.k"), "trace"),
    "design target": (lambda: design(RIG, 3, free="oil.k"), "target"),
    "design target value": (lambda: design(RIG, {"peak_pressure": "1e8"}, free="oil.k"),
                            "peak_pressure"),
    "design free": (lambda: design(RIG, {"peak_pressure": 1e8}, free=3), "free"),
    "design starts": (lambda: design(RIG, {"peak_pressure": 1e8}, free="oil.k", starts="4"),
                      "starts"),
    "design params": (lambda: design(RIG, {"peak_pressure": 1e8}, free="oil.k", params=[1]),
                      "params"),
    "design bounds": (lambda: design(RIG, {"peak_pressure": 1e8}, free="oil.k", bounds=3),
                      "bounds"),
    "design t_end": (lambda: design(RIG, {"peak_pressure": 1e8}, free="oil.k", t_end="1"),
                     "t_end"),
    "sensitivity ranges": (lambda: sensitivity(RIG, [("hammer.v0", 1, 2)]), "ranges"),
    "sensitivity n": (lambda: sensitivity(RIG, {"hammer.v0": (1, 2)}, n="4"), "N"),
    "sensitivity t_end": (lambda: sensitivity(RIG, {"hammer.v0": (1, 2)}, n=1, t_end="x"),
                          "t_end"),
    "design map n": (lambda: design_map(RIG, "hammer.v0=1:2", "oil.k=1e8:2e8", n="3"), "n"),
    "design map x": (lambda: design_map(RIG, 3, "oil.k=1e8:2e8", n=2), "axis"),
    "design map t_end": (lambda: design_map(RIG, "hammer.v0=1:2", "oil.k=1e8:2e8", n=2,
                                            t_end="x"), "t_end"),
}


@pytest.mark.parametrize("case", list(STUDIES))
def test_study_entry_points_refuse_a_wrong_type_naming_it(case):
    call, word = STUDIES[case]
    with pytest.raises(PdbfsError) as err:
        call()
    assert isinstance(err.value, (ParameterError,)) or case.endswith(("trace", "target"))
    assert word in str(err.value), str(err.value)
