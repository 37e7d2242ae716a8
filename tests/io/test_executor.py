"""Process pools: one module makes them all; an interrupt stops every pool at once, without worker tracebacks."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
POOL = re.compile(
    r"ProcessPoolExecutor|multiprocessing\s*\.\s*(Pool|Process)\b|\bmp\.Pool\b|from multiprocessing import"
)


def test_one_module_makes_process_pools():
    """Every pool of the package and its scripts comes from elastoactive.io.executor (worker counts, Ctrl-C,
    loading the kernels once are decided there)."""
    found = []
    for folder in ("elastoactive", "analysis", "scripts"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            if path == ROOT / "elastoactive" / "io" / "executor.py":
                continue
            for number, line in enumerate(path.read_text().splitlines(), 1):
                if POOL.search(line):
                    found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "process pools made outside elastoactive/io/executor.py:\n" + "\n".join(found)


INTERRUPTED = """
import signal
import sys

# a terminal's Ctrl-C: the default handler, whatever disposition the process that started this one left it
signal.signal(signal.SIGINT, signal.default_int_handler)
from elastoactive.batch import Case, run_cases
from elastoactive.core.params import Numerics, Physics

cases = [Case(Physics(n=7, sigma=0.8 + 0.01 * i), Numerics(sample_dt=1.0), 200000.0, "reduced") for i in range(4)]
print("started", flush=True)
try:
    run_cases(cases, workers=2, progress=False)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
"""


def _children(pid: int) -> list[str]:
    try:
        return Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
    except OSError:
        return []


def _alive(pid: str) -> bool:
    try:
        return "\nState:\tZ" not in Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False


def test_ctrl_c_stops_a_pool_at_once_without_worker_tracebacks():
    """Ctrl-C at a terminal goes to the whole process group: the workers must not print KeyboardInterrupt
    tracebacks, and the parent must not wait for their running tasks (minutes here) before it stops."""
    proc = subprocess.Popen(
        [sys.executable, "-c", INTERRUPTED],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        assert proc.stdout.readline().strip() == "started"
        deadline = time.monotonic() + 60
        while len(_children(proc.pid)) < 2 and time.monotonic() < deadline:  # the pool's two workers
            time.sleep(0.1)
        time.sleep(1.0)  # running their tasks
        workers = _children(proc.pid)
        assert proc.poll() is None and len(workers) == 2
        os.killpg(proc.pid, signal.SIGINT)
        sent = time.monotonic()
        out, err = proc.communicate(timeout=20)
        waited = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert "interrupted" in out
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert waited < 3.0, f"stopped {waited:.1f} s after Ctrl-C"
    time.sleep(0.5)
    assert not [w for w in workers if _alive(w)], "pool workers outlived the interrupted parent"
