"""``dynlab check CLASS --keys``: each submission bound to its student and judged against that
student's own variant; a variant handed in by another student named; copies told apart from
honest variants as a teacher tells them; what a student is asked for expected.

Every class is generated: variants written for a roster (``dynlab synth --students``), each
student's values our reduction of the file they hand in, written to four figures.
"""
import csv
from pathlib import Path

import numpy as np
import pytest

from labs.teachers.check import Check, asked, check, copies, read_variants
from labs.teachers.check_report import terminal
from labs.bench.check import copy_of
from labs.cli.main import main
from labs.registry import evaluate
from tests.cli_contract import assert_one_clear_error, run

STUDENTS = ("s01", "s02", "s03", "s04", "s05")


@pytest.fixture(scope="module")
def variants(tmp_path_factory):
    """Lab 5 variants of a class of five: the handouts and the keys."""
    out = tmp_path_factory.mktemp("lab5") / "variants"
    roster = out.parent / "roster.csv"
    roster.write_text("id,name\n" + "".join(f"{s},Student {s}\n" for s in STUDENTS),
                      encoding="utf-8")
    from labs.cli.main import main

    assert main(["synth", "lab5", "--students", str(roster), "--seed", "3",
                 "--out", str(out)]) == 0
    return out


def handout(variants: Path, sid: str) -> Path:
    return variants / "handouts" / sid / f"lab5_{sid}.toml"


def hand_in(folder: Path, sid: str, measurement: Path, values_from: Path | None = None,
            names=None) -> Path:
    """``sid``'s submission: the measurement file ``measurement`` with our reduction of
    ``values_from`` (the same file, unless given) reported to four figures."""
    results = evaluate(values_from or measurement, n_samples=0).results
    names = names or [n for n, r in results.items() if r.key or n == "M_reduced"]
    lines = [f'{n} = "{results[n].value:.4g} {results[n].unit}"' for n in names]
    path = folder / sid / measurement.name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(measurement.read_text("utf-8") + "\n[reported]\n" + "\n".join(lines) + "\n",
                    encoding="utf-8")
    return path


@pytest.mark.parametrize("owner_hands_in", [True, False])
def test_a_variant_handed_in_by_another_student_is_named_and_judged_against_their_own(
        tmp_path, capsys, variants, owner_hands_in):
    for sid in STUDENTS:
        if sid == "s01" and not owner_hands_in:
            continue
        hand_in(tmp_path / "class", sid, handout(variants, "s01" if sid == "s03" else sid))
    out = tmp_path / "summary"
    code, printed, _ = run(capsys, "check", tmp_path / "class", "--keys", variants,
                           "--roster", variants.parent / "roster.csv", "--out", out)
    assert code == 0 and "the readings of s01's variant, not s03's" in printed
    rows = [r for r in csv.DictReader((out / "summary.csv").open(encoding="utf-8"))
            if r["status"] == "checked"]
    s03 = [r for r in rows if r["id"] == "s03"]
    assert {r["readings_of"] for r in s03} == {"s01"}
    assert {r["student"] for r in s03} == {"Student s03"}
    assert "readings_of_variant" in {r["slip"] for r in s03}
    honest = [r for r in rows if r["id"] != "s03"]
    assert {r["verdict"] for r in honest} <= {"right", "over-precise"}
    assert not any(r["readings_of"] or r["values_of"] for r in honest)
    assert bool(s03[0]["copies"]) == owner_hands_in


def test_values_of_another_variant_over_ones_own_readings_are_named(tmp_path, variants):
    keys = read_variants(variants)
    path = hand_in(tmp_path, "s02", handout(variants, "s02"), handout(variants, "s04"))
    c = check(path, variants=keys, sid="s02")
    assert c.readings_of is None and c.values_of == "s04"
    wrong = [v for v in c.verdicts if v.verdict == "wrong"]
    assert wrong and {v.slip.name for v in wrong} == {"values_of_variant"}


def test_a_copy_reporting_the_other_variants_values_names_them_by_its_readings(tmp_path,
                                                                              variants):
    """A copy whose readings are another's variant (edited to hide it or not) with the values
    that variant gives (its key's, not our reduction of the readings handed in): every value
    wrong is named as the readings of that variant."""
    keys = read_variants(variants)
    measurement = handout(variants, "s01")
    lines = [f'{n} = "{keys.keys["s01"][n]:.4g} {r.unit}"'
             for n, r in evaluate(measurement, n_samples=0).results.items() if r.key]
    path = tmp_path / "s03" / measurement.name
    path.parent.mkdir()
    path.write_text(measurement.read_text("utf-8") + "\n[reported]\n" + "\n".join(lines) + "\n",
                    encoding="utf-8")
    c = check(path, variants=keys, sid="s03")
    wrong = [v for v in c.verdicts if v.verdict == "wrong"]
    assert c.readings_of == "s01" and wrong
    assert {v.slip.name if v.slip else None for v in wrong} == {"readings_of_variant"}, wrong
    shown = terminal(c)             # ours is the student's own key, which has no U
    assert "(s03's key)" in shown and " ± 0 " not in shown


def test_a_perfect_student_reporting_what_the_lab_asks_scores_full(tmp_path, variants):
    keys = read_variants(variants)
    path = hand_in(tmp_path, "s02", handout(variants, "s02"))
    c = check(path, variants=keys, sid="s02")
    names = {v.name for v in c.verdicts}
    assert names == set(asked("lab5", evaluate(handout(variants, "s02"), n_samples=0).results))
    assert {"c_total", "c_spring", "f_natural", "M_reduced"} <= names
    assert "c_total_load" not in names and "m_g" not in names
    assert {v.verdict for v in c.verdicts} <= {"right", "over-precise"}
    policy = tmp_path / "policy.toml"
    policy.write_text('[lab5]\nexpected = ["c_total", "f_natural"]\n', encoding="utf-8")
    only = hand_in(tmp_path / "b", "s02", handout(variants, "s02"), names=["c_total"])
    verdicts = {v.name: v.verdict for v in check(only, variants=keys, sid="s02",
                                                   policy=policy).verdicts}
    assert verdicts == {"c_total": "right", "f_natural": "missing"}


def test_a_submission_bound_by_its_meta_id_when_its_folder_is_no_id(tmp_path, capsys,
                                                                     variants):
    hand_in(tmp_path / "class", "Ivanov lab 5", handout(variants, "s02"))
    out = tmp_path / "summary"
    code, _, _ = run(capsys, "check", tmp_path / "class", "--keys", variants, "--out", out)
    rows = list(csv.DictReader((out / "summary.csv").open(encoding="utf-8")))
    assert code == 0 and {r["id"] for r in rows if r["status"] == "checked"} == {"s02"}
    assert {r["status"] for r in rows if r["id"] != "s02"} == {"absent"}
    from labs.teachers.check import read_class
    from labs.teachers.check_report import summary_csv

    with (out / "summary.csv").open(encoding="utf-8", newline="") as written:
        assert summary_csv(read_class(tmp_path / "class", keys=variants)) == written.read()


def test_roster_without_keys_is_refused(tmp_path, capsys, variants):
    hand_in(tmp_path / "class", "s01", handout(variants, "s01"))
    roster = variants.parent / "roster.csv"
    code, out, err = run(capsys, "check", tmp_path / "class", "--roster", roster,
                         "--out", tmp_path / "summary")
    assert_one_clear_error(code, out, err, roster, None, "--roster goes with --keys",
                           tmp_path / "summary")


def _texts(path: Path) -> tuple[str, ...]:
    from labs.teachers.check import _readings
    from processing.measurement import read_toml

    return _readings(read_toml(path))


def test_copies_with_up_to_two_edited_or_added_readings_are_found_with_the_evidence(
        variants):
    honest = [Check(str(handout(variants, s)), "lab5", s, [], _texts(handout(variants, s)))
              for s in STUDENTS]
    assert copies(honest) == []
    rng = np.random.default_rng(5)
    for edits in (0, 1, 2, 2, 2):
        copy = copy_of(honest[1], rng, edits)
        found = copies([*honest, copy])
        assert [(p.a.student, p.b.student) for p in found] == [("s02", "copy")], copy.readings
        assert found[0].differing <= edits and "readings the same in the same order" in \
            found[0].text()
        assert found[0].evidence and set(found[0].evidence) <= set(honest[1].readings)


def test_copies_of_recordings_are_found_by_their_bytes_and_a_file_everyone_has_is_none():
    """Labs 3, 4, 6, 7 keep their readings in recordings: a copy hands in the same files (its
    file's few readings edited); a file handed to the whole class is no evidence."""
    rng = np.random.default_rng(7)
    common = ("calibration.csv", "c0ffee")

    def student(k: int) -> Check:
        texts = tuple(f"{x:.1f}" for x in rng.uniform(1000, 2000, 4))   # the programme
        return Check(f"class/s{k:02}/lab7.toml", "lab7", f"s{k:02}", [], texts,
                     recordings=(common, (f"r{k}.csv", f"{k:064x}")))

    honest = [student(k) for k in range(8)]
    assert copies(honest) == []
    copy = copy_of(honest[3], rng, 2)
    (pair,) = copies([*honest, copy])
    assert {pair.a.student, pair.b.student} == {"s03", "copy"}
    assert pair.recordings == ("r3.csv",) and "r3.csv" in pair.text()
    assert "r3.csv" in pair.text("ru")


def test_a_recording_handed_in_twice_is_a_copy_whatever_the_files_readings(tmp_path):
    """Lab 9's decay recording in two submissions whose tables of readings differ, the
    second saved again as a spreadsheet in Russian writes it (';' between the columns,
    decimal commas, another header): a copy, named by the file; its digest is of the samples
    the check reads, not of the file's bytes."""
    sample = Path(__file__).resolve().parents[1] / "sample_data" / "lab9"
    text = (sample / "synthetic_damper.toml").read_text(encoding="utf-8")
    recording = (sample / "decay.csv").read_text(encoding="utf-8").splitlines()
    resaved = ["t, s;u, V"] + [row.replace(",", ";").replace(".", ",") for row in recording[1:]]
    checked = []
    for who, scale in (("ann", 1.0), ("bob", 1.07)):
        folder = tmp_path / who
        folder.mkdir()
        (folder / "decay.csv").write_text("\n".join(recording if scale == 1.0 else resaved)
                                          + "\n", encoding="utf-8")
        edited = text if scale == 1.0 else "\n".join(
            line if not line.startswith(("phi = ", "M = ")) else line.split("=")[0] + "= [" +
            ", ".join(f"{float(x) * scale:.2f}" for x in line.split("[")[1].rstrip("]")
                      .split(",")) + "]" for line in text.splitlines())
        (folder / "damper.toml").write_text(edited + '\n[reported]\nC_static = "1 N*m/rad"\n',
                                            encoding="utf-8")
        checked.append(check(folder / "damper.toml", confine=True))
    assert checked[0].readings != checked[1].readings
    (pair,) = copies(checked)
    assert pair.recordings == ("decay.csv",) and "decay.csv" in pair.text()


def test_the_class_summary_a_row_per_student_with_marks_units_and_moodle_grades(
        tmp_path, capsys, variants):
    """s01 perfect, s02 one value ×1000, s03 s01's variant, s04 refused, s05 absent: a row
    each, the mark by the policy, values in the lab's display units as written, the slip in
    words, the copy on both rows, Moodle's grade import with an empty cell for no mark."""
    cls = tmp_path / "class"
    hand_in(cls, "s01", handout(variants, "s01"))
    s02 = hand_in(cls, "s02", handout(variants, "s02"))
    head, tail = s02.read_text("utf-8").split("[reported]")
    s02.write_text(head + "[reported]" + tail.replace(' kg/s^2"', ' g/s^2"', 1), encoding="utf-8")
    hand_in(cls, "s03", handout(variants, "s01"))
    (cls / "s04").mkdir()
    (cls / "s04" / "lab5.toml").write_text('lab = "lab5"\n', encoding="utf-8")
    policy = tmp_path / "policy.toml"
    policy.write_text("points = 2\n", encoding="utf-8")
    out = tmp_path / "summary"
    code, printed, _ = run(capsys, "check", cls, "--keys", variants, "--roster",
                           variants.parent / "roster.csv", "--policy", policy, "--out", out)
    assert code == 2 and "kN/mm" in printed and "e+0" not in printed
    rows = list(csv.DictReader((out / "summary.csv").open(encoding="utf-8")))
    by_id = {}
    for r in rows:
        by_id.setdefault(r["id"], []).append(r)
    assert set(by_id) == set(STUDENTS)
    asked_n = len(by_id["s01"])
    assert {(r["mark"], r["out_of"]) for r in by_id["s01"]} == {(str(2 * asked_n),
                                                                 str(2 * asked_n))}
    wrong = [r for r in by_id["s02"] if r["verdict"] == "wrong"]
    assert len(wrong) == 1 and wrong[0]["slip"] == "prefix_div1000" and wrong[0]["slip_text"]
    assert by_id["s02"][0]["mark"] == str(2 * (asked_n - 1))
    c_total = next(r for r in by_id["s01"] if r["name"] == "c_total")
    assert c_total["unit"] == "kN/mm" and 0.5 < float(c_total["value"]) < 10
    assert all("e" not in r["value"].lower() and len(r["value"]) < 12 for r in rows
               if r["value"])
    assert all("e" not in r[c].lower() for r in rows for c in ("reported", "U", "z")), \
        [r["z"] for r in rows]
    assert by_id["s03"][0]["readings_of"] == "s01" and "s01" in by_id["s03"][0]["copies"]
    assert "s03" in by_id["s01"][0]["copies"]
    (refused,) = by_id["s04"]
    (absent,) = by_id["s05"]
    assert refused["status"] == "refused" and "rig" in refused["detail"]
    assert absent["status"] == "absent" and len(refused) == len(absent) == len(c_total)
    grades = list(csv.reader((out / "moodle.csv").open(encoding="utf-8")))
    assert grades[0] == ["ID number", "lab5"]
    assert dict(grades[1:]) == {"s01": str(2 * asked_n), "s02": str(2 * (asked_n - 1)),
                                "s03": "0", "s04": "", "s05": ""}
    page = (out / "summary.html").read_text(encoding="utf-8")
    assert "not handed in" in page and "sortBy" in page and "@media print" in page
    assert wrong[0]["slip_text"] in page.replace("&#x27;", "'")
    assert main(["check", str(cls), "--keys", str(variants), "--roster",
                 str(variants.parent / "roster.csv"), "--out", str(out), "--lang", "ru"]) == 2
    page = (out / "summary.html").read_text(encoding="utf-8")
    assert "не сдано" in page and "кН/мм" in page and "not handed in" not in page


def test_a_class_is_checked_with_one_blas_thread(monkeypatch, tmp_path):
    """check_class holds numpy's BLAS to one thread per process while it checks (and lets it
    go after): a check's fits are small and more threads only spin on a shared machine."""
    from threadpoolctl import threadpool_info

    import labs.teachers.check as ck
    from processing.diagnostics import InputError

    def blas_threads():
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    seen = []

    def counting(path, **options):
        seen.append(blas_threads())
        raise InputError("not checked here", "none")

    monkeypatch.setattr(ck, "check", counting)
    (tmp_path / "a.toml").write_text('lab = "lab1"\n', encoding="utf-8")
    before = blas_threads()
    result = ck.check_class([tmp_path / "a.toml"])
    assert seen == [[1] * len(before)] and list(result.refused) == [str(tmp_path / "a.toml")]
    assert blas_threads() == before


@pytest.mark.parametrize("written, says", [
    ('"1,84 кгм2"', "кгм"), ('"1.84 кН/мм/мм"', "dimension|unit"), ('"abc kN/mm"', "abc"),
    ('{ value = "1.84 kN/mm", u = "-1 kN/mm" }', "standard uncertainty")])
def test_a_value_that_cannot_be_read_is_unreadable_and_the_rest_of_the_class_judged(
        tmp_path, capsys, variants, written, says):
    """In a class, one value a student wrote in a unit we cannot read (кгм: a kilogram-force
    metre, or кг·м² run together?), a unit of another quantity, no number or a negative u
    is *unreadable*, with what to fix, earns nothing, and the submission's other values are
    judged; alone, the same file is refused with that message."""
    s01 = hand_in(tmp_path / "class", "s01", handout(variants, "s01"))
    text = s01.read_text("utf-8")
    assert '\nc_total = "' in text
    s01.write_text("\n".join(f"c_total = {written}" if line.startswith("c_total =") else line
                             for line in text.splitlines()) + "\n", encoding="utf-8")
    out = tmp_path / "summary"
    code, printed, _ = run(capsys, "check", tmp_path / "class", "--keys", variants, "--out", out)
    assert code == 0 and "unreadable" in printed and "Fix:" in printed
    rows = {r["name"]: r for r in csv.DictReader((out / "summary.csv").open(encoding="utf-8"))
            if r["id"] == "s01"}
    assert rows["c_total"]["verdict"] == "unreadable" and rows["c_total"]["slip_text"]
    others = [r["verdict"] for n, r in rows.items() if n != "c_total"]
    assert others and set(others) <= {"right", "rounded"}
    assert rows["c_total"]["mark"] == str(len(rows) - 1) and rows["c_total"]["out_of"] == \
        str(len(rows))
    assert_one_clear_error(*run(capsys, "check", s01), s01,
                           "reported.c_total" + (".u" if "u =" in written else ""), says,
                           tmp_path / "nothing")


def test_a_submission_saved_by_notepad_as_toml_txt_or_in_capitals_is_checked(tmp_path,
                                                                            variants, capsys):
    """Notepad's "Text Documents" saves lab5_s02.toml.txt; another student types LAB5.TOML:
    both handed in, neither shown as absent."""
    cls = tmp_path / "class"
    hand_in(cls, "s01", handout(variants, "s01"))
    txt = hand_in(cls, "s02", handout(variants, "s02"))
    txt.rename(txt.with_name(txt.name + ".txt"))
    upper = hand_in(cls, "s03", handout(variants, "s03"))
    upper.rename(upper.with_name("LAB5.TOML"))
    out = tmp_path / "check"
    main(["check", str(cls), "--keys", str(variants), "--out", str(out)])
    capsys.readouterr()
    rows = list(csv.DictReader((out / "summary.csv").open(encoding="utf-8")))
    status = {r["id"]: r["status"] for r in rows}
    assert status["s01"] == status["s02"] == status["s03"] == "checked", status


def test_dynlab_run_reduces_a_submission_and_points_to_dynlab_check(tmp_path, variants,
                                                                    capsys):
    path = hand_in(tmp_path, "s01", handout(variants, "s01"))
    code = main(["run", str(path), "--out", str(tmp_path / "reports")])
    out = capsys.readouterr().out
    assert code == 0 and f"judged by: dynlab check {path}" in out
