"""The measurement file's boundary as a Russian student types it, for every field of every lab.

Generated from the bundled samples (every quantity field each of them fills in): decimal
commas inside quotes read right, decimal commas outside quotes (where TOML split a reading or
cannot parse the line) refused with the line and its fix, whole numbers never refused, units
in Russian (every unit a report prints parses back), rotational speeds per second or in Hz
counting revolutions in every lab's speed field (the reduction equals the one from min⁻¹),
and unit slips outside a bench's range warned about with the likely slip. The values
``dynlab check`` reads from ``[reported]`` pass the same parsing.
"""
import ast
import math
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from cli_contract import ROOT, assert_one_clear_error, run
from labs.teachers.check import _quantity
from labs.registry import LABS, evaluate
from processing.decimal_comma import PAIRS_SPREAD, REPEATS_SPREAD, split_reading
from processing.diagnostics import ImplausibleValueWarning, InputError
from processing.measurement import load, plausible_range, read_toml
from processing.inputs.toml_writer import dumps
from processing.uncertainty import Measured
from processing.units import (QuantityError, parse_quantity, si_factor, unit_text)

SAMPLES = sorted((ROOT / "sample_data").glob("*/*.toml"))
SAMPLE_IDS = [f"{p.parent.name}/{p.stem}" for p in SAMPLES]


def _spec(data):
    return LABS[data["lab"]].SPEC


def _entries(data, spec):
    """(section, index or None, entry) of every table the file fills in."""
    for sec in spec.sections:
        raw = data.get(sec.name)
        if isinstance(raw, list):
            yield from ((sec, i, e) for i, e in enumerate(raw))
        elif isinstance(raw, dict):
            yield sec, None, raw


def _quantities(data):
    """(field path, entry, Field) of every quantity the file gives."""
    spec = _spec(data)
    for sec, i, entry in _entries(data, spec):
        where = sec.name if i is None else f"{sec.name}[{i}]"
        for f in sec.fields:
            if f.kind == "quantity" and f.name in entry:
                yield f"{where}.{f.name}", entry, f


def _loaded(path: Path, data: dict | None = None, text: str | None = None):
    """The file's inputs (written from ``data`` or ``text`` when given), and the
    ``implausible_value`` warnings loading it raised."""
    if data is not None or text is not None:
        path.write_text(text if text is not None else dumps(data), encoding="utf-8")
    doc = read_toml(path)
    doc.pop("reported", None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        inputs = load(path, _spec(doc), doc)
    return inputs, [str(w.message) for w in caught
                    if issubclass(w.category, ImplausibleValueWarning)]


def _measured(inputs):
    return {k: v for k, v in inputs.flat().items() if isinstance(v, Measured)}


def _same_measured(a: dict, b: dict):
    assert a.keys() == b.keys()
    for key in a:
        x, y = a[key], b[key]
        np.testing.assert_allclose(y.readings, x.readings, rtol=1e-9, err_msg=key)
        np.testing.assert_allclose([y.value, y.u], [x.value, x.u], rtol=1e-9, atol=1e-300,
                                   err_msg=key)


def _sample(sample: Path) -> dict:
    """The sample's document, every file it names made absolute (so that a rewritten copy in
    a test's folder reads the sample's recordings)."""
    data = tomllib.loads(sample.read_text(encoding="utf-8"))
    spec = _spec(data)
    for sec, _, entry in _entries(data, spec):
        for f in sec.fields:
            if f.kind == "file" and f.name in entry:
                entry[f.name] = str(sample.parent / entry[f.name])
    return data


def _holder(data: dict, where: str) -> tuple[dict, str]:
    """The table holding the field ``section.key`` (``section[i].key``), and the key."""
    section, key = where.rsplit(".", 1)
    name, _, index = section.partition("[")
    return (data[name][int(index[:-1])] if index else data[name]), key


# ----------------------------------------------------------- decimal commas inside quotes

def _russian(text: str) -> str:
    """A value's text as a Russian student writes it: decimal commas, units in Russian."""
    return unit_text(re.sub(r"(?<=\d)\.(?=\d)", ",", text), "ru")


def _as_typed(raw, f, i: int):
    """``raw`` rewritten the Russian way; a plain number becomes a text with a decimal comma
    (every other one with the field's unit in Russian)."""
    if isinstance(raw, str):
        return _russian(raw)
    if isinstance(raw, (int, float)) and not isinstance(raw, bool):
        unit = f" {f.unit}" if f.unit and i % 2 else ""
        return _russian(f"{raw!r}{unit}")
    if isinstance(raw, list):
        return [_as_typed(x, f, i + j) for j, x in enumerate(raw)]
    if isinstance(raw, dict):
        return {k: unit_text(v, "ru") if k == "unit" else _as_typed(v, f, i)
                for k, v in raw.items()}
    return raw


@pytest.mark.parametrize("sample", SAMPLES, ids=SAMPLE_IDS)
def test_every_field_reads_decimal_commas_and_russian_units(tmp_path, sample):
    """Each quantity of each sample, rewritten with decimal commas and Russian units inside
    quotes, reads to the same SI readings and uncertainty."""
    original, _ = _loaded(sample)
    data = _sample(sample)
    count = 0
    for i, (_, entry, f) in enumerate(_quantities(data)):
        entry[f.name] = _as_typed(entry[f.name], f, i)
        count += 1
    assert count, "the sample gives no quantity"
    rewritten, warned = _loaded(tmp_path / "typed_ru.toml", data)
    _same_measured(_measured(original), _measured(rewritten))
    assert not warned, warned


@pytest.mark.parametrize("text, unit, value, limit", [
    ("30,62", "s", 30.62, None),
    ("0,1706 kg*m^2", "kg*m^2", 0.1706, None),
    ("30,62 ± 0,05 s", "s", 30.62, 0.05),
    ("850,5 мм", "mm", 0.8505, None),
    ("850,5 ± 0,5 мм", "mm", 0.8505, 0.0005),
    ("1,5e3 мм", "mm", 1.5, None),
    ("0,98 кгс·м", "N*m", 0.98 * 9.80665, None),
    ("10,2 мВ/(м/с²)", "mV/(m/s^2)", 0.0102, None),
    ("2,5 Н·м×с", "N*m*s", 2.5, None),
    ("12,0 г/см²", "kg/m^2", 120.0, None),
    ("7200 кг/м³", "kg/m^3", 7200.0, None),
])
def test_decimal_comma_inside_quotes(text, unit, value, limit):
    got, got_limit = parse_quantity(text, unit)
    assert math.isclose(got, value, rel_tol=1e-12), got
    assert (got_limit is None) == (limit is None)
    if limit is not None:
        assert math.isclose(got_limit, limit, rel_tol=1e-12), got_limit


@pytest.mark.parametrize("text, problem", [
    ("1.234,5 mm", r"both a comma and a point"),
    ("1,234.5 mm", r"both a comma and a point"),
    ("1,234,5 mm", r"two commas"),
    ("30,62, 30,81", r"no decimal comma"),
    ("30, 62 s", r"no decimal comma"),
])
def test_ambiguous_commas_are_refused_with_how_to_write_them(text, problem):
    with pytest.raises(QuantityError, match=problem) as caught:
        parse_quantity(text, "mm")
    assert caught.value.fix and ("1234.5" in caught.value.fix or "array" in caught.value.fix)


@pytest.mark.parametrize("where, text, field, problem", [
    ("body.m", '"11.800,5 kg"', "body.m", r"both a comma and a point.*Fix: write the number "
     r"with one decimal separator"),
    ("trifilar.t", '["36,07", "36,21,5"]', "trifilar.t", r"two commas"),
    ("trifilar.R1", '{ value = "99,8", limit = "0,5,1 mm" }', "trifilar.R1", r"two commas"),
])
def test_ambiguous_commas_in_a_file(tmp_path, capsys, where, text, field, problem):
    data = tomllib.loads((ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8"))
    section, key = where.split(".")
    data[section][key] = "SENTINEL"
    path = tmp_path / "student.toml"
    path.write_text(dumps(data).replace('"SENTINEL"', text), encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, field, problem, tmp_path / "out")


def test_quoted_forms_of_the_issue(tmp_path):
    """``{ value = "5,432", unit = "kg" }``, a limit and u with commas, quoted arrays."""
    data = tomllib.loads((ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8"))
    data["body"]["m"] = {"value": "11,800", "unit": "кг", "limit": "0,002 кг"}
    data["trifilar"]["t"] = ["36,07", "36,21", "36,22"]
    data["trifilar"]["R2"] = {"value": "140,3", "u": "0,3"}
    data["trifilar"]["l"] = "79,98 см"
    inputs, warned = _loaded(tmp_path / "student.toml", data)
    assert not warned
    assert inputs["body"]["m"].value == pytest.approx(11.8)
    assert inputs["body"]["m"].limit == pytest.approx(0.002)
    assert inputs["trifilar"]["t"].readings == pytest.approx((36.07, 36.21, 36.22))
    assert inputs["trifilar"]["R2"].value == pytest.approx(0.1403)
    assert inputs["trifilar"]["R2"].u == pytest.approx(3e-4)
    assert inputs["trifilar"]["l"].value == pytest.approx(0.7998)


# ----------------------------------------------------- decimal commas outside quotes: refused

def _comma(x: float) -> str:
    return f"{x:.6g}".replace(".", ",")


def _split_cases():
    """Every quantity field of every sample whose reading is not whole, written with decimal
    commas outside quotes: a scalar (TOML cannot parse it) or an array (TOML reads whole
    numbers, or cannot parse a fraction with a leading zero)."""
    cases = []
    for sample, name in zip(SAMPLES, SAMPLE_IDS):
        data = _sample(sample)
        inputs, _ = _loaded(sample)
        flat = inputs.flat()
        for where, entry, f in _quantities(data):
            raw = entry[f.name]
            if isinstance(raw, dict):
                continue
            readings = [r / si_factor(f.unit) for r in flat[where].readings]
            if all(float(f"{x:.6g}").is_integer() for x in readings):
                continue
            if isinstance(raw, list):
                text = "[" + ", ".join(_comma(x) for x in readings) + "]"
            else:
                text = _comma(readings[0])
            cases.append(pytest.param(sample, where, text, id=f"{name}-{where}"))
    return cases


@pytest.mark.parametrize("sample, where, text", _split_cases())
def test_decimal_commas_outside_quotes_are_refused_showing_the_line(tmp_path, capsys, sample,
                                                                    where, text):
    data = _sample(sample)
    holder, key = _holder(data, where)
    holder[key] = "SENTINEL"
    source = dumps(data).replace('"SENTINEL"', text)
    path = tmp_path / "student.toml"
    path.write_text(source, encoding="utf-8")
    out_dir = tmp_path / "out"
    code, out, err = run(capsys, "run", path, "--out", out_dir)
    assert_one_clear_error(code, out, err, path, where, r"decimal comma", out_dir)
    line = next(i for i, s in enumerate(source.splitlines(), 1)
                if s.startswith(f"{key} = {text}"))
    assert f"line {line}, `{key} = {text}`" in err, err
    assert f"{key} = {text.replace(',', '.').replace('. ', ', ')}" in err, err


@pytest.mark.parametrize("source, values, readings", [
    ("t = [30,62, 30,81, 30,70]", [30, 62, 30, 81, 30, 70], (30.62, 30.81, 30.70)),
    ("t = [30,62,30,81,30,70]", [30, 62, 30, 81, 30, 70], (30.62, 30.81, 30.70)),
    ("t = [30,62, 30.81]", [30, 62, 30.81], (30.62, 30.81)),
    ("t = [30,62]", [30, 62], (30.62,)),
    ("phi = [1,25, 2,65, 4, 5,9]", [1, 25, 2, 65, 4, 5, 9], (1.25, 2.65, 4.0, 5.9)),
    ("t = [\n  30,62,\n  30,81,\n]", [30, 62, 30, 81], (30.62, 30.81)),
    ("t = { readings = [30,62, 30,81] }", [30, 62, 30, 81], (30.62, 30.81)),
])
def test_split_readings_are_found(source, values, readings):
    split = split_reading(source + "\n", source.split()[0], values)
    assert split is not None and split.readings == pytest.approx(readings)


def test_issue_lab1_six_integers_no_longer_gives_a_wrong_inertia(tmp_path, capsys):
    """The issue's case: lab 1 reported J = 0.27 ± 0.22 kg·m² (truth 0.08) from six integers."""
    text = (ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8")
    text = re.sub(r"^t = \[36.07, 36.21, 36.22\]", "t = [30,62, 30,81, 30,70]", text,
                  flags=re.M)
    path = tmp_path / "student.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, "trifilar.t", r"line \d+, `t = \[30,62, "
                           r"30,81, 30,70\]  +# flywheel on the platform`.*decimal comma.*Fix: write decimal points, t = "
                           r"\[30.62, 30.81, 30.70\], or put each number in quotes, t = "
                           r"\[\"30,62\", \"30,81\", \"30,70\"\]", tmp_path / "out")


@pytest.mark.parametrize("line, field", [
    ("m = 11,800", "body.m"),
    ("m = { value = 5,432, unit = \"kg\" }", "body.m"),
])
def test_issue_syntax_errors_name_the_decimal_comma(tmp_path, capsys, line, field):
    text = (ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8")
    text = re.sub(r'^m = "11.800 kg".*$', line, text, flags=re.M)
    path = tmp_path / "student.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, field, r"decimal comma outside quotes",
                           tmp_path / "out")
    assert "Unclosed" not in err and "Expected" not in err


def test_a_syntax_error_without_a_decimal_comma_is_not_blamed_on_one(tmp_path, capsys):
    path = tmp_path / "student.toml"
    path.write_text("lab = 'lab1'\n[body]\nt = [30,6x, 30,81]\n", encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, None, r"not a valid TOML", tmp_path / "out")
    assert "decimal comma" not in err


# ------------------------------------------------------------- whole numbers are never refused

def test_whole_numbers_written_with_spaces_are_never_split():
    rng = np.random.default_rng(27)
    for _ in range(2000):
        values = [int(v) for v in rng.integers(0, 5000, size=rng.integers(1, 12))]
        source = f"x = [{', '.join(map(str, values))}]\n"
        assert split_reading(source, "x", values) is None, source


def test_whole_repeats_written_tight_are_not_split():
    """Integer repeats of one quantity agree within REPEATS_SPREAD: never refused, however
    written; nor is any tight series of distinct values."""
    rng = np.random.default_rng(28)
    for _ in range(2000):
        base = rng.integers(1, 10000)
        n = rng.integers(2, 12)
        values = [int(v) for v in rng.integers(base, max(base * REPEATS_SPREAD, base + 1),
                                                 size=n, endpoint=True)]
        source = f"x = [{','.join(map(str, values))}]\n"
        assert split_reading(source, "x", values) is None, source
        series = sorted(int(v) for v in rng.integers(0, 20000, size=n))
        source = f"x = [{','.join(map(str, series))}]\n"
        assert split_reading(source, "x", series, series=True) is None, source


def test_the_spreads_leave_room_between_repeats_and_pairs():
    assert PAIRS_SPREAD < REPEATS_SPREAD


@pytest.mark.parametrize("sample, where, values", [
    ("lab9/table1.toml", "run[0].M", "[90,180,270,315,270,180,90,0]"),
    ("lab6/lab6_seed6.toml", "valve[0].load", "[0,300,600,900,1200,1500]"),
    ("lab1/flywheel.toml", "trifilar.t", "[36,36,37]"),
    ("lab7/lab7_seed7.toml", "calibration.h", "[0,1,2,3,4]"),
])
def test_tight_whole_numbers_in_a_file_are_read(tmp_path, sample, where, values):
    data = _sample(ROOT / "sample_data" / sample)
    holder, key = _holder(data, where)
    holder[key] = "SENTINEL"
    inputs, _ = _loaded(tmp_path / "student.toml",
                        text=dumps(data).replace('"SENTINEL"', values))
    f = _spec(data).section(where.split("[")[0].split(".")[0]).field(key)
    got = np.array(inputs.flat()[where].readings) / si_factor(f.unit)
    np.testing.assert_allclose(got, tomllib.loads(f"x = {values}")["x"], rtol=1e-12)


# ------------------------------------------------------------------------ units in Russian

def _declared_units() -> set[str]:
    """Every unit a lab declares for a field, and every display unit of a result (the
    ``(label, symbol, unit)`` tuples of the labs' result declarations)."""
    units = {f.unit for lab in LABS for s in LABS[lab].SPEC.sections for f in s.fields
             if f.kind == "quantity"}
    for path in (ROOT / "labs").glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Tuple) and len(node.elts) == 3:
                label, _, unit = node.elts
                if isinstance(label, ast.Call) and getattr(label.func, "id", "") == "bi" \
                        and isinstance(unit, ast.Constant) and isinstance(unit.value, str):
                    units.add(unit.value)
    return units


DECLARED = sorted(_declared_units())


def test_the_declared_units_are_found():
    assert {"kg*m^2", "rpm", "mm", "N*m/rad", "MPa", "um", "µm", "kHz"} <= set(DECLARED)


@pytest.mark.parametrize("unit", DECLARED)
@pytest.mark.parametrize("lang", ["en", "ru"])
def test_every_printed_unit_parses_back(unit, lang):
    printed = unit_text(unit, lang)
    value, _ = parse_quantity(f"2,5 {printed}".strip(), unit)
    assert value == pytest.approx(2.5 * si_factor(unit), rel=1e-12), (printed, value)


@pytest.mark.parametrize("text, unit, si", [
    ("1 кг", "kg", 1.0), ("1 г", "kg", 1e-3), ("1 м", "m", 1.0), ("1 мм", "m", 1e-3),
    ("1 см", "m", 1e-2), ("1 мкм", "m", 1e-6), ("1 с", "s", 1.0), ("1 мс", "s", 1e-3),
    ("1 мин", "s", 60.0), ("1 Н", "N", 1.0), ("1 кН", "N", 1e3), ("1 Н·м", "N*m", 1.0),
    ("1 Нм", "N*m", 1.0), ("1 кгс", "N", 9.80665), ("1 кгс·м", "N*m", 9.80665),
    ("1 об/мин", "rpm", math.pi / 30), ("1 мин⁻¹", "rpm", math.pi / 30),
    ("1 мин^-1", "rpm", math.pi / 30), ("1 об/с", "rpm", 2 * math.pi),
    ("1 рад/с", "rpm", 1.0), ("1 Гц", "Hz", 1.0), ("1 кГц", "Hz", 1e3), ("1 °", "deg",
                                                                           math.pi / 180),
    ("1 град", "deg", math.pi / 180), ("1 рад", "deg", 1.0), ("1 мрад", "deg", 1e-3),
    ("1 МПа", "Pa", 1e6), ("1 ГПа", "Pa", 1e9), ("1 Па", "Pa", 1.0), ("1 кПа", "Pa", 1e3),
    ("1 мВ/(м/с²)", "mV/(m/s^2)", 1e-3), ("1 В", "V", 1.0), ("1 мВ", "V", 1e-3),
    ("1 Дж", "J", 1.0), ("1 Вт", "W", 1.0), ("1 кВт", "W", 1e3), ("1 л", "L", 1e-3),
    ("1 кг·м²", "kg*m^2", 1.0), ("1 кг·мм²", "kg*m^2", 1e-6), ("1 Н·м/рад", "N*m/rad", 1.0),
    ("1 Н/мм", "N/m", 1e3), ("1 м/с²", "m/s^2", 1.0), ("1 мм/с", "m/s", 1e-3),
    ("1 кг/м³", "kg/m^3", 1.0), ("1 т", "kg", 1e3), ("1 сек", "s", 1.0),
    # as typed: powers without a caret, the wrong case, a Latin c on the с key
    ("1 кг·м2", "kg*m^2", 1.0), ("1 кг/м3", "kg/m^3", 1.0), ("1 м/с2", "m/s^2", 1.0),
    ("1 мин-1", "rpm", math.pi / 30), ("1 с-1", "rpm", 2 * math.pi), ("1 КГ", "kg", 1.0),
    ("1 Кг", "kg", 1.0), ("1 гц", "Hz", 1.0), ("1 МПА", "Pa", 1e6), ("30,62 c", "s", 30.62),
    ("1 мм/c", "m/s", 1e-3), ("1 мН", "N", 1e-3), ("1 МН", "N", 1e6),
])
def test_russian_units_of_the_issue(text, unit, si):
    assert parse_quantity(text, unit)[0] == pytest.approx(si, rel=1e-12)


# ------------------------------------------------------------------------ rotational speeds

SPEED_FORMS = ("1/s", "s^-1", "с⁻¹", "/s", "Hz", "Гц", "rps", "об/с", "1/min", "min^-1",
               "мин⁻¹", "rpm", "об/мин", "rad/s", "рад/с", "deg/s")
"""Ways of writing a speed; in revolutions per second unless the unit names an angle."""


def _speed_text(rad_per_s: float, form: str) -> str:
    if form in ("rad/s", "рад/с"):
        return f"{rad_per_s!r} {form}"
    if form == "deg/s":
        return f"{math.degrees(rad_per_s)!r} {form}"
    per_s = rad_per_s / (2 * math.pi)
    if form in ("1/min", "min^-1", "мин⁻¹", "rpm", "об/мин"):
        return f"{per_s * 60!r} {form}"
    return f"{per_s!r} {form}"


@pytest.mark.parametrize("form", SPEED_FORMS)
def test_a_rotational_speed_counts_revolutions(form):
    omega = 2000 * math.pi / 30
    assert parse_quantity(_speed_text(omega, form), "rpm")[0] == pytest.approx(omega,
                                                                                rel=1e-12)


@pytest.mark.parametrize("text, unit, si", [
    ("8 kHz", "kHz", 8000.0), ("8000 1/s", "kHz", 8000.0), ("8000 Гц", "kHz", 8000.0),
    ("7,5 Hz", "Hz", 7.5), ("450 rpm", "Hz", 7.5), ("450 об/мин", "Hz", 7.5),
    ("47.12388980384689 rad/s", "Hz", 7.5),
])
def test_a_frequency_keeps_cycles_per_second(text, unit, si):
    """A sample rate or a natural frequency: Hz = 1/s; a speed written there counts cycles."""
    assert parse_quantity(text, unit)[0] == pytest.approx(si, rel=1e-12)


def _speed_fields():
    """(sample, [(section, key)]) of every sample with a rotational speed field (declared
    in rpm), one sample per lab."""
    out, seen = [], set()
    for sample, name in zip(SAMPLES, SAMPLE_IDS):
        data = tomllib.loads(sample.read_text(encoding="utf-8"))
        fields = [where for where, _, f in _quantities(data) if f.unit == "rpm"]
        if fields and data["lab"] not in seen and "photo" not in name:
            seen.add(data["lab"])
            out.append(pytest.param(sample, id=name))
    return out


def test_every_lab_with_a_speed_field_is_covered():
    speed_labs = {lab for lab in LABS for s in LABS[lab].SPEC.sections for f in s.fields
                  if f.unit == "rpm"}
    covered = {tomllib.loads(p.values[0].read_text("utf-8"))["lab"] for p in _speed_fields()}
    assert covered == speed_labs, speed_labs - covered


@pytest.mark.parametrize("sample", _speed_fields())
def test_every_speed_field_of_the_lab_reduces_the_same_in_any_unit(tmp_path, sample):
    """Each speed of the lab's sample written in another form (the forms rotating over the
    file's speeds): every result equals the one from min⁻¹."""
    data = _sample(sample)
    original, _ = _loaded(sample)
    flat = original.flat()
    for i, (where, entry, f) in enumerate(w for w in _quantities(data) if w[2].unit == "rpm"):
        form = SPEED_FORMS[i % len(SPEED_FORMS)]
        speed = flat[where]
        entry[f.name] = _speed_text(speed.value, form) + (
            "" if not speed.limit else f" ± {_speed_text(speed.limit, form)}")
    target = tmp_path / "student_speeds.toml"
    rewritten, warned = _loaded(target, data)
    _same_measured(_measured(original), _measured(rewritten))
    assert not warned, warned
    a = evaluate(sample, n_samples=0).results
    b = evaluate(target, n_samples=0).results
    assert a.keys() == b.keys()
    for name in a:
        assert a[name].value == pytest.approx(b[name].value, rel=1e-9, nan_ok=True), name


@pytest.mark.parametrize("written", [
    {"value": 33.333333333333336, "unit": "Hz"}, {"value": "33,333333333333336", "unit": "об/с"},
    {"readings": [33.333333333333336, 33.333333333333336], "unit": "1/s"},
    {"value": 2000, "unit": "об/мин", "limit": "0,5 Гц"},
])
def test_a_speed_in_a_value_table_counts_revolutions(tmp_path, written):
    data = _sample(ROOT / "sample_data/lab8/d120.toml")
    data["engine"]["n"] = written
    inputs, warned = _loaded(tmp_path / "student.toml", data)
    assert not warned
    assert inputs["engine"]["n"].value == pytest.approx(2000 * math.pi / 30, rel=1e-12)
    if "limit" in written:
        assert inputs["engine"]["n"].limit == pytest.approx(math.pi, rel=1e-12)


def test_issue_lab4_takes_a_speed_in_hz(tmp_path):
    data = _sample(ROOT / "sample_data/lab4/lab4_seed4.toml")
    for reading in data["reading"]:
        n = float(reading["n"].split()[0])
        reading["n"] = f"{n / 60:.4f} Hz"
    inputs, warned = _loaded(tmp_path / "student.toml", data)
    assert not warned
    assert inputs["reading"][0]["n"].value * 30 / math.pi == pytest.approx(1999, abs=0.01)


# -------------------------------------------------------------- unit slips a range catches

def _slip_cases():
    """Every quantity field of every sample, its reading typed a thousand times too large
    and too small (grams as kg, metres as mm, ...), wherever that leaves the bench's range."""
    cases = []
    for sample, name in zip(SAMPLES, SAMPLE_IDS):
        data = tomllib.loads(sample.read_text(encoding="utf-8"))
        inputs, _ = _loaded(sample)
        for where, entry, f in _quantities(data):
            if isinstance(entry[f.name], dict):
                continue
            least, greatest = plausible_range(f)
            x = next((r for r in inputs.flat()[where].readings if r), None)
            if x is None:
                continue
            for k in (1e3, 1e-3):
                if not least <= x * k <= greatest:
                    cases.append(pytest.param(sample, where, x / si_factor(f.unit) * k,
                                              id=f"{name}-{where}-x{k:g}"))
    return cases


@pytest.mark.parametrize("sample, where, number", _slip_cases())
def test_a_unit_slip_outside_the_bench_warns(tmp_path, sample, where, number):
    data = _sample(sample)
    holder, key = _holder(data, where)
    holder[key] = [number] * len(holder[key]) if isinstance(holder[key], list) else number
    try:
        _, warned = _loaded(tmp_path / "student.toml", data)
    except InputError as exc:          # far outside, or beyond the method: refused, as before
        assert re.search(r"far outside what a lab bench measures|above .* where the method "
                         r"makes no sense", exc.problem), exc.problem
        return
    mine = [w for w in warned if w.startswith(f"'{where}'")]
    assert len(mine) == 1, warned
    assert "lies outside" in mine[0] and "what the manual's bench measures" in mine[0]


@pytest.mark.parametrize("where, value, message", [
    ("body.m", 8450, r"'body.m' \(mass of the part\) = 8450 kg lies outside 0.01–50 kg, what "
     r"the manual's bench measures: a value in g typed as kg\? 8450 g = 8.45 kg"),
    ("trifilar.R1", 0.1, r"= 0.1 mm lies outside 10–500 mm.*: a value in m typed as mm\? "
     r"0.1 m = 100 mm"),
    ("trifilar.t", [36070, 36210, 36220], r"= 36220 s \(and 2 more of its readings\) lies "
     r"outside 0.5–600 s.*a value in ms typed as s\? 36220 ms = 36.22 s"),
    ("trifilar.amplitude", "0.12", r"= 0.12 deg lies outside 0.5–45 deg.*a value in rad "
     r"typed as deg\? 0.12 rad = 6.875 deg"),
])
def test_issue_slips_name_the_likely_unit(tmp_path, where, value, message):
    data = tomllib.loads((ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8"))
    section, key = where.split(".")
    data[section][key] = value
    _, warned = _loaded(tmp_path / "student.toml", data)
    assert len(warned) == 1 and re.search(message, warned[0]), warned


def test_issue_clearance_of_metres(tmp_path):
    data = _sample(ROOT / "sample_data/lab6/lab6_seed6.toml")
    data["record"][0]["clearance"] = "0,8 м"
    _, warned = _loaded(tmp_path / "student.toml", data)
    assert len(warned) == 1 and re.search(r"'record\[0\].clearance' .* = 0.8 m lies outside "
                                          r"0.1–1.5 mm.*a value in mm typed as m\? 0.8 mm$",
                                          warned[0]), warned


def test_issue_speed_in_revolutions_per_second_typed_as_rpm(tmp_path):
    data = tomllib.loads((ROOT / "sample_data/lab8/d120.toml").read_text("utf-8"))
    data["engine"]["n"] = 33.3
    _, warned = _loaded(tmp_path / "student.toml", data)
    assert len(warned) == 1 and "a value in rps typed as rpm? 33.3 rps = 1998 rpm" in warned[0]


@pytest.mark.parametrize("sample", SAMPLES, ids=SAMPLE_IDS)
def test_samples_are_inside_every_range(sample):
    _, warned = _loaded(sample)
    assert not warned, warned


def test_every_quantity_field_declares_a_range():
    for lab in LABS:
        for sec in LABS[lab].SPEC.sections:
            for f in sec.fields:
                if f.kind == "quantity":
                    assert f.plausible, f"{lab} {sec.name}.{f.name} declares no range"
                    least, greatest = plausible_range(f)
                    assert 0 < least < greatest, (lab, sec.name, f.name)


# ------------------------------------------------------------------ dynlab check's [reported]

@pytest.mark.parametrize("text, unit, si", [
    ("0,1708 kg*m^2", "kg*m^2", 0.1708),
    ("0,1708 кг·м²", "kg*m^2", 0.1708),
    ("1798,4 мин⁻¹", "rad/s", 1798.4 * math.pi / 30),
    ("29,973 1/s", "rad/s", 29.973 * 2 * math.pi),
    ("29,973 Гц", "rad/s", 29.973 * 2 * math.pi),
    ("188,33 рад/с", "rad/s", 188.33),
    ("1,25 мм", "m", 1.25e-3),
    ("≈2,03 кН/мм", "N/m", 2.03e6),
    ("~ 5,8 kN/mm", "N/m", 5.8e6),
    ("c = 42,96 Н/мм", "N/m", 42960.0),
    ("J_трифиляр = 0,1708 кг·м²", "kg*m^2", 0.1708),
    ("2,228·10⁶ Н/м", "N/m", 2.228e6),
])
def test_reported_values_pass_the_same_parsing(text, unit, si):
    reported = _quantity("s.toml", "reported.x", text, None, unit)
    assert reported.value == pytest.approx(si, rel=1e-12)


def test_an_unreadable_reported_value_asks_for_the_labs_display_unit(tmp_path, capsys):
    """A stiffness is asked for in kN/mm as the report shows it, not in SI's kg/s²."""
    sample = ROOT / "sample_data/lab5/valve_train.toml"
    path = tmp_path / "student.toml"
    path.write_text(sample.read_text("utf-8") + '\n[reported]\nc_total = "две тысячи"\n',
                    encoding="utf-8")
    code, out, err = run(capsys, "check", path)
    assert_one_clear_error(code, out, err, path, "reported.c_total", "should start with a "
                           "number", tmp_path / "none")
    assert "kN/mm" in err and "kg/s" not in err


def test_reported_u_with_a_decimal_comma():
    reported = _quantity("s.toml", "reported.x", "0,1708 кг·м²", "0,0016 кг·м²", "kg*m^2")
    assert reported.u == pytest.approx(0.0016)


def test_check_reads_a_russian_submission(tmp_path, capsys):
    """A right value written with a decimal comma and a Russian unit is right: its digits are
    counted as 0.1708's (they read as one significant figure, 'rounded', before)."""
    text = (ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8")
    result = evaluate(ROOT / "sample_data/lab1/flywheel.toml", n_samples=0).results
    j = result["J_trifilar"].value
    path = tmp_path / "student.toml"
    path.write_text(text + f'\n[reported]\nJ_trifilar = "{j:.4f} кг·м²"\n'.replace(".", ","),
                    encoding="utf-8")
    code, out, err = run(capsys, "check", path, "--json")
    assert code == 0, err
    assert '"verdict": "right"' in out, out


@pytest.mark.parametrize("form", ["Гц", "1/s", "об/с", "rpm", "рад/с"])
def test_check_reads_a_speed_per_second_as_revolutions(tmp_path, capsys, form):
    """Lab 6's speed of record 1 reported per second, in Hz or in rad/s: read as the same
    speed (before, 1/s and Hz were radians per second, 2π times too slow)."""
    import json

    sample = ROOT / "sample_data/lab6/lab6_seed6.toml"
    omega = evaluate(sample, n_samples=0).results["n_1"].value
    data = _sample(sample)
    data["reported"] = {"n_1": _speed_text(omega, form)}
    path = tmp_path / "student.toml"
    path.write_text(dumps(data), encoding="utf-8")
    code, out, err = run(capsys, "check", path, "--json")
    assert code == 0, err
    verdict = json.loads(out)["verdicts"][0]
    assert verdict["reported"] == pytest.approx(omega, rel=1e-9), verdict
    assert verdict["verdict"] != "wrong", verdict


def test_check_names_a_decimal_comma_in_reported(tmp_path, capsys):
    text = (ROOT / "sample_data/lab1/flywheel.toml").read_text("utf-8")
    path = tmp_path / "student.toml"
    path.write_text(text + "\n[reported]\nJ_trifilar = 0,1708\n", encoding="utf-8")
    code, out, err = run(capsys, "check", path)
    assert code == 2 and "decimal comma" in err and "reported.J_trifilar" in err, err


@pytest.mark.parametrize("text, value, limit", [
    ("10,2 мВ/(м/с²) ± 2,5 %", 10.2e-3, 0.255e-3),
    ("100 mV/g ± 2 %", 0.1 / 9.80665, 0.002 / 9.80665),
    ("10.2 mV/(m/s^2) ± 0.2 mV/(m/s^2)", 10.2e-3, 0.2e-3),
])
def test_lab4_sensitivity_takes_a_limit_in_per_cent_with_a_decimal_comma(text, value, limit):
    """The accelerometer chart's accuracy as a per cent of the value, as typed in Russian
    (the limit '± 2,5 %' went through float() and was refused)."""
    from labs.lab4_vibration import sensitivity

    s = sensitivity(text)
    assert s.value == pytest.approx(value, rel=1e-12)
    assert s.limit == pytest.approx(limit, rel=1e-12)


# -------------------------------------------- an angle for a plain number, or back

@pytest.mark.parametrize("text, unit, problem", [
    ("1.5 deg", "", "is an angle, but a plain number is expected"),
    ("2 rad", "%", "is an angle, but a plain number is expected"),
    ("30 %", "deg", "is a plain number or share, but an angle is expected"),
    ("0,5 %", "rad", "is a plain number or share, but an angle is expected"),
    ("1:10", "", "and here no time is expected"),
    ("1:05,32", "mm", "and here no time is expected"),
    ("1:75", "s", "the seconds under 60"),
])
def test_a_text_of_another_kind_is_refused_saying_why(text, unit, problem):
    """pint takes an angle and a plain number both for dimensionless (1.5 deg would be read
    0.026 as a rocker ratio); a colon is a stopwatch's, where a time is expected."""
    with pytest.raises(QuantityError, match=problem):
        parse_quantity(text, unit)


@pytest.mark.parametrize("text, unit, si", [
    ("5 %", "", 0.05), ("30 deg", "rad", math.pi / 6), ("90 deg", "deg", math.pi / 2),
    ("1.509", "", 1.509), ("12 mrad", "deg", 0.012), ("5 N*m", "N*m/rad", 5.0),
])
def test_a_ratio_a_share_and_an_angle_are_read_in_their_own_units(text, unit, si):
    assert parse_quantity(text, unit)[0] == pytest.approx(si, rel=1e-12)


def test_a_rocker_ratio_in_degrees_is_refused_naming_the_field(tmp_path, capsys):
    data = _sample(ROOT / "sample_data/lab5/valve_train.toml")
    data["rig"]["i"] = "1.509 deg"
    path = tmp_path / "student.toml"
    path.write_text(dumps(data), encoding="utf-8")
    code, out, err = run(capsys, "run", path, "--out", tmp_path / "out")
    assert_one_clear_error(code, out, err, path, "rig.i", "is an angle", tmp_path / "out")


# ------------------------------------ numbers as written by hand or copied from a report

@pytest.mark.parametrize("text, unit, value, limit", [
    ("6,13·10⁶ Н/м", "N/m", 6.13e6, None),
    ("1,706*10^-1 kg*m^2", "kg*m^2", 0.1706, None),
    ("1,706×10^-1 кг·м²", "kg*m^2", 0.1706, None),
    ("5·10^(-3) m", "m", 0.005, None),
    ("2×10**3 mm", "m", 2.0, None),
    ("−0,5 мм", "m", -0.0005, None),
    ("(2,23 ± 0,06) кН/мм", "N/m", 2.23e6, 6e4),
    ("(6,13 ± 0,05)·10⁶ Н/м", "N/m", 6.13e6, 5e4),
    ("(6,13 ± 1 %)·10⁶ Н/м", "N/m", 6.13e6, 6.13e4),
    ("6,13·10⁶ ± 0,05·10⁶ Н/м", "N/m", 6.13e6, 5e4),
])
def test_powers_of_ten_minus_signs_and_bracketed_limits_are_read(text, unit, value, limit):
    got = parse_quantity(text, unit)
    assert got[0] == pytest.approx(value, rel=1e-12)
    assert got[1] == (None if limit is None else pytest.approx(limit, rel=1e-12))


def test_a_power_of_ten_reported_in_russian_is_judged(tmp_path):
    """A student's c_total copied from a Russian report: '2,228·10⁶ Н/м' is the value."""
    from labs.teachers.check import check

    sample = ROOT / "sample_data/lab5/valve_train.toml"
    ours = evaluate(sample, n_samples=0).results["c_total"].value
    mantissa = f"{ours / 1e6:.3f}".replace(".", ",")
    path = tmp_path / "student.toml"
    path.write_text(sample.read_text("utf-8") + f'\n[reported]\nc_total = "{mantissa}·10⁶ Н/м"\n', encoding="utf-8")
    (verdict,) = [v for v in check(path).verdicts if v.name == "c_total"]
    assert verdict.verdict == "right", verdict


@pytest.mark.parametrize("text, seconds", [
    ("1:05,32", 65.32), ("0:36.07", 36.07), ("1:02:05", 3725.0), ("2:30 ± 0,2 с", 150.0),
])
def test_a_stopwatch_reading_is_read_where_a_time_is_expected(text, seconds):
    assert parse_quantity(text, "s")[0] == pytest.approx(seconds, rel=1e-12)


def test_a_trifilar_timed_on_a_stopwatch_reduces_as_in_seconds(tmp_path):
    """Twenty oscillations of 1.8 s show as 0:36,07 on a stopwatch."""
    sample = next((ROOT / "sample_data/lab1").glob("*.toml"))
    data = _sample(sample)
    clock = [f"0:{t:05.2f}".replace(".", ",") for t in data["trifilar"]["t"]]
    plain = evaluate(sample, n_samples=0).results
    data["trifilar"]["t"] = clock
    path = tmp_path / "student.toml"
    path.write_text(dumps(data), encoding="utf-8")
    timed = evaluate(path, n_samples=0).results
    assert timed["J_trifilar"].value == pytest.approx(plain["J_trifilar"].value, rel=1e-12)


# ------------------------------------------------ a measurement file as an editor saved it

@pytest.mark.parametrize("encoding", ["cp1251", "utf-16", "utf-8-sig"])
def test_a_file_saved_by_a_russian_notepad_reduces_as_utf8(tmp_path, encoding):
    """Windows-1251 (an older Notepad's "ANSI"), UTF-16 with its mark ("Unicode") and UTF-8
    with its mark read as UTF-8: the same student, the same result."""
    sample = ROOT / "sample_data/lab2/" / next(p.name for p in (ROOT / "sample_data/lab2")
                                              .glob("*.toml"))
    text = re.sub(r'student = "[^"]*"', 'student = "Иванов Иван"',
                  sample.read_text("utf-8").replace("[meta]", "[meta]\n# Лабораторная 2", 1))
    plain, saved = tmp_path / "utf8.toml", tmp_path / f"{encoding}.toml"
    plain.write_text(text, encoding="utf-8")
    saved.write_bytes(text.encode(encoding, errors="replace"))    # its comments' Δ in 1251
    a, b = evaluate(plain, n_samples=0), evaluate(saved, n_samples=0)
    assert b.meta["student"] == "Иванов Иван"
    assert {k: r.value for k, r in a.results.items()} == {k: r.value for k, r in b.results.items()}


def test_a_reported_text_without_a_unit_is_read_in_the_labs_display_unit(tmp_path):
    """'2,228' for the drive's stiffness is 2.228 kN/mm, as the report prints it."""
    from labs.teachers.check import check

    sample = ROOT / "sample_data/lab5/valve_train.toml"
    ours = evaluate(sample, n_samples=0).results["c_total"].value
    path = tmp_path / "student.toml"
    path.write_text(sample.read_text("utf-8") + f'\n[reported]\nc_total = '
                    f'"{ours / 1e6:.3f}"\n'.replace(".", ","), encoding="utf-8")
    (verdict,) = [v for v in check(path).verdicts if v.name == "c_total"]
    assert verdict.verdict == "right", verdict
