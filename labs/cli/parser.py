"""The command line's parser, whose own messages (argparse's: a missing argument, a choice
not among those allowed, a number that is none; its help's headings) come out in the
language of the command's messages: English, or Russian under ``--lang ru`` or a Russian
locale.

argparse builds every message it prints from a format string passed through its gettext
hook (``argparse._``, ``argparse.ngettext``) before the values are put in; the Russian is
looked up by those format strings (:data:`ARGPARSE_RU`), by a :class:`gettext.NullTranslations`
put in the hook while a Russian parser works, so no finished English text is parsed back
and a Python whose argparse words a message differently falls back to English whole (the
tests list the format strings the command meets and check them against the running
argparse).
"""
from __future__ import annotations

import argparse
import contextlib
import gettext

ARGPARSE_RU = {
    "usage: ": "вызов: ",
    "positional arguments": "позиционные аргументы",
    "options": "ключи",
    "show this help message and exit": "показать эту справку и выйти",
    "%(prog)s: error: %(message)s\n": "%(prog)s: ошибка: %(message)s\n",
    "the following arguments are required: %s": "не заданы обязательные аргументы: %s",
    "argument %(argument_name)s: %(message)s": "аргумент %(argument_name)s: %(message)s",
    "invalid choice: %(value)r (choose from %(choices)s)":
        "значение %(value)r не из списка (возможны %(choices)s)",
    "unrecognized arguments: %s": "непонятные аргументы: %s",
    "expected one argument": "нужно одно значение",
    "expected at least one argument": "нужно хотя бы одно значение",
    "expected at most one argument": "нужно не больше одного значения",
    "invalid %(type)s value: %(value)r": "%(value)r — недопустимое значение",
    "ignored explicit argument %r": "лишнее значение %r",
    "not allowed with argument %s": "нельзя давать вместе с %s",
    "ambiguous option: %(option)s could match %(matches)s":
        "неоднозначный ключ %(option)s: подходят %(matches)s",
    "one of the arguments %s is required": "нужен один из аргументов %s",
    "can't open '%(filename)s': %(error)s": "не открыть '%(filename)s': %(error)s",
}
"""argparse's format strings (its gettext message ids, the same in Python 3.11–3.13) the
command can meet, in Russian."""

ARGPARSE_NGETTEXT_RU = {
    ("expected %s argument", "expected %s arguments"): "нужно значений: %s",
}
"""argparse's format strings with a plural (``ngettext``), in Russian."""

OWN_RU = {
    "a seed is a whole number from 0 to %(most)d, got %(got)r":
        "зерно — целое число от 0 до %(most)d, а не %(got)r",
    "unknown format %(bad)s; use a comma list of %(known)s":
        "неизвестный формат %(bad)s; перечислите через запятую из %(known)s",
    "a whole number from %(least)d to %(most)d, got %(got)r":
        "целое число от %(least)d до %(most)d, а не %(got)r",
    "a number of seconds above 0, got %(got)r": "число секунд больше 0, а не %(got)r",
    "%(got)r is not a number": "%(got)r — не число",
    "%(got)r is not a whole number": "%(got)r — не целое число",
}
"""The messages of the command's own argument types, in Russian (:func:`told`)."""


class Russian(gettext.NullTranslations):
    """argparse's messages and the command's own argument types' in Russian, by their format
    strings; a string without a translation stays English."""

    def gettext(self, message: str) -> str:
        return ARGPARSE_RU.get(message) or OWN_RU.get(message) or message

    def ngettext(self, singular: str, plural: str, n: int) -> str:
        return ARGPARSE_NGETTEXT_RU.get((singular, plural)) or \
            (singular if n == 1 else plural)


TRANSLATIONS = {"en": gettext.NullTranslations(), "ru": Russian()}
"""The translation of each language the command speaks."""

_speaking = TRANSLATIONS["en"]


@contextlib.contextmanager
def speaking(says: str):
    """Within the block, argparse's gettext hook and :func:`told` speak ``says``."""
    global _speaking
    saved = argparse._, argparse.ngettext, _speaking
    _speaking = TRANSLATIONS[says]
    argparse._, argparse.ngettext = _speaking.gettext, _speaking.ngettext
    try:
        yield
    finally:
        argparse._, argparse.ngettext, _speaking = saved


def told(message: str, **values) -> str:
    """An argument type's ``message`` (a format string of :data:`OWN_RU`) in the language
    the parser at work speaks, its ``values`` put in.

    >>> with speaking("ru"):
    ...     told("%(got)r is not a number", got="x")
    "'x' — не число"
    >>> told("%(got)r is not a number", got="x")
    "'x' is not a number"
    """
    return _speaking.gettext(message) % values


class Parser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` speaking ``says`` ("en" or "ru") in its usage
    line, help headings and error messages; its subcommands' parsers speak the same."""

    def __init__(self, *args, says: str = "en", **kwargs):
        self.says = says
        with speaking(says):
            super().__init__(*args, **kwargs)

    def add_subparsers(self, **kwargs):
        kwargs.setdefault("parser_class", lambda **kw: Parser(says=self.says, **kw))
        return super().add_subparsers(**kwargs)

    def parse_args(self, args=None, namespace=None):
        with speaking(self.says):
            return super().parse_args(args, namespace)

    def parse_known_args(self, args=None, namespace=None):
        with speaking(self.says):
            return super().parse_known_args(args, namespace)

    def format_usage(self) -> str:
        with speaking(self.says):
            return super().format_usage()

    def format_help(self) -> str:
        with speaking(self.says):
            return super().format_help()

    def error(self, message: str):
        with speaking(self.says):
            super().error(message)
