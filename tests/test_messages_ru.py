"""The command line's messages in Russian: the hostile-input corpora run again under a Russian
locale, and every refusal counted by the language it came out in.

The cases are the corpora's own (:mod:`test_hostile_inputs`, :mod:`test_hostile_cli`): each of
their tests that holds the bad-input contract (:func:`cli_contract.assert_one_clear_error`) is
called here with ``LANG=ru_RU.UTF-8`` and that contract swapped for its Russian form. A message
with Russian must be wholly Russian (``ошибка: <file>, поле '<field>': <problem>. Как
исправить: <fix>``); one without falls back to English whole, and keeps the English contract.
"""
import inspect
import re
from pathlib import Path

import pytest

import test_hostile_cli
import test_hostile_inputs
from cli_contract import assert_one_clear_error, run
from labs.cli.main import main
from processing.diagnostics import InputError

CORPORA = (test_hostile_inputs, test_hostile_cli)
FIXTURES = ("tmp_path", "capsys", "monkeypatch")

PARTLY_RUSSIAN: dict[str, int] = {}
"""The corpus tests whose refusals are not all in Russian yet, and how many of them are (a
count may only grow); every other corpus test's refusals must all be in Russian."""

LARGE_GRID, STRIDE = 30, 4
"""A corpus test of more than LARGE_GRID cases (the quantity corpus has 636, made of a few
kinds of slip crossed with every field) runs every STRIDE-th here: its kinds and fields all
come round, in a quarter of the time; the corpus itself runs every case in English."""

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
            if ("assert_one_clear_error(" not in source and "run_bad(" not in source) or \
                    any(m.name == "skipif" and m.args[0] for m in marks):
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
    for i, kwargs in enumerate(grid if len(grid) <= LARGE_GRID else grid[::STRIDE]):
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
