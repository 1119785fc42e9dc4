"""The Python examples of README.md run as written."""
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_blocks_run(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert len(blocks) >= 3
    monkeypatch.chdir(tmp_path)
    for block in blocks:                 # each block runs as written, on its own imports
        namespace = {}
        exec(compile(block, str(README), "exec"), namespace)
    assert (tmp_path / "pdbfs.fmu").stat().st_size > 10000
    assert (tmp_path / "r.csv").exists() and (tmp_path / "r.png").exists()
    osc = namespace["Oscillator"]().simulate(1.0, n_out=11)   # the last block's rig
    assert abs(osc["body.s"].max()) > 0
