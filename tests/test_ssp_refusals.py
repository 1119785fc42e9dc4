"""Bad input to export_ssp, ``pdbfs export-ssp`` and cosimulate is refused in
one line naming the culprit, before anything is written; the command line
exits with status 2. What a system needs of its FMUs is declared: the
controller of blocks only exports, its command an output."""
import zipfile

import pytest

import ssp_support as S
from pdbfs.cli import main
from pdbfs.errors import ExportError
from pdbfs.fmu import cosimulate, export_ssp, read_interface
from pdbfs.models import LOOP


def fmus():
    return {"plant": S.fmu_of("plant"), "controller": S.fmu_of("controller")}


def refused(tmp_path, words, path="x.ssp", fmus_=None, connections=LOOP, **kw):
    with pytest.raises(ExportError) as err:
        export_ssp(tmp_path / path, fmus() if fmus_ is None else fmus_, connections, **kw)
    line = str(err.value)
    assert "\n" not in line and all(w in line for w in words), line
    assert not [p for p in tmp_path.iterdir() if p.suffix in (".ssp", ".part")], list(tmp_path.iterdir())


def test_bad_systems_are_refused_in_one_line(tmp_path):
    plant = S.fmu_of("plant")
    (tmp_path / "junk.fmu").write_text("not a zip")
    with zipfile.ZipFile(tmp_path / "empty.fmu", "w") as z:
        z.writestr("readme.txt", "no model description")
    refused(tmp_path, ["x.fmu", "ends in .ssp"], path="x.fmu")
    refused(tmp_path, ["no such FMU file", "missing.fmu"], fmus_={"plant": tmp_path / "missing.fmu"},
            connections=[])
    refused(tmp_path, ["junk.fmu", "not an FMU"], fmus_={"plant": tmp_path / "junk.fmu"}, connections=[])
    refused(tmp_path, ["empty.fmu", "no modelDescription.xml"], fmus_={"plant": tmp_path / "empty.fmu"},
            connections=[])
    refused(tmp_path, ["component name 'pl.ant'", "no dots"], fmus_={"pl.ant": plant}, connections=[])
    refused(tmp_path, ["mapping of names to FMU files"], fmus_={})
    refused(tmp_path, ["no component 'valve'", "plant, controller"],
            connections=[("valve.y", "controller.measured")])
    refused(tmp_path, ["'opening' is not an output of plant", "sensor.y"],
            connections=[("plant.opening", "controller.measured")])
    refused(tmp_path, ["'pid.y' is not an input of controller", "measured"],
            connections=[("plant.sensor.y", "controller.pid.y")])
    refused(tmp_path, ["in Pa, the input in 1"], connections=[("plant.sensor.y", "plant.opening")])
    refused(tmp_path, ["controller.measured is fed twice", "plant.sensor.y", "plant.chamber.p"],
            connections=[("plant.sensor.y", "controller.measured"), ("plant.chamber.p", "controller.measured")])
    refused(tmp_path, ["give a pair"], connections=["plant.sensor.y:controller.measured"])
    refused(tmp_path, ["ELEMENT.VARIABLE"], connections=[("plant", "controller.measured")])
    refused(tmp_path, ["stop_time", "after start_time"], stop_time=0.0)
    refused(tmp_path, ["stop_time = nan"], stop_time=float("nan"))


def test_the_command_line_refuses_in_one_line_and_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    plant, ctrl = S.fmu_of("plant"), S.fmu_of("controller")
    cases = [([], "give the FMUs"),
             (["--example", "pulse-pid", "--fmu", f"plant={plant}"], "without --fmu"),
             (["--fmu", f"plant={plant}", "--connect", "plant.sensor.y->controller.measured"],
              "ELEMENT.OUTPUT:ELEMENT.INPUT"),
             (["--fmu", plant], "NAME=FILE.fmu"),
             (["--fmu", f"plant={plant}", "--fmu", f"plant={ctrl}"], "component plant is given twice"),
             (["--fmu", f"plant={plant}", "--fmi-version", "3"], "--fmi-version chooses"),
             (["-o", "loop.fmu", "--example", "pulse-pid"], "ends in .ssp"),
             (["--fmu", f"plant={plant}", "--fmu", f"controller={ctrl}", "--connect",
               "plant.sensor.y:controller.measure"], "'measure' is not an input of controller")]
    for args, words in cases:
        status = main(["export-ssp", *args])
        err = capsys.readouterr().err.strip().splitlines()
        assert status == 2 and len(err) == 1 and words in err[0], (args, err)
        assert list(tmp_path.iterdir()) == [], (args, list(tmp_path.iterdir()))


def test_the_command_line_writes_the_system(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    args = ["export-ssp", "-o", "loop.ssp", "--name", "pulse_pid"]
    for element, path in fmus().items():
        args += ["--fmu", f"{element}={path}"]
    for a, b in LOOP:
        args += ["--connect", f"{a}:{b}"]
    assert main(args) == 0 and "wrote loop.ssp" in capsys.readouterr().out
    assert (tmp_path / "loop.ssp").read_bytes() == open(S.loop_ssp(), "rb").read()


def test_cosimulate_refuses_bad_arguments():
    ssp = S.loop_ssp()
    for kw, words in ((dict(step=3e-5), "does not divide"), (dict(step=0.0), "step = 0.0"),
                      (dict(step=1e-5, t_end=0.0), "is not after the start"),
                      (dict(step=1e-5, outputs=["plant.nothing"]), "'plant.nothing': no such variable")):
        with pytest.raises(ExportError, match=words):
            cosimulate(ssp, **kw)


def test_a_controller_of_blocks_only_exports_with_its_command_as_an_output():
    ctrl = read_interface(S.fmu_of("controller", 3))
    assert set(ctrl.inputs) == {"measured"} and ctrl.inputs["measured"].unit == "Pa"
    assert "pid.y" in ctrl.outputs and ctrl.outputs["pid.y"].type == "Float64"
    plant = read_interface(S.fmu_of("plant"))
    assert set(plant.inputs) == {"opening"} and plant.outputs["sensor.y"].unit == "Pa"
    # an Input's own signal is the input, not an output of the rig
    assert "opening.y" not in plant.outputs and "measured.y" not in ctrl.outputs
