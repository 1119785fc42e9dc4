#!/usr/bin/env bash
# The main job: set up, simulate the paper's rig (results and plot in out/),
# then build pdbfs.fmu, validate it and simulate it with fmpy.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
pdbfs simulate --out out
pdbfs export-fmu -o pdbfs.fmu
python3 -m fmpy.cli validate pdbfs.fmu
python3 -m fmpy.cli simulate pdbfs.fmu --interface-type CoSimulation --output-file out/fmu_results.csv
echo "main job done: out/results.csv, out/results.png, pdbfs.fmu, out/fmu_results.csv"
