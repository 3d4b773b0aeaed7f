"""The page's sessions and their folders: every file a student sends lives in a folder of its
session, named by the server, and is deleted when the session expires.

No name from a request becomes a path: a session's folder and a submission's folder are
random names the server chose, looked up by the ids the server gave; an uploaded file keeps its
own name only as far as :func:`safe_name` lets it (one plain name, no folder, no leading dot).
"""
from __future__ import annotations

import re
import secrets
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path

from .worker import MEASUREMENT

_UNSAFE = re.compile(r"[^A-Za-z0-9._-]+")
_ID = re.compile(r"^[0-9a-f]{16}$")


def safe_name(filename: str, taken=()) -> str:
    """A file's name as it may be stored: its last part only, letters, digits and ``._-``,
    no leading dot, at most 100 characters, not the measurement file's, not one in ``taken``.

    >>> safe_name("../../etc/passwd"), safe_name("C:\\\\photos\\\\decay 1.jpg"), safe_name(".env")
    ('passwd', 'decay_1.jpg', 'env')
    >>> safe_name("decay.jpg", {"decay.jpg"}), safe_name("measurement.toml")
    ('1-decay.jpg', 'file-measurement.toml')
    """
    base = re.split(r"[/\\]", filename)[-1]
    name = _UNSAFE.sub("_", base).lstrip("._-")[-100:] or "file"
    if name == MEASUREMENT:
        name = f"file-{name}"
    stem, n = name, 0
    while name in taken:
        n += 1
        name = f"{n}-{stem}"
    return name


def valid_id(text: str) -> bool:
    """Whether ``text`` is of the form the server gives its ids."""
    return bool(_ID.match(text or ""))


@dataclass
class Run:
    """One submission: its folder (the measurement file, its files, the reports), its lab,
    the report's language and how its reduction ended."""

    id: str
    folder: Path
    lab: str
    lang: str
    status: str = "new"
    error: dict | None = None
    seconds: float = 0.0
    handed_in: str | None = None
    pdf: object = None
    """The task making the PDF report, once one was asked for."""

    def files(self) -> list[str]:
        """The files the measurement names, as stored beside it."""
        return sorted(p.name for p in self.folder.iterdir()
                      if p.is_file() and not p.name.startswith(".")
                      and p.name != MEASUREMENT and not p.name.startswith("report."))


@dataclass
class Session:
    """A browser's session: its CSRF token, its folder, its submissions, its language."""

    id: str
    csrf: str
    folder: Path
    lang: str
    touched: float = field(default_factory=time.monotonic)
    runs: dict[str, Run] = field(default_factory=dict)


class Store:
    """Every session, in folders under ``root``; a session untouched for ``ttl`` seconds is
    deleted with its files, and a session keeps its last ``max_runs`` submissions."""

    def __init__(self, root: Path, ttl: float = 2 * 3600, max_runs: int = 20,
                 max_sessions: int = 2000):
        self.root, self.ttl, self.max_runs, self.max_sessions = root, ttl, max_runs, max_sessions
        root.mkdir(parents=True, exist_ok=True)
        self.sessions: dict[str, Session] = {}

    def new(self, lang: str) -> Session:
        self.sweep()
        if len(self.sessions) >= self.max_sessions:
            oldest = min(self.sessions.values(), key=lambda s: s.touched)
            self.drop(oldest.id)
        folder = self.root / secrets.token_hex(8)
        folder.mkdir(mode=0o700)
        s = Session(secrets.token_urlsafe(24), secrets.token_urlsafe(24), folder, lang)
        self.sessions[s.id] = s
        return s

    def get(self, sid: str | None) -> Session | None:
        s = self.sessions.get(sid or "")
        if s is None:
            return None
        if time.monotonic() - s.touched > self.ttl:
            self.drop(s.id)
            return None
        s.touched = time.monotonic()
        return s

    def new_run(self, s: Session, lab: str) -> Run:
        """A new submission's folder in session ``s`` (its oldest dropped beyond
        ``max_runs``)."""
        while len(s.runs) >= self.max_runs:
            old = s.runs.pop(next(iter(s.runs)))
            shutil.rmtree(old.folder, ignore_errors=True)
        rid = secrets.token_hex(8)
        folder = s.folder / rid
        folder.mkdir(mode=0o700)
        run = Run(rid, folder, lab, s.lang)
        s.runs[rid] = run
        return run

    def run(self, s: Session, rid: str) -> Run | None:
        return s.runs.get(rid) if valid_id(rid) else None

    def drop(self, sid: str) -> None:
        s = self.sessions.pop(sid, None)
        if s is not None:
            shutil.rmtree(s.folder, ignore_errors=True)

    def sweep(self) -> int:
        """Delete the expired sessions; how many were."""
        now = time.monotonic()
        old = [sid for sid, s in self.sessions.items() if now - s.touched > self.ttl]
        for sid in old:
            self.drop(sid)
        return len(old)

    def close(self) -> None:
        """Delete every session and the root folder."""
        for sid in list(self.sessions):
            self.drop(sid)
        shutil.rmtree(self.root, ignore_errors=True)
