"""The bad-input corpus: every command x every kind of bad input, each a distinct case.

A case builds its inputs under ``d/in`` and names outputs under ``d/out``; it must end with exit
code 1 (one ``Error:`` line) or 2 (usage), no traceback, inputs unchanged and ``d/out`` empty.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from corpus_files import (
    GENERIC,
    generic,
    valid,
)


@dataclass
class Case:
    id: str
    build: Callable[[Path], list]
    env: dict = field(default_factory=dict)


CASES: list[Case] = []


def case(cid, env=None):
    def deco(fn):
        CASES.append(Case(cid, fn, env or {}))
        return fn
    return deco


def add(cid, fn, env=None):
    CASES.append(Case(cid, fn, env or {}))


def _i(d):
    return d / "in"


def _o(d):
    return d / "out"


# ---- base commands with valid inputs; a case changes one thing -------------------------------------
def denoise(d, *opts, src=None):
    src = src or valid("wav", _i(d) / "ok.wav")
    return ["denoise", src, "-o", _o(d) / "clean.wav", *opts]


def unwatermark(d, *opts, src=None, text=("--text", "SAMPLE")):
    src = src or valid("png", _i(d) / "ok.png")
    return ["unwatermark", src, *text, "-o", _o(d) / "clean.png", *opts]


def mismatch(d, *opts, src=None, model="oscillator"):
    src = src or valid("osc", _i(d) / "ok.csv")
    return ["mismatch", src, "--model", model, "--report", _o(d) / "r.json", *opts]


def separate(d, *opts, src=None, basis="x"):
    src = src or valid("csv", _i(d) / "ok.csv")
    return ["separate", src, "--basis", basis, "--report", _o(d) / "r.json", "-o", _o(d) / "parts.csv", *opts]


def simulate(d, *opts, name="figure2", out="fig.csv"):
    return ["simulate", name, "-o", _o(d) / out, *opts]


def batch(d, *opts, target="denoise"):
    valid("wav", _i(d) / "ok.wav")
    return ["batch", target, _i(d), "-o", _o(d) / "res", *opts]


# ---- 1. generic damaged files, for every file-reading command and every extension it reads ----------
READERS = {
    "denoise": (denoise, [(".wav", "wav"), (".flac", "wav"), (".ogg", "wav")]),
    "unwatermark": (unwatermark, [(".png", "png"), (".jpg", "png"), (".tif", "png")]),
    "mask": (lambda d, src: unwatermark(d, src=None, text=("--mask", src)), [(".png", "png")]),
    "mismatch": (mismatch, [(".csv", "osc"), (".wav", "wav"), (".npz", "npz")]),
    "separate": (separate, [(".csv", "csv"), (".npz", "npz")]),
}
for cmd, (base, exts) in READERS.items():
    for ext, kind in exts:
        for damage in GENERIC:
            if cmd == "mask":
                add(f"{cmd}-{damage}{ext}", lambda d, b=base, dm=damage, e=ext, k=kind: b(d, generic(dm, _i(d), e, k)))
            else:
                add(f"{cmd}-{damage}{ext}", lambda d, b=base, dm=damage, e=ext, k=kind:
                    b(d, src=generic(dm, _i(d), e, k)))

# a valid file of another kind under the expected extension
for cmd, (base, exts) in READERS.items():
    if cmd == "mask":
        continue
    for ext, kind in exts:
        for other in ("wav", "png", "csv", "npz"):
            if other == kind or (other == "csv" and kind == "osc"):
                continue
            add(f"{cmd}-{other}-as{ext}", lambda d, b=base, e=ext, o=other: b(d, src=_renamed(d, o, e)))



def _renamed(d, kind, ext):
    """A valid ``kind`` file under the extension ``ext``."""
    natural = {"wav": ".wav", "png": ".png", "csv": ".csv", "npz": ".npz"}[kind]
    return valid(kind, _i(d) / f"x{natural}").rename(_i(d) / f"y{ext}")


def _txt(d):
    p = _i(d) / "data.txt"
    p.write_text("1,2\n3,4\n")
    return p


# an unsupported extension
for cmd, (base, _) in READERS.items():
    if cmd != "mask":
        add(f"{cmd}-ext-txt", lambda d, b=base: b(d, src=_txt(d)))

# ---- 2. outputs: onto inputs, devices, folders, each other, bad names ------------------------------
OUT_FLAGS = {
    "denoise": (denoise, ["-o", "--report", "--plot"], "ok.wav"),
    "unwatermark": (unwatermark, ["-o", "--report", "--plot"], "ok.png"),
    "mismatch": (mismatch, ["--report", "--plot"], "ok.csv"),
    "separate": (separate, ["-o", "--report", "--plot"], "ok.csv"),
    "simulate": (simulate, ["-o", "--truth"], None),
}


def _with(argv, flag, value):
    argv = list(argv)
    names = {"-o": ("-o", "--output")}.get(flag, (flag,))
    for k, a in enumerate(argv):
        if a in names:
            argv[k + 1] = value
            return argv
    return argv + [flag, value]


for cmd, (base, flags, inp) in OUT_FLAGS.items():
    for flag in flags:
        tag = flag.strip("-")
        add(f"{cmd}-{tag}-devnull", lambda d, b=base, f=flag: _with(b(d), f, "/dev/null"))
        add(f"{cmd}-{tag}-folder", lambda d, b=base, f=flag: _with(b(d), f, str(_i(d))))
        add(f"{cmd}-{tag}-missing-dir", lambda d, b=base, f=flag: _with(b(d), f, str(_o(d) / "no" / "x.json")))
        add(f"{cmd}-{tag}-long-name", lambda d, b=base, f=flag: _with(b(d), f, str(_o(d) / ("y" * 300 + ".png"))))
        if inp:
            add(f"{cmd}-{tag}-is-input", lambda d, b=base, f=flag, i=inp: _with(b(d), f, str(_i(d) / i)))
            add(f"{cmd}-{tag}-link-to-input", lambda d, b=base, f=flag, i=inp: _with(
                b(d), f, str(_link(_i(d) / i, _o(d) / ("lnk" + Path(i).suffix)))))
    for a, b_ in [(x, y) for x in flags for y in flags if x < y]:
        add(f"{cmd}-{a.strip('-')}-same-as-{b_.strip('-')}", lambda d, b=base, f1=a, f2=b_:
            _with(_with(b(d), f1, str(_o(d) / "same.png")), f2, str(_o(d) / "same.png")))


def _link(target, link):
    link.parent.mkdir(parents=True, exist_ok=True)
    link.symlink_to(target)
    return link
