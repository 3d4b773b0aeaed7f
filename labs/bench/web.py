"""Load benchmark of ``dynlab serve`` on loopback (not a timed test):
``python -m labs.bench.web [--students 30] [--photos 5] [--within 60] [--workers 2]``.

Starts ``dynlab serve`` as a student would, warms it, then measures, idle, the form page and
a lab 1 reduction (form posted → the redirect to its report, the result JSON written; and
until the HTML report with its figures is there). Then a class arrives: ``--students`` hand
in lab 1 (the bundled sample's readings, typed with decimal commas) and ``--photos`` hand in
lab 9's photographed decay, at random moments within ``--within`` seconds. Every one must be
answered with its report and none lost; the server's memory (its process and all its
children, summed resident sets) is sampled every 0.2 s. Targets: the form page within
0.2 s and a warm lab 1 reduction within 0.5 s, every submission answered, the peak memory
bounded by the pool (``workers`` children and the server).
"""
from __future__ import annotations

import argparse
import random
import re
import socket
import statistics
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from labs.samples import sample_dir

LAB1 = {"meta.student": "bench", "body.m": "11,800", "body.g": "9,8156 ± 0,0005 m/s^2",
        "trifilar.R1": "99,8", "trifilar.R2": "140,3", "trifilar.l": "799,8",
        "trifilar.n_osc": "20", "trifilar.t": "36,07; 36,21; 36,22", "trifilar.m_p": "2,104",
        "trifilar.t_p": "34,38; 34,27; 34,33"}
LAB9 = {"meta.student": "bench", "decay.I": "0,03 ± 0,00015 kg*m^2",
        "decay.cal_phi": "0; 3; 6; 9", "decay.cal_reading": "0,06239; 10,47; 21; 31,48",
        "image.mark_period": "1", "image.paper_width": "120"}


def _client(base: str):
    try:
        import httpx2 as httpx
    except ImportError:
        import httpx
    return httpx.Client(base_url=base, timeout=600)


def _rss(pid: int) -> int:
    """Resident memory of ``pid`` and all its descendants [bytes] (Linux /proc)."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
        except (OSError, IndexError, ValueError):
            continue
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        todo += children.get(p, [])
        try:
            for line in Path(f"/proc/{p}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1]) * 1024
        except OSError:
            continue
    return total


def submit(base: str, lab: str, values: dict, files: dict) -> dict:
    """One student: the form, the posted readings, the report. Times in seconds."""
    with _client(base) as c:
        t0 = time.perf_counter()
        form = c.get(f"/lab/{lab}")
        t1 = time.perf_counter()
        csrf = re.search(r'name="csrf" value="([^"]+)"', form.text)[1]
        posted = c.post(f"/lab/{lab}", data={"csrf": csrf, **values},
                        files=files or {"_": ("", b"")})
        t2 = time.perf_counter()
        if posted.status_code != 303:
            return {"lab": lab, "status": posted.status_code, "form": t1 - t0}
        run = posted.headers["location"]
        html = c.get(f"{run}/report.html")
        t3 = time.perf_counter()
        ok = html.status_code == 200 and b"<html" in html.content[:2000].lower()
        return {"lab": lab, "status": 200 if ok else html.status_code, "form": t1 - t0,
                "reduce": t2 - t1, "report": t3 - t1}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _serve(workers: int) -> tuple[subprocess.Popen, str]:
    port = _free_port()
    proc = subprocess.Popen([sys.executable, "-m", "labs.cli.main", "serve", "--port", str(port),
                             "--workers", str(workers)], stdout=subprocess.DEVNULL)
    deadline = time.time() + 120
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return proc, f"http://127.0.0.1:{port}"
        except OSError:
            if time.time() > deadline or proc.poll() is not None:
                raise RuntimeError("dynlab serve did not start") from None
            time.sleep(0.2)


def _stats(xs: list[float]) -> str:
    xs = sorted(xs)
    if not xs:
        return "—"
    p95 = xs[min(len(xs) - 1, round(0.95 * (len(xs) - 1)))]
    return f"median {statistics.median(xs):.3f} s, p95 {p95:.3f} s, max {xs[-1]:.3f} s"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m labs.bench.web",
                                description=__doc__.splitlines()[0])
    p.add_argument("--students", type=int, default=30)
    p.add_argument("--photos", type=int, default=5)
    p.add_argument("--within", type=float, default=60.0)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args(argv)
    photo = {"decay.signal": ("decay.jpg", (sample_dir() / "lab9-photo/decay.jpg").read_bytes(),
                              "image/jpeg")}
    proc, base = _serve(args.workers)
    peak, stop = [0], threading.Event()

    def sample():
        while not stop.is_set():
            peak[0] = max(peak[0], _rss(proc.pid))
            time.sleep(0.2)

    try:
        for _ in range(2):                                   # warm: the forkserver, the pages
            submit(base, "lab1", LAB1, {})
        idle_rss = _rss(proc.pid)
        warm = [submit(base, "lab1", LAB1, {}) for _ in range(5)]
        print(f"warm, idle server ({args.workers} workers):")
        print(f"  form page        {_stats([w['form'] for w in warm])}")
        print(f"  lab 1 reduction  {_stats([w['reduce'] for w in warm])}  (posted → redirect, "
              f"result JSON written)")
        print(f"  lab 1 report     {_stats([w['report'] for w in warm])}  (form → HTML report "
              f"with its figures)")
        watcher = threading.Thread(target=sample, daemon=True)
        watcher.start()
        rng = random.Random(args.seed)
        jobs = [("lab1", LAB1, {})] * args.students + [("lab9", LAB9, photo)] * args.photos
        start = time.perf_counter()
        moments = sorted(rng.uniform(0, args.within) for _ in jobs)
        rng.shuffle(jobs)

        def student(k: int) -> dict:
            time.sleep(max(0.0, moments[k] - (time.perf_counter() - start)))
            lab, values, files = jobs[k]
            try:
                return submit(base, lab, values, files)
            except Exception as exc:
                return {"lab": lab, "status": f"{type(exc).__name__}: {exc}"}

        with ThreadPoolExecutor(len(jobs)) as pool:
            results = list(pool.map(student, range(len(jobs))))
        wall = time.perf_counter() - start
        stop.set()
        watcher.join()
        answered = [r for r in results if r["status"] == 200]
        print(f"\na class: {args.students} × lab 1 and {args.photos} × lab 9 photograph, "
              f"arriving within {args.within:g} s")
        print(f"  answered with their report: {len(answered)} of {len(jobs)}; lost or refused: "
              f"{[r['status'] for r in results if r['status'] != 200] or 'none'}")
        print(f"  all done after {wall:.1f} s")
        for lab in ("lab1", "lab9"):
            rs = [r for r in answered if r["lab"] == lab]
            print(f"  {lab}: form page {_stats([r['form'] for r in rs])}")
            print(f"        reduction {_stats([r['reduce'] for r in rs])}")
            print(f"        report    {_stats([r['report'] for r in rs])}")
        print(f"  memory (server and its children, resident): idle {idle_rss / 2**20:.0f} MiB, "
              f"peak {peak[0] / 2**20:.0f} MiB")
        return 0 if len(answered) == len(jobs) else 1
    finally:
        proc.terminate()
        proc.wait(10)


if __name__ == "__main__":
    sys.exit(main())
