"""A DAE's fingerprint: its names, and its functions evaluated at fixed
pseudo-random points. tests/data/dae_reference.json holds the fingerprints of
the rigs below made by the structural analysis before it was rewritten for
large rigs (issue 10); test_structure.py checks the compiler still builds the
same DAEs. Regenerate only on purpose: python tests/dae_fingerprint.py."""
import json
import pathlib

import numpy as np

REFERENCE = pathlib.Path(__file__).with_name("data") / "dae_reference.json"


def rigs():
    import test_core as C
    from pdbfs.models import drop_rig, paper_rig, split_piston_rig
    return {"paper": paper_rig, "paper-ln": lambda: paper_rig(law="lankarani-nikravesh"),
            "split1": lambda: split_piston_rig(n=1), "split3": lambda: split_piston_rig(n=3),
            "split12": lambda: split_piston_rig(n=12), "drop": drop_rig, "chain": lambda: C.Chain(3),
            "drop-sensors": C.Drop, "bench": C.Bench, "lever": _lever_rig}


def _lever_rig():
    import pdbfs
    import test_core as C
    from pdbfs.components import Force, Mass

    class R(pdbfs.Rig):
        def declare(self):
            self.push = Force(F=10.0)
            self.m1 = Mass(m=1.0)
            self.lever = C.Lever(ratio=3.0)
            self.m2 = Mass(m=0.5)
            self.connect(self.push.flange, self.m1.flange_a)
            self.connect(self.m1.flange_b, self.lever.flange_a)
            self.connect(self.lever.flange_b, self.m2.flange_a)
    return R()


def fingerprint(dae, points: int = 3) -> dict:
    rng = np.random.default_rng(12345)
    out = {"x": dae.x_names, "z": dae.z_names, "p": dae.p_names, "y": dae.y_names,
           "events": list(dae.event_names), "calculated": sorted(dae.calculated), "evals": []}
    p0 = dae.p_default()
    for _ in range(points):
        p = p0 * rng.uniform(0.9, 1.1, p0.size)
        x = rng.normal(0.0, 1e-3, dae.x.numel())
        z = rng.normal(0.0, 1e-3, dae.z.numel())
        t = float(rng.uniform(0.0, 0.01))
        ev = {k: np.asarray(dae.function(k)(t, x, z, p), float).ravel().tolist()
              for k in ("ode", "alg", "out", "events")}
        ev["start"] = np.asarray(dae.function("start")(p), float).ravel().tolist()
        out["evals"].append({"t": t, "x": x.tolist(), "z": z.tolist(), "p": p.tolist(), **ev})
    return out


if __name__ == "__main__":
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).parent))
    data = {name: fingerprint(make().compile()) for name, make in rigs().items()}
    REFERENCE.write_text(json.dumps(data))
    print(f"wrote {REFERENCE}: {', '.join(data)}")
