"""Write pdbfs/native/c/shared/pdbfs_erk_table.h: the coefficients of Dormand &
Prince's 8(5,3) pair with dense output (Hairer, Norsett & Wanner, Solving
ODEs I, 1993), as numbers; taken from scipy's table of the same method.

    python scripts/erk_table.py
"""
from pathlib import Path

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as d

OUT = Path(__file__).resolve().parents[1] / "pdbfs" / "native" / "c" / "shared" / "pdbfs_erk_table.h"
HEAD = """/* Dormand & Prince's explicit Runge-Kutta pair of order 8(5,3) with its
 * 7th-order dense output (E. Hairer, S. P. Norsett, G. Wanner, Solving
 * Ordinary Differential Equations I, 2nd ed., Springer 1993, the DOP853
 * table): published coefficients, written out by scripts/erk_table.py.
 * RK_A: 16 x 16 row major, stage s uses row s (rows 13-15: the dense
 * output's extra stages); RK_C: nodes; RK_B: weights of the 12 stages;
 * RK_E3, RK_E5: the error estimators over 13 stages (the 13th: f at the
 * step's end); RK_D: 4 x 16, the dense output's higher coefficients. */
#ifndef PDBFS_ERK_TABLE_H
#define PDBFS_ERK_TABLE_H

"""


def table(name, a):
    v = [repr(float(x)) for x in np.asarray(a, float).ravel()]
    rows = [", ".join(v[i:i + 3]) for i in range(0, len(v), 3)]
    return f"static const double {name}[{len(v)}] = {{\n    " + ",\n    ".join(rows) + "};\n"


if __name__ == "__main__":
    OUT.write_text(HEAD + "".join(table(n, getattr(d, k)) for n, k in (
        ("RK_A", "A"), ("RK_C", "C"), ("RK_B", "B"), ("RK_E3", "E3"), ("RK_E5", "E5"),
        ("RK_D", "D"))) + "\n#endif\n")
