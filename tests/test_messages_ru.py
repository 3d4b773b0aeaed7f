"""The command line's messages in Russian: the hostile-input corpora run again under a Russian
locale, and every refusal counted by the language it came out in.

The cases are the corpora's own (:mod:`test_hostile_inputs`, :mod:`test_hostile_cli`,
:mod:`test_hostile_images`, :mod:`test_hostile_records`): each of their tests that holds the
bad-input contract (:func:`cli_contract.assert_one_clear_error`) and needs no fixture of its
own is called here with ``LANG=ru_RU.UTF-8`` and that contract swapped for its Russian form. A
message with Russian must be wholly Russian (``ошибка: <file>, поле '<field>': <problem>. Как
исправить: <fix>``); one without falls back to English whole, and keeps the English contract.

The readers of photographs, films and traces are held closer: every refusal they build carries
its Russian (read off their source), the details they embed (why no trace, the lines found,
which way is up) are made in Russian where they are found; and the command's own parser and
help speak the language asked.
"""
import inspect
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import test_hostile_cli
import test_hostile_images
import test_hostile_inputs
import test_hostile_records
from cli_contract import assert_one_clear_error, run
from labs.cli.main import main
from processing.diagnostics import InputError

CORPORA = (test_hostile_inputs, test_hostile_cli, test_hostile_images, test_hostile_records)
FIXTURES = ("tmp_path", "capsys", "monkeypatch")
CONTRACT_CALLS = ("assert_one_clear_error(", "run_bad(", "refused(")
"""The calls through which a corpus test holds the bad-input contract."""

PARTLY_RUSSIAN: dict[str, int] = {}
"""The corpus tests whose refusals are not all in Russian yet, and how many of them are (a
count may only grow); every other corpus test's refusals must all be in Russian."""

LARGE_GRID, STRIDE = 30, 4
"""A corpus test of more than LARGE_GRID cases (the quantity corpus has 636, made of a few
kinds of slip crossed with every field) runs every STRIDE-th here: its kinds and fields all
come round, in a quarter of the time; the corpus itself runs every case in English."""

SLOW_CORPORA = {"test_hostile_records": 2}
"""Corpora whose every case reduces a lab's recording (seconds each): a test of more cases
than this runs every STRIDE-th here."""

ENGLISH = re.compile(r"\b(?:the|is|are|not|of|and|or|to|from|with|give|write|check|must|"
                     r"has|have|cannot|file|value|reading|readings|record|channel|column|row|"
                     r"samples|its)\b")
"""Common English words: one of them in a Russian message, outside what the message quotes
(a key, a value, a path, a command), is English left in."""

QUOTED = re.compile(r"'[^']*'|\"[^\"]*\"|`[^`]*`|\{[^}]*\}|\[[^\]]*\]|\S*/\S*|\w+ =")
"""What a message quotes from the file or the system: quoted text, tables, paths, keys."""


def _corpus_tests():
    """Every test of the corpora that goes through the bad-input contract, needs no fixture
    but :data:`FIXTURES` and is not skipped here: (module, function) pairs."""
    for module in CORPORA:
        for name, fn in vars(module).items():
            if not (name.startswith("test_") and callable(fn)):
                continue
            source = inspect.getsource(fn)
            marks = getattr(fn, "pytestmark", [])
            given = set(FIXTURES) | {n for g in _grid(fn) for n in g}
            if not any(call in source for call in CONTRACT_CALLS) or \
                    any(m.name == "skipif" and m.args[0] for m in marks) or \
                    not set(inspect.signature(fn).parameters) <= given:
                continue
            yield pytest.param(module, fn, id=f"{module.__name__}.{name}")


def _grid(fn) -> list[dict]:
    """The keyword arguments of each of ``fn``'s parametrised cases."""
    grid = [{}]
    for mark in (m for m in getattr(fn, "pytestmark", []) if m.name == "parametrize"):
        names = mark.args[0].split(",") if isinstance(mark.args[0], str) else mark.args[0]
        names = [n.strip() for n in names]
        rows = [p.values if hasattr(p, "values") else (p if len(names) > 1 else (p,))
                for p in mark.args[1]]
        grid = [{**g, **dict(zip(names, row))} for g in grid for row in rows]
    return grid


@pytest.mark.parametrize("module, fn", list(_corpus_tests()))
def test_the_corpora_refuse_in_russian_under_a_russian_locale(tmp_path, capsys, monkeypatch,
                                                              module, fn):
    tally = {"ru": 0, "en": [], "mixed": []}

    def contract_ru(code, out, err, file: Path, field, problem, out_dir):
        lines = err.strip().splitlines()
        shown = f"\n--- stderr:\n{err}"
        if not (lines and lines[0].startswith("ошибка: ")):
            tally["en"].append(lines[0] if lines else err)
            return assert_one_clear_error(code, out, err, file, field, problem, out_dir)
        assert code == 2 and len(lines) == 1 and "Traceback" not in out + err, shown
        msg = lines[0]
        assert file.name in msg, f"the file is not named{shown}"
        if field is not None:
            assert f"поле '{field}'" in msg, f"the field is not named{shown}"
        assert "Fix:" not in msg and msg.split("Как исправить:", 1)[1].strip(), shown
        told = msg.replace(str(file), "").replace(str(out_dir), "")
        if ENGLISH.search(QUOTED.sub("", told)):
            tally["mixed"].append(msg)
        assert out.strip() == "" and not (out_dir.exists() and any(out_dir.iterdir())), shown
        tally["ru"] += 1

    for var in ("LC_ALL", "LC_MESSAGES"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    monkeypatch.setattr(module, "assert_one_clear_error", contract_ru)
    wants = inspect.signature(fn).parameters
    grid = _grid(fn)
    largest = SLOW_CORPORA.get(module.__name__, LARGE_GRID)
    for i, kwargs in enumerate(grid if len(grid) <= largest else grid[::STRIDE]):
        case_dir = tmp_path / f"case{i}"
        case_dir.mkdir()
        given = {"tmp_path": case_dir, "capsys": capsys, "monkeypatch": monkeypatch}
        fn(**{k: v for k, v in given.items() if k in wants}, **kwargs)
    total = tally["ru"] + len(tally["en"])
    print(f"\n{fn.__name__}: refusals in Russian: {tally['ru']} of {total}")
    assert not tally["mixed"], "English words in Russian messages:\n" + "\n".join(tally["mixed"])
    english = "\n".join(sorted(set(tally["en"])))
    assert tally["ru"] >= PARTLY_RUSSIAN.get(fn.__name__, total), \
        f"only {tally['ru']} of {total} refusals in Russian; in English:\n{english}"


def test_a_message_without_russian_falls_back_to_english_whole(capsys, monkeypatch):
    e = InputError("a problem", "a fix", file="a.toml", field="x.y")
    assert e.line("ru") == e.line("en") == "error: a.toml, field 'x.y': a problem. Fix: a fix"
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    monkeypatch.delenv("LC_ALL", raising=False)
    monkeypatch.delenv("LC_MESSAGES", raising=False)
    code, out, err = run(capsys, "kinematics", "--lambda", "0.25", "--step", "0")
    assert code == 2 and err.startswith("ошибка: --step должен лежать в (0, 180]"), err
    monkeypatch.setenv("LC_ALL", "C")
    code, out, err = run(capsys, "kinematics", "--lambda", "0.25", "--step", "0")
    assert err.startswith("error: --step must be in (0, 180]"), err


@pytest.mark.parametrize("args, told", [
    (["run"], "dynlab run: ошибка: не заданы обязательные аргументы: FILE"),
    (["frob"], "dynlab: ошибка: аргумент command: значение 'frob' не из списка"),
    (["kinematics", "--lambda", "x"], "dynlab kinematics: ошибка: аргумент --lambda: 'x' — не "
                                      "число"),
    (["synth", "lab1", "--seed", "-3"], "dynlab synth: ошибка: аргумент --seed: зерно — целое"),
    (["run", "a.toml", "--format", "doc"], "dynlab run: ошибка: аргумент --format: неизвестный "
                                           "формат 'doc'"),
    (["run", "a.toml", "--bogus"], "dynlab: ошибка: непонятные аргументы: --bogus"),
])
def test_the_parsers_own_messages_speak_the_locale_or_lang(capsys, monkeypatch, args, told):
    """argparse's messages (a missing file, a choice not allowed, a number that is none) are
    the command's messages too: Russian under a Russian locale or ``--lang ru``, with the
    usage line and exit 2; English otherwise."""
    def run(capsys, *argv):
        with pytest.raises(SystemExit) as exited:
            main(list(argv))
        cap = capsys.readouterr()
        return exited.value.code, cap.out, cap.err

    monkeypatch.delenv("LC_ALL", raising=False)
    monkeypatch.delenv("LC_MESSAGES", raising=False)
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    code, out, err = run(capsys, *args)
    assert code == 2 and out == "" and err.startswith("вызов: dynlab"), err
    assert err.strip().splitlines()[-1].startswith(told), err
    monkeypatch.setenv("LANG", "C")
    code, out, err = run(capsys, *args, "--lang", "ru")
    assert code == 2 and err.strip().splitlines()[-1].startswith(told), err
    code, out, err = run(capsys, *args)
    assert code == 2 and "ошибка" not in err and ": error: " in err, err


def _english_left(text: str) -> str | None:
    """An English word in a Russian text, outside what it quotes (None if there is none)."""
    found = ENGLISH.search(QUOTED.sub("", text))
    return found and found.group()


def _refused_in_russian(call) -> InputError:
    """``call``'s refusal, checked to carry Russian with no English word left in it."""
    with pytest.raises(InputError) as refused:
        call()
    e = refused.value
    assert e.ru is not None, f"no Russian for: {e.line('en')}"
    assert _english_left(e.line("ru")) is None, e.line("ru")
    return e


def _paper_scene(zero_line: bool = True, mark_period: float = 0.01, tdc: bool = True):
    from processing.synth.paper_record import Beam, Layout, Shot, render

    def decay(t):
        return np.exp(-2.0 * t) * np.cos(2 * np.pi * 12 * t)

    layout = Layout(length=0.2, width=0.12, speed=0.5, mark_period=mark_period,
                    pip_duty=0.03 if mark_period > 0.05 else 0.3,
                    tdc_times=tuple(np.arange(0.013, 0.4, 0.0667)) if tdc else ())
    shot = Shot(size=(1000, 650), fill=0.8, rotation=1.5, blur=1.0, noise=3.0, jpeg=90)
    return render(layout, [Beam(decay, 0.06, 0.03, zero_line=zero_line)], shot, seed=3).image


@pytest.mark.parametrize("case", ["blank paper", "too few time marks", "no zero line",
                                  "gaps not bridged"])
def test_the_paper_readers_refusals_tell_their_details_in_russian(case):
    """The details a paper record's refusal embeds (why no trace, why no time base, the
    straight lines found) are made in Russian where they are found, not left in English."""
    from processing.vision import read_paper_record

    if case == "blank paper":
        blank = np.full((400, 800, 3), 215, np.uint8)
        e = _refused_in_russian(lambda: read_paper_record(blank, paper_speed=0.5, dpi=300))
        assert "ни одна линия записи" in e.ru[0], e.ru
    elif case == "too few time marks":
        image = _paper_scene(mark_period=0.2, tdc=False)
        e = _refused_in_russian(lambda: read_paper_record(image, mark_period=0.2,
                                                          paper_width=0.12))
        assert "отмет" in e.ru[0], e.ru
    elif case == "no zero line":
        image = _paper_scene(zero_line=False)
        e = _refused_in_russian(lambda: read_paper_record(image, mark_period=0.01,
                                                          paper_width=0.12, zero="line"))
        assert "найдены прямые линии" in e.ru[0] and "мм (отметки" in e.ru[0], e.ru
    else:
        rec = read_paper_record(_paper_scene(), mark_period=0.01, paper_width=0.12)
        holed = replace(rec, value=np.where(np.arange(rec.length) % 50 == 7, np.nan,
                                            rec.value))
        assert "вдоль" in rec.lines_ru or "найдены" in rec.lines_ru, rec.lines_ru
        assert _english_left(rec.lines_ru) is None, rec.lines_ru
        e = _refused_in_russian(lambda: list(holed.chunks()))
        assert "не прочитана" in e.ru[0], e.ru


@pytest.mark.parametrize("time_side, tdc_side, time_below", [(1, 1, True), (-1, None, False)])
def test_which_way_is_up_is_told_in_russian(time_side, tdc_side, time_below):
    """The signs of a sheet's orientation that disagree are named in the refusal's Russian."""
    from types import SimpleNamespace as Fake

    from processing.vision.record import _orientation_unknown, _where

    def pips(side, position):
        return None if side is None else Fake(side=side, line=Fake(position=position))

    laid = Fake(time_pips=pips(time_side, 300 if time_below else 100),
                tdc_pips=pips(tdc_side, 200))
    e = _orientation_unknown(_where("sheet.jpg", "decay.signal", "image"), laid)
    assert e.ru is not None and _english_left(e.line("ru")) is None, e.line("ru")
    assert "отметки времени направлены" in e.ru[0], e.ru


READERS = ("processing/vision/record.py", "processing/vision/video.py",
           "processing/vision/frames.py", "processing/vision/paper.py",
           "processing/vision/marks.py", "processing/vision/traces.py",
           "processing/vision/header.py", "processing/speed/cycle_range.py",
           "processing/oscillations/decay.py")
"""The readers of photographs, films and traces whose refusals embed details made deep down."""


def _without_russian(tree) -> list[int]:
    """Lines of ``tree`` that build a refusal with no Russian: an InputError, or a helper
    named ``*refuse``/``error`` given a problem and a fix, without ``ru``; a :class:`Reason`
    (or its subclasses) given fewer than two texts."""
    import ast

    lines = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else ""
        has_ru = any(k.arg in ("ru", None) for k in node.keywords)
        if name == "InputError" and not has_ru:
            lines.append(node.lineno)
        elif (name.endswith("refuse") or name == "error") and len(node.args) >= 2 and \
                not has_ru and len(node.args) < 5 - (name == "error"):
            lines.append(node.lineno)
        elif name in ("Reason", "NoTraceError", "TimeMarkError", "HeaderError",
                      "NoDecayError") and len(node.args) < 2:
            lines.append(node.lineno)
    return lines


@pytest.mark.parametrize("path", READERS)
def test_every_refusal_of_the_readers_carries_its_russian(path):
    """A refusal added to a reader of photographs, films or traces without its Russian text
    (``ru=(problem, fix)``, or a reason's ``ru``) is caught here, before a student meets it
    half in English."""
    import ast

    source = (Path(__file__).parents[1] / path).read_text(encoding="utf-8")
    missing = _without_russian(ast.parse(source))
    assert not missing, f"{path}: refusals without Russian at lines {missing}"


def _argparse_message_ids() -> set:
    """The format strings the running Python's argparse passes through its gettext hook
    (``_(...)``, ``ngettext(...)``): its message ids, read off its source."""
    import argparse
    import ast

    ids = set()
    for node in ast.walk(ast.parse(Path(inspect.getsourcefile(argparse)).read_text())):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                node.func.id in ("_", "ngettext"):
            texts = tuple(a.value for a in node.args[:2] if isinstance(a, ast.Constant))
            if texts:
                ids.add(texts[0] if node.func.id == "_" else texts)
    return ids


def test_the_parsers_russian_is_keyed_by_this_pythons_argparse_message_ids():
    """The Russian of argparse's messages is looked up by the format strings argparse
    itself passes to gettext, not by matching its finished English: each one translated is
    one this Python's argparse uses (a Python that words one differently fails here, naming
    it, instead of printing it in English unseen), and the command's own argument types
    translate through the same hook."""
    from labs.cli.parser import ARGPARSE_NGETTEXT_RU, ARGPARSE_RU, speaking, told

    ids = _argparse_message_ids()
    unknown = sorted(set(ARGPARSE_RU) - ids) + sorted(set(ARGPARSE_NGETTEXT_RU) - ids)
    assert not unknown, f"argparse no longer says: {unknown}"
    with speaking("ru"):
        assert told("%(got)r is not a whole number", got="2.5") == "'2.5' — не целое число"
    assert told("%(got)r is not a whole number", got="2.5") == "'2.5' is not a whole number"


def _helps(p) -> list[tuple[str, str]]:
    """(command, help) of every argument and subcommand of parser ``p`` and its
    subcommands'."""
    import argparse

    out = [("dynlab", p.description)]
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            out += [(name, c.help) for name, c in zip(action.choices, action._choices_actions)]
            for name, sub in action.choices.items():
                out += [(f"{name} {a.dest}", a.help) for a in sub._actions]
        else:
            out.append((f"dynlab {action.dest}", action.help))
    return out


def test_the_help_speaks_the_locale_or_lang(capsys, monkeypatch):
    """``dynlab --help`` and every subcommand's help are Russian under a Russian locale or
    ``--lang ru``: every argument's help (argparse's own -h included), the headings and the
    usage line; English otherwise."""
    from labs.cli.main import parser

    def helped(*argv):
        with pytest.raises(SystemExit) as exited:
            main(list(argv))
        assert exited.value.code == 0
        return capsys.readouterr().out

    latin = [(where, text) for where, text in _helps(parser("ru"))
             if text and not re.search("[а-яё]", text, re.I)]
    assert not latin, f"help left in English: {latin}"
    english = {text for _, text in _helps(parser("en")) if text}
    assert not english & {text for _, text in _helps(parser("ru"))}
    monkeypatch.delenv("LC_ALL", raising=False)
    monkeypatch.delenv("LC_MESSAGES", raising=False)
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    shown = helped("--help")
    assert shown.startswith("вызов: dynlab") and "позиционные аргументы:" in shown and \
        "показать эту справку и выйти" in shown, shown
    monkeypatch.setenv("LANG", "C")
    shown = helped("run", "--help", "--lang", "ru")
    assert shown.startswith("вызов: dynlab run") and "ключи:" in shown and \
        _english_left(shown) is None, shown
    shown = helped("run", "--help")
    assert shown.startswith("usage: dynlab run") and "options:" in shown, shown
