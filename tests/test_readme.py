"""README.md's Python example runs as written and prints what it says it
prints: the figures in its comment are computed again, here."""
import re
import zipfile

import docs_examples as D

README = (D.ROOT / "README.md").read_text()


def test_readme_python_example_runs_and_prints_its_comment(tmp_path, monkeypatch, capsys):
    (block,) = D.python_blocks(README)
    assert len(block.body.strip().splitlines()) <= 12          # a ten-line example
    stated = re.search(r"#\s*(peak [\d.]+ MPa at [\d.]+ ms, lasting [\d.]+ ms)\s*$", block.body, re.M)
    assert stated, "README's example should state what it prints"
    monkeypatch.chdir(tmp_path)
    exec(compile(block.body, "README.md", "exec"), {"__name__": "__readme__"})
    printed = capsys.readouterr().out
    assert stated.group(1) in printed, (stated.group(1), printed)
    assert (tmp_path / "pulse.png").stat().st_size > 10000
    assert (tmp_path / "pulse.csv").read_text().count("\n") == 2002      # header and 2001 rows
    with zipfile.ZipFile(tmp_path / "paper.fmu") as z:                  # FMI 3.0, as it says
        assert 'fmiVersion="3.0"' in z.read("modelDescription.xml").decode()
