"""Files a user names, judged before they are read: only regular files, only up to the size
their reader allows, and never more than that read.

Every file a user names — a measurement file, a recording, a counter's edge times, a
photograph, a film, a roster, a policy, an answer key — is opened through here. A symbolic
link is followed and its target judged. A named pipe (FIFO) would make the reader wait for a
writer for ever, a device such as ``/dev/zero`` would feed it without end, a file of gigabytes
read whole would fill the memory: each is refused with an
:class:`~processing.diagnostics.InputError` that says what the path is, before a byte is read.
A path the system cannot follow (a name too long, a file where a folder should be, a loop of
links, no permission) is refused the same way, naming the cause.

Each reader declares a :class:`Kind`: what the file is, for messages, and the largest file
it takes (None for WAV and HDF5 recordings, which stream; a film streams too, under a bound
no phone's film reaches).
:func:`read_bytes` reads at most that many bytes plus one, however the file grows meanwhile.
"""
from __future__ import annotations

import codecs
import errno
import os
import re
import stat
from dataclasses import dataclass
from pathlib import Path

from .diagnostics import InputError
from .numerals import localize_numbers

MiB = 1 << 20
GiB = 1 << 30

NAME_MAX = 255
"""Longest name of one file or folder on the usual file systems (ext4, NTFS, APFS). [bytes]"""


@dataclass(frozen=True)
class Kind:
    """What a reader takes.

    Parameters
    ----------
    what : str
        The file's name in messages ("measurement file", "CSV table").
    limit : int or None
        Largest file read [bytes]; None: any size (the reader streams it).
    fix : str
        What to do with a larger file.
    streamed : bool
        The reader streams the file (its limit is a sanity bound, not a memory one).
    ru : (str, str)
        ``what`` and ``fix`` in Russian (``what`` in the nominative: "файл измерений").
    """

    what: str
    limit: int | None = None
    fix: str = ""
    streamed: bool = False
    ru: tuple[str, str] = ("файл", "")

    @property
    def a(self) -> str:
        """The name with its article: 'a film', 'an image'."""
        return f"{'an' if self.what[0] in 'aeiou' else 'a'} {self.what}"


MEASUREMENT = Kind("measurement file", MiB,
                   "keep long series in a recording (CSV, WAV, HDF5) named by the measurement "
                   "file, and long notes short",
                   ru=("файл измерений", "длинные ряды держите в файле записи (CSV, WAV, HDF5), "
                       "названном в файле измерений, а примечания — короткими"))
"""A lab sheet: a few kB."""

MEASUREMENT_NAMES = (".toml", ".toml.txt")
"""How a measurement file's name ends, in lower case: Notepad saving a "Text Document" adds
``.txt`` to it."""

TABLE = Kind("CSV table", 64 * MiB, "save long recordings as WAV or HDF5, which are streamed",
             ru=("таблица CSV", "длинные записи сохраняйте в WAV или HDF5: их читают "
                 "по частям"))
"""A recording or a counter's edge times as text, parsed whole: 64 MiB is about 5 million
samples of two columns (8 minutes at 10 kHz); reading 63 MB peaked at 405 MB."""

STREAMED = Kind("recording", streamed=True, ru=("файл записи", ""))
"""A WAV or HDF5 recording: read block by block, any size."""

IMAGE = Kind("image", 256 * MiB,
             "save the photograph as JPEG or PNG, or scan at 300–600 dpi",
             ru=("изображение", "сохраните снимок как JPEG или PNG или сканируйте с "
                 "разрешением 300–600 dpi"))
"""A photograph or scan of a paper record: a phone's photo is 3–15 MB, a 600 dpi A3 colour
scan saved uncompressed 209 MB."""

FILM = Kind("film", 16 * GiB, "cut the film to the swings you measure", streamed=True,
            ru=("видеозапись", "обрежьте видеозапись до измеряемых колебаний"))
"""A phone's film, decoded frame by frame: 16 GiB is over half an hour of 4K at 60 frames per
second (a phone writes about 0.4 GB a minute)."""

ROSTER = Kind("roster", MiB, "give a CSV of the class: a header id,name and a row per student",
              ru=("список группы", "укажите CSV группы: заголовок id,name и строка на "
                  "студента"))
"""A class list: 1 MiB holds tens of thousands of students."""

POLICY = Kind("policy", MiB, "a policy holds rel_tol, sig_figs and expected, a few lines",
              ru=("файл допусков", "файл допусков — это несколько строк: rel_tol, sig_figs "
                  "и expected"))
"""The teacher's tolerances: a few lines of TOML."""

ANSWER_KEY = Kind("answer key", 16 * MiB, "give the answer_key.json that dynlab synth wrote",
                  ru=("ключ ответов", "укажите answer_key.json, записанный dynlab synth"))
"""An answer key of ``dynlab synth``: a few kB."""

REPORTED_TABLE = Kind("reported table", 8 * MiB,
                      "a reported table has a row per crank-angle step: a few hundred rows",
                      ru=("таблица результатов", "в таблице результатов строка на шаг угла "
                          "поворота: несколько сотен строк"))
"""A table a student reports for the coursework (CSV), read into Python lists whole."""

_TYPES = ((stat.S_ISFIFO, ("a named pipe (FIFO)", "reading it would wait for a writer without "
                          "end"), ("именованный канал (FIFO)", "чтение ждало бы писателя "
                                   "без конца")),
          (stat.S_ISCHR, ("a character device", "a device such as /dev/zero never ends"),
           ("символьное устройство", "устройство вроде /dev/zero не кончается")),
          (stat.S_ISBLK, ("a block device (a whole disk or partition)", "it is no file"),
           ("блочное устройство (целый диск или раздел)", "это не файл")),
          (stat.S_ISSOCK, ("a socket", "it is no file"), ("сокет", "это не файл")))


def _size(n: int, than: int | None = None, lang: str = "en") -> str:
    """A file size in binary units, to three figures, or as many more as tell it from the
    size ``than``.

    >>> _size(3 << 30), _size(1536 << 10), _size(900), _size(MiB + 20, than=MiB)
    ('3 GiB', '1.5 MiB', '900 bytes', '1.00002 MiB')
    >>> _size(1536 << 10, lang="ru"), _size(900, lang="ru")
    ('1,5 МиБ', '900 байт')
    """
    units = (("ГиБ", GiB), ("МиБ", MiB), ("КиБ", 1 << 10)) if lang == "ru" else \
        (("GiB", GiB), ("MiB", MiB), ("KiB", 1 << 10))
    for unit, scale in units:
        if n >= scale:
            digits = 3
            while than is not None and digits < 16 and \
                    f"{n / scale:.{digits}g}" == f"{than / scale:.{digits}g}":
                digits += 1
            return localize_numbers(f"{n / scale:.{digits}g} {unit}", lang)
    return f"{n} {'байт' if lang == 'ru' else 'bytes'}"


def _short(name: str, most: int = 40) -> str:
    return name if len(name) <= most else f"{name[:most // 2]}…{name[-most // 2:]}"


def regular(path, kind: Kind, *, field: str | None = None) -> os.stat_result:
    """Judge the file ``path`` names before a reader opens it: a regular file it may
    read, of at most the size it takes.

    Parameters
    ----------
    path : str or Path
        The file (a symbolic link is followed; its target is judged).
    kind : Kind
        What the reader takes.
    field : str, optional
        The measurement-file field that named it, for the message.

    Returns
    -------
    os.stat_result
        Of the file (the link's target).

    Raises
    ------
    InputError
        Not found (a link to nothing named as such), a directory, a FIFO, a device, a socket,
        larger than ``kind.limit``; a path the system cannot follow: a NUL character, a name
        or a path too long, a file where a folder should be, a loop of links, no permission.
    """
    path = Path(path)
    if "\x00" in str(path):
        raise InputError("the file name holds a NUL character",
                         "write the file's name without control characters",
                         file=str(path).replace("\x00", "\\0"), field=field,
                         ru=("в имени файла есть символ NUL",
                             "запишите имя файла без управляющих символов"))
    try:
        info = os.stat(path)
    except OSError as exc:
        raise _unreachable(path, kind, field, exc) from None
    _judge(path, kind, field, info)
    os.close(_open(path, kind, field))  # no permission: named here, not by a library
    return info


_FLAGS = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) \
    | getattr(os, "O_BINARY", 0)
"""Open for reading without blocking (were it a FIFO after all) or taking a terminal."""


def _open(path: Path, kind: Kind, field: str | None) -> int:
    try:
        return os.open(path, _FLAGS)
    except OSError as exc:
        raise _unreachable(path, kind, field, exc) from None


def read_bytes(path, kind: Kind, *, field: str | None = None) -> bytes:
    """The whole content of a regular file of at most ``kind.limit`` bytes.

    The file is judged by :func:`regular`, opened without blocking, judged again as opened
    (it may have been replaced meanwhile), and read to at most ``kind.limit + 1`` bytes:
    a file that grows past the limit while it is read is refused too.

    Raises
    ------
    InputError
        As :func:`regular`.
    ValueError
        ``kind`` has no limit (a streamed file is not read whole).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile(suffix=".toml", delete=False) as f:
    ...     _ = f.write(b'lab = "lab1"')
    >>> read_bytes(f.name, MEASUREMENT)
    b'lab = "lab1"'
    >>> os.remove(f.name)
    """
    if kind.limit is None:
        raise ValueError(f"read_bytes: a {kind.what} is streamed, not read whole")
    path = Path(path)
    regular(path, kind, field=field)
    with os.fdopen(_open(path, kind, field), "rb") as f:
        _judge(path, kind, field, os.fstat(f.fileno()))
        try:
            data = f.read(kind.limit + 1)
        except OSError as exc:
            raise _unreachable(path, kind, field, exc) from None
    if len(data) > kind.limit:
        raise _too_large(path, kind, field, (f"more than {_size(kind.limit)} (it grew while "
                                             "it was read)",
                                             f"больше {_size(kind.limit, lang='ru')} (он рос, "
                                             "пока его читали)"))
    return data


def read_text(path, kind: Kind, *, field: str | None = None, legacy: str | None = None,
              fix: str | None = None, fix_ru: str | None = None, binary: bool = False) -> str:
    """:func:`read_bytes` decoded: UTF-8 (a byte-order mark dropped), UTF-16 with its
    byte-order mark (a spreadsheet's "Unicode text"), else ``legacy`` (the code page a
    spreadsheet of the region writes, ``"cp1251"`` for Russian Excel); binary data refused
    unless ``binary`` (the caller then judges :func:`looks_binary` itself, to name a stray
    control character's line).

    Parameters
    ----------
    fix, fix_ru : str, optional
        The fix for binary data or text in another encoding, in English and Russian
        (default: save it as UTF-8 text; a message with ``fix`` but no ``fix_ru`` is English
        only).

    Raises
    ------
    InputError
        As :func:`read_bytes`; also binary data and, without ``legacy``, text that is not
        UTF-8.
    """
    raw = read_bytes(path, kind, field=field)
    fix, fix_ru = fix or f"save the {kind.what} as UTF-8 text", \
        fix_ru or (None if fix else f"сохраните его ({kind.ru[0]}) как текст UTF-8")
    try:
        text = unicode_text(raw)
    except UnicodeDecodeError:
        if legacy is None:
            raise InputError(f"not a text file in UTF-8 ({kind.a} is text)", fix,
                             file=str(path), field=field,
                             ru=fix_ru and (f"не текстовый файл в UTF-8 ({kind.ru[0]} — это "
                                            f"текст)", fix_ru)) from None
        text = raw.decode(legacy, errors="replace")
    if not binary and looks_binary(text):
        raise InputError(f"not a text file (binary data), so not {kind.a}", fix,
                         file=str(path), field=field,
                         ru=fix_ru and (f"не текстовый файл (двоичные данные), а значит, не "
                                        f"{kind.ru[0]}", fix_ru))
    return text


def unicode_text(raw: bytes) -> str:
    """Bytes decoded as UTF-8 (a byte-order mark dropped), or as UTF-16 where its byte-order
    mark opens them (a spreadsheet's or Notepad's "Unicode"). Raises UnicodeDecodeError for
    anything else."""
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return raw.decode("utf-16")
    return raw.decode("utf-8-sig")


_CONTROLS = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f]")
"""Control characters other than tab, CR and LF: a text file holds almost none."""


def looks_binary(text: str) -> bool:
    """Whether a decoded file is binary data: a NUL, or control characters (other than tab,
    CR and LF) in more than 1 % of its first 64 KiB."""
    head = text[:1 << 16]
    return "\x00" in head or len(_CONTROLS.findall(head)) > 0.01 * len(head)


def resolved(path) -> Path:
    """The absolute path with every symbolic link followed as far as it goes; never raises
    (a loop of links, a missing or too long path, a NUL character stay as they are
    written)."""
    try:
        return Path(os.path.realpath(os.path.abspath(path)))
    except ValueError:
        return Path(os.path.abspath(path))


def _judge(path: Path, kind: Kind, field: str | None, info: os.stat_result) -> None:
    """Refuse what is not a regular file of at most ``kind.limit`` bytes."""
    if stat.S_ISDIR(info.st_mode):
        raise InputError(f"is a directory (a folder), not {kind.a}",
                         f"give the path of the {kind.what} itself", file=str(path),
                         field=field, ru=(f"это каталог (папка), а не {kind.ru[0]}",
                                          f"укажите путь к самому файлу ({kind.ru[0]})"))
    if not stat.S_ISREG(info.st_mode):
        (what, why), (what_ru, why_ru) = next(
            ((en, ru) for test, en, ru in _TYPES if test(info.st_mode)),
            (("not a regular file", "it is no file"), ("не обычный файл", "это не файл")))
        link, link_ru = _through_link(path)
        raise InputError(f"{link}{what}, not {kind.a} saved on disk: {why}",
                         f"give the {kind.what} itself, a regular file",
                         file=str(path), field=field,
                         ru=(f"{link_ru}{what_ru}, а не обычный файл на диске ({kind.ru[0]}): "
                             f"{why_ru}", f"укажите сам файл ({kind.ru[0]}), обычный файл"))
    if kind.limit is not None and info.st_size > kind.limit:
        raise _too_large(path, kind, field, (_size(info.st_size, than=kind.limit),
                                             _size(info.st_size, than=kind.limit, lang="ru")))


def _through_link(path: Path) -> tuple[str, str]:
    """'a symbolic link to X, ' when ``path`` is a link, else 'it is ' (and in Russian)."""
    try:
        if path.is_symlink():
            target = os.path.realpath(path)
            return f"a symbolic link to {target}, ", f"символьная ссылка на {target}, "
    except OSError:
        pass
    return "it is ", "это "


def _too_large(path: Path, kind: Kind, field: str | None, size: tuple[str, str]) -> InputError:
    how = "" if kind.streamed else "is read whole and "
    how_ru = "" if kind.streamed else "читается целиком и "
    return InputError(f"the file is {size[0]}; {kind.a} {how}may be at most {_size(kind.limit)}",
                      kind.fix or f"give a smaller {kind.what}", file=str(path), field=field,
                      ru=(f"файл занимает {size[1]}; {kind.ru[0]} {how_ru}не может быть больше "
                          f"{_size(kind.limit, lang='ru')}",
                          kind.ru[1] or "укажите файл поменьше"))


def _unreachable(path: Path, kind: Kind, field: str | None, exc: OSError) -> InputError:
    """The :class:`InputError` of a path the system could not follow."""
    (problem, fix), (problem_ru, fix_ru) = _cause(path, exc)
    if exc.errno == errno.ENOENT and field is not None:
        fix += " (a file named in a measurement file is found from that file's folder)"
        fix_ru += " (файл, названный в файле измерений, ищется от папки этого файла)"
    return InputError(problem, fix, file=str(path), field=field, ru=(problem_ru, fix_ru))


def _cause(path: Path, exc: OSError) -> tuple[tuple[str, str], tuple[str, str]]:
    """What went wrong following ``path``, and the fix, in English and in Russian."""
    code = exc.errno
    relink = ("point the link at the real file, or give the file itself",
              "направьте ссылку на настоящий файл или укажите сам файл")
    if code == errno.ENOENT:
        if os.path.islink(path):
            target = os.readlink(path)
            return ((f"a symbolic link to {target}, which does not exist", relink[0]),
                    (f"символьная ссылка на {target}, которого нет", relink[1]))
        return (("file not found", "check the path and the file name"),
                ("файл не найден", "проверьте путь и имя файла"))
    if code == errno.ENAMETOOLONG:
        long = [p for p in path.parts if len(os.fsencode(p)) > NAME_MAX]
        if long:
            size = len(os.fsencode(long[0]))
            return ((f"the name '{_short(long[0])}' is {size} bytes long; "
                     f"a file system allows at most {NAME_MAX}",
                     "rename the file (or folder) to a shorter name"),
                    (f"имя '{_short(long[0])}' длиной {size} байт; файловая система допускает "
                     f"не более {NAME_MAX}", "переименуйте файл (или папку) короче"))
        size = len(os.fsencode(str(path)))
        return ((f"the path is {size} bytes long, more than the system allows",
                 "move the file to a folder nearer the root, or shorten the folders' names"),
                (f"путь длиной {size} байт, длиннее, чем допускает система",
                 "перенесите файл в папку ближе к корню или сократите имена папок"))
    if code == errno.ENOTDIR:
        blocker = next((p for p in reversed(path.parents) if p.exists() and not p.is_dir()),
                       None)
        where = f"'{blocker}' on the path" if blocker else "a part of the path"
        where_ru = f"'{blocker}' на пути" if blocker else "часть пути"
        return ((f"{where} is a file, not a folder", "check the path: a folder is expected there"),
                (f"{where_ru} — файл, а не папка", "проверьте путь: там должна быть папка"))
    if code == errno.ELOOP:
        return (("the path runs in a loop of symbolic links", relink[0]),
                ("путь зацикливается на символьных ссылках", relink[1]))
    if code in (errno.EACCES, errno.EPERM):
        return (("permission denied: the file (or a folder on its path) cannot be read",
                 "make it readable (chmod a+r on the file, a+x on its folders) or copy it "
                 "somewhere you can read"),
                ("нет доступа: файл (или папку на его пути) нельзя прочесть",
                 "откройте его для чтения (chmod a+r на файл, a+x на папки) или скопируйте "
                 "туда, где его можно прочесть"))
    return ((f"the file cannot be read ({exc.strerror or exc})",
             "copy the file again, or check the disk"),
            (f"файл не прочесть ({exc.strerror or exc})",
             "скопируйте файл заново или проверьте диск"))
