"""The command line's parser, whose own messages (argparse's: a missing argument, a choice
not among those allowed, a number that is none) come out in the language of the command's
messages: English, or Russian under ``--lang ru`` or a Russian locale."""
from __future__ import annotations

import argparse
import re
import sys

RU = (
    (r"the following arguments are required: (.+)", r"не заданы обязательные аргументы: \1"),
    (r"argument (\S+): invalid choice: (.+) \(choose from (.+)\)",
     r"аргумент \1: значение \2 не из списка (возможны \3)"),
    (r"unrecognized arguments: (.+)", r"непонятные аргументы: \1"),
    (r"argument (\S+): expected one argument", r"аргумент \1: нужно одно значение"),
    (r"argument (\S+): expected at least one argument",
     r"аргумент \1: нужно хотя бы одно значение"),
    (r"argument (\S+): expected (\d+) arguments?", r"аргумент \1: нужно значений: \2"),
    (r"argument (\S+): invalid float value: (.+)", r"аргумент \1: \2 — не число"),
    (r"argument (\S+): invalid int value: (.+)", r"аргумент \1: \2 — не целое число"),
    (r"argument (\S+): ignored explicit argument (.+)", r"аргумент \1: лишнее значение \2"),
    (r"argument (\S+): not allowed with argument (\S+)",
     r"аргумент \1 нельзя давать вместе с \2"),
    (r"ambiguous option: (\S+) could match (.+)", r"неоднозначный ключ \1: подходят \2"),
    (r"argument (\S+): a seed is a whole number from 0 to (\d+), got (.+)",
     r"аргумент \1: зерно — целое число от 0 до \2, а не \3"),
    (r"argument (\S+): unknown format (.+); use a comma list of (.+)",
     r"аргумент \1: неизвестный формат \2; перечислите через запятую из \3"),
)
"""argparse's messages (Python 3.11) and the command's own argument types', each a pattern
of the whole English message and its Russian."""


def russian(message: str) -> str:
    """``message`` of argparse in Russian, or as it is where the table has no translation.

    >>> russian("the following arguments are required: FILE")
    'не заданы обязательные аргументы: FILE'
    >>> russian("argument --lang: invalid choice: 'de' (choose from 'en', 'ru')")
    "аргумент --lang: значение 'de' не из списка (возможны 'en', 'ru')"
    """
    for en, ru in RU:
        if re.fullmatch(en, message):
            return re.sub(en, ru, message)
    return message


class Parser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` speaking ``says`` ("en" or "ru") in its usage line
    and error messages; its subcommands' parsers speak the same."""

    def __init__(self, *args, says: str = "en", **kwargs):
        super().__init__(*args, **kwargs)
        self.says = says

    def add_subparsers(self, **kwargs):
        kwargs.setdefault("parser_class", lambda **kw: Parser(says=self.says, **kw))
        return super().add_subparsers(**kwargs)

    def format_usage(self) -> str:
        usage = super().format_usage()
        return usage.replace("usage: ", "вызов: ", 1) if self.says == "ru" else usage

    def error(self, message: str):
        self.print_usage(sys.stderr)
        if self.says == "ru":
            self.exit(2, f"{self.prog}: ошибка: {russian(message)}\n")
        self.exit(2, f"{self.prog}: error: {message}\n")
