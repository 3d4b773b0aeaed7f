"""`dynlab kinematics`: the classic table of dimensionless piston motion."""
import io

import pandas as pd
import pytest

from labs.cli.main import main


def _csv(capsys, *args):
    assert main(["kinematics", *args, "--format", "csv"]) == 0
    return pd.read_csv(io.StringIO(capsys.readouterr().out)).set_index("alpha")


def test_exact_table_values_lambda_quarter(capsys):
    t = _csv(capsys, "--lambda", "0.25", "--step", "30")
    assert list(t.index) == list(range(0, 361, 30))
    # α = 0: j = 1 + λ; α = 180°: j = −(1 − λ); α = 90°: s = 1 + (1 − cos β)/λ, β = arcsin λ
    assert t.loc[0, "j/(R*omega^2)"] == pytest.approx(1.25, abs=1e-6)
    assert t.loc[180, "j/(R*omega^2)"] == pytest.approx(-0.75, abs=1e-6)
    assert t.loc[90, "s/R"] == pytest.approx(1 + 4 * (1 - (1 - 1 / 16) ** 0.5), abs=1e-6)
    assert t.loc[90, "beta"] == pytest.approx(14.477512, abs=1e-6)


def test_approximate_table_is_the_series(capsys):
    t = _csv(capsys, "--lambda", "0.32", "--step", "90", "--approx")
    # j ≈ cos α + λ cos 2α: 1.32 at TDC, −0.32 at 90°, −0.68 at BDC
    assert t["j/(R*omega^2)"].tolist() == pytest.approx([1.32, -0.32, -0.68, -0.32, 1.32])


def test_printed_table_and_bad_lambda(capsys):
    assert main(["kinematics", "--lambda", "0.25", "--step", "90"]) == 0
    out = capsys.readouterr().out
    assert "λ = 0.25" in out and "1.2500" in out and "-0.7500" in out
    assert main(["kinematics", "--lambda", "1.3"]) == 2
    assert "Fix:" in capsys.readouterr().err
