"""The README's promises: its quick start runs, and CI runs exactly its test command."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", README, flags=re.S)


def test_library_quick_start_runs(tmp_path, monkeypatch, capsys):
    code = _blocks("python")[0].replace('"sample_data/', f'"{ROOT}/sample_data/')
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert re.search(r"m_shp = 0\.26\d\d ± 0\.00\d\d kg", out), out
    assert (tmp_path / "reports" / "conrod.html").exists()


def test_ci_runs_the_readme_test_command():
    test_cmd = next(b.strip() for b in _blocks("sh") if "pytest" in b)
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert test_cmd in ci, f"README: {test_cmd!r} not in .ci/run"


def test_readme_toml_example_is_a_valid_lab1_file(tmp_path):
    from labs import lab1_inertia
    from processing.measurement import load

    toml = _blocks("toml")[0]
    path = tmp_path / "example.toml"
    path.write_text(toml, encoding="utf-8")
    inputs = load(path, lab1_inertia.SPEC)
    res = lab1_inertia.reduce(inputs, n_samples=2000)
    # the sample flywheel (sample_data/lab1): true J = 0.1712 kg·m²
    assert abs(res["J_trifilar"].value - 0.1712) < res["J_trifilar"].estimate.U


def test_kinematics_example_is_what_the_command_prints(capsys):
    from labs.cli import main

    block = next(b for b in _blocks("text") if b.startswith("$ dynlab kinematics"))
    command, *expected = block.strip().splitlines()
    assert main(command.split()[2:]) == 0
    assert capsys.readouterr().out.strip().splitlines() == expected
