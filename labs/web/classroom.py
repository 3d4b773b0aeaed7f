"""A teacher's class on the page: hand-ins under roster ids into the class folder, in the layout
``dynlab check`` reads (``CLASS/<id>/<lab>.toml`` with ``[meta] id`` and the student's
``[reported]`` values, its files beside it), and the class summary ``dynlab check`` writes,
made again in a worker whenever a submission arrives."""
from __future__ import annotations

import os
import re
import shutil
import time
import tomllib
from pathlib import Path

from processing.diagnostics import InputError
from processing.inputs.toml_writer import dumps

from .worker import MEASUREMENT, check_child

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_OUTPUT = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,100}\.(csv|html)$")


def reported(text: str) -> dict[str, str]:
    """The values a student reports, one a line ``name = value unit`` (or ``name: value``),
    as the ``[reported]`` table ``dynlab check`` judges.

    >>> reported("J_trifilar = 0,1978 kg*m^2\\nm_shp: 1.2 kg\\n")
    {'J_trifilar': '0,1978 kg*m^2', 'm_shp': '1.2 kg'}
    """
    out = {}
    for n, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line:
            continue
        name, sep, value = line.partition("=") if "=" in line else line.partition(":")
        name, value = name.strip(), value.strip().strip('"')
        if not sep or not _NAME.match(name) or not value:
            raise InputError(f"line {n} of the reported values, '{line[:60]}', is not "
                             f"'name = value unit'", "write one value a line, named as in the "
                             "report, e.g. J_trifilar = 0.1978 kg*m^2", field="reported",
                             ru=(f"строка {n} сообщённых значений, '{line[:60]}', — не "
                                 f"'имя = значение единица'", "запишите по одному значению в "
                                 "строке с именем, как в отчёте, например J_trifilar = "
                                 "0,1978 kg*m^2"))
        out[name] = value
    return out


class Classroom:
    """The class folder, its roster, its answer keys (optional) and the summary's folder."""

    def __init__(self, folder: str | Path, roster: str | Path, keys: str | Path | None = None,
                 out: str | Path | None = None):
        from labs.teachers.variants import read_roster

        self.roster_file = Path(roster)
        self.roster = read_roster(roster)
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.keys = None if keys is None else Path(keys)
        self.out = Path(out) if out else self.folder.parent / f"{self.folder.name}-check"
        self.version = 0
        self.checked = 0
        self.state = "idle"
        self.dirty = False
        self.log = ""

    def hand_in(self, run_folder: Path, lab: str, sid: str, reported_text: str,
                files: list[str]) -> Path:
        """Put a reduced submission into ``CLASS/<sid>/<lab>.toml`` with ``[meta] id`` and
        the ``[reported]`` values, its files beside it (a later hand-in replaces it)."""
        values = reported(reported_text)
        doc = tomllib.loads((run_folder / MEASUREMENT).read_text(encoding="utf-8"))
        doc.setdefault("meta", {})["id"] = sid
        if values:
            doc["reported"] = values
        home = self.folder / sid
        home.mkdir(exist_ok=True)
        for name in files:
            shutil.copyfile(run_folder / name, home / name)
        target = home / f"{lab}.toml"
        part = home / f".{lab}.toml.part"
        part.write_text(dumps(doc), encoding="utf-8")
        os.replace(part, target)
        self.version += 1
        return target

    def argv(self, lang: str) -> list[str]:
        """``dynlab check`` of the class, as the teacher would type it."""
        argv = ["check", str(self.folder), "--out", str(self.out), "--lang", lang]
        if self.keys is not None:
            argv += ["--keys", str(self.keys), "--roster", str(self.roster_file)]
        return argv

    async def refresh(self, pool, lang: str) -> None:
        """Check the class again in a worker, with one reduction's time and CPU per hand-in
        (once more if a hand-in came meanwhile)."""
        if self.state == "checking":
            self.dirty = True
            return
        self.state = "checking"
        try:
            while True:
                self.dirty = False
                seen = self.version
                handed_in = sum(1 for _ in self.folder.glob("*/*.toml"))
                outcome = await pool.run(check_child, self.folder, self.out, lang, self.keys,
                                         self.roster_file if self.keys is not None else None,
                                         scale=handed_in)
                self.log = (outcome.error or {}).get("en", "")
                self.checked = seen
                if not self.dirty:
                    break
        finally:
            self.state = "idle"

    def handins(self) -> list[dict]:
        """Who handed in what, and when, by the roster."""
        rows = []
        for sid, name in self.roster:
            home = self.folder / sid
            labs = sorted(home.glob("*.toml")) if home.is_dir() else []
            rows.append({"id": sid, "name": name, "labs": [p.stem for p in labs],
                         "time": time.strftime("%H:%M", time.localtime(
                             max(p.stat().st_mtime for p in labs))) if labs else ""})
        return rows

    def outputs(self) -> list[str]:
        """The summary's files ``dynlab check`` wrote (summary, grades), by name."""
        if not self.out.is_dir():
            return []
        return sorted(p.name for p in self.out.iterdir()
                      if p.is_file() and _OUTPUT.match(p.name))

    def output(self, name: str) -> Path | None:
        return self.out / name if name in self.outputs() else None

    def status(self) -> dict:
        return {"version": self.version, "checked": self.checked, "state": self.state,
                "handins": self.handins(), "files": self.outputs()}

    def command(self) -> str:
        """The command line the summary is made with (shown on the class page)."""
        return " ".join(["dynlab", *self.argv("en")[:-2]])

