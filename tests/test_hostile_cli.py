"""Hostile paths and files at every reader, and the inputs of ``dynlab check`` and
``dynlab synth``: the second hardening's corpus (issue 27), generated here.

Every path a user names is judged before it is read (:mod:`processing.files`): a FIFO, a
link to ``/dev/zero``, a file of gigabytes (sparse: it costs nothing), a folder, a loop of
links, a name too long, a path through a file must each give one clear message naming what
the path is — at the measurement file, at each reader's file (recordings, counter edges, a
photograph, a film), at the roster, the policy and the answer keys. A class check outlives
any one bad submission. ``dynlab check``'s [reported] values and policies and ``dynlab
synth``'s options are refused where they are out of what makes sense, with nothing written.

A case that runs for a minute is a hang: an alarm fails it (the FIFOs would hang for ever
without the check; memory and time limits live in the lead's child-process harness).
"""
import csv
import json
import os
import re
import shutil
import tomllib
from pathlib import Path

import pytest

from cli_contract import ROOT, assert_one_clear_error, run
from processing import files
from processing.diagnostics import InputError
from processing.inputs.toml_writer import dumps

pytestmark = pytest.mark.usefixtures("no_hang")

LAB2 = ROOT / "sample_data" / "lab2" / "conrod.toml"
LAB3 = ROOT / "sample_data" / "lab3" / "engine_2regimes.toml"
LAB9 = ROOT / "sample_data" / "lab9" / "synthetic_damper.toml"
LAB9_PHOTO = ROOT / "sample_data" / "lab9-photo" / "photographed_decay.toml"
LAB1_FILM = ROOT / "sample_data" / "lab1-film" / "flywheel_filmed.toml"


# ------------------------------------------------------------------------- hostile paths

HOSTILE = {
    "fifo": r"named pipe \(FIFO\).*wait for a writer",
    "dev-zero": r"symbolic link to /dev/zero, a character device",
    "huge": r"the file is \d+ GiB; an? .* may be at most",
    "folder": r"is a directory",
    "loop": r"loop of symbolic links",
    "dangling": r"symbolic link to .*which does not exist",
    "through-file": r"on the path is a file, not a folder",
    "long-name": r"is 5\d\d\d bytes long; a file system allows at most 255",
    "long-path": r"the path is \d+ bytes long",
}
"""Every kind of hostile path, and what its message must say."""


def hostile(folder: Path, kind: str, name: str, huge: int = 3 << 30) -> str:
    """Make a path of ``kind`` for the file ``name`` in ``folder``; returns the name to
    write in a measurement file (relative to ``folder``)."""
    stem, suffix = os.path.splitext(name)
    if kind == "fifo":
        os.mkfifo(folder / name)
    elif kind == "dev-zero":
        os.symlink("/dev/zero", folder / name)
    elif kind == "huge":
        with open(folder / name, "wb") as f:
            f.truncate(huge)
    elif kind == "folder":
        (folder / name).mkdir()
    elif kind == "loop":
        os.symlink(f"{stem}.other{suffix}", folder / name)
        os.symlink(name, folder / f"{stem}.other{suffix}")
    elif kind == "dangling":
        os.symlink(f"gone/{name}", folder / name)
    elif kind == "through-file":
        (folder / "notes.txt").write_text("a file, not a folder", encoding="utf-8")
        return f"notes.txt/{name}"
    elif kind == "long-name":
        return "r" * 5000 + suffix
    elif kind == "long-path":
        return "/".join(["d" * 200] * 25) + "/" + name
    return name


@pytest.mark.parametrize("kind", HOSTILE)
def test_hostile_measurement_file(tmp_path, capsys, kind):
    path = tmp_path / hostile(tmp_path, kind, "student.toml", huge=3 << 30)
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir)
    assert_one_clear_error(code, out, err, path, None, HOSTILE[kind], out_dir)


def _with(sample: Path, folder: Path, edit) -> Path:
    """The sample's measurement file in ``folder`` (with its recordings), edited."""
    for other in sample.parent.iterdir():
        if other.suffix != ".toml" and other.is_file():
            shutil.copy(other, folder / other.name)
    data = tomllib.loads(sample.read_text("utf-8"))
    edit(data)
    path = folder / "student.toml"
    path.write_text(dumps(data), encoding="utf-8")
    return path


def _set(where: str, value: str):
    """An edit that sets ``section[0].key`` or ``section.key`` to ``value``."""
    section, key = where.split(".")

    def edit(data):
        holder = data[section.removesuffix("[0]")]
        holder = holder[0] if section.endswith("[0]") else holder
        holder[key] = value
        if key == "edges":
            holder.pop("signal", None)
    return edit


READERS = [
    ("recording-csv", LAB3, "regime[0].signal", "regime.csv", 3 << 30),
    ("recording-wav", LAB3, "regime[0].signal", "regime.wav", 3 << 30),
    ("calibration-wav", LAB3, "wheel.calibration", "coast2.wav", 3 << 30),
    ("counter-edges", LAB3, "regime[0].edges", "edges.csv", 3 << 30),
    ("decay-csv", LAB9, "decay.signal", "decay2.csv", 3 << 30),
    ("photograph", LAB9_PHOTO, "decay.signal", "photo.jpg", 3 << 30),
    ("film", LAB1_FILM, "pendulum.video", "swing.mp4", 17 << 30),
]
"""Each reader of a file a measurement file names: the sample, the field, a file name, and
the size of a file too large for it (a WAV streams: its 3 GiB of zeros is no WAV)."""


def _reader_cases():
    cases = []
    for reader, sample, field, name, huge in READERS:
        for kind, problem in HOSTILE.items():
            if kind == "huge" and name.endswith(".wav"):
                problem = r"not a readable WAV"
            cases.append(pytest.param(sample, field, name, huge, kind, problem,
                                      id=f"{reader}-{kind}"))
    return cases


@pytest.mark.parametrize("sample, field, name, huge, kind, problem", _reader_cases())
def test_hostile_file_at_every_reader(tmp_path, capsys, sample, field, name, huge, kind,
                                      problem):
    """The reader's file is blamed, with the field that named it."""
    written = hostile(tmp_path, kind, name, huge)
    path = _with(sample, tmp_path, _set(field, written))
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir)
    assert_one_clear_error(code, out, err, tmp_path / written, field, problem, out_dir)


def _hostile_hdf5(folder: Path, kind: str) -> str:
    """An HDF5 recording whose samples lie in a FIFO (external or virtual storage), or in one
    chunk of 1 GiB (HDF5 decompresses a chunk whole; left unwritten, it costs nothing)."""
    import h5py

    os.mkfifo(folder / "samples.bin")
    with h5py.File(folder / "rec.h5", "w") as f:
        if kind == "external":
            ds = f.create_dataset("tooth", shape=(1000,), dtype="f8",
                                  external=[("samples.bin", 0, 8000)])
        elif kind == "virtual":
            layout = h5py.VirtualLayout(shape=(1000,), dtype="f8")
            layout[:] = h5py.VirtualSource("samples.bin", "tooth", shape=(1000,))
            ds = f.create_virtual_dataset("tooth", layout)
        else:
            ds = f.create_dataset("tooth", shape=(2**27,), dtype="f8", chunks=(2**27,),
                                  compression="gzip")
        ds.attrs["sample_rate"] = 1e5
    return "rec.h5"


@pytest.mark.parametrize("kind, problem", [
    ("external", r"keeps its samples in other files \(external storage\)"),
    ("virtual", r"keeps its samples in other files \(virtual storage\)"),
    ("huge-chunk", r"chunks of 1024 MiB, each read whole"),
])
def test_hdf5_that_reads_elsewhere_or_decompresses_gigabytes(tmp_path, capsys, kind, problem):
    """A recording whose samples HDF5 would fetch from a FIFO (a hang), or decompress a
    gigabyte at a time (a 1 MB file read for minutes), is refused before a sample is read."""
    name = _hostile_hdf5(tmp_path, kind)
    path = _with(LAB3, tmp_path, _set("regime[0].signal", name))
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir)
    assert_one_clear_error(code, out, err, tmp_path / name, "regime[0].signal", problem,
                           out_dir)


def test_a_symbolic_link_to_a_regular_file_is_read(tmp_path, capsys):
    """A link is followed: its target, a good measurement file, is reduced."""
    os.symlink(LAB2, tmp_path / "mine.toml")
    code, out, err = run(capsys, "run", tmp_path / "mine.toml", "--json")
    assert code == 0 and json.loads(out)["lab"] == "lab2", err


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a file whatever its mode")
def test_unreadable_measurement_file(tmp_path, capsys):
    path = tmp_path / "student.toml"
    shutil.copy(LAB2, path)
    path.chmod(0)
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir)
    assert_one_clear_error(code, out, err, path, None, r"permission denied", out_dir)


def test_permission_denied_is_named(tmp_path, monkeypatch):
    """As the system says it (root cannot be refused a read, so the refusal is simulated)."""
    path = tmp_path / "student.toml"
    shutil.copy(LAB2, path)
    real = os.stat

    def denied(p, *args, **kw):
        if str(p) == str(path):
            raise PermissionError(13, "Permission denied", str(p))
        return real(p, *args, **kw)

    monkeypatch.setattr(files.os, "stat", denied)
    with pytest.raises(InputError, match="permission denied") as exc:
        files.read_bytes(path, files.MEASUREMENT)
    assert exc.value.file == str(path) and "chmod" in exc.value.fix


def test_permission_denied_to_a_streamed_reader_is_named(tmp_path, monkeypatch):
    """A recording a library opens by its name (WAV, HDF5, film) is opened here first."""
    path = tmp_path / "r.wav"
    path.write_bytes(b"RIFF")
    real = os.open

    def denied(p, *args, **kw):
        if str(p) == str(path):
            raise PermissionError(13, "Permission denied", str(p))
        return real(p, *args, **kw)

    monkeypatch.setattr(files.os, "open", denied)
    with pytest.raises(InputError, match="permission denied") as exc:
        files.regular(path, files.STREAMED, field="regime[0].signal")
    assert exc.value.field == "regime[0].signal"


def test_a_file_that_grows_while_it_is_read_is_read_no_further(tmp_path, monkeypatch):
    """Judged small, grown since: at most limit + 1 bytes are read, then it is refused."""
    path = tmp_path / "student.toml"
    path.write_bytes(b"#" * (files.MEASUREMENT.limit + 4096))
    monkeypatch.setattr(files, "_judge", lambda *args: None)   # as if it was judged small
    with pytest.raises(InputError, match="grew while it was read"):
        files.read_bytes(path, files.MEASUREMENT)


# --------------------------------------------------------------------------- a class

def _submission(folder: Path, reported: str = 'l_shp_weighing = "118.06 mm"') -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "mine.toml"
    path.write_text(LAB2.read_text("utf-8") + f"\n[reported]\n{reported}\n", encoding="utf-8")
    return path


BAD_SUBMISSIONS = {
    **{k: v for k, v in HOSTILE.items() if k in ("fifo", "dev-zero", "huge", "folder", "loop")},
    "broken-toml": r"not a valid TOML",
    "no-reported": r"no \[reported\] table",
    "internal-error": r"internal error in .*bad.*: RuntimeError: a failure of the toolkit",
}


def _bad_submission(folder: Path, kind: str) -> Path:
    folder.mkdir(parents=True)
    if kind == "broken-toml":
        (folder / "mine.toml").write_text('lab = "lab2"\n[rod\n', encoding="utf-8")
    elif kind == "no-reported":
        shutil.copy(LAB2, folder / "mine.toml")
    elif kind == "internal-error":
        _submission(folder)
    else:
        hostile(folder, kind, "mine.toml")
    return folder / "mine.toml"


@pytest.mark.parametrize("kind", BAD_SUBMISSIONS)
def test_one_bad_submission_never_stops_a_class(tmp_path, capsys, monkeypatch, kind):
    """The good submissions are checked and summarised, the bad one is listed as refused
    with its reason, and the exit code says something was refused."""
    import labs.teachers.check

    real = labs.teachers.check.read_inputs

    def failing(path, **kw):
        if Path(path).parent.name == "bad":
            raise RuntimeError("a failure of the toolkit")
        return real(path, **kw)

    if kind == "internal-error":
        monkeypatch.setattr(labs.teachers.check, "read_inputs", failing)
    for who in ("ann", "bob"):
        _submission(tmp_path / "class" / who)
    bad = _bad_submission(tmp_path / "class" / "bad", kind)
    out_dir = tmp_path / "summary"
    code, out, err = run(capsys, "check", tmp_path / "class", "--out", out_dir)
    assert code == 2, f"exit {code}\n{err}"
    assert "Traceback" not in out + err
    assert "ann" in out and "bob" in out, out
    rows = list(csv.DictReader((out_dir / "summary.csv").open(encoding="utf-8")))
    verdicts = {Path(r["file"]).parent.name: r for r in rows}
    assert verdicts["ann"]["verdict"] == "right" and verdicts["bob"]["verdict"] == "right"
    assert verdicts["bad"]["verdict"] == "refused", rows
    assert re.search(BAD_SUBMISSIONS[kind], verdicts["bad"]["detail"]), verdicts["bad"]
    assert str(bad) in err and re.search(BAD_SUBMISSIONS[kind], err), err
    assert "bad" in (out_dir / "summary.html").read_text(encoding="utf-8")


def test_several_submissions_named_one_by_one_outlive_a_bad_one(tmp_path, capsys):
    good = _submission(tmp_path / "ann")
    bad = tmp_path / hostile(tmp_path, "fifo", "bob.toml")
    code, out, err = run(capsys, "check", good, bad, "--json")
    assert code == 2 and "named pipe" in err and str(bad) in err, err
    (one,) = json.loads(out)
    assert one["verdicts"][0]["verdict"] == "right"


def test_a_class_summary_that_cannot_be_written_is_refused_first(tmp_path, capsys):
    _submission(tmp_path / "class" / "ann")
    (tmp_path / "summary").write_text("a file", encoding="utf-8")
    out_dir = tmp_path / "summary" / "here"
    code, out, err = run(capsys, "check", tmp_path / "class", "--out", out_dir)
    assert code == 2 and "cannot write the class summary" in err and not out, err


# ------------------------------------------------------------------ [reported] and policies

REPORTED = [
    ('l_shp_weighing = { value = "118 mm", u = "-0.5 mm" }', "reported.l_shp_weighing.u",
     r"not a standard uncertainty"),
    ('l_shp_weighing = { value = "118 mm", uu = "0.5 mm" }', "reported.l_shp_weighing.uu",
     r"unknown key 'uu'.*did you mean 'u'"),
    ('l_shp_weighing = { u = "0.5 mm" }', "reported.l_shp_weighing", r"gives no value"),
    ('l_shp_weighing = "nan mm"', "reported.l_shp_weighing", r"finite|not a number|nan"),
    ('l_shp_weighing = "inf mm"', "reported.l_shp_weighing", r"finite|inf"),
    ('l_shp_weighing = { value = "118 ± 1 mm", u = "0.5 mm" }', "reported.l_shp_weighing.u",
     r"given twice"),
    ('l_shp_weighing = { value = "118 mm", u = 0.5 }', "reported.l_shp_weighing.u",
     r"has no unit"),
    ('l_shp_weighing = { value = "118 mm", u = "0.5 kg" }', "reported.l_shp_weighing.u",
     r"kg|dimension|length|expected"),
    ('l_shp_weighing = { value = "118 mm", u = "nan mm" }', "reported.l_shp_weighing.u",
     r"finite|standard uncertainty|nan"),
    ('l_shp_weighing = { value = "118 mm", u = true }', "reported.l_shp_weighing.u",
     r"not an uncertainty"),
    ('l_shp_weighing = ["118 mm", "119 mm"]', "reported.l_shp_weighing", r"is not a value"),
    ('l_shp_weighting = "118 mm"', "reported.l_shp_weighting",
     r"not a result.*did you mean 'l_shp_weighing'"),
]


@pytest.mark.parametrize("reported, field, problem", [pytest.param(*c, id=c[1] + "-" + str(i))
                                                      for i, c in enumerate(REPORTED)])
def test_bad_reported_values(tmp_path, capsys, reported, field, problem):
    path = _submission(tmp_path, reported)
    code, out, err = run(capsys, "check", path)
    assert_one_clear_error(code, out, err, path, field, problem, tmp_path / "out")


@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "huge", "loop", "through-file"])
def test_hostile_reported_table_of_the_coursework(tmp_path, capsys, kind):
    name = hostile(tmp_path, kind, "forces.csv")
    path = tmp_path / "mine.toml"
    path.write_text((ROOT / "sample_data" / "dyncalc" / "car_petrol.toml").read_text("utf-8")
                    + f'\n[reported]\nM_mean = "10 N*m"\n[reported.tables]\nforces = "{name}"\n',
                    encoding="utf-8")
    code, out, err = run(capsys, "check", path)
    assert_one_clear_error(code, out, err, tmp_path / name, "reported.tables.forces",
                           HOSTILE[kind], tmp_path / "out")


def test_reported_that_is_not_a_table(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    path.write_text('reported = 5\n' + LAB2.read_text("utf-8"), encoding="utf-8")
    code, out, err = run(capsys, "check", path)
    assert_one_clear_error(code, out, err, path, "reported", r"must be a table",
                           tmp_path / "out")


POLICIES = [
    ("rel_tol = -0.01", "rel_tol", r"negative"),
    ("rel_tol = nan", "rel_tol", r"not a number"),
    ("rel_tol = inf", "rel_tol", r"not a number"),
    ("rel_tol = 5", "rel_tol", r"not below 1.*Fix:.*rel_tol = 0.05 for 5 %"),
    ('rel_tol = "1 %"', "rel_tol", r"not a number"),
    ("rel_tol = true", "rel_tol", r"not a number"),
    ("sig_figs = 0", "sig_figs", r"not a whole number from 1"),
    ("sig_figs = 2.5", "sig_figs", r"not a whole number"),
    ("sig_figs = 99", "sig_figs", r"not a whole number from 1 to 15"),
    ('expected = "l_shp_weighing"', "expected", r"not a list of result names"),
    ("expected = [1, 2]", "expected", r"not a list of result names"),
    ('expected = [""]', "expected", r"not a list of result names"),
    ("rel_tool = 0.01", "rel_tool", r"unknown policy key.*did you mean 'rel_tol'"),
    ("[lab10]\nrel_tol = 0.01", "lab10", r"not a lab"),
    ("lab2 = 0.01", "lab2", r"must be a table"),
    ("[lab2]\nsig_fig = 3", "lab2.sig_fig", r"unknown policy key.*did you mean 'sig_figs'"),
    ('expected = ["l_shp_weighting"]', "expected",
     r"'l_shp_weighting' is not a result of lab2.*did you mean 'l_shp_weighing'"),
    ('[lab2]\nexpected = ["m_shpp_weighing"]', "lab2.expected",
     r"'m_shpp_weighing' is not a result of lab2.*did you mean 'm_shp_weighing'"),
    ("rel_tol = [", None, r"not a valid TOML"),
]


@pytest.mark.parametrize("policy, field, problem", [pytest.param(*c, id=c[0][:30])
                                                    for c in POLICIES])
def test_bad_policy(tmp_path, capsys, policy, field, problem):
    """Refused before a class is checked: no summary is written."""
    _submission(tmp_path / "class" / "ann")
    path = tmp_path / "policy.toml"
    path.write_text(policy + "\n", encoding="utf-8")
    out_dir = tmp_path / "summary"
    code, out, err = run(capsys, "check", tmp_path / "class", "--policy", path, "--out",
                         out_dir)
    assert_one_clear_error(code, out, err, path, field, problem, out_dir)


@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "huge", "folder", "loop"])
def test_hostile_policy_file(tmp_path, capsys, kind):
    submission = _submission(tmp_path / "ann")
    path = tmp_path / hostile(tmp_path, kind, "policy.toml")
    code, out, err = run(capsys, "check", submission, "--policy", path)
    assert_one_clear_error(code, out, err, path, None, HOSTILE[kind], tmp_path / "out")


def test_valid_policies_are_taken(tmp_path, capsys):
    """A tolerance of 0 (the z-score alone), a lab's own rules over the top's, expected
    results not reported (missing)."""
    path = _submission(tmp_path / "ann")
    policy = tmp_path / "policy.toml"
    policy.write_text('rel_tol = 0\nsig_figs = 1\n[lab2]\nrel_tol = 0.02\n'
                      'expected = ["l_shp_weighing", "m_shk_swinging", "m_shk_weighing"]\n',
                      encoding="utf-8")
    code, out, err = run(capsys, "check", path, "--policy", policy, "--json")
    assert code == 0, err
    verdicts = {v["name"]: v["verdict"] for v in json.loads(out)["verdicts"]}
    assert verdicts == {"l_shp_weighing": "right", "m_shk_swinging": "missing",
                        "m_shk_weighing": "missing"}


ANSWER_KEYS = [
    ("not-json", "{results", r"not an answer key"),
    ("results-a-list", '{"results": [1, 2]}', r"not a table of result names"),
    ("value-text", '{"results": {"l_shp_weighing": "0.118"}}', r"not a finite number"),
    ("value-nan", '{"results": {"l_shp_weighing": NaN}}', r"not a finite number"),
    ("fifo", None, HOSTILE["fifo"]),
    ("dev-zero", None, HOSTILE["dev-zero"]),
]


@pytest.mark.parametrize("kind, text, problem", [pytest.param(*c, id=c[0])
                                                 for c in ANSWER_KEYS])
def test_bad_answer_key_refuses_its_submission_alone(tmp_path, capsys, kind, text, problem):
    for who in ("st01", "st02"):
        _submission(tmp_path / "class" / who)
        (tmp_path / "keys" / who).mkdir(parents=True)
    (tmp_path / "keys" / "st01" / "answer_key.json").write_text(
        '{"results": {"l_shp_weighing": 0.11806}}', encoding="utf-8")
    if text is None:
        hostile(tmp_path / "keys" / "st02", kind, "answer_key.json")
    else:
        (tmp_path / "keys" / "st02" / "answer_key.json").write_text(text, encoding="utf-8")
    out_dir = tmp_path / "summary"
    code, out, err = run(capsys, "check", tmp_path / "class", "--keys", tmp_path / "keys",
                         "--out", out_dir)
    assert code == 2 and "Traceback" not in err and re.search(problem, err), err
    rows = list(csv.DictReader((out_dir / "summary.csv").open(encoding="utf-8")))
    assert {Path(r["file"]).parent.name: r["verdict"] for r in rows} == \
        {"st01": "right", "st02": "refused"}


# ---------------------------------------------------------------------------- rosters

ROSTERS = [
    ("id,name\n" + "x" * 300 + ",A\n", "id", "row 2: the id is 300 characters long"),
    ("id,name\na\x00b,A\n", "id", r"row 2: the id 'a\\x00b' holds a control character"),
    ("id,name\nst/01,A\n", "id", r"row 2: id 'st/01' cannot name a folder"),
    ("id,name\nst\\01,A\n", "id", r"row 2: id .* cannot name a folder"),
    ("id,name\n..,A\n", "id", r"row 2: id '\.\.' cannot name a folder"),
    ("id,name\ns1,A\ns2,B\ns1,C\n", "id", r"id 's1' is in rows 2 and 4"),
    ("id,name\nSt01,A\nst01,B\n", "id", r"rows 2 and 3 .*letter case"),
    ("id,name\n,A\n", "id", r"row 2: the id is empty"),
    ("id,name\nCON,A\n", "id", r"cannot name a folder on Windows"),
    ("id,name\nst01,Ann\x07\n", "name", r"row 2: the name holds a control character"),
    ("name\nA\n", "id", r"no 'id' column"),
    ("id,name\n", "id", r"names no student"),
    ("id,name\n" + "".join(f"s{i},N\n" for i in range(5001)), None, r"5001 rows"),
    (b"PK\x03\x04" + bytes(range(256)) * 8, None, r"binary data"),
]


@pytest.mark.parametrize("text, field, problem", [pytest.param(*c, id=f"roster-{i}")
                                                  for i, c in enumerate(ROSTERS)])
def test_bad_roster_writes_nothing(tmp_path, capsys, text, field, problem):
    roster = tmp_path / "roster.csv"
    if isinstance(text, bytes):
        roster.write_bytes(text)
    else:
        roster.write_text(text, encoding="utf-8")
    out_dir = tmp_path / "class"
    code, out, err = run(capsys, "synth", "lab2", "--students", roster, "--out", out_dir)
    assert_one_clear_error(code, out, err, roster, field, problem, out_dir)


@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "huge", "folder", "loop", "long-name"])
def test_hostile_roster_file(tmp_path, capsys, kind):
    roster = tmp_path / hostile(tmp_path, kind, "roster.csv")
    out_dir = tmp_path / "class"
    code, out, err = run(capsys, "synth", "lab2", "--students", roster, "--out", out_dir)
    assert_one_clear_error(code, out, err, roster, None, HOSTILE[kind], out_dir)


@pytest.mark.parametrize("encoding, sep", [("cp1251", ";"), ("utf-16", "\t"),
                                           ("utf-8-sig", ",")])
def test_a_spreadsheets_roster_is_read(tmp_path, capsys, encoding, sep):
    """As Russian Excel saves a class list (Windows-1251, semicolons), as a spreadsheet's
    "Unicode text" (UTF-16, tabs), with a byte-order mark; the header's case aside."""
    roster = tmp_path / "roster.csv"
    roster.write_bytes(f"ID{sep}Name\nst01{sep}Анна Иванова\nst02{sep}Борис\n"
                       .encode(encoding))
    code, out, err = run(capsys, "synth", "lab2", "--students", roster, "--out",
                         tmp_path / "class")
    assert code == 0, err
    text = (tmp_path / "class" / "handouts" / "st01" / "lab2_st01.toml").read_text("utf-8")
    assert 'student = "Анна Иванова"' in text


# ---------------------------------------------------------------------------- synth

SYNTH = [
    (["lab5", "--runs", "0"], r"--runs 0 .*lab5"),
    (["lab9", "--runs", "0"], r"--runs 0 .*lab9"),
    (["lab5", "--runs", "1000000"], r"--runs 1000000 .*whole number from 1 to 20"),
    (["lab5", "--friction", "nan"], r"--friction nan"),
    (["lab5", "--friction", "-1"], r"--friction -1"),
    (["lab5", "--friction", "1e9"], r"--friction 1e\+09"),
    (["lab5", "--contact", "-5"], r"--contact -5"),
    (["lab5", "--lash", "inf"], r"--lash inf"),
    (["lab3", "--sample-rate", "0"], r"--sample-rate 0"),
    (["lab3", "--sample-rate", "1e9"], r"--sample-rate 1e\+09"),
    (["lab3", "--sample-rate", "44.1001"], r"whole number of samples per second"),
    (["lab6", "--sample-rate", "0"], r"--sample-rate 0"),
    (["lab7", "--sample-rate", "0"], r"--sample-rate 0"),
    (["lab7", "--sample-rate", "-4"], r"--sample-rate -4"),
    (["lab9", "--sample-rate", "nan"], r"--sample-rate nan"),
    (["lab9", "--periods", "0"], r"--periods 0"),
    (["lab9", "--periods", "nan"], r"--periods nan"),
    (["lab9", "--periods", "1e12"], r"--periods 1e\+12"),
    (["lab9", "--paper", "--periods", "2"], r"--periods 2 .*four maxima.*from 3 to 20"),
    (["lab9", "--amplitude-exponent", "nan"], r"--amplitude-exponent nan"),
    (["lab9", "--amplitude-exponent", "50"], r"--amplitude-exponent 50"),
    (["lab3", "--snr", "inf"], r"--snr inf"),
    (["lab4", "--snr", "nan"], r"--snr nan"),
    (["lab6", "--snr", "-1000"], r"--snr -1000"),
    (["lab7", "--snr", "1e300"], r"--snr 1e\+300"),
    (["lab9", "--snr=-inf"], r"--snr -inf"),
    (["lab3", "--pitch-error", "0.3"], r"--pitch-error 0.3"),
    (["lab6", "--format", "wav"], r"--format wav: lab6 writes its records as csv, h5"),
    (["lab3", "--format", "mp3"], r"--format mp3"),
    (["lab2", "--runs", "2"], r"takes no runs"),
    (["lab2", "--seed", "9" * 30], r"a seed is a whole number from 0"),
]


@pytest.mark.parametrize("argv, problem", [pytest.param(*c, id=" ".join(c[0])[:40])
                                           for c in SYNTH])
def test_synth_options_out_of_the_scene(tmp_path, capsys, argv, problem):
    """Refused with exit 2 before anything is written, naming the option and the range."""
    out_dir = tmp_path / "s"
    try:
        code, out, err = run(capsys, "synth", *argv, "--out", out_dir)
    except SystemExit as exc:  # argparse
        code, err = exc.code, capsys.readouterr().err
    assert code == 2, f"exit {code}\n{err}"
    assert "Traceback" not in err and "internal error" not in err, err
    assert re.search(problem, err), f"stderr does not say {problem!r}:\n{err}"
    assert "Fix:" in err or "usage:" in err, err
    assert not out_dir.exists(), sorted(out_dir.rglob("*"))


@pytest.mark.parametrize("where", ["file", "under-a-file", "long-name"])
def test_synth_out_that_is_no_folder(tmp_path, capsys, where):
    (tmp_path / "taken").write_text("a file", encoding="utf-8")
    out_dir = {"file": tmp_path / "taken", "under-a-file": tmp_path / "taken" / "s",
               "long-name": tmp_path / ("s" * 300)}[where]
    code, out, err = run(capsys, "synth", "lab2", "--out", out_dir)
    assert_one_clear_error(code, out, err, out_dir, None, r"cannot write the synthetic "
                           r"measurement there", tmp_path / "nothing")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken"]


def test_synth_at_the_edges_of_the_scene(tmp_path, capsys):
    """The ends of a range are the scene's: a lab 5 variant at the largest friction and runs
    is written and reduced."""
    out_dir = tmp_path / "s"
    code, _, err = run(capsys, "synth", "lab5", "--friction", "500", "--runs", "20",
                       "--lash", "1000", "--out", out_dir)
    assert code == 0, err
    code, out, err = run(capsys, "run", next(out_dir.glob("*.toml")), "--json")
    assert code == 0 and json.loads(out)["results"], err


# ---------------------------------------------------------------------------- outputs

@pytest.mark.parametrize("kind", ["fifo", "dev-zero", "folder"])
def test_template_never_writes_into_a_special_file(tmp_path, capsys, kind):
    target = tmp_path / hostile(tmp_path, kind, "blank.toml")
    code, out, err = run(capsys, "template", "lab1", "-o", target)
    assert code == 2 and "Traceback" not in err and "Fix:" in err and str(target) in err, err


def test_reports_into_a_path_the_system_cannot_make(tmp_path, capsys):
    out_dir = tmp_path / ("o" * 300)
    code, out, err = run(capsys, "run", LAB2, "--out", out_dir)
    assert_one_clear_error(code, out, err, out_dir, None, r"cannot write the reports",
                           tmp_path / "nothing")


def test_a_reader_that_stops_reading_is_no_internal_error():
    """``dynlab kinematics ... | head -1``: the pipe closes under the output; the command ends
    quietly with 0 (was 'internal error: BrokenPipeError')."""
    import subprocess
    import sys

    read, write = os.pipe()
    os.close(read)
    child = subprocess.run([sys.executable, "-m", "labs.cli.main", "kinematics",
                            "--lambda", "0.25"], stdout=write, stderr=subprocess.PIPE, text=True,
                           timeout=60)
    os.close(write)
    assert child.returncode == 0 and child.stderr == "", child.stderr


def test_a_submission_given_twice_is_checked_once_and_no_copy_of_itself(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text((ROOT / "sample_data/lab2/conrod.toml").read_text("utf-8")
                    + '\n[reported]\nm_shp_weighing = "0.5 kg"\n', encoding="utf-8")
    code, out, err = run(capsys, "check", path, path)
    assert code == 0, err
    assert "given more than once" in err and "same readings" not in out, out + err
