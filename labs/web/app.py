"""The web page's application (Starlette): the lab list, each lab's form, the reduction in the
worker pool, the report with its downloads, and, with a class, the hand-in and the class page.

The page is a front end and nothing more (ARCHITECTURE.md, "Front ends"): a posted form is
written as the measurement file the command line reads (:mod:`labs.web.forms`), reduced in a
worker as ``dynlab run --confine`` reduces it (:mod:`labs.web.worker`), and the page shows the
report ``dynlab run`` writes. Safety (``docs/web.md``): a token on any address but loopback,
upload limits checked before reading, a CSRF token on every form, jinja2's autoescaping, the
session's folder as the only place a request's files go, sessions that expire.
"""
from __future__ import annotations

import asyncio
import re
import contextlib
import hmac
import io
import secrets
import shutil
import tempfile
import time
import tomllib
import zipfile
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import jinja2
from starlette.applications import Starlette
from starlette.datastructures import UploadFile
from starlette.formparsers import MultiPartException, MultiPartParser
from starlette.requests import Request
from starlette.responses import (FileResponse, HTMLResponse, JSONResponse, RedirectResponse,
                                 Response)
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from processing.diagnostics import InputError
from processing.files import MEASUREMENT as MEASUREMENT_KIND, MEASUREMENT_NAMES
from processing.measurement import TomlDocument, measurement_text
from processing.reporting.i18n import LANGS
from processing.inputs.toml_writer import dumps

from ..catalogue import CATALOGUE
from . import forms
from .classroom import Classroom
from .sessions import Run, Session, Store, safe_name
from .text import TEXT
from .worker import (MEASUREMENT, REPORTS, Busy, Limits, Pool, pdf_child, ready_child,
                     reduce_child)

MiB = 1 << 20
COOKIE = "dynlab_session"
TOKEN_COOKIE = "dynlab_token"
LOOPBACK = ("127.0.0.1", "localhost", "::1")
PAGE_POLICY = ("default-src 'self'; img-src 'self' data:; style-src 'self'; script-src 'self'; "
               "frame-ancestors 'none'; form-action 'self'")
"""What the page's own documents may load: nothing from elsewhere, no inline script."""


@dataclass
class Settings:
    """What ``dynlab serve`` was started with.

    ``token``: required of every request (None on loopback); ``teacher_token``: required of
    the class page; ``file_limit``/``submission_limit``: the largest uploaded file and the
    largest request [bytes]; ``hosts``: the Host headers answered (None: any, behind the
    token)."""

    lang: str = "en"
    token: str | None = None
    teacher_token: str = field(default_factory=lambda: secrets.token_urlsafe(16))
    file_limit: int = 200 * MiB
    submission_limit: int = 400 * MiB
    max_files: int = 40
    ttl: float = 2 * 3600
    workers: int = 2
    queue: int = 64
    limits: Limits = Limits()
    hosts: tuple[str, ...] | None = ("127.0.0.1", "localhost", "testserver")
    root: Path | None = None
    classroom: Classroom | None = None
    report_wait: float = 60.0
    on_start: Callable[[], None] | None = None


class TooLarge(Exception):
    """An upload beyond a limit (its message says which)."""


class _LimitedParser(MultiPartParser):
    """Starlette's multipart parser, stopping at the first byte beyond the per-file limit."""

    def __init__(self, *args, file_limit: int, **kwargs):
        super().__init__(*args, **kwargs)
        self.file_limit = file_limit
        self._seen: dict[int, int] = {}

    def on_part_data(self, data: bytes, start: int, end: int) -> None:
        part = self._current_part
        if part.file is not None:
            n = self._seen.get(id(part), 0) + end - start
            self._seen[id(part)] = n
            if n > self.file_limit:
                raise TooLarge(f"file:{part.file.filename}")
        super().on_part_data(data, start, end)


async def _limited(stream, limit: int):
    total = 0
    async for chunk in stream:
        total += len(chunk)
        if total > limit:
            raise TooLarge("submission")
        yield chunk


def _templates() -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.PackageLoader("labs.web", "templates"), autoescape=True,
        undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True)
    return env


class WebApp:
    """The application's state and its handlers."""

    def __init__(self, settings: Settings):
        self.s = settings
        root = settings.root or Path(tempfile.mkdtemp(prefix="dynlab-serve-"))
        self.store = Store(root / "sessions", ttl=settings.ttl)
        self.pool = Pool(settings.workers, settings.queue, settings.limits)
        self.env = _templates()
        self.classroom = settings.classroom
        self._sweeper: asyncio.Task | None = None

    # ------------------------------------------------------------------ plumbing
    def page(self, request: Request, session: Session, name: str, status: int = 200,
             **context) -> HTMLResponse:
        lang = session.lang
        html = self.env.get_template(name).render(
            t=TEXT[lang], lang=lang, langs=LANGS, csrf=session.csrf, path=request.url.path,
            catalogue=CATALOGUE, classroom=self.classroom is not None, **context)
        response = HTMLResponse(html, status_code=status, headers={
            "Content-Security-Policy": PAGE_POLICY, "X-Content-Type-Options": "nosniff",
            "Referrer-Policy": "no-referrer"})
        self._cookie(response, session)
        return response

    def _cookie(self, response: Response, session: Session) -> None:
        response.set_cookie(COOKIE, session.id, httponly=True, samesite="strict",
                            max_age=int(self.s.ttl))

    def session(self, request: Request) -> Session:
        s = self.store.get(request.cookies.get(COOKIE))
        if s is None:
            s = self.store.new(self.s.lang)
        lang = request.query_params.get("lang")
        if lang in LANGS:
            s.lang = lang
        return s

    def refuse(self, request: Request, session: Session, key: str, status: int,
               detail: str = "") -> HTMLResponse:
        return self.page(request, session, "refused.html", status, message=TEXT[session.lang][key],
                         detail=detail)

    async def posted(self, request: Request, session: Session) -> dict:
        """The posted form, parsed within the limits, its CSRF token checked; files as
        :class:`UploadFile`. Raises :class:`TooLarge` or :class:`PermissionError`."""
        if request.cookies.get(COOKIE) != session.id:
            raise PermissionError("no session")
        length = request.headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > self.s.submission_limit):
            raise TooLarge("submission")
        if not request.headers.get("content-type", "").startswith("multipart/form-data"):
            raise PermissionError("not a form")
        parser = _LimitedParser(request.headers,
                                _limited(request.stream(), self.s.submission_limit),
                                max_files=self.s.max_files, max_fields=5000,
                                max_part_size=MiB, file_limit=self.s.file_limit)
        try:
            data = await parser.parse()
        except MultiPartException as exc:
            raise PermissionError(str(exc)) from None
        if not hmac.compare_digest(str(data.get("csrf", "")), session.csrf):
            raise PermissionError("csrf")
        form = {k: v for k, v in data.multi_items()}
        if "files" in form:                     # a .toml opened with its files
            form["files"] = data.getlist("files")
        return form

    async def guarded(self, request: Request, handler) -> Response:
        """Run a POST handler, answering a refused upload or a forged form plainly."""
        session = self.session(request)
        try:
            form = await self.posted(request, session)
        except TooLarge as exc:
            what = str(exc)
            detail = what[5:] if what.startswith("file:") else ""
            key = "file_too_large" if detail else "submission_too_large"
            return self.refuse(request, session, key, 413, detail)
        except PermissionError:
            return self.refuse(request, session, "forbidden", 403)
        return await handler(request, session, form)

    # ------------------------------------------------------------------ pages
    async def home(self, request: Request) -> Response:
        session = self.session(request)
        return self.page(request, session, "labs.html")

    def form_page(self, request: Request, session: Session, lab: str, values: dict,
                  counts: dict, run: Run | None = None, error: dict | None = None,
                  status: int = 200) -> HTMLResponse:
        module_spec = _spec(lab)
        paths = _paths(module_spec, counts)
        at = error.get("field") if error else None
        top = error if error and at not in paths else None
        return self.page(request, session, "form.html", status, spec=module_spec, values=values,
                         counts=counts, source=run.id if run else "",
                         kept=run.files() if run else [], error=error, error_at=at, top=top,
                         forms=forms, filled={re.split(r"[.\[]", k)[0] for k in values})

    async def lab_form(self, request: Request) -> Response:
        lab = request.path_params["lab"]
        session = self.session(request)
        if lab not in CATALOGUE:
            return self.refuse(request, session, "not_found", 404)
        return self.form_page(request, session, lab, {}, {})

    async def reduce(self, request: Request) -> Response:
        lab = request.path_params["lab"]
        if lab not in CATALOGUE:
            return self.refuse(request, self.session(request), "not_found", 404)
        return await self.guarded(request, lambda r, s, f: self._reduce(r, s, f, lab))

    async def _reduce(self, request: Request, session: Session, form: dict,
                      lab: str) -> Response:
        spec = _spec(lab)
        run = self.store.new_run(session, lab)
        texts = {k: v for k, v in form.items() if isinstance(v, str)}
        source = self.store.run(session, texts.get("source", ""))
        taken: set[str] = set()
        for key, value in form.items():
            if isinstance(value, UploadFile) and value.filename:
                name = safe_name(value.filename, taken)
                taken.add(name)
                with open(run.folder / name, "wb") as out:
                    await asyncio.to_thread(shutil.copyfileobj, value.file, out)
                texts[key] = name
        for key, value in list(texts.items()):
            if key.endswith(":kept") and value and not texts.get(key[:-5]) and source:
                name = Path(value).name
                if name in source.files() and name not in taken:
                    shutil.copyfile(source.folder / name, run.folder / name)
                    taken.add(name)
                    texts[key[:-5]] = name
        try:
            doc = forms.document(spec, texts)
        except InputError as exc:
            run.status, run.error = "input", _error(exc)
            return self.form_page(request, session, lab, texts, _counts(spec, texts), run,
                                  run.error, 422)
        (run.folder / MEASUREMENT).write_text(dumps(doc), encoding="utf-8")
        return await self._reduce_run(request, session, run, doc)

    async def _reduce_run(self, request: Request, session: Session, run: Run,
                          doc: dict) -> Response:
        try:
            outcome = await self.pool.run(reduce_child, str(run.folder), session.lang)
        except Busy:
            return self.refuse(request, session, "busy", 503)
        run.status, run.error, run.seconds = outcome.status, outcome.error, outcome.seconds
        if outcome.status == "input":
            values, counts = forms.values(doc, _spec(run.lab))
            return self.form_page(request, session, run.lab, values, counts, run,
                                  outcome.error, 422)
        return RedirectResponse(f"/run/{run.id}", status_code=303)

    def _run(self, request: Request) -> tuple[Session, Run | None]:
        session = self.session(request)
        return session, self.store.run(session, request.path_params["run"])

    async def run_page(self, request: Request) -> Response:
        session, run = self._run(request)
        if run is None:
            return self.refuse(request, session, "not_found", 404)
        if run.status != "ok":
            return self.page(request, session, "failed.html", 500, run=run)
        roster = self.classroom.roster if self.classroom else []
        return self.page(request, session, "run.html", run=run, lab=CATALOGUE[run.lab],
                         roster=roster)

    async def report(self, request: Request) -> Response:
        session, run = self._run(request)
        fmt = request.path_params["fmt"]
        if run is None or run.status != "ok" or fmt not in REPORTS:
            return self.refuse(request, session, "not_found", 404)
        path = run.folder / REPORTS[fmt]
        if fmt == "pdf" and not path.exists():
            if run.pdf is None or (run.pdf.done() and run.pdf.result().status != "ok"):
                run.pdf = asyncio.get_running_loop().create_task(
                    self.pool.run(pdf_child, str(run.folder), run.lang))
            try:
                outcome = await asyncio.shield(run.pdf)
            except Busy:
                run.pdf = None
                return self.refuse(request, session, "busy", 503)
            if outcome.status != "ok":
                return self.refuse(request, session, "report_missing", 500,
                                   (outcome.error or {}).get(session.lang, ""))
        deadline = time.monotonic() + self.s.report_wait
        while not path.exists() and time.monotonic() < deadline:
            await asyncio.sleep(0.05)
        if not path.exists():
            return self.refuse(request, session, "report_missing", 503)
        stem = f"{run.lab}-{run.id[:6]}"
        headers = {"Content-Security-Policy": "script-src 'none'; frame-ancestors 'self'"} \
            if fmt == "html" else {}
        disposition = "inline" if fmt == "html" or request.query_params.get("view") else \
            "attachment"
        return FileResponse(path, filename=f"{stem}.{fmt}", headers=headers,
                            content_disposition_type=disposition)

    async def measurement_zip(self, request: Request) -> Response:
        session, run = self._run(request)
        if run is None or not (run.folder / MEASUREMENT).exists():
            return self.refuse(request, session, "not_found", 404)
        blob = io.BytesIO()
        stem = f"{run.lab}-{run.id[:6]}"
        with zipfile.ZipFile(blob, "w", zipfile.ZIP_DEFLATED) as z:
            z.write(run.folder / MEASUREMENT, f"{stem}/{stem}.toml")
            for name in run.files():
                z.write(run.folder / name, f"{stem}/{name}")
        return Response(blob.getvalue(), media_type="application/zip", headers={
            "Content-Disposition": f'attachment; filename="{stem}.zip"'})

    async def edit(self, request: Request) -> Response:
        session, run = self._run(request)
        if run is None or not (run.folder / MEASUREMENT).exists():
            return self.refuse(request, session, "not_found", 404)
        doc = tomllib.loads((run.folder / MEASUREMENT).read_text(encoding="utf-8"))
        values, counts = forms.values(doc, _spec(run.lab))
        return self.form_page(request, session, run.lab, values, counts, run)

    async def open_zip(self, request: Request) -> Response:
        return await self.guarded(request, self._open_zip)

    async def _open_zip(self, request: Request, session: Session, form: dict) -> Response:
        uploads = form.get("files", [])
        if not any(isinstance(u, UploadFile) and u.filename for u in uploads):
            return self.refuse(request, session, "bad_zip", 422)
        run = self.store.new_run(session, "")
        try:
            doc, renamed = await asyncio.to_thread(
                _opened, uploads, run.folder, self.s.file_limit, self.s.submission_limit,
                self.s.max_files)
        except InputError as exc:
            return self.refuse(request, session, "bad_zip", 422, exc.text(session.lang))
        lab = doc.get("lab")
        if lab not in CATALOGUE:
            return self.refuse(request, session, "bad_zip", 422, str(lab)[:80])
        spec = _spec(lab)
        values, counts = forms.values(doc, spec)
        missing = {path: name for path, name in forms.named_files(values, spec).items()
                   if _base_name(name) not in renamed}
        if missing:
            listed = ", ".join(f"{name} ({path})" for path, name in missing.items())
            return self.refuse(request, session, "bad_zip", 422, _bad_opening(
                f"the .toml names {listed}, not given with it",
                f"в .toml названы {listed}, но не даны вместе с ним").text(session.lang))
        run.lab = lab
        values = {k: renamed.get(_base_name(v), v) if isinstance(v, str) else v
                  for k, v in values.items()}
        (run.folder / MEASUREMENT).write_text(dumps(doc), encoding="utf-8")
        return self.form_page(request, session, lab, values, counts, run)

    # ------------------------------------------------------------------ class
    async def hand_in(self, request: Request) -> Response:
        return await self.guarded(request, self._hand_in)

    async def _hand_in(self, request: Request, session: Session, form: dict) -> Response:
        run = self.store.run(session, request.path_params["run"])
        if self.classroom is None or run is None or run.status != "ok":
            return self.refuse(request, session, "not_found", 404)
        sid = str(form.get("student", ""))
        if sid not in dict(self.classroom.roster):
            return self.refuse(request, session, "unknown_student", 422)
        try:
            self.classroom.hand_in(run.folder, run.lab, sid, str(form.get("reported", "")),
                                   run.files())
        except InputError as exc:
            return self.page(request, session, "run.html", 422, run=run, lab=CATALOGUE[run.lab],
                             roster=self.classroom.roster, hand_in_error=exc.text(session.lang))
        run.handed_in = sid
        asyncio.get_running_loop().create_task(self.classroom.refresh(self.pool, session.lang))
        return RedirectResponse(f"/run/{run.id}", status_code=303)

    def teacher(self, request: Request) -> bool:
        given = request.query_params.get("key") or request.cookies.get("dynlab_teacher", "")
        return self.classroom is not None and hmac.compare_digest(given,
                                                                  self.s.teacher_token)

    async def class_page(self, request: Request) -> Response:
        session = self.session(request)
        if not self.teacher(request):
            return self.refuse(request, session, "forbidden", 403)
        if not self.classroom.outputs() and self.classroom.state == "idle":
            asyncio.get_running_loop().create_task(
                self.classroom.refresh(self.pool, session.lang))
        response = self.page(request, session, "class.html", room=self.classroom)
        response.set_cookie("dynlab_teacher", self.s.teacher_token, httponly=True,
                            samesite="strict", max_age=int(self.s.ttl))
        return response

    async def class_status(self, request: Request) -> Response:
        if not self.teacher(request):
            return JSONResponse({"error": "forbidden"}, status_code=403)
        return JSONResponse(self.classroom.status())

    async def class_file(self, request: Request) -> Response:
        session = self.session(request)
        if not self.teacher(request):
            return self.refuse(request, session, "forbidden", 403)
        path = self.classroom.output(request.path_params["name"])
        if path is None:
            return self.refuse(request, session, "not_found", 404)
        inline = path.suffix == ".html"
        return FileResponse(path, filename=path.name,
                            content_disposition_type="inline" if inline else "attachment",
                            headers={"Content-Security-Policy": "script-src 'unsafe-inline'"}
                            if inline else {})

    # ------------------------------------------------------------------ lifetime
    @contextlib.asynccontextmanager
    async def lifespan(self, app):
        self._sweeper = asyncio.get_running_loop().create_task(self._sweep())
        if self.s.on_start is not None:
            await self.pool.run(ready_child)       # the toolkit imported before students come
            self.s.on_start()
        try:
            yield
        finally:
            self._sweeper.cancel()
            self.store.close()

    async def _sweep(self) -> None:
        while True:
            await asyncio.sleep(min(60.0, self.s.ttl / 4))
            self.store.sweep()


def _spec(lab: str):
    from ..registry import LABS

    return LABS[lab].SPEC


def _counts(spec, texts: dict) -> dict[str, int]:
    return {sec.name: max(1, len(forms.entry_indices(texts, sec.name)))
            for sec in spec.sections if sec.many}


def _paths(spec, counts: dict) -> set[str]:
    """Every field path and section name the form shows (where an error can stand)."""
    paths = {"meta." + k for k in ("student", "group", "date", "rig", "notes")}
    for sec in spec.sections:
        paths.add(sec.name)
        for i in range(counts.get(sec.name, 1)) if sec.many else [None]:
            where = sec.name if i is None else f"{sec.name}[{i}]"
            paths |= {f"{where}.{f.name}" for f in sec.fields}
    return paths


def _error(exc: InputError) -> dict:
    return {"field": exc.field, "en": exc.text("en"), "ru": exc.text("ru")}


def _base_name(name: str) -> str:
    """A file's name without its folders, of either separator (a zip made on Windows)."""
    return name.replace("\\", "/").rsplit("/", 1)[-1]


def _bad_opening(problem: str, problem_ru: str) -> InputError:
    return InputError(problem, "open the measurement's .toml together with the files it names "
                      "(select them all), or the measurement zip downloaded from this page",
                      ru=(problem_ru, "откройте .toml измерения вместе с файлами, которые в нём "
                          "названы (выберите их все), или zip измерения, скачанный с этой "
                          "страницы"))


def _opened(uploads: list, folder: Path, file_limit: int, total_limit: int,
            max_files: int) -> tuple[TomlDocument, dict[str, str]]:
    """What a student opens: a measurement zip downloaded from this page (:func:`_unpack`), or
    a measurement's .toml with the files it names selected with it (a handout of
    ``dynlab synth --students``), each read as :func:`_stored` reads a zip's files."""
    uploads = [u for u in uploads if isinstance(u, UploadFile) and u.filename]
    if not uploads:
        raise _bad_opening("no file chosen", "файл не выбран")
    if len(uploads) == 1 and not uploads[0].filename.lower().endswith(MEASUREMENT_NAMES):
        return _unpack(uploads[0].file, folder, file_limit, total_limit, max_files)
    return _stored([(u.filename, lambda u=u: contextlib.nullcontext(u.file)) for u in uploads],
                   folder, file_limit, total_limit, max_files, "chosen")


def _unpack(source, folder: Path, file_limit: int, total_limit: int,
            max_files: int) -> tuple[TomlDocument, dict[str, str]]:
    """A measurement zip's TOML document and its other files, stored by :func:`_stored`."""
    try:
        z = zipfile.ZipFile(source)
        infos = [i for i in z.infolist() if not i.is_dir()]
    except (zipfile.BadZipFile, OSError):
        raise _bad_opening("not a zip file", "не zip-файл") from None
    try:
        return _stored([(i.filename, lambda i=i: z.open(i)) for i in infos], folder,
                       file_limit, total_limit, max_files, "in the zip")
    except (zipfile.BadZipFile, zlib.error, EOFError, NotImplementedError) as exc:
        raise _bad_opening(f"the zip is damaged ({exc})", f"zip повреждён ({exc})") from None


def _stored(entries: list, folder: Path, file_limit: int, total_limit: int, max_files: int,
            where: str) -> tuple[TomlDocument, dict[str, str]]:
    """The TOML document of ``entries`` ((name, opener) pairs: one .toml and its files), the
    other files written into ``folder`` under safe names (returned: name given → name
    stored), within the limits: at most ``max_files`` files, each at most ``file_limit``
    bytes and all at most ``total_limit`` (counted as they are written, whatever a zip
    declares)."""
    ru_where = {"in the zip": "в zip", "chosen": "выбрано"}[where]
    grows, grows_ru = (("unpacks to", "распаковывается больше чем в") if where == "in the zip"
                       else ("is", "больше"))
    if len(entries) > max_files:
        raise _bad_opening(f"{len(entries)} files {where}, more than {max_files}",
                           f"{ru_where} {len(entries)} файлов, больше {max_files}")
    tomls = [e for e in entries if e[0].lower().endswith(MEASUREMENT_NAMES)]
    if len(tomls) != 1:
        raise _bad_opening(f"{len(tomls)} .toml files {where}, not one",
                           f"{ru_where} {len(tomls)} файлов .toml, а не один")
    left, renamed, text = total_limit, {}, ""

    def copy(name: str, opener, target, limit: int) -> int:
        size = 0
        with opener() as f:
            while chunk := f.read(1 << 20):
                size += len(chunk)
                if size > limit:
                    raise _bad_opening(f"{name} {grows} more than {limit // MiB} MiB",
                                       f"{name} {grows_ru} {limit // MiB} МиБ")
                target.write(chunk)
        return size

    for name, opener in entries:
        if name.lower().endswith(MEASUREMENT_NAMES):
            blob = io.BytesIO()
            left -= copy(name, opener, blob, min(MEASUREMENT_KIND.limit, left))
            text = measurement_text(blob.getvalue())
            if text is None:
                raise _bad_opening(f"{name} is not a text file in UTF-8, UTF-16 or "
                                   f"Windows-1251", f"{name} — не текстовый файл в UTF-8, "
                                   f"UTF-16 или Windows-1251")
            continue
        base = _base_name(name)
        renamed[base] = safe_name(base, set(renamed.values()))
        with open(folder / renamed[base], "wb") as out:
            left -= copy(name, opener, out, min(file_limit, left))
    try:
        return TomlDocument(tomllib.loads(text), text), renamed
    except tomllib.TOMLDecodeError as exc:
        raise _bad_opening(f"its .toml does not parse ({exc})", f"его .toml не читается ({exc})") \
            from None


class TokenGate:
    """ASGI middleware: a request without the token (in the link, then in a cookie) is refused
    with 403; one with a Host not served is refused with 400 (a page on loopback does not
    answer another site's name: DNS rebinding)."""

    def __init__(self, app, token: str | None, hosts: tuple[str, ...] | None):
        self.app, self.token, self.hosts = app, token, hosts

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        request = Request(scope)
        host = (request.headers.get("host") or "").rsplit(":", 1)[0].strip("[]")
        if self.hosts is not None and host not in self.hosts:
            return await Response("unknown host", 400)(scope, receive, send)
        if self.token is None or scope["path"].startswith("/static/"):
            return await self.app(scope, receive, send)
        given = request.query_params.get("token")
        if given is not None and hmac.compare_digest(given, self.token):
            response = RedirectResponse(scope["path"], status_code=303)
            response.set_cookie(TOKEN_COOKIE, self.token, httponly=True, samesite="lax")
            return await response(scope, receive, send)
        if hmac.compare_digest(request.cookies.get(TOKEN_COOKIE, ""), self.token):
            return await self.app(scope, receive, send)
        text = TEXT["en"]["no_token"] + " / " + TEXT["ru"]["no_token"]
        return await Response(text, 403, media_type="text/plain; charset=utf-8")(
            scope, receive, send)


def create_app(settings: Settings | None = None) -> Starlette:
    """The page's application, with ``settings`` (defaults: loopback, no class)."""
    settings = settings or Settings()
    web = WebApp(settings)
    static = resources.files("labs.web").joinpath("static")
    app = Starlette(routes=[
        Route("/", web.home),
        Route("/lab/{lab}", web.lab_form, methods=["GET"]),
        Route("/lab/{lab}", web.reduce, methods=["POST"]),
        Route("/open", web.open_zip, methods=["POST"]),
        Route("/run/{run}", web.run_page),
        Route("/run/{run}/report.{fmt}", web.report),
        Route("/run/{run}/measurement.zip", web.measurement_zip),
        Route("/run/{run}/edit", web.edit),
        Route("/run/{run}/hand-in", web.hand_in, methods=["POST"]),
        Route("/class", web.class_page),
        Route("/class/status", web.class_status),
        Route("/class/file/{name}", web.class_file),
        Mount("/static", StaticFiles(directory=str(static)), name="static"),
    ], lifespan=web.lifespan)
    app.state.web = web
    app.add_middleware(TokenGate, token=settings.token, hosts=settings.hosts)
    return app

