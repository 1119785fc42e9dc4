#!/usr/bin/env bash
# The main job: set up, simulate the paper's rig (results and plot in out/),
# then build pdbfs.fmu, validate it and simulate it with fmpy.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
pdbfs simulate --out out
pdbfs export-fmu -o pdbfs.fmu
python -m fmpy.cli validate pdbfs.fmu
python -m fmpy.cli simulate pdbfs.fmu --interface-type CoSimulation --output-interval 1e-5 \
    --output-file out/fmu_results.csv
python - <<'PY'
import numpy as np
py = np.genfromtxt("out/results.csv", delimiter=",", names=True)
fmu = np.genfromtxt("out/fmu_results.csv", delimiter=",", names=True)
a, b = py["oilpressure_Pa"].max(), fmu["oilpressure"].max()
print(f"peak pressure: Python {a / 1e6:.6f} MPa, FMU (fmpy) {b / 1e6:.6f} MPa, "
      f"relative difference {abs(a - b) / a:.1e}")
PY
echo "main job done: out/results.csv, out/results.png, pdbfs.fmu, out/fmu_results.csv"
