"""The README's promises: its examples are valid, and CI runs exactly its test command; the
documentation's examples run too (the library's in the API reference, the kinematics table in
the students' guide)."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
DOCS = sorted((ROOT / "docs").glob("*.md"))


def _blocks(lang, text=README):
    return re.findall(rf"```{lang}\n(.*?)```", text, flags=re.S)


def _doc_blocks(lang):
    return [b for page in DOCS for b in _blocks(lang, page.read_text(encoding="utf-8"))]


def _api_example() -> str:
    """The code block of the API reference's "Using the library"."""
    text = (ROOT / "docs" / "api.rst").read_text(encoding="utf-8")
    block = re.search(r".. code-block:: python\n\n((?:   .*\n|\n)+)", text).group(1)
    return "\n".join(line[3:] for line in block.splitlines())


def test_library_example_runs(tmp_path, monkeypatch, capsys):
    code = _api_example().replace('"sample_data/', f'"{ROOT}/sample_data/')
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

    toml = next(b for b in _blocks("toml") if 'lab = "lab1"' in b)
    path = tmp_path / "example.toml"
    path.write_text(toml, encoding="utf-8")
    inputs = load(path, lab1_inertia.SPEC)
    res = lab1_inertia.reduce(inputs, n_samples=2000)
    # the sample flywheel (sample_data/lab1): true J = 0.1712 kg·m²
    assert abs(res["J_trifilar"].value - 0.1712) < res["J_trifilar"].estimate.U


def test_readme_lab3_example_reduces_with_the_sample_recordings(tmp_path):
    import shutil

    import numpy as np

    from labs.registry import evaluate
    from processing.speed.edges import detect_edges
    from processing.inputs.signals import open_channel

    sample = ROOT / "sample_data" / "lab3"
    for name in ("regime1.wav", "coast.wav"):
        shutil.copy(sample / name, tmp_path / name)
    second = open_channel(sample / "regime2.wav")
    edges = detect_edges(second.read()) / second.sample_rate
    np.savetxt(tmp_path / "edges2.csv", edges, header="t", comments="")
    path = tmp_path / "example.toml"
    path.write_text(next(b for b in _doc_blocks("toml") if 'lab = "lab3"' in b), encoding="utf-8")
    res = evaluate(path, n_samples=2000)
    truth = [0.01853, 0.01747]      # sample_data/lab3/answer_key.json
    for r, delta in enumerate(truth, start=1):
        assert abs(res[f"delta_{r}"].value / delta - 1) < 0.03


def test_kinematics_example_is_what_the_command_prints(capsys):
    from labs.cli.main import main

    block = next(b for b in _doc_blocks("text") if b.startswith("$ dynlab kinematics"))
    command, *expected = block.strip().splitlines()
    assert main(command.split()[2:]) == 0
    assert capsys.readouterr().out.strip().splitlines() == expected


def test_every_documentation_link_leads_to_a_file():
    for page in [ROOT / "README.md", *DOCS]:
        text = page.read_text(encoding="utf-8")
        for target in re.findall(r"\]\(([^)#:]+)\)", text):
            assert (page.parent / target).exists(), f"{page.name}: link to {target} leads nowhere"
