"""The ``dynlab`` command: bad input, templates, output formats, the installed script.

Every run is in-process (``labs.cli.main.main``) except one smoke test of the console script.
A bad measurement file must give one line on stderr naming the file, the field and the fix,
exit with 2, and leave no report behind.
"""
import json
import math
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from cli_contract import LAB1, LAB2, assert_one_clear_error, run, sample
from labs.cli.main import main
from labs.registry import LABS
from processing.inputs.toml_writer import dumps


# ----------------------------------------------------------------------- bad measurement files

def _set(section, key, value):
    def edit(d):
        d[section][key] = value
    return edit


def _del(section, key=None):
    def edit(d):
        if key is None:
            del d[section]
        else:
            del d[section][key]
    return edit


def _first_analytic(key, value):
    def edit(d):
        d["analytic"][0][key] = value
    return edit


# (id, lab, edit of the parsed sample, field named in the message, what the message says)
BAD_FILES = [
    ("missing-field", "lab1", _del("trifilar", "R1"), "trifilar.R1", r"'R1'.*missing"),
    ("missing-required-section", "lab2", _del("rod"), "rod", r"\[rod\] is missing"),
    ("wrong-unit", "lab1", _set("trifilar", "l", "12 kg"), "trifilar.l",
     r"'12 kg' is a mass, but a length is expected"),
    ("wrong-unit-in-table", "lab1", _set("trifilar", "R1", {"value": 99.8, "unit": "kg"}),
     "trifilar.R1", r"'kg'.*is a mass, but a length is expected"),
    ("unknown-unit-in-table", "lab1", _set("trifilar", "R1", {"value": 99.8, "unit": "mmm"}),
     "trifilar.R1", r"unit 'mmm'.*not known"),
    ("negative-length", "lab1", _set("trifilar", "l", -799.8), "trifilar.l", r"must be > 0"),
    ("negative-length-with-unit", "lab2", _set("swinging", "l_CD", "-199.3 mm"),
     "swinging.l_CD", r"must be > 0"),
    ("zero-time", "lab1", _set("pendulum", "t", 0), "pendulum.t", r"must be > 0, got 0"),
    ("zero-among-readings", "lab2", _set("swinging", "t_C", [16.34, 0.0, 16.27]),
     "swinging.t_C", r"must be > 0"),
    ("empty-array", "lab1", _set("trifilar", "t", []), "trifilar.t", r"'t'.*is empty"),
    ("empty-string", "lab2", _set("rod", "m_sh", ""), "rod.m_sh", r"'m_sh'.*is empty"),
    ("unknown-lab", "lab1", lambda d: d.update(lab="lab99"), "lab",
     r"unknown lab 'lab99'.*lab1, lab2"),
    ("no-lab-key", "lab1", lambda d: d.pop("lab"), "lab", r"does not say which lab"),
    ("unknown-key-did-you-mean", "lab1", _set("trifilar", "R3", 99.8), "trifilar.R3",
     r"unknown key 'R3'.*did you mean 'R[12]'\?"),
    ("misspelt-key-did-you-mean", "lab2", _set("swinging", "amplitud", "7 deg"),
     "swinging.amplitud", r"unknown key 'amplitud'.*did you mean 'amplitude'\?"),
    ("misspelt-length-lists-keys", "lab1", _set("trifilar", "lenght", 799.8), "trifilar.lenght",
     r"unknown key 'lenght'.*Fix: known keys: .*\bl\b"),
    ("misspelt-section", "lab1", lambda d: d.update(trifilr=d.pop("trifilar")), "trifilr",
     r"unknown section or key 'trifilr'.*did you mean 'trifilar'\?"),
    ("unknown-meta-key", "lab1", _set("meta", "studnet", "I. Petrov"), "meta.studnet",
     r"unknown key 'studnet' in \[meta\].*did you mean 'student'\?"),
    ("nan", "lab1", _set("trifilar", "R1", math.nan), "trifilar.R1", r"not a finite number"),
    ("infinity", "lab2", _set("rod", "l_sh", math.inf), "rod.l_sh", r"not a finite number"),
    ("count-zero", "lab1", _set("trifilar", "n_osc", 0), "trifilar.n_osc",
     r"whole number ≥ 1, got 0"),
    ("count-fraction", "lab2", _set("swinging", "n_osc", 2.5), "swinging.n_osc",
     r"whole number ≥ 1, got 2\.5"),
    ("count-as-text", "lab1", _set("pendulum", "n_osc", "20"), "pendulum.n_osc",
     r"whole number"),
    ("choice-typo", "lab1", _first_analytic("shape", "cilinder"), "analytic[0].shape",
     r"'cilinder' is not one of .*did you mean 'cylinder'\?"),
    ("choice-typo-lab2", "lab2", _set("rod", "engine", "petrl"), "rod.engine",
     r"did you mean 'petrol'\?"),
    ("flag-not-bool", "lab1", _first_analytic("hole", "yes"), "analytic[0].hole",
     r"true or false"),
    ("number-not-text", "lab1", _set("trifilar", "R1", "about a hundred"), "trifilar.R1",
     r"cannot read 'about a hundred'"),
    ("boolean-as-number", "lab1", _set("body", "m", True), "body.m",
     r"must be a number or a string with a unit"),
    ("section-not-a-table", "lab1", lambda d: d.update(pendulum=5), "pendulum",
     r"must be a table"),
]


@pytest.mark.parametrize("lab, edit, field, problem",
                         [pytest.param(*case[1:], id=case[0]) for case in BAD_FILES])
def test_bad_value_gives_one_clear_error_and_no_report(tmp_path, capsys, lab, edit, field,
                                                       problem):
    data = sample(lab)
    edit(data)
    bad = tmp_path / "student.toml"
    bad.write_text(dumps(data), encoding="utf-8")
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", bad, "--out", out_dir)
    assert_one_clear_error(code, out, err, bad, field, problem, out_dir)


@pytest.mark.parametrize("content, problem", [
    pytest.param("This is my lab report, see the table below.\n", r"not a valid TOML file",
                 id="prose"),
    pytest.param(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xd8\xff", r"not a text file",
                 id="binary-not-utf8"),
    pytest.param(b"lab = \"lab1\"\n\x00\x01\x02\x03", r"not a valid TOML file",
                 id="binary-utf8-control-chars"),
    pytest.param('lab = "lab1"\n[body\nm = 1\n', r"not a valid TOML file", id="broken-header"),
    pytest.param("", r"does not say which lab", id="empty-file"),
])
def test_file_that_is_not_a_measurement_file(tmp_path, capsys, content, problem):
    bad = tmp_path / "notes.toml"
    if isinstance(content, bytes):
        bad.write_bytes(content)
    else:
        bad.write_text(content, encoding="utf-8")
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", bad, "--out", out_dir)
    field = "lab" if "which lab" in problem else None
    assert_one_clear_error(code, out, err, bad, field, problem, out_dir)


def test_missing_file_path(tmp_path, capsys):
    missing = tmp_path / "no_such_dir" / "flywheel.toml"
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", missing, "--out", out_dir)
    assert_one_clear_error(code, out, err, missing, None, r"file not found", out_dir)


def test_directory_instead_of_file(tmp_path, capsys):
    folder = tmp_path / "measurements.toml"
    folder.mkdir()
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", folder, "--out", out_dir)
    assert_one_clear_error(code, out, err, folder, None, r"is a directory", out_dir)


def test_unwritable_out_is_an_input_error_not_a_crash(tmp_path, capsys):
    not_a_folder = tmp_path / "reports"
    not_a_folder.write_text("I am a file", encoding="utf-8")
    code, out, err = run(capsys, "run", LAB2, "--out", not_a_folder, "--format", "json")
    assert code == 2, f"exit {code}; stderr:\n{err}"
    assert "Traceback" not in err and "internal error" not in err, err
    assert "Fix:" in err and str(not_a_folder) in err, err


def test_good_files_are_reported_even_when_one_is_bad(tmp_path, capsys):
    data = sample("lab1")
    data["trifilar"]["n_osc"] = 0
    bad = tmp_path / "bad_flywheel.toml"
    bad.write_text(dumps(data), encoding="utf-8")
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", bad, LAB2, "--out", out_dir, "--format", "json,html")
    assert code == 2, f"one bad file must make the exit code 2, got {code}\n{err}"
    written = sorted(p.name for p in out_dir.iterdir())
    assert written == ["conrod.html", "conrod.json"], \
        f"the good file's reports (and only those) should be written, got {written}"
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "bad_flywheel.toml" in lines[0] and "trifilar.n_osc" in lines[0], err
    assert "Reducing the connecting-rod mass" in out, f"the good file's summary is missing:\n{out}"


def test_argument_errors_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", str(LAB1), "--format", "docx"])
    err = capsys.readouterr().err
    assert exc.value.code == 2, f"argparse should exit 2, got {exc.value.code}"
    assert "unknown format 'docx'" in err and "html, pdf, json" in err, err


# ----------------------------------------------------------------------------- templates

def test_template_of_unknown_lab_lists_the_labs(capsys):
    code, out, err = run(capsys, "template", "lab99")
    assert code == 2, f"exit {code}; stderr:\n{err}"
    assert "Traceback" not in err
    assert "unknown lab 'lab99'" in err and "lab1" in err and "lab2" in err, err
    assert "Fix:" in err and out == "", (out, err)


@pytest.mark.parametrize("lab", ["lab1", "lab2"])
@pytest.mark.parametrize("lang", ["en", "ru"])
def test_template_is_valid_toml_for_its_lab(capsys, lab, lang):
    code, out, err = run(capsys, "template", lab, "--lang", lang)
    assert code == 0, err
    data = tomllib.loads(out)  # raises, with the line, if the template is not TOML
    assert data["lab"] == lab, f"template for {lab} says lab = {data.get('lab')!r}"
    assert set(data["meta"]) >= {"student", "group", "date"}, data["meta"]
    if lang == "ru":
        assert re.search("[А-Яа-я]{4}", out), "the Russian template has no Russian text"


# What a student writes into the blanks, keyed (section, key); optional lines ("# key = ")
# listed here are uncommented and filled too.
LAB1_FILLED = {
    ("meta", "student"): '"I. Petrov"', ("meta", "group"): '"DVS-121"',
    ("meta", "date"): '"2026-03-02"', ("meta", "rig"): '"rig 1"',
    ("body", "m"): '"11.800 kg"',
    ("trifilar", "R1"): "99.8", ("trifilar", "R2"): "140.3", ("trifilar", "l"): "799.8",
    ("trifilar", "n_osc"): "20", ("trifilar", "t"): "[36.07, 36.21, 36.22]",
    ("trifilar", "m_p"): '"2.104 kg"', ("trifilar", "t_p"): "[34.38, 34.27, 34.33]",
    ("trifilar", "amplitude"): '"7 deg"',
    ("pendulum", "c"): "35.5", ("pendulum", "n_osc"): "20",
    ("pendulum", "t"): "[26.93, 26.95, 27.03]",
}
LAB2_FILLED = {
    ("meta", "student"): '"I. Petrov"', ("meta", "group"): '"DVS-121"',
    ("meta", "date"): '"2026-03-02"', ("meta", "rig"): '"rig 2"',
    ("rod", "m_sh"): '"1013 g"', ("rod", "l_sh"): "160.1", ("rod", "engine"): '"petrol"',
    ("weighing", "R_A"): '"266 g"',
}
ROUND_TRIPS = {
    # lab: (values, sections the student deletes, results expected, results absent)
    "lab1": (LAB1_FILLED, {"analytic", "unifilar"}, ("J_trifilar", "J_pendulum_cm"),
             ("J_analytic", "J_unifilar")),
    "lab2": (LAB2_FILLED, {"swinging"}, ("m_shp_weighing", "m_shp_statistics"),
             ("m_shp_swinging",)),
}


def fill_template(text: str, values: dict, drop: set) -> str:
    """Fill a template as a student would: blanks filled, unmeasured sections deleted."""
    out, section, used = [], None, set()
    for line in text.splitlines():
        header = re.match(r"^\[\[?(\w+)\]\]?\s*$", line)
        if header:
            section = header.group(1)
        if section in drop:
            continue
        blank = re.match(r'^(# )?(\w+) = ""$', line)
        if blank:
            key = (section, blank.group(2))
            if key in values:
                line = f"{blank.group(2)} = {values[key]}"
                used.add(key)
            else:
                assert blank.group(1), (f"the template asks for {key[0]}.{key[1]}, which this "
                                        f"test does not know how to fill:\n{text}")
        out.append(line)
    unused = set(values) - used
    assert not unused, f"the template has no blank for {sorted(unused)}:\n{text}"
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("lab, lang", [("lab1", "en"), ("lab2", "en"), ("lab1", "ru")])
def test_template_fill_run_round_trip(tmp_path, capsys, lab, lang):
    values, drop, present, absent = ROUND_TRIPS[lab]
    blank = tmp_path / f"{lab}_{lang}.toml"
    code, out, err = run(capsys, "template", lab, "--lang", lang, "-o", blank)
    assert code == 0 and blank.is_file(), f"template -o did not write {blank}: {err}"
    assert str(blank) in out, f"template -o should say where it wrote: {out!r}"

    # Run as written: it must say which field is still empty.
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", blank, "--out", out_dir)
    first_required = {"lab1": "body.m", "lab2": "rod.m_sh"}[lab]
    assert_one_clear_error(code, out, err, blank, first_required, r"is empty", out_dir)

    filled = tmp_path / f"{lab}_{lang}_filled.toml"
    filled.write_text(fill_template(blank.read_text(encoding="utf-8"), values, drop),
                      encoding="utf-8")
    code, out, err = run(capsys, "run", filled, "--out", out_dir, "--lang", lang)
    assert code == 0, f"the filled template does not run:\n{err}\n{filled.read_text()}"
    assert "Traceback" not in err
    written = sorted(p.name for p in out_dir.iterdir())
    stem = filled.stem
    assert written == sorted(f"{stem}.{x}" for x in ("html", "json", "pdf")), written
    result = json.loads((out_dir / f"{stem}.json").read_text(encoding="utf-8"))
    assert result["meta"]["student"] == "I. Petrov", result["meta"]
    for name in present:
        assert name in result["results"], f"{name} missing from {sorted(result['results'])}"
    for name in absent:
        assert name not in result["results"], f"{name} reported for a deleted section"


# ----------------------------------------------------------------------------- formats

def test_format_json_writes_only_json(tmp_path, capsys):
    code, out, err = run(capsys, "run", LAB1, "--out", tmp_path, "--format", "json")
    assert code == 0, err
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written == ["flywheel.json"], f"--format json wrote {written}"
    assert json.loads((tmp_path / "flywheel.json").read_text(encoding="utf-8"))["lab"] == "lab1"
    assert "flywheel.json" in out, f"the summary should list the written file:\n{out}"
    umask = os.umask(0o022)
    os.umask(umask)
    mode = (tmp_path / "flywheel.json").stat().st_mode & 0o777
    assert mode == 0o666 & ~umask, \
        f"report mode {mode:o}: should be an ordinary file ({0o666 & ~umask:o} under umask {umask:o})"


def test_json_flag_prints_only_the_result_json(tmp_path, capsys):
    code, out, err = run(capsys, "run", LAB2, "--out", tmp_path, "--format", "json", "--json")
    assert code == 0, err
    try:
        doc = json.loads(out)
    except json.JSONDecodeError as exc:
        pytest.fail(f"--json stdout is not one JSON document ({exc}):\n{out[:500]}")
    assert doc["lab"] == "lab2" and "m_shp_weighing" in doc["results"], sorted(doc)
    on_disk = json.loads((tmp_path / "conrod.json").read_text(encoding="utf-8"))
    assert doc == on_disk, "--json output and the .json report differ"


def test_json_flag_with_several_files_prints_one_array(tmp_path, capsys):
    code, out, err = run(capsys, "run", LAB1, LAB2, "--out", tmp_path, "--format", "json",
                         "--json")
    assert code == 0, err
    docs = json.loads(out)
    assert [d["lab"] for d in docs] == ["lab1", "lab2"]


def test_json_inputs_are_si(tmp_path, capsys):
    run(capsys, "run", LAB2, "--out", tmp_path, "--format", "json")
    inputs = json.loads((tmp_path / "conrod.json").read_text(encoding="utf-8"))["inputs"]
    # the file says l_sh = "160.1 mm" and t_C in seconds; the contract is SI
    assert inputs["rod.l_sh"]["value"] == pytest.approx(0.1601) and inputs["rod.l_sh"]["unit"] == "m"
    assert inputs["rod.m_sh"]["unit"] == "kg"
    assert len(inputs["swinging.t_C"]["readings"]) == 3


def test_files_with_the_same_name_do_not_overwrite_each_other(tmp_path, capsys):
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "rod.toml").write_text(LAB2.read_text(encoding="utf-8"),
                                                    encoding="utf-8")
    out = tmp_path / "out"
    code, _, err = run(capsys, "run", tmp_path / "a" / "rod.toml", tmp_path / "b" / "rod.toml",
                       "--out", out, "--format", "json")
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == ["a-rod.json", "b-rod.json"]


def test_negative_moment_about_the_centre_of_mass_is_an_input_error(tmp_path, capsys):
    data = sample("lab1")
    data["pendulum"]["c"] = 500.0   # pivot far beyond the radius of gyration: J_c < 0
    path = tmp_path / "bad_c.toml"
    path.write_text(dumps(data), encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, "pendulum.c", "≤ 0", tmp_path / "out")


def test_list_names_both_labs(capsys):
    code, out, err = run(capsys, "list")
    assert code == 0, err
    ids = [line.split()[0] for line in out.strip().splitlines()]
    assert ids[:2] == ["lab1", "lab2"], f"dynlab list printed:\n{out}"
    assert "Moments of inertia" in out and "Приведение масс шатуна" in out, out


# ------------------------------------------------------------------ the installed console script

def test_installed_console_script_reports_bad_input(tmp_path):
    script = Path(sys.executable).with_name("dynlab")
    if not script.exists():
        pytest.skip(f"no dynlab console script next to {sys.executable}")
    bad = tmp_path / "typo.toml"
    bad.write_text(LAB2.read_text(encoding="utf-8").replace("[swinging]", "[swinging]\nn_osk = 3"),
                   encoding="utf-8")
    proc = subprocess.run([str(script), "run", str(bad), "--out", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    assert "Traceback" not in proc.stderr, proc.stderr
    assert "field 'swinging.n_osk'" in proc.stderr and "did you mean 'n_osc'?" in proc.stderr, \
        proc.stderr
    assert not (tmp_path / "out").exists(), "reports were written for a bad file"


def test_demo_finds_the_sample_data_from_any_folder(tmp_path, monkeypatch):
    # installed from a wheel, the copy shipped in labs/sample_data; from the source tree, its own
    from labs.samples import sample_dir

    monkeypatch.chdir(tmp_path)
    found = sample_dir(None)
    source = Path(__file__).resolve().parents[1] / "sample_data"
    assert sorted(p.relative_to(found) for p in found.rglob("*") if p.is_file()) == \
        sorted(p.relative_to(source) for p in source.rglob("*") if p.is_file())


def test_version(capsys):
    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0 and re.fullmatch(r"dynlab \d+\.\d+\.\d+\S*\n", capsys.readouterr().out)


@pytest.mark.parametrize("argv", [["list"], ["--help"], ["run", "--help"]])
def test_list_and_help_import_no_lab_and_no_numerics(argv):
    """``dynlab list`` and ``--help`` answer at once: no lab, numpy or report engine is loaded
    (importing them is what took a second before)."""
    code = "\n".join([
        "import sys", "from labs.cli.main import main", "try:", f"    main({argv!r})",
        "except SystemExit:", "    pass",
        "heavy = ('numpy', 'pandas', 'matplotlib', 'pint', 'labs.lab1_inertia')",
        "print('loaded:', [m for m in heavy if m in sys.modules])"])
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip().endswith("loaded: []"), done.stdout[-300:]


def test_list_names_every_registered_lab_with_its_specs_title(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for lab_id, module in LABS.items():
        assert f"{lab_id:8} {module.SPEC.title['en']}  /  {module.SPEC.title['ru']}" in out


@pytest.mark.parametrize("written, meant", [('"Lab1"', "lab1"), ('"лаб 01"', "lab1"),
                                            ("5", "lab5"), ('"DynCalc"', "dyncalc")])
def test_a_misspelt_lab_is_refused_saying_which_lab_it_means(tmp_path, capsys, written, meant):
    path = tmp_path / "mine.toml"
    path.write_text(f"lab = {written}\n", encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, "lab", "unknown lab", tmp_path / "out")
    assert f'write lab = "{meant}"' in err
