"""A lab's form, generated from its :class:`~processing.measurement.LabSpec`, and the two ways
between a form's values and a measurement document.

A form field is named by the path the boundary names it in its messages (``trifilar.l``,
``analytic[1].R``), so that an :class:`~processing.diagnostics.InputError` lands beside its
field. The form owns no unit rule and no check: :func:`document` writes what was typed into
the measurement document (a TOML file the command line reads), and the boundary
(:func:`processing.measurement.load`) judges it. :func:`values` is the way back, for a
measurement file opened again for editing.

How a typed value becomes TOML (``docs/web.md``): readings are separated by ``;`` (or by
spaces when each is a bare number), a number with a decimal point is written as a number and
one with a decimal comma as a string ("24,31", which the boundary reads), a number is written
with the unit chosen beside it where that is not the field's own, and a value opening with
``[`` or ``{`` is taken as TOML as it stands (an inline table ``{ value = ..., u = ... }``).
"""
from __future__ import annotations

import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache

from processing.diagnostics import InputError
from processing.measurement import META_KEYS, Field, LabSpec
from processing.inputs.toml_writer import value_text
from processing.units import SLIP_UNITS, same_kind, unit_text

FILE_ACCEPT = "image/*,video/*,.csv,.tsv,.txt,.lvm,.wav,.h5,.hdf5"
"""What a file field offers to pick: a phone's camera (photographs, films) and recordings."""

FILM_ACCEPT = "video/*"
"""What a film field offers: the camera's video."""

_NUMBER = re.compile(r"^[-+]?(?:\d+[.,]?\d*|[.,]\d+)(?:[eE][-+]?\d+)?$")
_POINT_NUMBER = re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$")
_INTEGER = re.compile(r"^[-+]?\d+$")
_ENTRY = re.compile(r"^(?P<section>[a-z_][a-z0-9_]*)(?:\[(?P<index>\d{1,3})\])?\.(?P<field>[A-Za-z_][A-Za-z0-9_]*)$")

MAX_ENTRIES = 200
"""Most entries of a repeated section one form takes."""


@dataclass(frozen=True)
class UnitChoice:
    """A unit offered beside a field: its pint spelling and how a page prints it."""

    value: str
    text: str


def unit_choices(f: Field, lang: str) -> list[UnitChoice]:
    """The units a field's plain number may be given in: its own first, then the usual units
    of the same dimension (:data:`processing.units.SLIP_UNITS`)."""
    if f.kind != "quantity" or f.unit is None:
        return []
    return [UnitChoice(u, unit_text(u, lang) or "—") for u in _units_like(f.unit)]


def warm(specs) -> None:
    """Work out every field's units now (pint: about a second for all labs), not while a
    student waits for the first form."""
    for spec in specs:
        for sec in spec.sections:
            for f in sec.fields:
                if f.kind == "quantity" and f.unit is not None:
                    _units_like(f.unit)


@cache
def _units_like(unit: str) -> tuple[str, ...]:
    """``unit``, then the usual units of its kind (:func:`processing.units.same_kind`: no
    degrees beside a ratio); a page asks for each field's."""
    return (unit, *[u for u in SLIP_UNITS if u and u != unit and same_kind(u, unit)])


def hint(f: Field, lang: str) -> str:
    """What a field's help line says besides its label: repeats, instrument, default."""
    ru = lang == "ru"
    bits = []
    if f.repeated:
        bits.append("повторные отсчёты через «;»" if ru else "repeated readings, separated by ';'")
    elif f.series:
        bits.append("ряд значений через «;»" if ru else "a series of values, separated by ';'")
    if f.limit:
        bits.append(f"{'прибор' if ru else 'instrument'} ± {unit_text(f.limit, lang)}")
    if f.default is not None:
        shown = str(f.default).lower() if isinstance(f.default, bool) else \
            unit_text(str(f.default), lang) if f.unit else f.default
        bits.append(f"{'по умолчанию' if ru else 'default'} {shown}")
    elif not f.required:
        bits.append("необязательно" if ru else "optional")
    return "; ".join(bits)


def accept(f: Field) -> str:
    """The ``accept`` of a file field: a film's field the camera's video, any other a
    photograph, a film or a recording."""
    return FILM_ACCEPT if f.name.startswith("video") else FILE_ACCEPT


def placeholder(f: Field) -> str:
    """A field's example, as the form shows it greyed."""
    if f.example is None:
        return ""
    if isinstance(f.example, (list, tuple)):
        return "; ".join(str(x) for x in f.example)
    return str(f.example)


def field_text(value) -> str:
    """A value of a measurement document as its form field shows it (:func:`values`)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Mapping):
        return value_text(value)
    if isinstance(value, list):
        if all(isinstance(x, (int, float, str)) and not isinstance(x, bool)
               and ";" not in str(x) for x in value):
            return "; ".join(str(x) for x in value)
        return value_text(value)
    return str(value)


def values(doc: Mapping, spec: LabSpec) -> tuple[dict[str, str], dict[str, int]]:
    """A measurement document as form values keyed by field path, and the number of entries
    of each repeated section (at least one)."""
    out = {f"meta.{k}": str(v) for k, v in (doc.get("meta") or {}).items()}
    counts = {}
    for sec in spec.sections:
        raw = doc.get(sec.name)
        entries = raw if isinstance(raw, list) else [raw] if isinstance(raw, dict) else []
        if sec.many:
            counts[sec.name] = max(1, len(entries))
        for i, entry in enumerate(entries if sec.many else entries[:1]):
            where = f"{sec.name}[{i}]" if sec.many else sec.name
            for key, v in (entry or {}).items():
                out[f"{where}.{key}"] = field_text(v)
    return out, counts


def named_files(form: Mapping[str, str], spec: LabSpec) -> dict[str, str]:
    """The files a document's form values (:func:`values`) name, by the path of their field
    (``decay.signal``, ``record[2].signal``)."""
    files = {f.name for sec in spec.sections for f in sec.fields if f.kind == "file"}
    return {path: text for path, text in form.items()
            if path.rsplit(".", 1)[-1] in files and text}


def _error(path: str, problem: str, fix: str, ru: tuple[str, str]) -> InputError:
    return InputError(problem, fix, field=path, ru=ru)


def _literal(text: str, path: str):
    """A value typed as TOML (``[...]`` or ``{...}``)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError as exc:
        raise _error(path, f"'{text[:60]}' is not a TOML value ({exc})",
                     "write readings separated by ';', or a whole TOML array [1.5, 2.5] or "
                     "table { value = \"12.5 mm\", u = \"0.1 mm\" }",
                     (f"'{text[:60]}' — не значение TOML ({exc})",
                      "запишите отсчёты через «;» или целиком массив TOML [1.5, 2.5] или "
                      "таблицу { value = \"12,5 мм\", u = \"0,1 мм\" }")) from None


def readings(text: str) -> list[str]:
    """The readings typed into one field: split at ';', or at spaces where every part is a
    bare number (decimal comma or point); otherwise the one value as typed.

    >>> readings("36,07; 36,21;36,22"), readings("36.07 36.21"), readings("850 ± 0.5 mm")
    (['36,07', '36,21', '36,22'], ['36.07', '36.21'], ['850 ± 0.5 mm'])
    """
    if ";" in text:
        return [p.strip() for p in text.split(";") if p.strip()]
    parts = text.split()
    if len(parts) > 1 and all(_NUMBER.match(p) for p in parts):
        return parts
    return [text]


def _reading(part: str, unit: str | None, own: str | None):
    """One reading as TOML takes it: a number where it is one with a point in the field's
    own unit, otherwise a string (with the chosen unit after a bare number)."""
    if _NUMBER.match(part) and unit and unit != own:
        return f"{part} {unit}"
    if _POINT_NUMBER.match(part):
        return int(part) if _INTEGER.match(part) else float(part)
    return part


def _quantity(text: str, unit: str | None, f: Field, path: str):
    if text[0] in "[{":
        return _literal(text, path)
    parts = [_reading(p, unit, f.unit) for p in readings(text)]
    return parts[0] if len(parts) == 1 else parts


def field_value(f: Field, text: str, unit: str | None, path: str):
    """What a typed field puts into the document (None: nothing, the field left out)."""
    if f.kind == "text":
        text = text.replace("\r\n", "\n")
        return text if text.strip() else None
    text = text.strip()
    if f.kind == "flag":
        return True if text in ("on", "true") else (
            False if f.required and f.default is None else None)
    if not text:
        return None
    if f.kind == "count":
        return int(text) if _INTEGER.match(text) else text
    if f.kind in ("choice", "file"):
        return text
    return _quantity(text, unit, f, path)


def entry_indices(form: Mapping[str, str], section: str) -> list[int]:
    """The indices of a repeated section's entries a form posted, in order."""
    found = set()
    for key in form:
        m = _ENTRY.match(key.split(":")[0])
        if m and m["section"] == section and m["index"] is not None:
            found.add(int(m["index"]))
    return sorted(found)[:MAX_ENTRIES]


def _entry(sec, form: Mapping[str, str], prefix: str, where: str) -> dict:
    entry = {}
    for f in sec.fields:
        v = field_value(f, form.get(f"{prefix}.{f.name}", ""),
                        form.get(f"{prefix}.{f.name}:unit"), f"{where}.{f.name}")
        if v is not None:
            entry[f.name] = v
    return entry


def document(spec: LabSpec, form: Mapping[str, str]) -> dict:
    """The measurement document a posted form describes: ``lab``, ``[meta]`` and each
    section that has a value (an entry of a repeated section with none is dropped; the rest
    are numbered again from 0, as the boundary will name them)."""
    meta = {k: form[f"meta.{k}"].strip() for k in META_KEYS
            if form.get(f"meta.{k}", "").strip()}
    doc: dict = {"lab": spec.id, "meta": meta}
    for sec in spec.sections:
        if sec.many:
            entries = [_entry(sec, form, f"{sec.name}[{i}]", f"{sec.name}[{n}]")
                       for n, i in enumerate(entry_indices(form, sec.name))]
            entries = [e for e in entries if _has_values(sec, e)]
            if entries:
                doc[sec.name] = entries
        else:
            entry = _entry(sec, form, sec.name, sec.name)
            if _has_values(sec, entry):
                doc[sec.name] = entry
    if not meta:
        del doc["meta"]
    return doc


def _has_values(sec, entry: dict) -> bool:
    """Whether an entry holds anything typed (a flag left at false does not count)."""
    return any(v is not False for v in entry.values())
