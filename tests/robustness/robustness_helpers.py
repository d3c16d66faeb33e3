"""Shared helpers for the robustness suite: generated inputs, runs with a time cap, debris checks."""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
TIME_CAP_S = 120


def env() -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT) + os.pathsep + e.get("PYTHONPATH", "")
    return e


def run_cli(args, cwd, timeout=TIME_CAP_S, mem_mb=None):
    """Run ``python -m odnn_sep.cli ARGS`` in a subprocess with a time (and address-space) cap."""
    pre = None
    if mem_mb:
        def pre():
            import resource

            resource.setrlimit(resource.RLIMIT_AS, (mem_mb << 20, mem_mb << 20))
    return subprocess.run([sys.executable, "-m", "odnn_sep.cli", *map(str, args)], cwd=cwd, env=env(),
                          capture_output=True, text=True, timeout=timeout, preexec_fn=pre)


def snapshot(folder) -> dict:
    """{relative path: sha256} of every file under ``folder`` (hidden ones included)."""
    import stat

    out = {}
    for dirpath, _, names in os.walk(folder):
        for n in names:
            p = Path(dirpath) / n
            try:
                st = p.stat()
            except OSError:  # a broken link or a loop
                out[str(p.relative_to(folder))] = "link:" + os.readlink(p)
                continue
            if stat.S_ISREG(st.st_mode):
                out[str(p.relative_to(folder))] = hashlib.sha256(p.read_bytes()).hexdigest()
            else:  # never open a pipe or a device (it would block)
                out[str(p.relative_to(folder))] = f"mode:{stat.S_IFMT(st.st_mode)}"
    return out


def debris(folder) -> list[str]:
    """Temporary or hidden leftovers under ``folder``."""
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*")
                  if any(part.startswith(".") for part in p.relative_to(folder).parts))


def write_wav(path, seconds=4.0, sr=8000, hum=0.2, seed=0, channels=1):
    import soundfile as sf

    t = np.arange(int(seconds * sr)) / sr
    rng = np.random.default_rng(seed)
    y = 0.1 * rng.normal(size=(t.size, channels)) + hum * np.sin(2 * np.pi * 50.02 * t)[:, None]
    st = "PCM_16" if Path(path).suffix.lower() in (".wav", ".flac") else None
    sf.write(str(path), y if channels > 1 else y[:, 0], sr, subtype=st)
    return path


def write_csv(path, n=400, seed=0):
    rng = np.random.default_rng(seed)
    x = np.linspace(-np.pi, np.pi, n)
    y = 0.5 * x**2 * np.sin(5 * x) + np.cos(x) + 0.01 * rng.normal(size=n)
    np.savetxt(path, np.c_[x, y], delimiter=",", header="x,y", comments="", fmt="%.10g")
    return path


def write_oscillator_csv(path, n=600, seed=0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 20, n)
    y = np.exp(-0.05 * t) * np.cos(2.0 * t) + 0.01 * rng.normal(size=n)
    np.savetxt(path, np.c_[t, y], delimiter=",", header="t,x", comments="", fmt="%.10g")
    return path


def write_png(path, size=(96, 128), seed=0):
    import cv2

    rng = np.random.default_rng(seed)
    img = (rng.uniform(0, 255, size=(*size, 3))).astype(np.uint8)
    cv2.imwrite(str(path), img)
    return path


def write_npz(path, nx=40, ny=30):
    x = np.linspace(0, 1, nx)
    y = np.linspace(0, 1, ny)
    X, Y = np.meshgrid(x, y)
    z = np.sin(3 * X) * np.cos(2 * Y)
    np.savez(path, x=x, y=y, z=z)
    return path


def one_error_line(stderr: str) -> bool:
    """Exactly one line starting 'Error:' and no traceback."""
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    return ("Traceback" not in stderr and sum(ln.startswith("Error:") for ln in lines) == 1)
