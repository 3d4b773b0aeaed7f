"""``dynlab serve``: start the page on an address, print its link (with the token where one
is needed) and serve until interrupted."""
from __future__ import annotations

import secrets
import sys
from pathlib import Path

from processing.diagnostics import InputError

from .worker import Limits

MiB = 1 << 20


def _missing() -> InputError:
    return InputError("the web page needs its extra packages (starlette, uvicorn, "
                      "python-multipart)", "install them: pip install 'dynlab[web]'",
                      ru=("веб-странице нужны дополнительные пакеты (starlette, uvicorn, "
                          "python-multipart)", "установите их: pip install 'dynlab[web]'"))


def settings(args):
    """The page's settings from ``dynlab serve``'s options."""
    from .app import LOOPBACK, Settings
    from .classroom import Classroom

    local = args.host in LOOPBACK
    if args.roster is not None and args.class_dir is None:
        raise InputError("--roster goes with --class", "give the class folder: --class DIR "
                         "--roster roster.csv", file=args.roster,
                         ru=("--roster задаётся вместе с --class",
                             "укажите папку группы: --class DIR --roster roster.csv"))
    if args.class_dir is not None and args.roster is None:
        raise InputError("--class needs the class's roster", "give --roster roster.csv "
                         "(columns id,name)", file=args.class_dir,
                         ru=("для --class нужен список группы",
                             "укажите --roster roster.csv (столбцы id,name)"))
    room = None if args.class_dir is None else Classroom(args.class_dir, args.roster, args.keys)
    return Settings(lang=args.lang, token=None if local else secrets.token_urlsafe(16),
                    file_limit=args.max_file * MiB, submission_limit=args.max_upload * MiB,
                    workers=args.workers, limits=Limits(seconds=args.time_limit,
                                                        memory=args.memory_limit * MiB),
                    hosts=(args.host, "localhost") if local else None, classroom=room)


def _can_listen(host: str, port: int) -> None:
    """Refuse an address this machine cannot listen on (a port in use, a foreign address)
    before the link is printed."""
    import socket

    try:
        with socket.create_server((host, port)):
            pass
    except OSError as exc:
        raise InputError(f"cannot listen on {host}:{port} ({exc.strerror or exc})",
                         "give another --port, or a --host of this machine",
                         ru=(f"не удаётся слушать {host}:{port} ({exc.strerror or exc})",
                             "укажите другой --port или --host этой машины")) from None


def _announce(args, s, say) -> None:
    """Print the page's link (with its token) and the class page's, once it answers."""
    shown = "localhost" if args.host == "127.0.0.1" else args.host
    link = f"http://{shown}:{args.port}/" + (f"?token={s.token}" if s.token else "")
    print(say(f"dynlab serve: open {link}", f"dynlab serve: откройте {link}"), flush=True)
    if s.token:
        print(say("  (students need this link with its token; the page refuses requests "
                  "without it)", "  (студентам нужна эта ссылка с ключом; без него страница "
                  "отказывает)"), flush=True)
    if s.classroom is not None:
        print(say(f"  class page (the teacher's): {link.split('?')[0]}class?key={s.teacher_token}"
                  + (f"&token={s.token}" if s.token else ""),
                  f"  страница группы (для преподавателя): {link.split('?')[0]}class?key="
                  f"{s.teacher_token}" + (f"&token={s.token}" if s.token else "")), flush=True)
        print(say(f"  hand-ins go to {Path(s.classroom.folder).resolve()}/<id>/, the summary to "
                  f"{s.classroom.out.resolve()}/", f"  сданные работы — в "
                  f"{Path(s.classroom.folder).resolve()}/<id>/, сводка — в "
                  f"{s.classroom.out.resolve()}/"), flush=True)


def main(args) -> int:
    try:
        import multipart  # noqa: F401
        import uvicorn
    except ImportError:
        raise _missing() from None
    from .app import create_app

    s = settings(args)
    _can_listen(args.host, args.port)
    say = (lambda en, ru: ru) if args.says == "ru" else (lambda en, ru: en)
    print(say("dynlab serve: starting (the toolkit is imported once, for every reduction) …",
              "dynlab serve: запуск (программа загружается один раз для всех обработок) …"),
          file=sys.stderr, flush=True)
    s.on_start = lambda: _announce(args, s, say)
    app = create_app(s)
    app.state.web.pool.warm()
    from ..registry import LABS
    from .forms import warm

    warm(LABS[lab].SPEC for lab in LABS)
    uvicorn.run(app, host=args.host, port=args.port, log_level="warning",
                limit_concurrency=200, timeout_keep_alive=5)
    return 0

