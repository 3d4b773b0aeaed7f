"""A corpus of bad and hostile inputs, generated here, over every lab, every reader and the CLI.

Each bad case runs ``dynlab run`` in-process and must keep the contract of
:func:`cli_contract.assert_one_clear_error`: exit 2, no traceback, no internal error, one
message naming the file and the field with a fix, nothing written. Hostile but valid inputs
(markup in names, huge notes, long reading lists, a byte-order mark) must be reported, escaped,
with their warning. A case that runs for a minute is a hang: an alarm fails it (no case comes
near; the corpus takes seconds).
"""
import os
import re
import struct
import tomllib
from pathlib import Path

import cv2
import h5py
import numpy as np
import pytest

from cli_contract import ROOT, assert_one_clear_error, run
from labs.registry import LABS
from processing.inputs.signals import write_hdf5, write_wav
from processing.inputs.toml_writer import dumps

SAMPLES = {
    "lab1": ROOT / "sample_data" / "lab1" / "flywheel.toml",
    "lab2": ROOT / "sample_data" / "lab2" / "conrod.toml",
    "lab3": ROOT / "sample_data" / "lab3" / "engine_2regimes.toml",
    "lab4": ROOT / "sample_data" / "lab4" / "lab4_seed4.toml",
    "lab5": ROOT / "sample_data" / "lab5" / "valve_train.toml",
    "lab6": ROOT / "sample_data" / "lab6" / "lab6_seed6.toml",
    "lab7": ROOT / "sample_data" / "lab7" / "lab7_seed7.toml",
    "lab8": ROOT / "sample_data" / "lab8" / "d120.toml",
    "lab8-inline4": ROOT / "sample_data" / "lab8" / "inline4.toml",
    "lab9": ROOT / "sample_data" / "lab9" / "synthetic_damper.toml",
    "lab9-table": ROOT / "sample_data" / "lab9" / "table1.toml",
    "lab9-photo": ROOT / "sample_data" / "lab9-photo" / "photographed_decay.toml",
    "dyncalc": ROOT / "sample_data" / "dyncalc" / "car_petrol.toml",
    "dyncalc-diesel": ROOT / "sample_data" / "dyncalc" / "marine_diesel.toml",
}
pytestmark = pytest.mark.usefixtures("no_hang")


def parsed(sample: str) -> dict:
    return tomllib.loads(SAMPLES[sample].read_text(encoding="utf-8"))


def run_bad(tmp_path, capsys, data_or_text, field, problem, *args, name="student.toml",
            blamed=None):
    """Write the file, run it, and hold the bad-input contract (the message names the file
    ``blamed``, by default the measurement file)."""
    path = tmp_path / name
    if isinstance(data_or_text, dict):
        path.write_text(dumps(data_or_text), encoding="utf-8")
    elif isinstance(data_or_text, bytes):
        path.write_bytes(data_or_text)
    else:
        path.write_text(data_or_text, encoding="utf-8")
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir, *args)
    assert_one_clear_error(code, out, err, blamed or path, field, problem, out_dir)


# --------------------------------------------------------------------- every quantity, mutated

def _fields(sample: str):
    """(section, index or None, key, Field) of every quantity the sample gives."""
    data = parsed(sample)
    spec = LABS[data["lab"]].SPEC
    for sec in spec.sections:
        raw = data.get(sec.name)
        entry, index = (raw[0], 0) if isinstance(raw, list) else (raw, None)
        if not isinstance(entry, dict):
            continue
        for f in sec.fields:
            if f.name in entry and f.kind == "quantity":
                yield sec.name, index, f.name, f


def _other_unit(f) -> str:
    """A unit of another dimension than the field's."""
    return "5 s" if "s" not in f.unit or f.unit in ("mm", "m/s^2") else "5 kg"


MUTATIONS = [
    ("nan", lambda f: float("nan"), r"not a finite number"),
    ("negative", lambda f: -1.0, r"must be (> 0|≥ 0)"),
    ("huge", lambda f: 1e300, r"far outside what a lab bench measures|not a finite number"),
    ("tiny", lambda f: f"1e-300 {f.unit}", r"far outside what a lab bench measures"),
    ("wrong-dimension", _other_unit, r"is (a|an) .*, but .* is expected"),
    ("prose", lambda f: "about ten", r"cannot read 'about ten'"),
    ("boolean", lambda f: True, r"must be a number or a string with a unit"),
    ("empty", lambda f: "", r"is empty"),
    ("negative-limit", lambda f: f"1 ± -1 {f.unit}", r"limit .* is negative"),
    ("unknown-unit", lambda f: "5 furlongz", r"cannot read '5 furlongz'"),
    ("too-many-readings", lambda f: [1.0] * 1001, r"1001 readings; at most 1000"),
]


def _quantity_cases():
    cases = []
    for sample in SAMPLES:
        for i, (section, index, key, f) in enumerate(_fields(sample)):
            for j in range(4):  # four mutations a field, rotating: each lab meets each kind
                name, value, problem = MUTATIONS[(i + 3 * j) % len(MUTATIONS)]
                where = f"{section}[{index}].{key}" if index is not None else f"{section}.{key}"
                cases.append(pytest.param(sample, section, index, key, value(f), where, problem,
                                          id=f"{sample}-{where}-{name}"))
    return cases


@pytest.mark.parametrize("sample, section, index, key, value, field, problem", _quantity_cases())
def test_bad_quantity(tmp_path, capsys, sample, section, index, key, value, field, problem):
    data = parsed(sample)
    entry = data[section][index] if index is not None else data[section]
    entry[key] = value
    run_bad(tmp_path, capsys, data, field, problem)


# --------------------------------------------------------------------- the file's structure

def _structure_cases():
    cases = []
    for sample in SAMPLES:
        data = parsed(sample)
        spec = LABS[data["lab"]].SPEC
        for sec in spec.sections:
            raw = data.get(sec.name)
            if raw is None:
                continue
            entry = raw[0] if isinstance(raw, list) else raw
            where = f"{sec.name}[0]" if isinstance(raw, list) else sec.name
            first = next(iter(entry))
            cases.append(pytest.param(sample, ("typo", sec.name, first), f"{where}.{first}x",
                                      rf"unknown key '{first}x'.*did you mean '{first}'",
                                      id=f"{sample}-{sec.name}-misspelt-key"))
            if sec.required:
                cases.append(pytest.param(sample, ("drop-section", sec.name), sec.name,
                                          rf"\[{sec.name}\] is missing",
                                          id=f"{sample}-{sec.name}-section-missing"))
                cases.append(pytest.param(sample, ("scalar-section", sec.name), sec.name,
                                          r"must be (a table|one or more tables)",
                                          id=f"{sample}-{sec.name}-not-a-table"))
            for f in sec.fields:
                if f.required and f.default is None and f.name in entry:
                    cases.append(pytest.param(sample, ("drop-field", sec.name, f.name),
                                              f"{where}.{f.name}", rf"'{f.name}'.*is missing",
                                              id=f"{sample}-{where}.{f.name}-missing"))
                    break
        cases.append(pytest.param(sample, ("unknown-section",), "extra",
                                  r"unknown section or key 'extra'",
                                  id=f"{sample}-unknown-section"))
        cases.append(pytest.param(sample, ("meta-typo",), "meta.studnet",
                                  r"did you mean 'student'", id=f"{sample}-meta-typo"))
    return cases


def _edit(data: dict, how: tuple) -> None:
    kind, *args = how
    if kind == "typo":
        section, key = args
        entry = data[section][0] if isinstance(data[section], list) else data[section]
        entry[key + "x"] = entry.pop(key)
    elif kind == "drop-section":
        del data[args[0]]
    elif kind == "scalar-section":
        data[args[0]] = 5
    elif kind == "drop-field":
        section, key = args
        entry = data[section][0] if isinstance(data[section], list) else data[section]
        del entry[key]
    elif kind == "unknown-section":
        data["extra"] = {"x": 1}
    elif kind == "meta-typo":
        data.setdefault("meta", {})["studnet"] = "I. Petrov"


@pytest.mark.parametrize("sample, how, field, problem", _structure_cases())
def test_bad_structure(tmp_path, capsys, sample, how, field, problem):
    data = parsed(sample)
    _edit(data, how)
    run_bad(tmp_path, capsys, data, field, problem)


@pytest.mark.parametrize("content, field, problem", [
    pytest.param(b"\xef\xbb\xbflab = 'lab1'\n[body\n", None, r"not a valid TOML", id="bom-broken"),
    pytest.param("lab = 'lab1'\n" + "# " + "x" * (1 << 20) + "\n", None, r"MiB; a measurement file",
                 id="over-a-mebibyte"),
    pytest.param("lab = 7\n", "lab", r"unknown lab '7'", id="lab-not-text"),
    pytest.param("lab = 'lab1'\nmeta = 3\n", "meta", r"\[meta\] must be a table", id="meta-scalar"),
    pytest.param("lab = 'lab1'\n[meta]\nstudent = 'A'\n", "body", r"\[body\] is missing",
                 id="only-meta"),
    pytest.param("lab = 'lab2'\nlab = 'lab1'\n", None, r"not a valid TOML", id="duplicate-key"),
    pytest.param(b"lab = \"lab1\"\n\xff\xfe", None, r"not a text file", id="invalid-utf8"),
])
def test_bad_file(tmp_path, capsys, content, field, problem):
    run_bad(tmp_path, capsys, content, field, problem)


# ------------------------------------------------------------------ physics refused, not reported

PHYSICS = [
    ("lab1", lambda d: d["analytic"].append({"shape": "cylinder", "R": 400.0, "r": 0.0,
                                             "h": 100.0, "rho": "7200 kg/m^3", "hole": True}),
     "analytic[3]", r"holes remove more than the solid parts hold"),
    ("lab1", lambda d: d["trifilar"].update(amplitude="400 deg"), "trifilar.amplitude",
     r"above 90 deg"),
    ("lab1", lambda d: d["pendulum"].update(amplitude="180 deg"), "pendulum.amplitude",
     r"above 90 deg"),
    ("lab1", lambda d: d["pendulum"].update(c=500.0), "pendulum.c", r"≤ 0"),
    ("lab2", lambda d: d["swinging"].update(amplitude="95 deg"), "swinging.amplitude",
     r"above 90 deg"),
    ("lab2", lambda d: d["weighing"].update(R_A="2 kg"), "weighing.R_A", r"not smaller"),
    ("lab3", lambda d: d["wheel"].update(missing=60), "wheel.missing", r"not usable"),
    ("lab3", lambda d: d["wheel"].update(z=2), "wheel.z", r"cannot time a revolution"),
    ("lab3", lambda d: d.update(analysis={"orders": 100000}), "analysis.orders",
     r"cannot be resolved"),
    ("lab3", lambda d: d["engine"].update(strokes=3), "engine.strokes", r"strokes = 3"),
]


@pytest.mark.parametrize("sample, edit, field, problem",
                         [pytest.param(*c, id=f"{c[0]}-{c[2]}") for c in PHYSICS])
def test_physically_impossible(tmp_path, capsys, sample, edit, field, problem):
    data = parsed(sample)
    edit(data)
    run_bad(tmp_path, capsys, data, field, problem)


# --------------------------------------------------------------------------- recordings

def _recordings(folder: Path) -> dict[str, Path]:
    """Broken recordings of every reader, made here."""
    x = (np.sin(np.arange(4800) / 3) * 10000).astype(np.int16)
    write_wav(folder / "ok.wav", x, 48000)
    good = (folder / "ok.wav").read_bytes()
    files = {
        "cut-header.wav": good[:30], "riff-only.wav": b"RIFF", "empty.wav": b"",
        "cut-data.wav": good[:len(good) // 2],
        "no-channels.wav": good[:22] + struct.pack("<H", 0) + good[24:],
        "random.wav": os.urandom(3000), "random.csv": bytes(range(256)) * 20,
        "random.h5": os.urandom(3000), "png.csv": b"\x89PNG\r\n\x1a\n" + os.urandom(500),
        "decimal-commas.csv": ("t,u\n" + "".join(f"0,{i:03d},0,{i % 7}\n" for i in range(50)))
        .encode(), "prose.csv": b"my recording is attached below\nthanks\n",
        "ragged.csv": b"t,u\n0,1\n0.001,2,3\n0.002\n", "one-row.csv": b"t,u\n0,1\n",
        "nan-cell.csv": ("t,u\n" + "".join(f"{i / 1e4},{'' if i == 7 else 1}\n"
                                          for i in range(20))).encode(),
        "text-cell.csv": ("t,u\n" + "".join(f"{i / 1e4},{'x' if i == 7 else 1}\n"
                                           for i in range(20))).encode(),
        "header-only.csv": b"t,u\n", "comments.csv": b"# nothing\n# here\n",
        "time-backwards.csv": b"t,u\n0.002,1\n0.001,2\n0,3\n",
        "flat.csv": ("t,u\n" + "".join(f"{i / 1e4},0\n" for i in range(2000))).encode(),
        "unknown.xyz": b"1,2,3\n",
    }
    for name, blob in files.items():
        (folder / name).write_bytes(blob)
    with h5py.File(folder / "corrupt.h5", "w") as f:
        d = f.create_dataset("tooth", data=np.sin(np.arange(100000) / 10), chunks=(10000,),
                             compression="gzip")
        d.attrs["sample_rate"] = 1e5
        offset = d.id.get_chunk_info(2).byte_offset
    blob = bytearray((folder / "corrupt.h5").read_bytes())
    blob[offset + 10:offset + 200] = bytes(190)
    (folder / "corrupt.h5").write_bytes(bytes(blob))
    write_hdf5(folder / "two.h5", {"a": np.ones(10), "b": np.ones(10)}, 1e3)
    write_hdf5(folder / "no-rate.h5", {"tooth": np.ones(10)}, 1e3)
    with h5py.File(folder / "no-rate.h5", "a") as f:
        for holder in (f, f["tooth"]):
            holder.attrs.pop("sample_rate", None)
    return {p.name: p for p in folder.iterdir()}


RECORDINGS = [
    ("cut-header.wav", r"header is cut short"), ("riff-only.wav", r"header is cut short"),
    ("empty.wav", r"empty \(0 bytes\)"), ("cut-data.wav", r"cut short"),
    ("no-channels.wav", r"no channels"), ("random.wav", r"not a readable WAV"),
    ("random.csv", r"binary data"), ("random.h5", r"not a readable HDF5"),
    ("png.csv", r"binary data"), ("decimal-commas.csv", r"decimal commas"),
    ("prose.csv", r"holds no number"), ("ragged.csv", r"regular table"),
    ("one-row.csv", r"one row"), ("nan-cell.csv", r"is empty"), ("text-cell.csv", r"not a number"),
    ("header-only.csv", r"only a header"), ("comments.csv", r"only blank or comment"),
    ("time-backwards.csv", r"time|ris"), ("flat.csv", r"no tooth pulses"),
    ("unknown.xyz", r"\.xyz"), ("corrupt.h5", r"damaged or cut short"),
    ("two.h5", r"dataset|channel"), ("no-rate.h5", r"sample rate"),
    ("missing.wav", r"not found|no such|does not exist"),
]


def _lab3(regime: dict, **wheel) -> dict:
    data = parsed("lab3")
    data["regime"] = [{"n_tach": 1800, **regime}]
    data["wheel"] = {"z": 60, "missing": 2, **wheel}
    return data


@pytest.mark.parametrize("name, problem", [pytest.param(*r, id=r[0]) for r in RECORDINGS])
def test_bad_recording(tmp_path, capsys, name, problem):
    _recordings(tmp_path)
    run_bad(tmp_path, capsys, _lab3({"signal": name}), "regime[0].signal", problem,
            blamed=tmp_path / name)


READER_FAULTS = [r for r in RECORDINGS if r[0] not in ("flat.csv", "two.h5")]
"""The faults any lab's reader finds, whatever the recording is of."""


def _with_record(sample: str, where: str, name: str) -> dict:
    """The sample with its first record (``section[0].key`` or ``section.key``) replaced, and
    what the sample says of its channels and rate dropped (the file's own are read)."""
    data = parsed(sample)
    section, key = where.split(".")
    holder = data[section.removesuffix("[0]")]
    holder = holder[0] if section.endswith("[0]") else holder
    for told in ("sample_rate", "channel", "marks_channel"):
        holder.pop(told, None)
    holder[key] = name
    return data


@pytest.mark.parametrize("sample, where", [("lab7", "record[0].signal"),
                                           ("lab9", "decay.signal")])
@pytest.mark.parametrize("name, problem", [pytest.param(*r, id=r[0]) for r in READER_FAULTS])
def test_bad_recording_of_other_labs(tmp_path, capsys, sample, where, name, problem):
    _recordings(tmp_path)
    if (sample, name) == ("lab7", "corrupt.h5"):  # lab 7 looks for its TDC channel first
        problem = r"no dataset 'tdc'"
    run_bad(tmp_path, capsys, _with_record(sample, where, name), where, problem,
            blamed=tmp_path / name)


IMAGES = [
    ("text.jpg", b"a photo of my oscillogram\n", r"not an image"),
    ("random.png", os.urandom(3000), r"not an image"),
    ("blank.png", cv2.imencode(".png", np.full((600, 1500, 3), 230, np.uint8))[1].tobytes(),
     r"no (time base|trace)|sheet|mark"),
    ("empty.jpg", b"", r"empty|not an image"),
]


@pytest.mark.parametrize("name, blob, problem", [pytest.param(*r, id=r[0]) for r in IMAGES])
def test_bad_photograph(tmp_path, capsys, name, blob, problem):
    """A photographed record that is no photograph, or shows no record: the image is blamed."""
    (tmp_path / name).write_bytes(blob)
    run_bad(tmp_path, capsys, _with_record("lab9-photo", "decay.signal", name), None, problem,
            blamed=tmp_path / name)


@pytest.mark.parametrize("name, problem", [pytest.param(*r, id=r[0]) for r in RECORDINGS[:8]])
def test_bad_calibration_record(tmp_path, capsys, name, problem):
    _recordings(tmp_path)
    run_bad(tmp_path, capsys, _lab3({"signal": "flat.csv"}, calibration=name),
            "wheel.calibration", problem, blamed=tmp_path / name)


@pytest.mark.parametrize("name, problem", [
    ("random.csv", r"binary data"), ("prose.csv", r"holds no number"),
    ("time-backwards.csv", r"ris|increas|order"), ("missing.csv", r"not found"),
    ("empty.wav", r"empty|\.csv"),
])
def test_bad_counter_edges(tmp_path, capsys, name, problem):
    _recordings(tmp_path)
    run_bad(tmp_path, capsys, _lab3({"edges": name}), "regime[0].edges", problem,
            blamed=tmp_path / name)


@pytest.mark.parametrize("where", ["../elsewhere/r.wav", "/etc/passwd", "sub/../../r.wav"])
def test_confined_run_reads_nothing_outside_the_submission(tmp_path, capsys, where):
    submission = tmp_path / "student1"
    submission.mkdir()
    run_bad(submission, capsys, _lab3({"signal": where}), "regime[0].signal",
            r"outside the submission's folder", "--confine")


# ----------------------------------------------------------------- hostile, but to be reported

def _reported(tmp_path, capsys, data, *args, name="student.toml"):
    path = tmp_path / name
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(dumps(data), encoding="utf-8")
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir, *args)
    assert code == 0, f"exit {code}\n{err}"
    assert "Traceback" not in out + err and "internal error" not in err, err
    html = (out_dir / f"{path.stem}.html").read_text(encoding="utf-8")
    return out, html


def test_markup_in_every_text_is_escaped(tmp_path, capsys):
    data = parsed("lab2")
    evil = "<script>alert('x')</script><img src=x onerror=alert(1)>"
    data["meta"] = {k: evil for k in ("student", "group", "date", "rig", "notes", "teacher")}
    _, html = _reported(tmp_path, capsys, data)
    assert "<script>alert" not in html and "<img src=x" not in html
    assert "&lt;script&gt;" in html


def test_huge_notes_are_cut_with_a_warning(tmp_path, capsys):
    data = parsed("lab2")
    data["meta"]["notes"] = "long notes " * 80000
    out, html = _reported(tmp_path, capsys, data, "--format", "html,pdf")
    assert "text_truncated" in out
    assert len(html) < 200_000, f"the HTML carries the whole text: {len(html)} bytes"


def test_long_reading_lists_are_summarised_in_every_format(tmp_path, capsys):
    data = parsed("lab1")
    data["trifilar"]["t"] = [36.1 + 0.0005 * (i % 9) for i in range(1000)]
    _, html = _reported(tmp_path, capsys, data)
    assert "(n = 1000)" in html


def test_byte_order_mark_is_read(tmp_path, capsys):
    text = SAMPLES["lab2"].read_text(encoding="utf-8")
    _reported(tmp_path, capsys, b"\xef\xbb\xbf" + text.encode("utf-8"), "--format", "html")


def test_implausible_but_possible_value_warns(tmp_path, capsys):
    data = parsed("lab8")
    data["engine"]["m_engine"] = "2e6 kg"
    out, _ = _reported(tmp_path, capsys, data, "--format", "html")
    assert "implausible_value" in out


# ---------------------------------------------------------------------------- the command

CLI = [
    (["run"], 2, r"required: FILE|the following arguments"),
    (["run", "{sample}", "--format", "docx"], 2, r"unknown format 'docx'"),
    (["run", "{sample}", "--format", ","], 2, r"unknown format"),
    (["run", "{sample}", "--lang", "de"], 2, r"invalid choice: 'de'"),
    (["run", "{tmp}/nothing.toml"], 2, r"file not found"),
    (["run", "{tmp}"], 2, r"is a directory"),
    (["run", "{sample}", "--out", "{tmp}/file"], 2, r"cannot write the reports"),
    (["template", "lab99"], 2, r"unknown lab 'lab99'"),
    (["template"], 2, r"the following arguments|required"),
    (["kinematics", "--lambda", "nan"], 2, r"lambda"),
    (["kinematics", "--lambda", "5"], 2, r"lambda"),
    (["kinematics", "--lambda", "0.25", "--step", "0"], 2, r"--step"),
    (["kinematics", "--lambda", "0.25", "--step", "nan"], 2, r"--step"),
    (["kinematics", "--lambda", "0.25", "--offset", "1e300"], 2, r"offset"),
    (["synth", "lab3", "--seed", "-1", "--out", "{tmp}/s"], 2, r"seed"),
    (["synth", "lab3", "--snr", "nan", "--out", "{tmp}/s"], 2, r"snr|SNR"),
    (["synth", "lab3", "--sample-rate", "0", "--out", "{tmp}/s"], 2, r"sample.rate|samples"),
    (["synth", "lab3", "--pitch-error", "-1", "--out", "{tmp}/s"], 2, r"pitch"),
    (["synth", "lab99"], 2, r"invalid choice"),
    (["synth", "lab1", "--part", "0", "--out", "{tmp}/s"], 2, r"takes no part"),
    (["synth", "lab3", "--part", "x", "--out", "{tmp}/s"], 2, r"seed"),
    (["demo", "--data", "{tmp}/nowhere"], 2, r"no sample data"),
    (["frobnicate"], 2, r"invalid choice"),
]


@pytest.mark.parametrize("argv, code, problem", [pytest.param(*c, id=" ".join(c[0]))
                                                 for c in CLI])
def test_command_line_misuse(tmp_path, capsys, argv, code, problem):
    (tmp_path / "file").write_text("not a folder", encoding="utf-8")
    argv = [a.format(sample=SAMPLES["lab2"], tmp=tmp_path) for a in argv]
    try:
        got, out, err = run(capsys, *argv)
    except SystemExit as exc:  # argparse
        got, cap = exc.code, capsys.readouterr()
        out, err = cap.out, cap.err
    assert got == code, f"exit {got}, expected {code}\n{out}\n{err}"
    assert "Traceback" not in out + err and "internal error" not in err, err
    assert re.search(problem, err, flags=re.I), f"stderr does not say {problem!r}:\n{err}"
    assert not (tmp_path / "s").exists() or not any((tmp_path / "s").iterdir()), \
        "synth wrote files although its arguments were bad"


def test_same_stem_in_nested_folders_and_the_same_file_twice(tmp_path, capsys):
    for top in ("a", "b"):
        (tmp_path / top / "x").mkdir(parents=True)
        (tmp_path / top / "x" / "rod.toml").write_text(SAMPLES["lab2"].read_text("utf-8"),
                                                       encoding="utf-8")
    a, b = tmp_path / "a" / "x" / "rod.toml", tmp_path / "b" / "x" / "rod.toml"
    code, _, err = run(capsys, "run", a, b, a, "--out", tmp_path / "out", "--format", "json")
    assert code == 0, err
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["a-x-rod.json",
                                                                    "b-x-rod.json"]
    assert "given more than once" in err


def test_json_alone_prints_and_writes_nothing(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "run", SAMPLES["lab2"], "--json")
    assert code == 0, err
    assert out.lstrip().startswith("{") and not any(tmp_path.iterdir()), list(tmp_path.iterdir())


def test_a_second_run_says_it_replaced_the_reports(tmp_path, capsys):
    args = ("run", SAMPLES["lab2"], "--out", tmp_path, "--format", "json")
    run(capsys, *args)
    code, out, _ = run(capsys, *args)
    assert code == 0 and "conrod.json (replaced)" in out, out


def test_corpus_is_large_enough():
    """The issue's bar: at least 150 bad or hostile inputs across the labs, readers and CLI."""
    count = (len(_quantity_cases()) + len(_structure_cases()) + len(PHYSICS) + 7
             + len(RECORDINGS) + 8 + 5 + 3 + 5 + len(CLI))
    labs = {c.values[0].split("-")[0] for c in _quantity_cases()}
    assert count >= 150 and labs >= {"lab1", "lab2", "lab3", "lab8", "dyncalc"}, (count, labs)

