"""``slosh-bif tank`` and ``--params FILE`` (issue 21): a file written by ``tank`` or ``info --out``
reads back to the same parameters, a command run from a preset's file gives the preset's results
byte for byte, and bad files or tanks are one-line errors naming what is wrong."""

import json

import pytest

from slosh_bif.cli import main
from slosh_bif.model.parameter_file import read_parameter_file
from slosh_bif.model.presets import get_preset
from slosh_bif.model.tank import Site, Tank, tank_model

TANK = [
    "tank",
    "--shape",
    "cylinder",
    "--radius",
    "5",
    "--depth",
    "8",
    "--structure-mass",
    "2e6",
    "--structure-frequency",
    "0.8",
    "--excitation-frequency",
    "0.72",
    "--ground-acceleration",
    "0.5",
    "--clearance",
    "1",
]


def test_tank_writes_a_file_that_reads_back_to_its_parameters(tmp_path, capsys):
    path = tmp_path / "tank.toml"
    assert main([*TANK, "--n", "20", "--out", str(path)]) == 0
    out = capsys.readouterr().out
    assert "eps = m_1 / M" in out and "Abramson" in out
    expected = tank_model(
        Tank("cylinder", depth=8.0, radius=5.0), Site(2e6, 0.8, 0.72, 0.5, 1.0), wall={"n": 20}
    ).params
    assert read_parameter_file(path).params == expected
    assert main(["info", "--params", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["params"] == expected.as_dict()


def test_a_preset_written_as_a_file_gives_the_presets_results(tmp_path):
    path = tmp_path / "fig13.toml"
    assert main(["info", "--preset", "fig13", "--out", str(path)]) == 0
    preset, read = get_preset("fig13"), read_parameter_file(path)
    assert (read.params, read.uv0, read.t_window) == (preset.params, preset.uv0, preset.t_window)
    assert main(["frc", "--preset", "fig13", "--out", str(tmp_path / "a")]) == 0
    assert main(["frc", "--params", str(path), "--out", str(tmp_path / "b")]) == 0
    assert (tmp_path / "a" / "frc.csv").read_bytes() == (tmp_path / "b" / "frc.csv").read_bytes()
    # JSON works alike, and --set still overrides
    (tmp_path / "p.json").write_text(json.dumps({"params": preset.params.as_dict()}))
    assert main(["info", "--params", str(tmp_path / "p.json"), "--set", "Abar=2", "--json"]) == 0


@pytest.mark.parametrize(
    "text, says",
    [
        ("[params]\neps = 0.05\nomega = 1\n", "unknown key 'omega' in [params]"),
        ("[params]\neps = 0.05\n", "[params] needs beta"),
        (
            "[params]\neps = -1\nbeta = 0\ngamma = 0.2\nsigma = 1\nAbar = 1\nlam = 0.35\nchi = "
            "0.2\nn = 50\npbar = 0\n",
            "parameter eps must be in (0, inf)",
        ),
        (
            "[tank]\nshape = 'cylinder'\ndepth = 8\nradius = 5\nstructure_mass = "
            "2e6\nstructure_frequency = 0.8\nexcitation_frequency = 0.72\nground_acceleration = "
            "0.5\nclearance = 1\nheight = 6\n",
            "depth 8 m exceeds the tank's height 6 m",
        ),
        ("[tank]\nshape = 'cylinder'\ndepth = 8\n", "[tank] needs structure_mass"),
        ("[params]\n[tank]\n", "exactly one of the tables"),
        ("[initial]\nuv0 = [0, 1]\n[params]\neps = 1\n", "needs beta"),
        ("eps = = 1", "is not valid TOML"),
    ],
)
def test_bad_parameter_files_are_one_line_errors_naming_the_file(tmp_path, capsys, text, says):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert main(["info", "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert says in err and str(path) in err and err.strip().count("\n") == 0, err


def test_bad_tanks_are_one_line_errors(tmp_path, capsys):
    for argv, says in [
        (["tank", "--shape", "cylinder", "--depth", "8", *TANK[5:]], "a cylinder needs --radius"),
        ([*TANK, "--length", "3"], "--length do not describe a cylinder"),
        ([*TANK, "--height", "6"], "exceeds the tank's height"),
        ([*TANK[:4], "-5", *TANK[5:]], "radius must be a positive finite number"),
    ]:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert says in err and err.strip().count("\n") == 0, err
    assert main(["info", "--preset", "fig10", "--out", str(tmp_path)]) == 2  # a file is written, not a folder
    assert "is a folder; give a file name" in capsys.readouterr().err
    assert (
        main([*TANK[:-6], "--excitation-frequency", "3", *TANK[-4:]]) == 0
    )  # far from resonance: a warning, not an error
    assert "far from 1:1 resonance" in capsys.readouterr().err


def test_the_storage_tank_example_runs_and_writes_a_file_that_reads_back(tmp_path, capsys):
    import importlib.util
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "examples" / "storage_tank.py"
    spec = importlib.util.spec_from_file_location("storage_tank_example", script)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    example.main(tmp_path)
    out = capsys.readouterr().out
    assert out.count("from rest:") == len(example.ACCELERATIONS) and "Abar_b" in out
    assert (
        read_parameter_file(tmp_path / "storage_tank.toml").params
        == tank_model(example.TANK, example.SITE).params
    )
