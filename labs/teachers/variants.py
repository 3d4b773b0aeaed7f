"""One variant of a lab per student: a synthetic measurement (its own part, readings and
noise) with its answer key, reproducible from the class's seed and the student's id."""
from __future__ import annotations

import csv
import hashlib
import re
import tomllib
from pathlib import Path


from processing.diagnostics import InputError
from processing.inputs.toml_writer import dumps

from labs.registry import lab_module
from labs.teachers.sheet import all_sheets, reading_sheet


MAX_ID = 64
"""Longest student id [characters]: it names the student's folder (a file system allows
255 bytes, four a character at most)."""

MAX_STUDENTS = 5000
"""Most students of a roster: a class list, not a register of the university."""

_RESERVED = re.compile(r"(con|prn|aux|nul|com\d|lpt\d)(\..*)?", re.I)
"""Names Windows keeps for its devices: no folder may take them."""

_CONTROL = re.compile(r"[\x00-\x1f\x7f]")


FIX_RU = "сохраните список группы как CSV (строка заголовка id,name и по строке на студента)"
"""How to write a roster, in Russian."""


def read_roster(path: str | Path) -> list[tuple[str, str]]:
    """(id, name) of every student of a roster CSV with the columns ``id`` and ``name``
    (``name`` optional), ids unique and usable as folder names.

    The roster is a text file (:data:`processing.files.ROSTER`: UTF-8, or Windows-1251 as
    Russian Excel saves it) with a header row; its cells are separated by commas, semicolons
    (Excel in a comma-decimal region) or tabs.

    Raises
    ------
    InputError
        Not a roster (:mod:`processing.files`: a FIFO, a device, too large, binary data);
        no ``id`` column; more than :data:`MAX_STUDENTS` rows; an id that is empty, longer
        than :data:`MAX_ID`, holds a control character, a path separator or a character
        Windows forbids in names, is ``.``, ``..`` or a Windows device name, or repeats
        another (letter case aside) — naming the roster's row and the fix.
    """
    from processing.files import ROSTER, looks_binary, read_text

    path = Path(path)
    fix = "save the roster as CSV (a header row id,name and a row per student)"
    text = read_text(path, ROSTER, legacy="cp1251", fix=fix, binary=True)
    lines = text.splitlines()
    sep = next((s for s in (";", "\t") if lines and s in lines[0]), ",")
    try:
        reader = csv.reader(lines, delimiter=sep)
        header = [h.strip().lower() for h in next(reader, [])]
        rows = list(reader)
    except csv.Error as exc:
        raise InputError(f"not a CSV table ({exc})", "save the roster as CSV: a header row "
                         "id,name and a row per student", file=str(path),
                         ru=(f"это не таблица CSV ({exc})", FIX_RU)) from None
    if "id" not in header:
        if looks_binary(text):
            raise InputError("not a text file (binary data), so not a roster", fix,
                             file=str(path), ru=("это не текстовый файл (двоичные данные), "
                                                 "а значит, не список группы", FIX_RU))
        raise InputError("the roster has no 'id' column", "write a header row id,name and a "
                         "row per student", file=str(path), field="id",
                         ru=("в списке группы нет столбца 'id'", "напишите строку заголовка "
                             "id,name и по строке на студента"))
    if len(rows) > MAX_STUDENTS:
        raise InputError(f"{len(rows)} rows: a roster holds at most {MAX_STUDENTS} students",
                         "give the roster of one class or group", file=str(path),
                         ru=(f"{len(rows)} строк: в списке группы не больше {MAX_STUDENTS} "
                             "студентов", "укажите список одной группы"))
    at, named = header.index("id"), header.index("name") if "name" in header else None
    students, seen = [], {}
    for line, row in enumerate(rows, start=2):
        if not any(cell.strip() for cell in row):
            continue
        sid = row[at].strip() if at < len(row) else ""
        _check_id(path, line, sid)
        if sid.casefold() in seen:
            raise InputError(f"id {sid!r} is in rows {seen[sid.casefold()]} and {line}"
                             + ("" if sid in (s for s, _ in students) else
                                " (ids that differ only in letter case name one folder on "
                                "Windows and macOS)"),
                             "give every student a different id", file=str(path), field="id",
                             ru=(f"номер {sid!r} стоит в строках {seen[sid.casefold()]} и "
                                 f"{line}" + ("" if sid in (s for s, _ in students) else
                                              " (номера, различающиеся только регистром букв, "
                                              "называют одну папку в Windows и macOS)"),
                                 "дайте каждому студенту свой номер"))
        seen[sid.casefold()] = line
        name = row[named].strip() if named is not None and named < len(row) else ""
        if _CONTROL.search(name):
            raise InputError(f"row {line}: the name holds a control character",
                             "write the student's name as plain text", file=str(path),
                             field="name", ru=(f"строка {line}: в имени управляющий символ",
                                               "запишите имя студента простым текстом"))
        students.append((sid, name or sid))
    if not students:
        raise InputError("the roster names no student", "add a row per student under the "
                         "header id,name", file=str(path), field="id",
                         ru=("в списке группы нет ни одного студента", "добавьте по строке на "
                             "студента под заголовком id,name"))
    return students


def _check_id(path: Path, line: int, sid: str) -> None:
    """Refuse an id that cannot name a folder on every system a class is copied to."""
    def refuse(problem: str, problem_ru: str) -> InputError:
        return InputError(f"row {line}: {problem}", "give each student a plain id (letters, "
                          f"digits, - or _, at most {MAX_ID} characters)", file=str(path),
                          field="id", ru=(f"строка {line}: {problem_ru}", "дайте каждому "
                                          "студенту простой номер (буквы, цифры, - или _, не "
                                          f"больше {MAX_ID} знаков)"))

    if not sid:
        raise refuse("the id is empty", "номер пуст")
    if len(sid) > MAX_ID:
        raise refuse(f"the id is {len(sid)} characters long, more than {MAX_ID}",
                     f"в номере {len(sid)} знаков, больше {MAX_ID}")
    if _CONTROL.search(sid):
        raise refuse(f"the id {sid!r} holds a control character",
                     f"в номере {sid!r} управляющий символ")
    if any(c in sid for c in '/\\:*?"<>|') or sid in (".", ".."):
        raise refuse(f"id {sid!r} cannot name a folder (a path separator or a character "
                     "file systems forbid)", f"номер {sid!r} не может быть именем папки "
                     "(разделитель пути или символ, запрещённый файловыми системами)")
    if _RESERVED.fullmatch(sid) or sid.endswith((".", " ")):
        raise refuse(f"id {sid!r} cannot name a folder on Windows",
                     f"номер {sid!r} не может быть именем папки в Windows")


def student_seed(seed: int, student_id: str) -> int:
    """The variant's seed: the class's seed and the student's id, hashed (stable across
    machines and Python versions)."""
    digest = hashlib.sha256(f"{seed}:{student_id}".encode()).digest()
    return int.from_bytes(digest[:4], "little")


HANDOUTS, KEYS = "handouts", "keys"
"""The two folders ``dynlab synth --students`` writes: what each student gets
(``handouts/<id>/``: the measurement file, its recordings, a printable sheet of its readings)
and what the teacher keeps (``keys/<id>/answer_key.json``)."""


def write_variants(write, out_dir: str | Path, roster: str | Path, seed: int,
                   **options) -> dict[str, dict[str, Path]]:
    """``write(folder, seed, **options)`` (a lab's ``write_synthetic``) once per student of
    the roster: the handout in ``out_dir/handouts/<id>/`` — the measurement file, its
    ``[meta] student`` the student's name and ``id`` the student's id, its recordings, and
    ``readings.html``, a printable sheet of its readings
    (:func:`labs.teachers.sheet.reading_sheet`) — and the answer key in
    ``out_dir/keys/<id>/answer_key.json``; every sheet in one document to print,
    ``out_dir/handouts/readings.html`` (:func:`labs.teachers.sheet.all_sheets`). No handout
    names its key, nor the seed the key could be made again from (the measurement file is
    ``<lab>_<id>.toml``)."""
    students = read_roster(roster)
    written = {}
    for sid, name in students:
        files = write(Path(out_dir) / HANDOUTS / sid, student_seed(seed, sid), **options)
        doc = tomllib.loads(files["toml"].read_text(encoding="utf-8"))
        kept = {k: v for k, v in doc.get("meta", {}).items()
                if k not in ("student", "id", "notes")}
        doc["meta"] = {"student": name, "id": sid, **kept, "notes": f"variant of {sid}"}
        files["toml"].unlink()           # its name holds the seed, from which the key is made
        files["toml"] = files["toml"].parent / f"{doc.get('lab', 'lab')}_{sid}.toml"
        files["toml"].write_text(dumps(doc), encoding="utf-8")
        key = Path(out_dir) / KEYS / sid / "answer_key.json"
        key.parent.mkdir(parents=True, exist_ok=True)
        files["answer"].replace(key)
        files["answer"] = key
        files["sheet"] = files["toml"].parent / "readings.html"
        files["sheet"].write_text(reading_sheet(doc, lab_module(doc["lab"]).SPEC),
                                  encoding="utf-8")
        written[sid] = files
    sheets = Path(out_dir) / HANDOUTS / "readings.html"
    sheets.write_text(all_sheets([f["sheet"].read_text(encoding="utf-8")
                                  for f in written.values()]), encoding="utf-8")
    return written
