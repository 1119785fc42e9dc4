"""Options the command line once took without a word or answered with a
message that misled: an option given twice (the last won), absurd numbers
(ending in a solver's generic failure, a C driver's "2 output times", or
CasADi's integrators copying the state over an interval shorter than 1e-9 s),
--out '' (the current folder), a PDBFS_SUNDIALS_SDIST naming no file (the
cache said it was ready); and the start messages of --initial, once up to
570 characters."""
import argparse

import pytest

from pdbfs.cli import build_parser
from pdbfs.cli.common import Once
from pdbfs.models import RIGS, paper_rig

from cli_support import cli, one_line


# -- given twice ------------------------------------------------------------------------
@pytest.mark.parametrize("args,words", [
    (["simulate", "--t-end", "0.01", "--t-end", "0.02"], ["--t-end given twice (0.01 and 0.02)"]),
    (["simulate", "--method", "bdf", "--method", "adams"], ["--method given twice (bdf and adams)"]),
    (["simulate", "--initial", "steady", "--initial", "hammer.s"], ["--initial given twice"]),
    (["simulate", "--rig", "paper", "--rig", "drop"], ["--rig given twice (paper and drop)"]),
    (["sweep", "--set", "hammer.v0=2,3", "--out", "a", "--out", "b"], ["--out given twice (a and b)"]),
    (["export-fmu", "-o", "a.fmu", "--output", "b.fmu"], ["--output given twice"]),
    (["design", "--peak", "1e8", "--peak", "2e8", "--free", "hammer.v0"], ["--peak given twice"]),
    (["simulate", "--set", "hammer.v0=3", "--set", "hammer.v0=4"],
     ["--set hammer.v0 given twice (3 and 4)"]),          # the message --set always had
])
def test_an_option_given_twice_is_refused_before_any_work(args, words, tmp_path):
    one_line(cli(*args, cwd=tmp_path), *words, "give it once")
    assert list(tmp_path.iterdir()) == []


def test_every_option_of_one_value_takes_it_once():
    """One mechanism for all: every option that stores one value is a Once
    (appended options check their names, flags cannot disagree)."""
    plain = []

    def walk(p):
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                for sp in a.choices.values():
                    walk(sp)
            elif type(a) is argparse._StoreAction:
                plain.append(a.option_strings)
            elif a.nargs is None and a.option_strings and not isinstance(
                    a, (Once, argparse._AppendAction, argparse._VersionAction)):
                plain.append(a.option_strings)
    walk(build_parser())
    assert plain == []


# -- numbers beyond what a run can mean ----------------------------------------------------
@pytest.mark.parametrize("args,words", [
    # the C driver once said "need at least 2 output times, got 1"
    (["simulate", "--t-end", "1e-12"], ["--t-end 1e-12 s", "shorter than 1e-09 s"]),
    (["simulate", "--t-end", "1e-6"], ["--t-end 1e-06 s with --n-out 2001", "5e-10 s apart"]),
    (["simulate", "--t-end", "1e-10", "--n-out", "2"], ["--t-end 1e-10 s", "shorter than 1e-09 s"]),
    (["simulate", "--t-end", "1e300"], ["--t-end 1e+300 s", "longer than 4.5e+09 s"]),
    (["sweep", "--set", "hammer.v0=2,3", "--t-end", "1e300"], ["--t-end 1e+300 s"]),
    (["calibrate", "--trace", "x.csv", "--free", "oil.k", "--t-end", "1e300"], ["--t-end 1e+300 s"]),
    (["design", "--peak", "1e8", "--free", "hammer.v0", "--t-end", "1e300"], ["--t-end 1e+300 s"]),
    (["design-map", "--x", "hammer.v0=2:3", "--y", "oil.k=2e8:3e8", "--t-end", "1e-10"],
     ["--t-end 1e-10 s"]),
    (["simulate", "--atol", "1e-300"], ["--atol 1e-300", "below 1e-30"]),
    (["sweep", "--set", "hammer.v0=2,3", "--atol", "1e-300"], ["--atol 1e-300"]),
    (["simulate", "--n-out", "1"], ["--n-out 1", "at least 2 output points"]),
    (["modes", "--at", "5e-10"], ["at=5e-10", "0 or at least 1e-09 s"]),
    (["simulate", "--rtol", "1e-300"], ["--rtol 1e-300", "must be in [1e-15, 0.1]"]),
])
def test_absurd_numbers_are_refused_naming_the_option_and_value(args, words, tmp_path):
    out = [] if args[0] == "modes" else ["--out", "o"]        # (modes writes no files)
    line = one_line(cli(*args, *out, cwd=tmp_path), *words)
    assert "t_end" not in line and "atol =" not in line
    assert list(tmp_path.iterdir()) == []


def test_the_api_refuses_them_in_its_own_words():
    from pdbfs.errors import ParameterError
    rig = paper_rig()
    with pytest.raises(ParameterError, match=r"^t_end = 1e\+300 s: longer than"):
        rig.simulate(1e300)
    with pytest.raises(ParameterError, match=r"^atol = 1e-300: below 1e-30"):
        rig.simulate(atol=1e-300)
    with pytest.raises(ParameterError, match=r"^max_step = 1e-300: below 1e-09 s"):
        rig.simulate(max_step=1e-300)
    with pytest.raises(ParameterError, match=r"^t_out: .* apart, closer than 1e-09 s"):
        rig.simulate(t_out=[0.0, 1e-3, 1e-3 + 2e-10])


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_output_points_closer_than_a_nanosecond_are_refused_not_answered_wrong(backend):
    """CasADi's integrators copy the state over an output interval shorter
    than 1e-9 s: 1e-10 s of the paper rig gave hammer.s = 0, not v0 t. At
    1e-9 s both back ends give the free flight v0 t (the contact has no
    force yet: its onset is at t = 0)."""
    import warnings

    from pdbfs.errors import ParameterError
    v0 = {p.name: p.value for p in paper_rig().parameters()}["hammer.v0"]
    for t_out in ([0.0, 1e-10], [0.0, 1e-3, 1e-3 + 1e-10]):
        with pytest.raises(ParameterError, match="closer than 1e-09 s"):
            paper_rig().simulate(t_out=t_out, backend=backend)
    with pytest.raises(ParameterError, match="^t_end = 1e-10 s: shorter than 1e-09 s"):
        paper_rig().simulate(1e-10, n_out=2, backend=backend)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")            # "no pulse" in a nanosecond
        res = paper_rig().simulate(1e-9, n_out=2, backend=backend)
    assert res["hammer.s"][-1] == pytest.approx(v0 * 1e-9, rel=1e-6)


# -- files only where the user said ------------------------------------------------------
@pytest.mark.parametrize("command", [["simulate"], ["sweep", "--set", "hammer.v0=2,3"],
                                     ["example-data"], ["design-map", "--x", "hammer.v0=2:3",
                                                        "--y", "oil.k=2e8:3e8", "--n", "2"]],
                         ids=lambda c: c[0])
def test_out_empty_is_refused_not_the_current_folder(command, tmp_path):
    one_line(cli(*command, "--out", "", cwd=tmp_path), "--out ''", "empty")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("value,words", [("/nonexistent/amici.tar.gz", ["no such file"]),
                                         ("here.txt", ["not amici-1.1.0.tar.gz", "SHA-256"])])
def test_prepare_offline_refuses_a_sdist_variable_naming_no_sdist(value, words, tmp_path):
    (tmp_path / "here.txt").write_text("not an sdist\n")
    line = one_line(cli("prepare-offline", "--platforms", "none", cwd=tmp_path,
                        env={"PDBFS_SUNDIALS_SDIST": value}), *words)
    assert f"PDBFS_SUNDIALS_SDIST={value}" in line and "ready" not in line


# -- --initial's messages ---------------------------------------------------------------
@pytest.mark.parametrize("rig", list(RIGS))
def test_a_start_that_cannot_be_solved_says_so_in_a_short_line(rig):
    """Every shipped rig that cannot start 'steady' (a body free to lie
    anywhere, an accumulator's oil volume that no rate fixes) says which
    states are left free, in one line of about 160 characters; the rigs
    that can (the drop rigs, at rest on their mounts) do."""
    from pdbfs.errors import ModelError
    from pdbfs.models import rig_from
    try:
        rig_from(rig).simulate(0.001, n_out=3, initial="steady")
    except ModelError as e:
        msg = str(e)
        assert "\n" not in msg and len(msg) <= 175, (len(msg), msg)
        assert rig not in ("drop", "drop-rest"), msg
        if rig in ("paper", "bar-piston", "hydraulic-pulse", "hydraulic-pulse-line"):
            assert "is not determined" in msg and " free (" in msg, msg
    else:
        assert rig not in ("paper", "bar-piston", "hydraulic-pulse", "hydraulic-pulse-line")


@pytest.mark.parametrize("command,option", [(["linearize"], "--out"),
                                            (["export-ssp", "--example", "pulse-pid"], "-o")],
                         ids=lambda c: c[0] if isinstance(c, list) else c)
def test_an_empty_file_name_is_named_empty_not_a_folder(command, option, tmp_path):
    line = one_line(cli(*command, option, "", cwd=tmp_path), f"{option} ''", "empty")
    assert "folder" not in line
    assert list(tmp_path.iterdir()) == []


# -- --max-step ----------------------------------------------------------------------------
@pytest.mark.parametrize("command", [["simulate"], ["sweep", "--set", "hammer.v0=2,3", "--quiet"]],
                         ids=lambda c: c[0])
@pytest.mark.parametrize("value", ["0", "-1e-3", "nan"])
def test_a_max_step_that_is_no_step_is_refused_naming_the_option(command, value, tmp_path):
    one_line(cli(*command, "--max-step", value, cwd=tmp_path), "--max-step", "positive")
    assert list(tmp_path.iterdir()) == []


def test_max_step_reaches_the_run_and_changes_no_figure(tmp_path):
    """The longest step bounds the steps (the run over 0.02 s takes at least
    0.02 / max_step of them), and the pulse is the one without it."""
    import json
    free = json.loads(cli("simulate", "--json", cwd=tmp_path).stdout)
    held = json.loads(cli("simulate", "--json", "--max-step", "2e-6", cwd=tmp_path).stdout)
    assert held["stats"]["steps"] >= 0.02 / 2e-6 > 3 * free["stats"]["steps"]
    assert held["peak_pressure"] == pytest.approx(free["peak_pressure"], rel=1e-6)


@pytest.mark.parametrize("option,words", [("--atol", "positive"), ("--rtol", "must be in"),
                                          ("--t-end", "positive")])
def test_a_negative_number_in_scientific_notation_is_a_value_not_an_option(option, words, tmp_path):
    """argparse read -1e-3 as an option: a usage text and 'expected one argument'."""
    line = one_line(cli("simulate", option, "-1e-3", cwd=tmp_path), option, words)
    assert "expected one argument" not in line
