"""Reductions off the page's process: each in a process of its own, with a time and a memory
limit, a bounded number at a time.

A reduction runs in a child forked from a server process that imported the toolkit once
(``multiprocessing``'s *forkserver*, preloaded with this module), so it starts warm: the 1.7 s
of imports the command line pays each time are paid once. The child sets its own limits
(:func:`resource.setrlimit`: address space and CPU seconds), reduces the measurement file
exactly as ``dynlab run`` does (:func:`labs.registry.evaluate`, confined to its folder), writes
the result JSON, says so, then draws the figures and writes the HTML report; the PDF is made
when it is asked for (:func:`pdf_child`). A child that runs past its time is
killed; one that dies (out of memory, a crash in a decoder) is reported as such; neither stops
the page. At most ``workers`` children run at once and at most ``queue`` requests wait for
one; more are turned away (:class:`Busy`) rather than queued without end.
"""
from __future__ import annotations

import asyncio
import os
import resource
import time
from dataclasses import dataclass, replace
from pathlib import Path

MEASUREMENT = "measurement.toml"
"""The measurement file's name in a submission's folder."""

REPORTS = {"json": "report.json", "html": "report.html", "pdf": "report.pdf"}
"""The reports a reduction writes into its folder, by format."""

MiB = 1 << 20


class Busy(Exception):
    """Every worker is busy and the queue is full."""


@dataclass(frozen=True)
class Limits:
    """What one reduction may take: wall-clock seconds, address space [bytes], CPU seconds."""

    seconds: float = 120.0
    memory: int = 3072 * MiB
    cpu: int = 300


@dataclass(frozen=True)
class Outcome:
    """How a reduction ended: ``ok``, ``input`` (bad input: ``error`` holds its field and its
    message in both languages), ``timeout`` or ``crash`` (``error["en"]`` says what)."""

    status: str
    error: dict | None = None
    seconds: float = 0.0


def _limit(limits: Limits) -> None:
    """Bound this process: its address space and its CPU time."""
    resource.setrlimit(resource.RLIMIT_AS, (limits.memory, limits.memory))
    resource.setrlimit(resource.RLIMIT_CPU, (limits.cpu, limits.cpu + 5))


def _write(folder: Path, name: str, blob: bytes) -> None:
    """Write a report whole or not at all (nothing if its session expired meanwhile)."""
    part = folder / f".{name}.part"
    try:
        part.write_bytes(blob)
        os.replace(part, folder / name)
    except FileNotFoundError:
        return


def _child(target, conn, args: tuple, limits: Limits) -> None:
    """A child's life: its limits set, then ``target(conn, *args)``."""
    _limit(limits)
    target(conn, *args)


def reduce_child(conn, folder: str, lang: str) -> None:
    """The child's work: reduce ``folder/measurement.toml`` as ``dynlab run --confine`` does,
    write the result JSON, report the outcome on ``conn``, then draw the figures and write
    the HTML report (the page waits for it)."""
    from processing.reporting.render import figure_png, to_html, to_json

    here = Path(folder)
    result = _evaluate(conn, here)
    if result is None:
        return
    _write(here, REPORTS["json"], to_json(result).encode("utf-8"))
    conn.send(("ok", None))
    conn.close()
    pngs = [figure_png(f, lang) for f in result.figures]
    _write(here, REPORTS["html"], to_html(result, lang, pngs).encode("utf-8"))


def pdf_child(conn, folder: str, lang: str) -> None:
    """The child's work for a PDF report, asked for when a student downloads it: the same
    reduction, its figures, the A4 PDF."""
    from processing.reporting.render import render

    here = Path(folder)
    result = _evaluate(conn, here)
    if result is None:
        return
    _write(here, REPORTS["pdf"], render(result, ("pdf",), lang)["pdf"])
    conn.send(("ok", None))


def _evaluate(conn, here: Path):
    """:func:`labs.registry.evaluate` of the folder's measurement file, confined to the
    folder and named as the student's download names it; None (the outcome sent on
    ``conn``) when it fails."""
    from processing.diagnostics import InputError

    from labs.registry import evaluate

    os.chdir(here)
    try:
        return evaluate(MEASUREMENT, confine=True)
    except InputError as exc:
        conn.send(("input", {"field": exc.field, "en": exc.text("en"), "ru": exc.text("ru")}))
    except MemoryError:
        conn.send(("crash", {"en": "the reduction ran out of its memory",
                             "ru": "обработке не хватило отведённой памяти"}))
    except Exception as exc:
        text = f"internal error: {type(exc).__name__}: {exc}"
        conn.send(("crash", {"en": text, "ru": text}))
    return None


def ready_child(conn) -> None:
    """A child that only says it started: the forkserver has imported the toolkit."""
    conn.send(("ok", None))


def check_child(conn, folder: Path, out: Path, lang: str, keys: Path | None,
                roster: Path | None) -> None:
    """The child's work for a class: ``dynlab check`` of ``folder`` (against the answer keys
    and the roster, if given) with its summary written to ``out``; the refusals sent as its
    log."""
    from labs.teachers.check import read_class
    from labs.teachers.check_report import write_summary
    from processing.diagnostics import InputError

    def crash(exc: Exception, path: str) -> str:
        return f"{path}: internal error: {type(exc).__name__}: {exc}"

    try:
        result = read_class(folder, keys=keys, roster=roster, lang=lang, crash=crash)
        write_summary(Path(out), result, lang)
    except InputError as exc:                   # no hand-in yet, or bad keys: said, not fatal
        conn.send(("ok", {"en": exc.text("en")}))
        return
    said = [p if isinstance(p, str) else p.line("en") for p in result.problems.values()]
    conn.send(("ok", {"en": "\n".join(said)[-2000:]}))


class Pool:
    """A bounded pool of reductions, each in a fresh child of a warm forkserver."""

    def __init__(self, workers: int = 2, queue: int = 64, limits: Limits = Limits()):
        import multiprocessing

        for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ.setdefault(name, "1")   # one core per child: the pool shares them
        self.ctx = multiprocessing.get_context("forkserver")
        self.ctx.set_forkserver_preload(["labs.web.preload"])
        self.workers, self.queue, self.limits = workers, queue, limits
        self.waiting = 0
        self.running = 0
        self._slots: asyncio.Semaphore | None = None

    def warm(self) -> None:
        """Start the forkserver now (it imports the toolkit: a few seconds), not on the first
        student's request."""
        from multiprocessing import forkserver

        forkserver.ensure_running()

    async def run(self, target, *args, scale: int = 1) -> Outcome:
        """Run ``target(conn, *args)`` in a child under the limits (its time and CPU ``scale``
        times one reduction's: a class's check reduces each hand-in); the outcome it sends, or
        ``timeout``/``crash``. Raises :class:`Busy` when the queue is full."""
        limits = replace(self.limits, seconds=self.limits.seconds * max(scale, 1),
                         cpu=self.limits.cpu * max(scale, 1))
        if self._slots is None:
            self._slots = asyncio.Semaphore(self.workers)
        if self.waiting >= self.queue:
            raise Busy()
        self.waiting += 1
        try:
            await self._slots.acquire()
        finally:
            self.waiting -= 1
        self.running += 1
        start = time.monotonic()
        try:
            receive, send = self.ctx.Pipe(duplex=False)
            child = self.ctx.Process(target=_child, args=(target, send, args, limits),
                                     daemon=True)
            child.start()
            send.close()
        except BaseException:
            self._release()
            raise
        outcome = await asyncio.to_thread(self._outcome, receive, child, start, limits.seconds)
        asyncio.get_running_loop().create_task(self._finish(child, start, limits.seconds))
        return outcome

    def _outcome(self, receive, child, start: float, limit: float) -> Outcome:
        """Wait for the child's word, at most its time ``limit`` [s]; kill it if it is late."""
        late = not receive.poll(limit)
        seconds = time.monotonic() - start
        if late:
            child.kill()
            return Outcome("timeout", {"en": f"the reduction took longer than "
                                             f"{limit:g} s and was stopped",
                                       "ru": f"обработка заняла больше {limit:g} с "
                                             f"и была остановлена"}, seconds)
        try:
            status, error = receive.recv()
        except (EOFError, OSError):
            child.join(5)
            return Outcome("crash", {"en": f"the reduction's process died (exit code "
                                           f"{child.exitcode}; out of memory?)",
                                     "ru": f"процесс обработки завершился аварийно (код "
                                           f"{child.exitcode}; не хватило памяти?)"}, seconds)
        finally:
            receive.close()
        return Outcome(status, error, seconds)

    async def _finish(self, child, start: float, limit: float) -> None:
        """Let the child finish its PDF within its time ``limit`` [s], then free its slot."""
        try:
            left = max(0.0, limit - (time.monotonic() - start))
            await asyncio.to_thread(child.join, left)
            if child.is_alive():
                child.kill()
                await asyncio.to_thread(child.join, 5)
        finally:
            self._release()

    def _release(self) -> None:
        self.running -= 1
        self._slots.release()
