"""Benchmark of the boundary (topic ``boundary`` of ``python -m processing.bench``): a corpus of
bad, odd and hostile inputs, each run as a user runs it — ``dynlab`` in a child process — with
its peak memory and time measured.

Every case writes its input into a folder of its own (from a bundled sample, a synthetic
scene, or bytes made here: nothing is checked in), runs one ``dynlab`` command there, and is
judged by what a user would see (:func:`judge`):

- ``hang``: still running after :data:`HANG_SECONDS`;
- ``traceback`` / ``internal``: Python's words reached the user, or exit code 1;
- ``memory``: the child's peak resident memory above :data:`MEMORY_LIMIT`;
- ``accepted-wrong``: exit 0 where a refusal is due, a result off the truth or missing a
  warning it must carry, or carrying one that is false;
- ``refused-valid``: exit 2 where the input is valid;
- ``misleading``: refused, but the message misses the cause, the file, the field or a fix,
  or something was written;
- ``ok``.

The child's address space is capped at :data:`ADDRESS_CAP` so that a runaway reader fails
there (and is counted as ``memory``) instead of taking the machine. Targets: no case other
than ``ok``, no input over 1 GB, and every refusal within :data:`REFUSAL_SECONDS` (the
interpreter's start and imports included).
"""
from __future__ import annotations

import json
import os
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import numpy as np
import pandas as pd

from processing.bench.harness import Target, environment, write_rows, write_targets

from labs.samples import sample_dir

HANG_SECONDS = 120.0
"""A case still running after this is a hang. [s]"""
MEMORY_LIMIT = 1 << 30
"""No input may take more than this peak resident memory. [bytes]"""
ADDRESS_CAP = 6 << 30
"""The child's address-space limit: a runaway stops here. [bytes]"""
REFUSAL_SECONDS = 5.0
"""A refused input answers within this, start-up included. [s]"""


@dataclass(frozen=True)
class Expect:
    """What a case must give.

    ``code`` 0 (accepted), 2 (refused) or None (either: a reader may read an odd input or
    refuse it, as long as a refusal names ``cause`` and an acceptance is right)."""

    code: int | None
    cause: str = ""
    field: str | None = None
    warns: tuple[str, ...] = ()
    quiet: tuple[str, ...] = ()
    same: tuple[str, ...] = ()
    key: tuple[str, ...] = ()
    written: tuple[str, ...] = ()
    says: str = ""
    """A pattern an accepted run's standard output must hold."""


@dataclass(frozen=True)
class Case:
    """One input: ``build(folder)`` writes it and returns the ``dynlab`` arguments."""

    name: str
    kind: str
    build: Callable[[Path], list[str]]
    expect: Expect
    sample: str | None = None
    """The sample whose unchanged results ``Expect.same`` compares with."""
    limits: bool = field(default=False)
    """A case about hangs or memory: run by the tests in a child too."""


# --------------------------------------------------------------------------- building inputs

def _sample(folder: Path, name: str) -> Path:
    """The sample ``name`` (``lab1/flywheel.toml``) copied with its folder; its new path."""
    src = sample_dir() / name
    for f in src.parent.iterdir():
        if f.is_file() and f.name != "README.md":
            shutil.copy(f, folder / f.name)
    return folder / src.name


def _edit(path: Path, old: str, new: str, count: int = 1) -> Path:
    """Replace ``old`` by ``new`` in the file (``count`` times, 0: all); a builder whose text
    is not there is a bug of the corpus."""
    text = path.read_text(encoding="utf-8")
    if old not in text:
        raise AssertionError(f"{path.name}: {old!r} not found")
    path.write_text(text.replace(old, new, count or -1), encoding="utf-8")
    return path


def _report(path: Path, *extra: str) -> list[str]:
    return ["run", path.name, "--out", "out", "--format", "json", *extra]


def _edited(sample: str, *edits: tuple[str, str]) -> Callable[[Path], list[str]]:
    def build(folder: Path) -> list[str]:
        path = _sample(folder, sample)
        for old, new in edits:
            _edit(path, old, new, 0)
        return _report(path)
    return build


def _csv_column(folder: Path, name: str, column: str, change: Callable[[np.ndarray], np.ndarray]):
    """Rewrite one column of a sample's CSV recording."""
    frame = pd.read_csv(folder / name)
    frame[column] = change(frame[column].to_numpy(dtype=float))
    frame.to_csv(folder / name, index=False, float_format="%.6g")


def _recorded(sample: str, csv: str, column: str, change) -> Callable[[Path], list[str]]:
    def build(folder: Path) -> list[str]:
        path = _sample(folder, sample)
        for name in ([csv] if csv != "*" else sorted(p.name for p in folder.glob("r*.csv"))):
            _csv_column(folder, name, column, change)
        return _report(path)
    return build


def _clip(level: float) -> Callable[[np.ndarray], np.ndarray]:
    """Clip at ``level`` of the way from the record's median to each extreme (an overload)."""
    def change(x):
        mid = np.median(x)
        return np.clip(x, mid - level * (mid - x.min()), mid + level * (x.max() - mid))
    return change


def _noise(x: np.ndarray) -> np.ndarray:
    return np.random.default_rng(7).normal(np.mean(x), np.std(x), x.size)


def _photo(sample: str, image: str, turn: Callable[[np.ndarray], np.ndarray]):
    def build(folder: Path) -> list[str]:
        import cv2

        path = _sample(folder, sample)
        cv2.imwrite(str(folder / image), turn(cv2.imread(str(folder / image))))
        return _report(path)
    return build


def _rotations():
    import cv2

    return {"180": lambda im: cv2.rotate(im, cv2.ROTATE_180),
            "portrait-right": lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE),
            "portrait-left": lambda im: cv2.rotate(im, cv2.ROTATE_90_COUNTERCLOCKWISE),
            "mirrored": lambda im: im[:, ::-1].copy()}


def _png_header(width: int, height: int) -> bytes:
    """A valid PNG of ``width`` × ``height`` grey pixels, all zero: tiny on disk."""
    row = b"\x00" + bytes(width)
    body = zlib.compress(row * height, 9)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(
            ">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0,
                                                               0, 0, 0))
            + chunk(b"IDAT", body) + chunk(b"IEND", b""))


def _jpeg_claiming(width: int, height: int) -> bytes:
    """A 1 kB JPEG whose frame header claims ``width`` × ``height``."""
    import cv2

    small = cv2.imencode(".jpg", np.full((16, 16), 200, np.uint8))[1].tobytes()
    at = small.index(b"\xff\xc0")
    return small[:at + 5] + struct.pack(">HH", height, width) + small[at + 9:]


def _with_image(blob: Callable[[], bytes]):
    def build(folder: Path) -> list[str]:
        path = _sample(folder, "lab9-photo/photographed_decay.toml")
        (folder / "decay.jpg").write_bytes(blob())
        return _report(path)
    return build


def _sparse(folder: Path, name: str, size: int, head: bytes = b"") -> Path:
    path = folder / name
    with open(path, "wb") as f:
        f.write(head)
        f.truncate(size)
    return path


def _fifo_measurement(folder: Path) -> list[str]:
    os.mkfifo(folder / "m.toml")
    return _report(folder / "m.toml")


def _zero_link(folder: Path) -> list[str]:
    os.symlink("/dev/zero", folder / "m.toml")
    return _report(folder / "m.toml")


def _class_with(bad: Callable[[Path], None]):
    """A class of two good submissions and a bad one."""
    def build(folder: Path) -> list[str]:
        for sid in ("s01", "s02"):
            (folder / "class" / sid).mkdir(parents=True)
            path = _sample(folder / "class" / sid, "lab2/conrod.toml")
            text = path.read_text(encoding="utf-8")
            path.write_text(text + '\n[reported]\nm_shp = "0.5 kg"\n', encoding="utf-8")
        (folder / "class" / "s03").mkdir()
        bad(folder / "class" / "s03")
        return ["check", "class", "--out", "summary"]
    return build


def _roster(rows: str | None, *, fifo: bool = False):
    def build(folder: Path) -> list[str]:
        if fifo:
            os.mkfifo(folder / "roster.csv")
        else:
            (folder / "roster.csv").write_text(rows, encoding="utf-8")
        return ["synth", "lab5", "--students", "roster.csv", "--out", "variants"]
    return build


def _signal_named(length: int):
    def build(folder: Path) -> list[str]:
        path = _sample(folder, "lab9/synthetic_damper.toml")
        _edit(path, 'signal = "decay.csv"', f'signal = "{"d" * length}.csv"')
        return _report(path)
    return build


def _lab4_without_marks(folder: Path) -> list[str]:
    import h5py

    path = _sample(folder, "lab4/lab4_seed4.toml")
    for h5 in folder.glob("r*.h5"):
        with h5py.File(h5, "a") as f:
            del f["tdc"]
    text = re.sub(r'(?m)^tdc_channel = .*\n', "", path.read_text(encoding="utf-8"))
    path.write_text(text, encoding="utf-8")
    return _report(path)


def _lab7_chain_alone(folder: Path) -> list[str]:
    path = _sample(folder, "lab7/lab7_seed7.toml")
    text = path.read_text(encoding="utf-8")
    path.write_text(text[:text.index("[[record]]")], encoding="utf-8")
    return _report(path)


def _lab9_left_running(folder: Path) -> list[str]:
    """A decay that dies within ten periods, recorded for a hundred at 200 kHz."""
    from labs.lab9_damper import write_synthetic

    return _report(write_synthetic(folder, 3, periods=100, sample_rate=200e3)["toml"])


def _check_with(reported: str, policy: str | None = None, *, json: bool = False):
    def build(folder: Path) -> list[str]:
        path = _sample(folder, "lab1/flywheel.toml")
        path.write_text(path.read_text(encoding="utf-8") + f"\n[reported]\n{reported}\n",
                        encoding="utf-8")
        argv = ["check", path.name, *(["--json"] if json else [])]
        if policy is not None:
            (folder / "policy.toml").write_text(policy, encoding="utf-8")
            argv += ["--policy", "policy.toml"]
        return argv
    return build


def _synth(*args: str, existing: bool = False):
    def build(folder: Path) -> list[str]:
        if existing:
            (folder / "out").write_text("a file where the folder should go\n", encoding="utf-8")
        return ["synth", *args, "--out", "out"]
    return build


# --------------------------------------------------------------------------- the corpus

LAB1 = "lab1/flywheel.toml"
LAB4 = "lab4/lab4_seed4.toml"
LAB5 = "lab5/valve_train.toml"
LAB6 = "lab6/lab6_seed6.toml"
LAB7 = "lab7/lab7_seed7.toml"
LAB8 = "lab8/d120.toml"
LAB9 = "lab9/synthetic_damper.toml"
LAB9_PHOTO = "lab9-photo/photographed_decay.toml"
LAB3_PHOTO = "lab3-photo/photographed_oscillogram.toml"
J = ("J_trifilar", "J_unifilar", "J_pendulum_cm")
REFUSED_COMMA = Expect(2, cause=r"decimal comma")


def _commas() -> list[Case]:
    return [
        Case("lab1 readings split by TOML into integers", "decimal comma",
             _edited(LAB1, ("t = [36.07, 36.21, 36.22]", "t = [36,17, 36,21, 36,22]")),
             Expect(2, cause=r"decimal comma", field="trifilar.t")),
        Case("lab1 readings with a leading-zero fraction", "decimal comma",
             _edited(LAB1, ("t = [36.07, 36.21, 36.22]", "t = [36,07, 36,21, 36,22]")),
             REFUSED_COMMA),
        Case("lab1 unquoted mass with a comma", "decimal comma",
             _edited(LAB1, ('m_p = "2.104 kg"', "m_p = 2,104")), REFUSED_COMMA),
        Case("lab1 quoted values with commas", "decimal comma",
             _edited(LAB1, ('m = "11.800 kg"', 'm = "11,800 kg"'),
                     ('m_p = "2.104 kg"', 'm_p = "2,104 kg"'),
                     ("t = [36.07, 36.21, 36.22]", 't = ["36,07", "36,21", "36,22"]')),
             Expect(0, same=J), sample=LAB1),
        Case("lab1 a limit with a comma", "decimal comma",
             _edited(LAB1, ('g = "9.8156 ± 0.0005 m/s^2"', 'g = "9,8156 ± 0,0005 m/s^2"')),
             Expect(0, same=J), sample=LAB1),
        Case("lab9 calibration readings with commas in quotes", "decimal comma",
             _edited(LAB9, ("cal_phi = [0.00, 3.00, 6.00, 9.00]",
                            'cal_phi = ["0,00", "3,00", "6,00", "9,00"]')),
             Expect(0, same=("log_decrement",)), sample=LAB9),
        Case("lab5 speed with a comma", "decimal comma",
             _edited(LAB5, ('n = "2000 rpm"', 'n = "2000,0 мин⁻¹"')), Expect(0, same=("cam_order", "f_natural")),
             sample=LAB5),
    ]


def _russian_units() -> list[Case]:
    return [
        Case("lab1 in Russian units", "Russian units",
             _edited(LAB1, ('m = "11.800 kg"', 'm = "11,800 кг"'),
                     ('m_p = "2.104 kg"', 'm_p = "2104 г"'), ("l = 799.8", 'l = "0,7998 м"'),
                     ('g = "9.8156 ± 0.0005 m/s^2"', 'g = "9,8156 ± 0,0005 м/с²"')),
             Expect(0, same=J), sample=LAB1),
        Case("lab8 speed in об/мин and masses in кг", "Russian units",
             _edited(LAB8, ("n = 2000 ", 'n = "2000 об/мин" '),
                     ('m_piston = "2.006 kg"', 'm_piston = "2,006 кг"')),
             Expect(0, same=("F_j1", "M_j1_max")), sample=LAB8),
        Case("lab4 sensitivity in мВ/(м/с²)", "Russian units",
             _edited(LAB4, ('"10.2 mV/(m/s^2) ± 2 %"', '"10,2 мВ/(м/с²) ± 2 %"')),
             Expect(0, same=("a_rms_1",)), sample=LAB4),
        Case("lab9 inertia in кг·м²", "Russian units",
             _edited(LAB9, ('I = "0.03 ± 0.00015 kg*m^2"', 'I = "0,03 ± 0,00015 кг·м²"')),
             Expect(0, same=("log_decrement",)), sample=LAB9),
    ]


def _speeds() -> list[Case]:
    per_second = "33.333333333 1/s"
    return [
        Case("lab5 speed per second", "speed unit",
             _edited(LAB5, ('n = "2000 rpm"', f'n = "{per_second}"')), Expect(0, same=("cam_order", "f_natural")),
             sample=LAB5),
        Case("lab5 speed in Hz", "speed unit",
             _edited(LAB5, ('n = "2000 rpm"', 'n = "33.333333333 Hz"')),
             Expect(0, same=("cam_order", "f_natural")), sample=LAB5),
        Case("lab5 speed in rad/s", "speed unit",
             _edited(LAB5, ('n = "2000 rpm"', 'n = "209.43951024 rad/s"')),
             Expect(0, same=("cam_order", "f_natural")), sample=LAB5),
        Case("lab8 speed per second", "speed unit",
             _edited(LAB8, ("n = 2000 ", f'n = "{per_second}" ')), Expect(0, same=("F_j1", "M_j1_max")),
             sample=LAB8),
        Case("lab8 speed in s⁻¹", "speed unit",
             _edited(LAB8, ("n = 2000 ", 'n = "33.333333333 с⁻¹" ')), Expect(0, same=("F_j1", "M_j1_max")),
             sample=LAB8),
        Case("lab4 speed in Hz", "speed unit",
             _edited(LAB4, ('n = "1999 ± 10 rpm"', 'n = "33.316666667 ± 0.16666667 Hz"')),
             Expect(0, same=("a1_2", "a2_2")), sample=LAB4),
    ]


def _unit_slips() -> list[Case]:
    return [
        Case("lab1 mass in grams in a kg field", "unit slip",
             _edited(LAB1, ('m = "11.800 kg"', "m = 11800")),
             Expect(0, warns=("implausible_value",))),
        Case("lab1 radius in metres in a mm field", "unit slip",
             _edited(LAB1, ("R1 = 99.8", "R1 = 0.0998")), Expect(0, warns=("implausible_value",))),
        Case("lab6 clearance in metres", "unit slip",
             _edited(LAB6, ('clearance = "0.3 mm"', 'clearance = "0.3 m"')),
             Expect(None, cause=r"clearance", warns=("implausible_value",))),
    ]


def _records() -> list[Case]:
    return [
        Case("lab9 decay clipped", "record", _recorded(LAB9, "decay.csv", "u", _clip(0.6)),
             Expect(None, cause=r"clipped", warns=("clipped_record",), key=("log_decrement",))),
        Case("lab9 decay all zero", "record", _recorded(LAB9, "decay.csv", "u", np.zeros_like),
             Expect(2, cause=r"flat", field="decay.signal")),
        Case("lab9 decay white noise", "record", _recorded(LAB9, "decay.csv", "u", _noise),
             Expect(2, cause=r"noise", field="decay.signal")),
        Case("lab7 records clipped", "record", _recorded(LAB7, "*", "phi", _clip(0.5)),
             Expect(None, cause=r"clipped", warns=("clipped_record",))),
        Case("lab7 a white-noise torsiogram", "record", _recorded(LAB7, "r05.csv", "phi", _noise),
             Expect(2, cause=r"noise", field="record[4].channel")),
        Case("lab6 record flat", "record",
             _recorded(LAB6, "r03.csv", "in", lambda x: np.full_like(x, x[0])),
             Expect(2, cause=r"flat", field="record[2].signal")),
        Case("lab6 record white noise", "record", _recorded(LAB6, "r03.csv", "in", _noise),
             Expect(2, cause=r"noise", field="record[2].signal")),
        Case("lab6 record clipped", "record", _recorded(LAB6, "r03.csv", "in", _clip(0.3)),
             Expect(None, cause=r"clipped", warns=("clipped_record",))),
        Case("lab6 calibration that never changes", "record",
             _edited(LAB6, ("deflection = [0, 17.8, 35.8, 54, 71.9, 89.9]",
                            "deflection = [50, 50, 50, 50, 50, 50]")),
             Expect(2, cause=r"calibration|deflection", field="valve[0].deflection")),
    ]


def _photographs() -> list[Case]:
    cases = []
    for turn, how in _rotations().items():
        cases.append(Case(f"lab3 photograph {turn}", "photograph turned",
                          _photo(LAB3_PHOTO, "regime1.jpg", how),
                          Expect(None, cause=r"rotat|turn|mirror", same=("delta_osc_1",)),
                          sample=LAB3_PHOTO))
        cases.append(Case(f"lab9 photograph {turn}", "photograph turned",
                          _photo(LAB9_PHOTO, "decay.jpg", how),
                          Expect(None, cause=r"rotat|turn|mirror", same=("log_decrement",)),
                          sample=LAB9_PHOTO))
    return cases


def _check_inputs() -> list[Case]:
    return [
        Case("check: a negative u", "check", _check_with('J_trifilar = { value = "0.247 kg*m^2", '
                                                         'u = "-0.001 kg*m^2" }'),
             Expect(2, cause=r"negative|≥ 0", field="reported.J_trifilar.u")),
        Case("check: a misspelt u", "check", _check_with('J_trifilar = { value = "0.247 kg*m^2", '
                                                         'uu = "0.001 kg*m^2" }'),
             Expect(2, cause=r"uu", field="reported.J_trifilar.uu")),
        Case("check: a negative tolerance", "check",
             _check_with('J_trifilar = "0.247 kg*m^2"', "rel_tol = -0.01\n"),
             Expect(2, cause=r"rel_tol")),
        Case("check: a mistyped expected result", "check",
             _check_with('J_trifilar = "0.247 kg*m^2"', 'expected = ["J_trifilarr"]\n'),
             Expect(2, cause=r"J_trifilarr")),
    ]


def _synth_options() -> list[Case]:
    return [
        Case("synth lab5 --runs 0", "synth", _synth("lab5", "--runs", "0"),
             Expect(2, cause=r"runs")),
        Case("synth lab5 --friction nan", "synth", _synth("lab5", "--friction", "nan"),
             Expect(2, cause=r"friction")),
        Case("synth --out an existing file", "synth", _synth("lab2", existing=True),
             Expect(2, cause=r"out|folder|exists")),
        Case("synth lab7 --sample-rate 0", "synth", _synth("lab7", "--sample-rate", "0"),
             Expect(2, cause=r"sample.rate")),
        Case("synth lab9 --periods 0", "synth", _synth("lab9", "--periods", "0"),
             Expect(2, cause=r"periods")),
        Case("roster id of 300 characters", "synth", _roster(f"id,name\n{'x' * 300},A\n"),
             Expect(2, cause=r"id")),
        Case("roster id with a NUL byte", "synth", _roster("id,name\ns\x0001,A\n"),
             Expect(2, cause=r"id|NUL|character")),
        Case("roster id with a path", "synth", _roster("id,name\n../up,A\n"),
             Expect(2, cause=r"id")),
    ]


def _valid() -> list[Case]:
    return [
        Case("lab4 without TDC marks", "valid refused", _lab4_without_marks,
             Expect(0, same=("a_rms_1",)), sample=LAB4),
        Case("lab7 chain without records", "valid refused", _lab7_chain_alone, Expect(0)),
        Case("lab9 recorder left running after the decay", "valid refused", _lab9_left_running,
             Expect(0, key=("log_decrement", "T_d"))),
        Case("check: a right value in Russian", "valid refused",
             _check_with('J_trifilar = "0,1708 кг·м²"', json=True),
             Expect(0, says=r'"verdict": "right"')),
    ]


def _limits() -> list[Case]:
    return [
        Case("a FIFO as the measurement file", "hang", _fifo_measurement,
             Expect(2, cause=r"FIFO|pipe|not a regular file"), limits=True),
        Case("m.toml -> /dev/zero", "hang", _zero_link,
             Expect(2, cause=r"device|not a regular file"), limits=True),
        Case("a FIFO in a class", "hang", _class_with(lambda d: os.mkfifo(d / "s.toml")),
             Expect(2, written=("summary/summary.csv",)), limits=True),
        Case("a /dev/zero link in a class", "hang",
             _class_with(lambda d: os.symlink("/dev/zero", d / "s.toml")),
             Expect(2, written=("summary/summary.csv",)), limits=True),
        Case("a FIFO as the roster", "hang", _roster(None, fifo=True),
             Expect(2, cause=r"FIFO|pipe|not a regular file"), limits=True),
        Case("a 20 000 x 20 000 PNG", "memory", _with_image(lambda: _png_header(20000, 20000)),
             Expect(2, cause=r"pixel|px|large", field="decay.signal"), limits=True),
        Case("a 1 kB JPEG claiming 20 000 x 20 000", "memory",
             _with_image(lambda: _jpeg_claiming(20000, 20000)),
             Expect(2, cause=r"pixel|px|large|header", field="decay.signal"), limits=True),
        Case("a 3 GB CSV", "memory",
             lambda d: (_sparse(d, "decay.csv", 3 << 30, b"t,u\n0,1\n"),
                        _report(_sample_keep(d, LAB9, "decay.csv")))[1],
             Expect(2, cause=r"GB|GiB|MiB|MB|large|size", field="decay.signal"), limits=True),
        Case("a 3 GB JPEG", "memory",
             lambda d: (_report(_sample(d, LAB9_PHOTO)),
                        _sparse(d, "decay.jpg", 3 << 30, b"\xff\xd8\xff\xe0"))[0],
             Expect(2, cause=r"GB|GiB|MiB|MB|large|size", field="decay.signal"), limits=True),
        Case("a signal file name of 5000 characters", "internal", _signal_named(5000),
             Expect(2, cause=r"name|long", field="decay.signal")),
    ]


def _sample_keep(folder: Path, name: str, keep: str) -> Path:
    """The sample copied, but for ``keep`` (already written by the case)."""
    kept = (folder / keep).rename(folder / (keep + ".case"))
    path = _sample(folder, name)
    (folder / keep).unlink()
    kept.rename(folder / keep)
    return path


def corpus() -> list[Case]:
    """Every case, by kind."""
    return [*_commas(), *_russian_units(), *_speeds(), *_unit_slips(), *_records(),
            *_photographs(), *_check_inputs(), *_synth_options(), *_valid(), *_limits()]


# --------------------------------------------------------------------------- running a case

@dataclass(frozen=True)
class Outcome:
    """What a case gave: exit code (None: hung), output, peak memory, time."""

    code: int | None
    out: str
    err: str
    peak: int
    seconds: float


def _limit_child():
    os.setsid()
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_CAP, ADDRESS_CAP))


def run_child(argv: list[str], cwd: Path, *, hang: float = HANG_SECONDS) -> Outcome:
    """``dynlab *argv`` in a child process in ``cwd``, address space capped, killed (with its
    process group) after ``hang`` seconds; its peak resident memory from ``wait4``."""
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}
    with open(cwd / ".stdout", "w+b") as out, open(cwd / ".stderr", "w+b") as err:
        start = time.perf_counter()
        child = subprocess.Popen([sys.executable, "-m", "labs.cli.main", *argv], cwd=cwd,
                                 stdin=subprocess.DEVNULL, stdout=out, stderr=err, env=env,
                                 preexec_fn=_limit_child)
        code, usage = None, None
        while time.perf_counter() - start < hang:
            pid, status, usage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                code = os.waitstatus_to_exitcode(status)
                break
            time.sleep(0.05)
        seconds = time.perf_counter() - start
        if code is None:
            os.killpg(child.pid, signal.SIGKILL)
            _, _, usage = os.wait4(child.pid, 0)
        child.returncode = code if code is not None else -9
        out.seek(0)
        err.seek(0)
        texts = [f.read().decode("utf-8", "replace") for f in (out, err)]
    (cwd / ".stdout").unlink()
    (cwd / ".stderr").unlink()
    return Outcome(code, *texts, usage.ru_maxrss * 1024, seconds)


@cache
def _sample_results(sample: str) -> dict:
    from labs.registry import evaluate

    return {k: (v.value, v.u) for k, v in evaluate(sample_dir() / sample).results.items()}


def judge(case: Case, got: Outcome, folder: Path) -> tuple[str, str]:
    """(verdict, detail) of a case's outcome: see the module's notes."""
    e = case.expect
    said = got.out + got.err
    if got.code is None:
        return "hang", f"still running after {got.seconds:.0f} s"
    if got.peak > MEMORY_LIMIT or "MemoryError" in said:
        return "memory", f"peak {got.peak / 2**20:.0f} MiB"
    if "Traceback" in said:
        return "traceback", said.strip().splitlines()[-1][:200]
    if got.code == 1 or "internal error" in got.err:
        return "internal", got.err.strip()[:200]
    for name in e.written:
        if not (folder / name).is_file():
            return "accepted-wrong", f"{name} was not written"
    if got.code == 2 and e.written:
        return "ok", ""
    if got.code == 2:
        return _judge_refusal(e, got, folder)
    if got.code != 0:
        return "internal", f"exit {got.code}: {got.err.strip()[:200]}"
    if e.code == 2:
        return "accepted-wrong", "exit 0 where a refusal is due"
    if e.says and not re.search(e.says, got.out):
        return "accepted-wrong", f"the output does not say /{e.says}/"
    return _judge_result(case, folder)


def _judge_refusal(e: Expect, got: Outcome, folder: Path) -> tuple[str, str]:
    if e.code == 0:
        return "refused-valid", got.err.strip()[:200]
    message = got.err.strip()
    if not message.startswith("error: ") or "Fix:" not in message:
        return "misleading", f"no error with a fix: {message[:200]}"
    if e.field and f"field '{e.field}'" not in message:
        return "misleading", f"does not name field {e.field}: {message[:200]}"
    if e.cause and not re.search(e.cause, message, flags=re.I):
        return "misleading", f"does not say /{e.cause}/: {message[:200]}"
    left = list((folder / "out").iterdir()) if (folder / "out").is_dir() else []
    if left:
        return "misleading", f"wrote {[p.name for p in left]} although refused"
    return "ok", ""


def _judge_result(case: Case, folder: Path) -> tuple[str, str]:
    e = case.expect
    written = list((folder / "out").glob("*.json")) if (folder / "out").is_dir() else []
    if not written:
        return "ok", ""
    doc = json.loads(written[0].read_text(encoding="utf-8"))
    codes = {w["code"] for w in doc["warnings"]}
    for code in e.warns:
        if code not in codes:
            return "accepted-wrong", f"no {code} warning (warnings: {sorted(codes)})"
    for code in e.quiet:
        if code in codes:
            return "accepted-wrong", f"false {code} warning"
    results = doc["results"]
    for name in e.same:
        ref_value, ref_u = _sample_results(case.sample)[name]
        value = results.get(name, {}).get("value")
        if value is None or abs(value - ref_value) > max(1e-6 * abs(ref_value), 0.5 * ref_u):
            return "accepted-wrong", f"{name} = {value} against the sample's {ref_value:.6g}"
    if e.key:
        key = json.loads((folder / "answer_key.json").read_text(encoding="utf-8"))["results"]
        for name in e.key:
            lo, hi = results[name]["interval95"]
            if not lo <= key[name] <= hi:
                return "accepted-wrong", f"{name} interval [{lo:.5g}, {hi:.5g}] misses {key[name]:.5g}"
    return "ok", ""


def run_case(case: Case, root: Path, *, hang: float = HANG_SECONDS) -> dict:
    """Build, run and judge one case in a folder of its own under ``root``."""
    folder = Path(tempfile.mkdtemp(dir=root))
    argv = case.build(folder)
    got = run_child(argv, folder, hang=hang)
    verdict, detail = judge(case, got, folder)
    shutil.rmtree(folder, ignore_errors=True)
    return {"case": case.name, "kind": case.kind, "verdict": verdict, "detail": detail,
            "code": got.code, "peak_mib": got.peak / 2**20, "seconds": got.seconds,
            "message": got.err.strip().splitlines()[-1][:300] if got.err.strip() else ""}


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Run the corpus (the quick plan: the hang and memory cases), write ``bench.csv`` and
    ``targets.json`` to ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cases = [c for c in corpus() if c.limits or not quick]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for case in cases:
            rows.append(run_case(case, Path(tmp)))
            log(f"  {rows[-1]['verdict']:14} {case.name}  {rows[-1]['detail']}")
    frame = write_rows(rows, out / "bench.csv")
    refused = frame[frame["code"] == 2]
    targets = [Target("cases not handled as they must be", float((frame["verdict"] != "ok").sum()),
                      0, detail=", ".join(frame.loc[frame["verdict"] != "ok", "case"])),
               Target("peak memory of any input", float(frame["peak_mib"].max()),
                      MEMORY_LIMIT / 2**20, unit="MiB"),
               Target("slowest refusal", float(refused["seconds"].max()) if len(refused) else 0.0,
                      REFUSAL_SECONDS, unit="s")]
    write_targets(targets, out / "targets.json", environment())
    return frame, targets


def summary_lines(frame: pd.DataFrame) -> list[str]:
    lines = [f"{len(frame)} inputs: " + ", ".join(f"{n} {v}" for v, n in
                                                  frame["verdict"].value_counts().items())]
    for kind, group in frame.groupby("kind", sort=False):
        bad = group[group["verdict"] != "ok"]
        lines.append(f"  {kind:18} {len(group) - len(bad)}/{len(group)} ok, peak "
                     f"{group['peak_mib'].max():.0f} MiB, slowest {group['seconds'].max():.1f} s"
                     + "".join(f"\n      {r.verdict}: {r.case}: {r.detail}"
                               for r in bad.itertuples()))
    return lines
