"""The ``dynlab`` command: a thin layer over the library.

    dynlab run FILE... [--out DIR] [--format html,pdf,json] [--lang en|ru] [--json] [--confine]
    dynlab list
    dynlab template LAB [--lang en|ru] [-o FILE]
    dynlab demo [--out DIR] [--lang en|ru]
    dynlab kinematics --lambda 0.25 [--offset z] [--step 5] [--approx] [--format table|csv]
    dynlab serve [--host 127.0.0.1] [--port 8000] [--lang en|ru] [--class DIR --roster CSV]

Bad input prints one message naming the file, the field and the fix, and exits with 2.
The command's own lines and its messages are in the language of ``--lang``, or, where a
command is given none, of the locale (``LC_ALL``, ``LC_MESSAGES``, ``LANG`` beginning with
``ru``); a message the toolkit has no Russian for is printed in English.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from processing import __version__
from processing.diagnostics import InputError
from processing.files import MEASUREMENT, regular, resolved
from processing.reporting.i18n import LANGS

from labs.catalogue import CATALOGUE
from .parser import Parser, told
from labs.registry import LABS, evaluate, lab_module

# The report engine (matplotlib, pandas, pint) and the labs are imported where they are used,
# so that `dynlab list` and `--help` answer at once.

EXIT_INPUT = 2


def locale_lang(environ=os.environ) -> str:
    """The language of the command's messages when no ``--lang`` is given: the locale's
    (the first of ``LC_ALL``, ``LC_MESSAGES``, ``LANG`` that is set, as POSIX reads them).

    >>> locale_lang({"LANG": "ru_RU.UTF-8"}), locale_lang({"LC_ALL": "C", "LANG": "ru_RU"})
    ('ru', 'en')
    """
    for name in ("LC_ALL", "LC_MESSAGES", "LANG"):
        if environ.get(name):
            return "ru" if environ[name].lower().startswith("ru") else "en"
    return "en"


def say(lang: str, en: str, ru: str) -> str:
    """One of the command's own lines in ``lang``."""
    return ru if lang == "ru" else en


MAX_SEED = 2**63 - 1
"""Largest seed: 19 digits, which the written files' names carry."""


def _seed(text: str) -> int:
    """A seed of the random generators: a whole number from 0 to :data:`MAX_SEED`."""
    if not (text.isascii() and text.isdigit()) or int(text) > MAX_SEED:
        raise argparse.ArgumentTypeError(told("a seed is a whole number from 0 to %(most)d, "
                                              "got %(got)r", most=MAX_SEED, got=text[:40]))
    return int(text)


def _count(least: int, most: int):
    """An option's whole number from ``least`` to ``most``."""
    def parse(text: str) -> int:
        if not (text.isascii() and text.isdigit()) or not least <= int(text) <= most:
            raise argparse.ArgumentTypeError(told("a whole number from %(least)d to %(most)d, "
                                                  "got %(got)r", least=least, most=most,
                                                  got=text[:40]))
        return int(text)
    return parse


def _seconds(text: str) -> float:
    """A positive, finite number of seconds."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < 1e6:
        raise argparse.ArgumentTypeError(told("a number of seconds above 0, got %(got)r",
                                              got=text[:40]))
    return value


def _number(text: str) -> float:
    """An option's number (as ``float`` reads it)."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(told("%(got)r is not a number", got=text[:40])) from None


def _whole(text: str) -> int:
    """An option's whole number (as ``int`` reads it)."""
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(told("%(got)r is not a whole number",
                                              got=text[:40])) from None


def _formats(text: str) -> tuple[str, ...]:
    from processing.reporting.render import FORMATS

    fmts = tuple(f.strip() for f in text.split(",") if f.strip())
    bad = [f for f in fmts if f not in FORMATS]
    if bad or not fmts:
        raise argparse.ArgumentTypeError(told("unknown format %(bad)s; use a comma list of "
                                              "%(known)s", bad=repr(', '.join(bad) or text),
                                              known=', '.join(FORMATS)))
    return fmts


def _progress(items, desc: str):
    from tqdm import tqdm

    return tqdm(items, desc=desc, unit="file", file=sys.stderr, leave=False,
                disable=len(items) < 2 or not sys.stderr.isatty())


def _write(result, out: Path, stem: str, formats, lang: str) -> list[Path]:
    """:func:`write_reports`, with an unwritable ``--out`` reported as bad input."""
    from processing.reporting.render import write_reports

    try:
        return write_reports(result, out, stem, formats, lang)
    except OSError as exc:
        raise InputError(f"cannot write the reports there ({exc.strerror or exc})",
                         "give --out a folder you can write to", file=str(out),
                         ru=(f"отчёты туда не записать ({exc.strerror or exc})",
                             "укажите в --out папку, в которую можно писать")) from None


def _stems(files) -> list[str]:
    """Report names, one per file and all different: the file's stem, prefixed by as many of
    its folders as it takes to tell files of the same stem apart.

    >>> _stems(["a/x/rod.toml", "b/x/rod.toml", "flywheel.toml"])
    ['a-x-rod', 'b-x-rod', 'flywheel']
    """
    paths = [resolved(f) for f in files]
    stems = []
    for p in paths:
        rivals = [q for q in paths if q.stem == p.stem and q != p]
        depth = 0
        while rivals and depth < len(p.parts) - 1:
            depth += 1
            rivals = [q for q in rivals if q.parts[-depth - 1:-1] == p.parts[-depth - 1:-1]]
        stems.append("-".join([*p.parts[len(p.parts) - 1 - depth:-1], p.stem]))
    return stems


def _unique(files, lang: str = "en") -> list[str]:
    """The files, each once (a file given twice is reduced once, and the user told)."""
    seen, kept = set(), []
    for f in files:
        key = resolved(f)
        if key in seen:
            print(say(lang, f"note: {f} is given more than once; it is reduced once",
                      f"примечание: {f} указан не один раз; он обработан однажды"),
                  file=sys.stderr)
            continue
        seen.add(key)
        kept.append(f)
    return kept


def _internal(exc: Exception, where: str | None = None) -> str:
    """The line that reports an internal error (of one file, if ``where``)."""
    return (f"internal error{f' in {where}' if where else ''}: {type(exc).__name__}: {exc} "
            "(run with --debug for the traceback, and please report it)")


def _run_files(files, out: Path | None, formats, lang: str, as_json: bool,
               confine: bool = False, debug: bool = False, says: str = "en") -> int:
    """Reduce each file; write its reports to ``out`` (None: write nothing) in ``formats``
    (None: every format). A bad file, or one the toolkit fails on, is reported and the others
    are reduced; a path that is no measurement file is refused before the reduction's and the
    reports' libraries are loaded. The messages are in ``says``, the reports in ``lang``."""
    failures, crashes, documents = 0, 0, []
    files = _unique(files, says)
    for path, stem in _progress(list(zip(files, _stems(files))), "reducing"):
        try:
            regular(path, MEASUREMENT)
            from processing.measurement import read_toml

            data = read_toml(path)
            reported = data.pop("reported", None)       # a submission's: dynlab check's table
            result = evaluate(path, data=data, confine=confine)
            from processing.reporting.render import FORMATS, to_json, to_terminal

            formats = formats or FORMATS
            replaced = [p for p in (out / f"{stem}.{f}" for f in formats) if p.exists()] \
                if out is not None else []
            written = _write(result, out, stem, formats, lang) if out is not None else []
        except InputError as exc:
            print(exc.line(says), file=sys.stderr)
            failures += 1
            continue
        except Exception as exc:
            if debug or len(files) == 1:
                raise
            print(_internal(exc, str(path)), file=sys.stderr)
            crashes += 1
            continue
        if as_json:
            documents.append(to_json(result))
        else:
            print(to_terminal(result, lang))
            replaced_word = say(says, " (replaced)", " (заменён)")
            print("  → " + ", ".join(str(p) + (replaced_word if p in replaced else "")
                                     for p in written))
            if reported is not None:
                print(say(says, f"  [reported]: your values are judged by: dynlab check {path}",
                          f"  [reported]: ваши значения проверит: dynlab check {path}"))
    if documents:
        print(documents[0] if len(files) == 1 else "[\n" + ",\n".join(documents) + "\n]")
    return 1 if crashes else EXIT_INPUT if failures else 0


def _run(args) -> int:
    writes = not args.json or args.out is not None or args.format is not None
    out = Path(args.out or "reports") if writes else None
    if out is not None:
        _writable_folder(out, "--out", "the reports")
    return _run_files(args.files, out, args.format, args.lang, args.json, args.confine,
                      args.debug, args.says)


def _demo(args) -> int:
    from processing.reporting.render import FORMATS, to_terminal

    from labs.samples import sample_dir

    data = sample_dir(args.data)
    files = sorted(data.glob("*/*.toml"))
    out = Path(args.out)
    print(say(args.says, f"dynlab demo: {len(files)} sample files from {data} → {out}/",
              f"dynlab demo: {len(files)} файлов примеров из {data} → {out}/"))
    results = []
    for path in _progress(files, "demo"):
        results.append(evaluate(path))
        _write(results[-1], out, path.stem, FORMATS, args.lang)
    for result in results:
        print()
        print(to_terminal(result, args.lang))
    print(say(args.says, f"\nreports (html, pdf, json) for {len(results)} files written to "
                         f"{out.resolve()}",
              f"\nотчёты (html, pdf, json) по {len(results)} файлам записаны в {out.resolve()}"))
    return 0


def _template(args) -> int:
    module = lab_module(args.lab)
    from processing.measurement import template

    text = template(module.SPEC, args.lang)
    if args.output:
        _write_file(Path(args.output), text, "-o")
        print(say(args.says, f"wrote {args.output}: fill it in, then run: dynlab run {args.output}",
                  f"записан {args.output}: заполните его, затем запустите: dynlab run "
                  f"{args.output}"))
    else:
        sys.stdout.write(text)
    return 0


def _write_file(path: Path, text: str, option: str) -> None:
    """Write ``text`` to a new or regular file (a FIFO would block the writer, a device
    swallow the text), an unwritable path reported as bad input."""
    import stat

    try:
        kind = path.stat().st_mode
    except OSError:
        kind = None
    if kind is not None and not stat.S_ISREG(kind):
        raise InputError("it exists and is not a regular file", f"give {option} the name of "
                         "a new file, or of a file to replace", file=str(path),
                         ru=("он существует и не является обычным файлом",
                             f"укажите в {option} имя нового файла или файла, который можно "
                             "заменить"))
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot write it ({exc.strerror or exc})", f"give {option} a file "
                         "in a folder you can write to", file=str(path),
                         ru=(f"его не записать ({exc.strerror or exc})",
                             f"укажите в {option} файл в папке, в которую можно писать")
                         ) from None


def _kinematics(args) -> int:
    from processing.crank.kinematics import kinematics_table

    if not 0 < args.step <= 180:
        raise InputError(f"--step must be in (0, 180] degrees, got {args.step:g}",
                         "give a step such as 5 or 15",
                         ru=(f"--step должен лежать в (0, 180] градусов, а не {args.step:g}",
                             "задайте шаг, например 5 или 15"))
    table = kinematics_table(args.lambda_, args.offset, step_deg=args.step,
                             method="approx" if args.approx else "exact")
    table = table.rename(columns={"alpha_deg": "alpha", "beta_deg": "beta",
                                  "v": "v/(R*omega)", "j": "j/(R*omega^2)", "s": "s/R"})
    if args.format == "csv":
        sys.stdout.write((table.round(6) + 0.0).to_csv(index=False))
    else:
        kind = "approximate (to λ²)" if args.approx else "exact"
        print(f"# crank-slider kinematics, {kind}: λ = {args.lambda_:g}, z = k/R = "
              f"{args.offset:g}; α, β in degrees")
        shown = table.round({"beta": 2, "s/R": 4, "v/(R*omega)": 4, "j/(R*omega^2)": 4}) + 0.0
        print(shown.to_string(index=False, formatters={
            "alpha": "{:g}".format, "beta": "{:.2f}".format,
            **{c: "{:.4f}".format for c in ("s/R", "v/(R*omega)", "j/(R*omega^2)")}}))
    return 0


def _check(args) -> int:
    """Judge each submission's [reported] values; a folder is a class: every .toml in it,
    a summary written, the pairs with the same readings named. In a class, a submission
    that cannot be checked (bad input, or a failure of the toolkit) is listed as refused
    with its reason and the others are checked."""
    import json

    from labs.teachers.check import (ClassCheck, check, check_class, read_policy, read_variants,
                                     submissions, unknown_expected)
    from labs.teachers.check_report import terminal, write_summary
    from labs.teachers.variants import read_roster

    files, folders = [], []
    for item in args.files:
        p = Path(item)
        if _is_folder(p):
            folders.append(p)
            files += submissions(p)
        else:
            files.append(p)
    if folders and not files:
        raise InputError("no .toml submission in the folder", "give the folder holding the "
                         "students' measurement files", file=str(folders[0]),
                         ru=("в папке нет ни одного файла .toml",
                             "укажите папку с файлами измерений студентов"))
    files = _unique(files, args.says)              # a file given twice is no pair of copies
    policy = read_policy(args.policy)
    if args.keys is not None and not folders:
        raise InputError("--keys goes with a class folder", "give the folder of the students' "
                         "subfolders (as dynlab synth --students wrote them)", file=args.keys,
                         ru=("--keys задают вместе с папкой группы",
                             "укажите папку с подпапками студентов (как их записал dynlab "
                             "synth --students)"))
    if args.keys is not None and not Path(args.keys).is_dir():
        raise InputError("--keys is not a folder", "give the folder of the answer keys, "
                         "KEYDIR/<id>/answer_key.json, as dynlab synth --students wrote it",
                         file=args.keys,
                         ru=("--keys — не папка", "укажите папку ключей ответов, "
                             "KEYDIR/<id>/answer_key.json, как её записал dynlab synth "
                             "--students"))
    if args.roster is not None and args.keys is None:
        raise InputError("--roster goes with --keys", "give the answer keys' folder with "
                         "--keys KEYDIR (the roster names whose each key is)", file=args.roster,
                         ru=("--roster задаётся вместе с --keys", "укажите папку ключей "
                             "ответов: --keys KEYDIR (список группы говорит, чей каждый ключ)"))
    out = Path(args.out)
    if folders:
        _writable_folder(out, "--out", "the class summary")
    variants = None if args.keys is None else read_variants(
        args.keys, None if args.roster is None else read_roster(args.roster))
    alone = len(files) == 1 and not folders

    def crash(exc: Exception, path: str) -> str:
        if args.debug:
            raise exc
        return _internal(exc, path)

    if alone:                                      # bad input stops a single file
        checks = [check(files[0], policy=policy)]
        unknown_expected(checks, policy)
        result = ClassCheck(checks, {}, [], policy)
    else:
        result = check_class([Path(f) for f in files], folders, policy=policy,
                             variants=variants, keys=args.keys, lang=args.lang,
                             progress=lambda items: _progress(items, "check"), crash=crash)
    checks, pairs = result.checks, result.pairs
    said = [p if isinstance(p, str) else p.line(args.says) for p in result.problems.values()]
    if args.json:
        print(json.dumps([c.to_dict() for c in checks] if not alone else checks[0].to_dict(),
                         ensure_ascii=False, indent=1))
    else:
        for c in checks:
            print(terminal(c, args.lang))
        for pair in pairs:
            print(say(args.says, f"copies: {pair.a.file} and {pair.b.file}: {pair.text('en')}",
                      f"копии: {pair.a.file} и {pair.b.file}: {pair.text('ru')}"))
    for line in said:
        print(line, file=sys.stderr)
    if folders:
        try:
            written = write_summary(out, result, args.lang)
        except OSError as exc:
            raise InputError(f"cannot write the summary there ({exc.strerror or exc})",
                             "give --out a folder you can write to", file=str(out),
                             ru=(f"сводку туда не записать ({exc.strerror or exc})",
                                 "укажите в --out папку, в которую можно писать")) from None
        print(say(args.says, "class summary: ", "сводка по группе: ")
              + ", ".join(str(w) for w in written), file=sys.stderr)
    return EXIT_INPUT if result.refused else 0


def _writable_folder(out: Path, option: str, what: str) -> None:
    """Refuse an output folder that is a file, or lies under one, or that the system cannot
    make (nothing is written yet)."""
    problem = problem_ru = None
    try:
        for p in (out, *out.parents):
            if p.exists():
                if not p.is_dir():
                    problem = f"{'it' if p == out else repr(str(p))} is a file, not a folder"
                    problem_ru = f"{'это' if p == out else repr(str(p))} — файл, а не папка"
                break
    except OSError as exc:
        problem = problem_ru = exc.strerror or str(exc)
    if problem is not None:
        raise InputError(f"cannot write {what} there: {problem}",
                         f"give {option} a folder you can write to (a new one is made)",
                         file=str(out), ru=(f"туда не записать: {problem_ru}",
                                            f"укажите в {option} папку, в которую можно писать "
                                            "(новая будет создана)"))


def _is_folder(path: Path) -> bool:
    """Whether ``path`` is a folder (a path the system cannot follow is not)."""
    try:
        return path.is_dir()
    except OSError:
        return False


def _serve(args) -> int:
    from labs.web.serve import main as serve

    return serve(args)


def _list(_args) -> int:
    for lab_id, entry in CATALOGUE.items():
        print(f"{lab_id:8} {entry.title['en']}  /  {entry.title['ru']}")
    return 0


def _synth(args) -> int:
    """``write_synthetic`` of the lab, with the options it takes; an option it does not take,
    a value its scene does not model (:mod:`labs.cli.synth_options`) or an ``--out`` that is no
    folder is bad input, refused before anything is written."""
    import inspect

    from .synth_options import check_options

    given = {name: value for name, value in
             (("fmt", args.format), ("snr_db", args.snr), ("pitch_error_deg", args.pitch_error),
              ("sample_rate", args.sample_rate), ("runs", args.runs),
              ("friction", args.friction), ("contact", args.contact), ("lash", args.lash),
              ("periods", args.periods), ("amplitude_exponent", args.amplitude_exponent),
              ("paper", args.paper or None), ("image", args.image or None),
              ("film", args.film or None),
              ("recording", False if args.no_recording else None), ("part", args.part))
             if value is not None}
    check_options(args.lab, given)
    out = Path(args.out)
    _writable_folder(out, "--out", "the synthetic measurement")
    module = LABS[args.lab]
    write = getattr(module, "write_synthetic", None)
    if write is None:
        scenes = [k for k, m in LABS.items() if hasattr(m, "write_synthetic")]
        raise InputError(f"{args.lab} has no synthetic scene yet",
                         f"use one of {', '.join(scenes)}",
                         ru=(f"у {args.lab} пока нет синтетической сцены",
                             f"выберите одну из {', '.join(scenes)}"))
    takes = inspect.signature(write).parameters
    foreign = [name for name in given if name not in takes]
    if foreign:
        raise InputError(f"dynlab synth {args.lab} takes no {', '.join(foreign)}",
                         f"leave those options out for {args.lab}",
                         ru=(f"dynlab synth {args.lab} не принимает {', '.join(foreign)}",
                             f"уберите эти параметры для {args.lab}"))
    fmt = given.get("fmt", takes["fmt"].default if "fmt" in takes else None)
    _check_format(module, args.lab, fmt, given.get("sample_rate"))
    given.update({k: round(given[k] * 1e3, 6) for k in ("sample_rate",) if k in given})
    given.update({k: given[k] * 1e-6 for k in ("contact", "lash") if k in given})
    try:
        if args.students is not None:
            from labs.teachers.variants import write_variants

            variants = write_variants(write, out, args.students, args.seed, **given)
            for sid, files in variants.items():
                print(f"{sid}: {files['toml']}")
            print(f"handouts (give each student their folder): {out / 'handouts'}\n"
                  f"answer keys (keep them; dynlab check CLASS --keys {out}): {out / 'keys'}")
            return 0
        written = write(out, args.seed, **given)
    except OSError as exc:
        raise InputError(f"cannot write the synthetic measurement there "
                         f"({exc.strerror or exc})", "give --out a folder you can write to, "
                         "on a disk with room", file=str(out),
                         ru=(f"синтетическое измерение туда не записать "
                             f"({exc.strerror or exc})", "укажите в --out папку, в которую "
                             "можно писать, на диске со свободным местом")) from None
    for path in written.values():
        print(path)
    return 0


def _check_format(module, lab: str, fmt: str | None, sample_rate: float | None) -> None:
    """The recording format is one the lab writes; a WAV's rate is a whole number of Hz."""
    formats = getattr(module, "SYNTH_FORMATS", ())
    if fmt is None or not formats:
        return
    if fmt not in formats:
        raise InputError(f"--format {fmt}: {lab} writes its records as "
                         f"{', '.join(formats)}", f"give --format {' or '.join(formats)}",
                         ru=(f"--format {fmt}: {lab} записывает свои записи как "
                             f"{', '.join(formats)}", f"задайте --format {' или '.join(formats)}"))
    if fmt == "wav" and sample_rate is not None and \
            abs(sample_rate * 1e3 - round(sample_rate * 1e3)) > 1e-6:
        raise InputError(f"--sample-rate {sample_rate:g} kHz is not a whole number of "
                         "samples per second, which a WAV file stores",
                         "give a sound card's rate, e.g. --sample-rate 44.1 or 48",
                         ru=(f"--sample-rate {sample_rate:g} кГц — не целое число отсчётов в "
                             "секунду, а WAV-файл хранит только целое",
                             "задайте частоту звуковой карты, например --sample-rate 44.1 "
                             "или 48"))


LANG_HELP = ("language of the reports and the messages: en or ru (default: en; the messages "
             "follow a Russian locale)",
             "язык отчётов и сообщений: en или ru (по умолчанию en; сообщения следуют русской "
             "локали)")


def parser(says: str = "en") -> argparse.ArgumentParser:
    """The command's arguments; ``says`` is the language of the parser's own messages and
    of its help."""
    def t(en: str, ru: str) -> str:
        return say(says, en, ru)

    lang_help = t(*LANG_HELP)
    p = Parser(prog="dynlab", description=t(
        "Reduce engine-dynamics lab measurements into checked, standardised reports.",
        "Обработка измерений лабораторных работ по динамике двигателей в проверенные отчёты "
        "единого вида."), says=says)
    p.add_argument("--debug", action="store_true",
                   help=t("show tracebacks of internal errors",
                          "показывать трассировку внутренних ошибок"))
    p.add_argument("--version", action="version", version=f"dynlab {__version__}",
                   help=t("show the version and exit", "показать версию и выйти"))
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help=t("reduce measurement files into reports",
                                       "обработать файлы измерений в отчёты"))
    run.add_argument("files", nargs="+", metavar="FILE",
                     help=t("measurement files (TOML)", "файлы измерений (TOML)"))
    run.add_argument("--out", help=t("folder for the reports (default: reports; with --json "
                                     "alone nothing is written)",
                                     "папка для отчётов (по умолчанию reports; с одним --json "
                                     "ничего не записывается)"))
    run.add_argument("--format", type=_formats,
                     help=t("comma list of html,pdf,json (default: all)",
                            "список через запятую из html,pdf,json (по умолчанию все)"))
    run.add_argument("--lang", choices=LANGS, help=lang_help)
    run.add_argument("--json", action="store_true",
                     help=t("print the result JSON to stdout",
                            "вывести JSON результатов в stdout"))
    run.add_argument("--confine", action="store_true",
                     help=t("read no file outside each measurement file's folder (for "
                            "checking a class's submissions)",
                            "не читать файлов вне папки каждого файла измерений (для проверки "
                            "работ группы)"))
    run.set_defaults(func=_run)
    sub.add_parser("list", help=t("list the labs", "список лабораторных работ")
                   ).set_defaults(func=_list)
    tpl = sub.add_parser("template", help=t("write a blank measurement file for a lab",
                                            "записать пустой файл измерений для работы"))
    tpl.add_argument("lab", help=t("the lab (dynlab list)", "работа (dynlab list)"))
    tpl.add_argument("--lang", choices=LANGS, help=lang_help)
    tpl.add_argument("-o", "--output", help=t("file to write (default: print)",
                                              "файл для записи (по умолчанию вывести)"))
    tpl.set_defaults(func=_template)
    demo = sub.add_parser("demo", help=t("reduce the bundled sample data into reports",
                                         "обработать прилагаемые примеры данных в отчёты"))
    demo.add_argument("--out", default="dynlab-reports",
                      help=t("folder for the reports (default: dynlab-reports)",
                             "папка для отчётов (по умолчанию dynlab-reports)"))
    demo.add_argument("--lang", choices=LANGS, help=lang_help)
    demo.add_argument("--data", help=t("the sample_data folder (default: found automatically)",
                                       "папка sample_data (по умолчанию находится сама)"))
    demo.set_defaults(func=_demo)
    kin = sub.add_parser("kinematics", help=t("table of dimensionless piston motion s, v, j",
                                              "таблица безразмерных перемещения, скорости и "
                                              "ускорения поршня s, v, j"))
    kin.add_argument("--lambda", dest="lambda_", metavar="LAMBDA", type=_number, required=True,
                     help=t("λ = R/L, crank radius over rod length",
                            "λ = R/L, отношение радиуса кривошипа к длине шатуна"))
    kin.add_argument("--offset", type=_number, default=0.0,
                     help=t("pin offset ratio z = k/R", "относительное смещение оси z = k/R"))
    kin.add_argument("--step", type=_number, default=5.0,
                     help=t("crank-angle step, degrees", "шаг угла поворота кривошипа, градусы"))
    kin.add_argument("--approx", action="store_true",
                     help=t("the series to λ² instead of exact",
                            "ряд до λ² вместо точных формул"))
    kin.add_argument("--format", choices=("table", "csv"), default="table",
                     help=t("table or csv (default: table)",
                            "table (таблица) или csv (по умолчанию table)"))
    kin.set_defaults(func=_kinematics)
    chk = sub.add_parser("check", help=t(
        "judge the values a student reported ([reported]) against the reduction; a folder "
        "checks a class",
        "проверить значения, которые сообщил студент ([reported]), по обработке; папка — "
        "проверка группы"))
    chk.add_argument("files", nargs="+", metavar="FILE_OR_FOLDER",
                     help=t("measurement files, or folders of a class's submissions",
                            "файлы измерений или папки с работами группы"))
    chk.add_argument("--policy", help=t(
        "the teacher's tolerances: a TOML file with rel_tol, sig_figs, expected (per lab in "
        "[labN] tables)",
        "допуски преподавателя: файл TOML с rel_tol, sig_figs, expected (по работам в "
        "таблицах [labN])"))
    chk.add_argument("--out", default="check", help=t(
        "folder for a class's summary.csv, summary.html and moodle.csv, the marks for "
        "Moodle's grade import (default: check)",
        "папка для summary.csv, summary.html и moodle.csv группы (оценки для импорта в "
        "Moodle; по умолчанию check)"))
    chk.add_argument("--keys", metavar="KEYDIR", help=t(
        "the answer keys of the variants (KEYDIR/keys/<id>/answer_key.json as dynlab synth "
        "--students wrote them, or KEYDIR/<id>/answer_key.json): each submission, bound to "
        "its student by its folder FOLDER/<id>/ or its [meta] id, is judged against that "
        "student's key, and named where its readings or values are another student's",
        "ключи ответов вариантов (KEYDIR/keys/<id>/answer_key.json, как их записал dynlab "
        "synth --students, или KEYDIR/<id>/answer_key.json): каждая работа, привязанная к "
        "студенту папкой FOLDER/<id>/ или своим [meta] id, проверяется по ключу этого "
        "студента, а если её отсчёты или значения — чужие, это называется"))
    chk.add_argument("--roster", metavar="ROSTER.csv", help=t(
        "with --keys: the class's roster (columns id,name): the ids a submission may be bound "
        "to and the names shown (default: every id of KEYDIR)",
        "с --keys: список группы (столбцы id,name): id, к которым можно привязать работу, и "
        "показываемые имена (по умолчанию все id из KEYDIR)"))
    chk.add_argument("--lang", choices=LANGS, help=lang_help)
    chk.add_argument("--json", action="store_true",
                     help=t("print the verdicts as JSON", "вывести вердикты в JSON"))
    chk.set_defaults(func=_check)
    syn = sub.add_parser("synth", help=t("write a synthetic measurement with its answer key",
                                         "записать синтетическое измерение с ключом ответов"))
    syn.add_argument("lab", choices=tuple(CATALOGUE),
                     help=t("the lab", "работа"))
    syn.add_argument("--seed", type=_seed, default=0,
                     help=t("seed of the random generators (default 0)",
                            "зерно генераторов случайных чисел (по умолчанию 0)"))
    syn.add_argument("--out", default="synthetic",
                     help=t("folder to write (default: synthetic)",
                            "папка для записи (по умолчанию synthetic)"))
    syn.add_argument("--format", help=t(
        "labs 3, 4, 6, 7: recording format, wav, csv or h5 (lab 3's default wav, lab 4's h5, "
        "labs 6 and 7 csv)",
        "работы 3, 4, 6, 7: формат записи, wav, csv или h5 (по умолчанию у работы 3 wav, у "
        "работы 4 h5, у работ 6 и 7 csv)"))
    syn.add_argument("--snr", type=_number, help=t(
        "sensor SNR, dB (lab 4: in the worst band)",
        "отношение сигнал/шум датчика, дБ (работа 4: в худшей полосе)"))
    syn.add_argument("--pitch-error", type=_number, help=t(
        "lab 3: σ of the wheel's tooth angles, degrees (default 0.03)",
        "работа 3: σ угловых положений зубьев колеса, градусы (по умолчанию 0,03)"))
    syn.add_argument("--sample-rate", type=_number,
                     help=t("sample rate, kHz", "частота дискретизации, кГц"))
    syn.add_argument("--runs", type=_whole, help=t("lab 5, lab 9: number of loading runs",
                                                   "работы 5 и 9: число нагружений"))
    syn.add_argument("--friction", type=_number,
                     help=t("lab 5: friction in the joints, N", "работа 5: трение в сочленениях, Н"))
    syn.add_argument("--contact", type=_number, help=t(
        "lab 5: contact deformation at 1000 N, µm (stiffening table)",
        "работа 5: контактная деформация при 1000 Н, мкм (ужесточающаяся таблица)"))
    syn.add_argument("--lash", type=_number, help=t("lab 5: lash taken up first, µm",
                                                    "работа 5: выбираемый сначала зазор, мкм"))
    syn.add_argument("--periods", type=_number, help=t(
        "lab 9: decay record length, periods", "работа 9: длина записи затухания, периоды"))
    syn.add_argument("--amplitude-exponent", type=_number, help=t(
        "lab 9: p in δ(A) = δ₀·(A/φ₀)^p (0: linear damping)",
        "работа 9: p в δ(A) = δ₀·(A/φ₀)^p (0 — линейное демпфирование)"))
    syn.add_argument("--paper", action="store_true", help=t(
        "lab 9: maxima read off a paper record instead of a recording",
        "работа 9: максимумы, снятые с бумажной записи, вместо цифровой записи"))
    syn.add_argument("--film", action="store_true", help=t(
        "labs 1, 2: the swings filmed (MP4) instead of timed by hand",
        "работы 1, 2: качания сняты на видео (MP4), а не засечены секундомером"))
    syn.add_argument("--students", metavar="ROSTER.csv", help=t(
        "one variant per student of a roster (columns id,name): the handouts in "
        "OUT/handouts/<id>/ (the measurement file, its recordings, readings.html to print) "
        "and the answer keys, which the teacher keeps, in OUT/keys/<id>/answer_key.json",
        "по варианту на каждого студента из списка (столбцы id,name): задания в "
        "OUT/handouts/<id>/ (файл измерений, его записи, readings.html для печати) и ключи "
        "ответов, которые хранит преподаватель, в OUT/keys/<id>/answer_key.json"))
    syn.add_argument("--image", action="store_true", help=t(
        "labs 3, 6, 7, 9: the records as photographs of their paper (JPEG, read with OpenCV)",
        "работы 3, 6, 7, 9: записи в виде фотографий их бумаги (JPEG, читаются OpenCV)"))
    syn.add_argument("--no-recording", action="store_true", help=t(
        "lab 3 with --image: the photographed oscillograms alone, no sensor recording",
        "работа 3 с --image: только сфотографированные осциллограммы, без записи датчика"))
    syn.add_argument("--part", type=_seed, metavar="SEED", help=t(
        "labs 3–7: the rig of this seed (0: the scene's own) under --seed's readings and "
        "noise (default: --seed's own rig)",
        "работы 3–7: установка этого зерна (0 — собственная установка сцены) при отсчётах и "
        "шуме зерна --seed (по умолчанию установка самого --seed)"))
    syn.set_defaults(func=_synth)
    srv = sub.add_parser("serve", help=t(
        "a local web page: each lab's form, its report; with --class, students hand in and "
        "the teacher watches the class",
        "локальная веб-страница: форма каждой работы и её отчёт; с --class студенты сдают "
        "работы, а преподаватель следит за группой"))
    srv.add_argument("--host", default="127.0.0.1", help=t(
        "address to listen on (default 127.0.0.1, this machine only; any other needs the "
        "printed link's token)",
        "адрес для приёма (по умолчанию 127.0.0.1, только этот компьютер; для любого другого "
        "нужен токен из напечатанной ссылки)"))
    srv.add_argument("--port", type=_count(1, 65535), default=8000,
                     help=t("port to listen on (default 8000)",
                            "порт для приёма (по умолчанию 8000)"))
    srv.add_argument("--lang", choices=LANGS, help=lang_help)
    srv.add_argument("--class", dest="class_dir", metavar="DIR", help=t(
        "the class folder: hand-ins go to DIR/<id>/ as dynlab check reads them",
        "папка группы: сданные работы попадают в DIR/<id>/, как их читает dynlab check"))
    srv.add_argument("--roster", metavar="ROSTER.csv", help=t(
        "with --class: the class's roster (columns id,name)",
        "с --class: список группы (столбцы id,name)"))
    srv.add_argument("--keys", metavar="KEYDIR", help=t(
        "with --class: the answer keys of the variants (as for dynlab check --keys)",
        "с --class: ключи ответов вариантов (как для dynlab check --keys)"))
    srv.add_argument("--workers", type=_count(1, 64), default=2,
                     help=t("reductions at once (default 2)",
                            "обработок одновременно (по умолчанию 2)"))
    srv.add_argument("--time-limit", type=_seconds, default=120.0,
                     help=t("seconds one reduction may take (default 120; the class's "
                            "check that per hand-in)",
                            "секунд на одну обработку (по умолчанию 120; проверка класса — "
                            "столько на каждую сданную работу)"))
    srv.add_argument("--memory-limit", type=_count(256, 1 << 20), default=3072,
                     help=t("MiB of address space one reduction may take (default 3072)",
                            "МиБ адресного пространства на одну обработку (по умолчанию "
                            "3072)"))
    srv.add_argument("--max-file", type=_count(1, 1 << 20), default=200,
                     help=t("largest uploaded file, MiB (default 200)",
                            "наибольший загружаемый файл, МиБ (по умолчанию 200)"))
    srv.add_argument("--max-upload", type=_count(1, 1 << 20), default=400,
                     help=t("largest submission (all its files), MiB (default 400)",
                            "наибольшая сдаваемая работа (все её файлы), МиБ (по умолчанию "
                            "400)"))
    srv.set_defaults(func=_serve)
    return p


def _asked_lang(argv: list[str]) -> str | None:
    """The ``--lang`` of a command line not parsed yet, if it names a language.

    >>> _asked_lang(["run", "a.toml", "--lang", "ru"]), _asked_lang(["run", "--lang=en"])
    ('ru', 'en')
    """
    for i, arg in enumerate(argv):
        value = arg[7:] if arg.startswith("--lang=") else \
            argv[i + 1] if arg == "--lang" and i + 1 < len(argv) else None
        if value in LANGS:
            return value
    return None


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    says = _asked_lang(argv) or locale_lang()       # the messages' language
    args = parser(says).parse_args(argv)
    args.says = getattr(args, "lang", None) or says
    if hasattr(args, "lang"):
        args.lang = args.lang or "en"          # a report's language is asked, not guessed
    try:
        return args.func(args)
    except InputError as exc:
        print(exc.line(args.says), file=sys.stderr)
        return EXIT_INPUT
    except BrokenPipeError:
        # the reader of stdout stopped (`dynlab run ... | head`): nothing is wrong with the
        # work; the rest of the output goes nowhere, and Python's flush at exit stays quiet
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as exc:
        if args.debug:
            raise
        print(f"internal error: {type(exc).__name__}: {exc} (run with --debug for the "
              f"traceback, and please report it)", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
