"""Bad input files, generated at test time (nothing binary is committed)."""
from __future__ import annotations

import gzip
import io
import os
import struct
import zipfile
import zlib
from pathlib import Path

import numpy as np
from robustness_helpers import write_csv, write_npz, write_oscillator_csv, write_png, write_wav

# Generic damage that any file-reading command must refuse with one line.
GENERIC = ("missing", "directory", "empty", "devnull", "fifo", "random_bytes", "text", "nul_bytes", "utf16",
           "gzip", "zip", "head_only", "long_name", "symlink_loop", "dangling_link")


def valid(kind: str, path: Path) -> Path:
    """A small valid file of ``kind`` (wav, png, csv, osc, npz)."""
    {"wav": lambda p: write_wav(p, seconds=1.0), "png": lambda p: write_png(p, size=(64, 64)),
     "csv": lambda p: write_csv(p, n=200), "osc": lambda p: write_oscillator_csv(p, n=300),
     "npz": lambda p: write_npz(p)}[kind](path)
    return path


def generic(damage: str, folder: Path, ext: str, good_kind: str) -> Path:
    """A file (or non-file) named ``bad<ext>`` in ``folder`` with the given damage."""
    p = folder / f"bad{ext}"
    rng = np.random.default_rng(1)
    if damage == "missing":
        return p
    if damage == "directory":
        p.mkdir()
    elif damage == "empty":
        p.write_bytes(b"")
    elif damage == "devnull":
        return Path("/dev/null")
    elif damage == "fifo":
        os.mkfifo(p)
    elif damage == "random_bytes":
        p.write_bytes(rng.integers(0, 256, 4096, dtype=np.uint8).tobytes())
    elif damage == "text":
        p.write_text("hello, this is not data\n")
    elif damage == "nul_bytes":
        p.write_bytes(b"\0" * 2048)
    elif damage == "utf16":
        # UTF-16 with no byte-order mark: nothing says how to decode it (behind a mark, as Excel's
        # "Unicode text" writes it, a CSV is read: tests/cli/test_cli_csv_unicode.py)
        p.write_bytes("x,y\n1,2\n3,4\n".encode("utf-16-le"))
    elif damage == "gzip":
        p.write_bytes(gzip.compress(valid(good_kind, folder / f"g{ext}").read_bytes()))
        (folder / f"g{ext}").unlink()
    elif damage == "zip":
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w") as z:
            z.writestr("readme.txt", "not an array")
        p.write_bytes(buf.getvalue())
    elif damage == "head_only":
        full = valid(good_kind, folder / f"g{ext}").read_bytes()
        (folder / f"g{ext}").unlink()
        p.write_bytes(full[:12])
    elif damage == "long_name":
        return folder / ("x" * 300 + ext)
    elif damage == "symlink_loop":
        p.symlink_to(p)
    elif damage == "dangling_link":
        p.symlink_to(folder / "nowhere")
    else:
        raise ValueError(damage)
    return p


def wav_special(kind: str, path: Path) -> Path:
    import soundfile as sf

    sr = 8000
    y = 0.1 * np.sin(2 * np.pi * 50 * np.arange(sr) / sr)
    if kind == "nan":
        y[100] = np.nan
    elif kind == "inf":
        y[100] = np.inf
    elif kind == "huge":
        y[:] = 1e300
    if kind == "zero_frames":
        sf.write(str(path), np.zeros(0), sr, subtype="PCM_16")
    elif kind == "one_sample":
        sf.write(str(path), np.zeros(1), sr, subtype="PCM_16")
    else:
        sf.write(str(path), y, sr, subtype="DOUBLE" if kind == "huge" else "FLOAT")
    return path


def csv_special(kind: str, path: Path) -> Path:
    t = np.linspace(0, 10, 200)
    v = np.exp(-0.1 * t) * np.cos(2 * t)
    lines = ["t,x"]
    if kind == "header_only":
        pass
    elif kind == "one_row":
        lines.append("0,1")
    elif kind == "one_column":
        lines = ["t"] + [f"{a:g}" for a in t]
    elif kind == "ragged":
        lines += [f"{a:g},{b:g}" if i % 7 else f"{a:g}" for i, (a, b) in enumerate(zip(t, v))]
    elif kind == "words":
        lines += [f"{a:g},{'abc' if i == 50 else format(b, 'g')}" for i, (a, b) in enumerate(zip(t, v))]
    else:
        bad = {"nan": "nan", "inf": "inf", "huge": "1e300", "neg_huge": "-1e300"}[kind]
        lines += [f"{a:g},{bad if i == 50 or kind in ('huge', 'neg_huge') else format(b, 'g')}"
                  for i, (a, b) in enumerate(zip(t, v))]
    path.write_text("\n".join(lines) + "\n")
    return path


def npz_special(kind: str, path: Path) -> Path:
    x, y = np.linspace(0, 1, 20), np.linspace(0, 1, 10)
    z = np.ones((10, 20))
    if kind == "missing_z":
        np.savez(path, x=x, y=y)
    elif kind == "shape_mismatch":
        np.savez(path, x=x, y=y, z=np.ones((20, 10)))
    elif kind == "object_array":
        np.savez(path, x=x, y=y, z=np.array([{"a": 1}, None], dtype=object))
    elif kind == "nan_field":
        z[3, 4] = np.nan
        np.savez(path, x=x, y=y, z=z)
    elif kind == "huge_values":
        np.savez(path, x=x, y=y, z=z * 1e300)
    elif kind == "one_d_z":
        np.savez(path, x=x, y=y, z=np.ones(200))
    elif kind == "truncated":
        np.savez(path, x=x, y=y, z=z)
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    elif kind == "string_array":
        np.savez(path, x=x, y=y, z=np.array(["a", "b"]))
    elif kind == "giant_header":
        _npz_with_fake_shape(path, (20000, 20000))
    else:
        raise ValueError(kind)
    return path


def _npz_with_fake_shape(path: Path, shape) -> None:
    """An .npz whose z declares ``shape`` (3.2 GB as float64) but holds a few bytes: loading it naively
    would allocate the whole field."""
    def npy(arr_header_shape, payload=b""):
        header = {"descr": "<f8", "fortran_order": False, "shape": arr_header_shape}
        h = repr(header).encode("latin1")
        h += b" " * ((64 - (10 + len(h) + 1) % 64) % 64) + b"\n"
        return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(h)) + h + payload

    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("x.npy", npy((shape[1],), np.zeros(shape[1]).tobytes()))
        zf.writestr("y.npy", npy((shape[0],), np.zeros(shape[0]).tobytes()))
        zf.writestr("z.npy", npy(tuple(shape), b"\0" * 1024))


def giant_png(path: Path, width=20000, height=20000) -> Path:
    """A PNG whose header declares width x height pixels (400 MP) with almost no data."""
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    idat = zlib.compress(b"\0" * 1000)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
    return path


def truncated_png(path: Path) -> Path:
    data = valid("png", path).read_bytes()
    path.write_bytes(data[: len(data) // 3])
    return path
