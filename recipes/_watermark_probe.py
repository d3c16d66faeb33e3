"""Probe generator for ``odnn-sep unwatermark --text``: marks the other watermark recipes never draw.

Font sources none of the other recipes use (nothing is downloaded, no font file is copied):
- Pillow's built-in scalable face (``ImageFont.load_default(size)``: Aileron Regular, shipped inside the
  Pillow wheel);
- OpenCV's Hershey stroke fonts (``cv2.putText``: simplex, duplex, complex, triplex, script, italic;
  shipped inside the opencv wheel), drawn with a stroke thickness of 1-4 px;
- the WOFF2 faces of a Rust toolchain's documentation when one is installed (Fira Sans, Open Sans,
  Source Serif 4, Source Code Pro); skipped where absent.

Cases per draw: text of 1 character to a long sentence, one mark, a tiled (repeated) mark or a mark of
2-3 lines (the command run once per line, each on the previous output: the probe's own protocol; the
command also takes every line at once, separated by line breaks); grey or colour
photos (skimage's bundled images the other recipes do not use, plus ../shared/data/photos_clean_skimage),
small (about 100-200 px), normal or large (upscaled 2x); mark near the border (partly cut) or anywhere;
white, black or any colour; opacity low (0.1-0.2), middle or high (0.85-0.95); angle 0 or up to 35 deg;
after the blend nothing, JPEG q 70, or an upscale by 1.5 (bicubic; the clean photo gets the same upscale
and is the reference). Clean photos (no mark, a random text) check false alarms.

The command is run as a user would (subprocess, ``--keep-partial`` so the output can be scored; its exit
code is what it reports). Scored against the clean photo with the true coverage M:
- ``band``: M > 0.05 dilated 2 px; PSNR over the image and in the band, for the input, the output and
  ``cv2.inpaint`` (Telea) with the band as mask;
- ``left``: the RMS of output - clean in the band beyond the format's noise floor (JPEG: the clean photo
  put through the same JPEG), 8-bit levels;
- ``share``: how much of the mark's own structure the output keeps: the larger of |projection of
  output - clean on input - clean| and the share of the input's edge energy across the mark's contours
  that output - clean keeps (rims left by a wrong glyph shape run along the contours).

A mark is **still there** when ``left >= 4`` levels and ``share >= 0.25``. An outcome is **dishonest**
when the command exits 0 ("removed") and the mark is still there; **over-cautious** when it exits 3
(still visible) and the mark is not still there; a **false alarm** when a clean photo gets exit 0 or 3;
a **crash** when the exit code is not 0, 1 or 3, or stderr holds a traceback.
"""
from __future__ import annotations

import glob
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
HERSHEY = ("SIMPLEX", "DUPLEX", "COMPLEX", "TRIPLEX", "SCRIPT_SIMPLEX", "SIMPLEX_ITALIC", "COMPLEX_ITALIC")
RUST_FACES = ("FiraSans-Regular", "FiraSans-Medium", "open-sans-v17-all-charsets-700-",
              "open-sans-v17-all-charsets-300-", "SourceSerif4-Regular", "SourceSerif4-Bold", "SourceSerif4-It",
              "SourceCodePro-Semibold")
SK_PHOTOS = ("hubble_deep_field.jpg", "ihc.png", "grass.png", "gravel.png", "brick.png", "moon.png",
             "motorcycle_right.png", "retina.jpg", "page.png", "clock_motion.png")
ONE = ("X", "7", "@", "W")
SHORT = ("DEMO", "Proof", "Foto", "wm", "ACME", "N0 COPY")
MEDIUM = ("Preview only", "Do not copy", "(c) Jane Roe 2025", "www.example.org", "Stock photo 4471")
LONG = ("Licensed for internal review only - not for redistribution",
        "Property of Northwind Imaging Ltd, all rights reserved",
        "Sample image, purchase a licence to remove this mark")
LINES = (("Northwind", "Imaging Ltd"), ("DRAFT", "not final", "v0.3"), ("Photo: A. Smith", "agency use only"))


def font_sources() -> list[tuple[str, str]]:
    """(kind, name or path) of every probe font found on this machine (Pillow and OpenCV always).

    >>> any(k == "hershey" for k, _ in font_sources())
    True
    """
    out = [("pillow", "Aileron")] + [("hershey", h) for h in HERSHEY]
    for pat in RUST_FACES:
        hits = sorted(glob.glob(os.path.expanduser(f"~/.rustup/toolchains/*/share/doc/rust/html/*/{pat}*.woff2"))
                      + glob.glob(os.path.expanduser(f"~/.rustup/toolchains/*/share/doc/rust/html/*/fonts/{pat}*.woff2")))
        if hits:
            out.append(("file", hits[0]))
    return out


def render(text: str, kind: str, name: str, size: int, thick: int) -> np.ndarray:
    """Coverage in [0, 1] of one line of ``text`` about ``size`` px tall, tightly cropped (2 px margin)."""
    import cv2
    from PIL import Image, ImageDraw, ImageFont

    if kind == "hershey":
        flag = getattr(cv2, "FONT_HERSHEY_" + name.replace("_ITALIC", ""))
        if name.endswith("_ITALIC"):
            flag |= cv2.FONT_ITALIC
        scale = size / 22.0
        (w, h), base = cv2.getTextSize(text, flag, scale, thick)
        canvas = np.zeros((h + base + 4 * thick + 8, w + 4 * thick + 8), np.uint8)
        cv2.putText(canvas, text, (2 * thick + 4, h + 2 * thick + 4), flag, scale, 255, thick, cv2.LINE_AA)
        a = canvas.astype(np.float64) / 255.0
    else:
        f = ImageFont.load_default(size) if kind == "pillow" else ImageFont.truetype(name, size)
        x0, y0, x1, y1 = f.getbbox(text)
        im = Image.new("L", (int(x1 - x0) + 8, int(y1 - y0) + 8), 0)
        ImageDraw.Draw(im).text((4 - x0, 4 - y0), text, font=f, fill=255)
        a = np.asarray(im, dtype=np.float64) / 255.0
    rr, cc = np.nonzero(a > 0)
    return a[max(0, rr.min() - 2):rr.max() + 3, max(0, cc.min() - 2):cc.max() + 3]


def rotate(cov: np.ndarray, angle: float) -> np.ndarray:
    """``cov`` rotated by ``angle`` degrees (bicubic, canvas expanded)."""
    from PIL import Image

    if not angle:
        return cov
    im = Image.fromarray((cov * 255).astype(np.uint8)).rotate(angle, resample=Image.BICUBIC, expand=True)
    a = np.asarray(im, dtype=np.float64) / 255.0
    rr, cc = np.nonzero(a > 0)
    return a[rr.min():rr.max() + 1, cc.min():cc.max() + 1]


def photos() -> list[tuple[str, np.ndarray]]:
    """(name, uint8 RGB or grey array) of the probe's photos."""
    import skimage

    from odnn_sep.image.io import read_image

    sk = Path(skimage.__file__).parent / "data"
    files = [sk / n for n in SK_PHOTOS] + sorted((DATA / "photos_clean_skimage").glob("*.png"))
    out = []
    for f in files:
        if f.is_file():
            img = read_image(f)
            if img.dtype != np.uint8:
                img = (img.astype(np.float64) / np.iinfo(img.dtype).max * 255).round().astype(np.uint8)
            if img.ndim == 3:
                img = img[:, :, :3]
            out.append((f.name, np.ascontiguousarray(img)))
    return out


def _resize(img, scale, inter):
    import cv2

    H, W = img.shape[:2]
    return cv2.resize(img, (max(8, round(W * scale)), max(8, round(H * scale))), interpolation=inter)


def prepare_photo(img: np.ndarray, rng) -> tuple[np.ndarray, dict]:
    """The photo after the probe's grey / size choices."""
    import cv2

    info = {}
    if img.ndim == 3 and rng.random() < 0.3:
        img = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
        info["grey"] = True
    elif img.ndim == 2:
        info["grey"] = True
    r = rng.random()
    H, W = img.shape[:2]
    if r < 0.2:
        s = rng.uniform(100, 200) / max(H, W)
        img = _resize(img, s, cv2.INTER_AREA)
        info["scale"] = "small"
    elif r < 0.35:
        s = min(2.0, 1100 / max(H, W))
        img = _resize(img, s, cv2.INTER_CUBIC)
        info["scale"] = "large"
    else:
        if max(H, W) > 700:
            img = _resize(img, 700 / max(H, W), cv2.INTER_AREA)
        info["scale"] = "normal"
    return np.ascontiguousarray(img), info


def draw_case(img: np.ndarray, rng, fonts) -> dict:
    """One marked case: the watermarked image, the clean reference, the true coverage, the lines given to
    the command and the truth (a dict)."""
    H, W = img.shape[:2]
    layout = str(rng.choice(["single", "single", "single", "tiled", "lines"]))
    r = rng.random()
    lines = ([str(rng.choice(ONE))] if r < 0.15 else [str(rng.choice(SHORT))] if r < 0.45 else
             [str(rng.choice(MEDIUM))] if r < 0.8 else [str(rng.choice(LONG))])
    if layout == "lines":
        lines = list(LINES[int(rng.integers(len(LINES)))])
    kind, name = fonts[int(rng.integers(len(fonts)))]
    thick = int(rng.integers(1, 5))
    angle = float(rng.uniform(-35, 35)) if rng.random() < 0.3 else 0.0
    longest = max(lines, key=len)
    size = int(rng.integers(max(10, min(H, W) // 20), max(12, min(H, W) // 6)))
    for _ in range(20):
        cov = render(longest, kind, name, size, thick)
        if cov.shape[1] <= W - 6 and cov.shape[0] * len(lines) <= H - 6:
            break
        size = max(8, int(size * 0.8))
    covs = [rotate(render(t, kind, name, size, thick), angle) for t in lines]
    near_border = rng.random() < 0.25
    M = np.zeros((H, W))
    line_masks = []
    if layout == "tiled":
        c = covs[0]
        h, w = c.shape
        gy, gx = h + int(rng.integers(h // 2 + 4, 2 * h + 8)), w + int(rng.integers(8, w // 2 + 16))
        oy, ox = int(rng.integers(0, gy)), int(rng.integers(0, gx))
        for y0 in range(oy - gy, H, gy):
            for x0 in range(ox - gx + (gx // 2 if (y0 // gy) % 2 else 0), W, gx):
                ya, xa, yb, xb = max(0, y0), max(0, x0), min(H, y0 + h), min(W, x0 + w)
                if yb > ya and xb > xa:
                    M[ya:yb, xa:xb] = np.maximum(M[ya:yb, xa:xb], c[ya - y0:yb - y0, xa - x0:xb - x0])
        line_masks.append(M.copy())
    else:
        total_h = sum(c.shape[0] for c in covs) + 4 * (len(covs) - 1)
        wmax = max(c.shape[1] for c in covs)
        if near_border:
            side = int(rng.integers(4))
            cut = int(rng.integers(-6, 3))          # negative: the mark runs off the image
            x0 = cut if side == 0 else W - wmax - cut if side == 1 else int(rng.integers(0, max(1, W - wmax)))
            y0 = cut if side == 2 else H - total_h - cut if side == 3 else int(rng.integers(0, max(1, H - total_h)))
        else:
            x0 = int(rng.integers(2, max(3, W - wmax - 2)))
            y0 = int(rng.integers(2, max(3, H - total_h - 2)))
        yy = y0
        for c in covs:
            Mi = np.zeros((H, W))
            h, w = c.shape
            ya, xa, yb, xb = max(0, yy), max(0, x0), min(H, yy + h), min(W, x0 + w)
            if yb > ya and xb > xa:
                Mi[ya:yb, xa:xb] = c[ya - yy:yb - yy, xa - x0:xb - x0]
            line_masks.append(Mi)
            M = np.maximum(M, Mi)
            yy += h + 4
    r = rng.random()
    alpha = float(rng.uniform(0.1, 0.2) if r < 0.25 else rng.uniform(0.85, 0.95) if r < 0.4 else rng.uniform(0.3, 0.7))
    r = rng.random()
    color = np.array((255, 255, 255) if r < 0.4 else (0, 0, 0) if r < 0.75 else rng.integers(0, 256, 3), float)
    photo = img.astype(np.float64)
    aM = alpha * (M[..., None] if photo.ndim == 3 else M)
    col = color if photo.ndim == 3 else color.mean()
    y = np.clip(np.round((1 - aM) * photo + aM * col), 0, 255).astype(np.uint8)
    post = str(rng.choice(["none", "none", "jpeg70", "upscale"]))
    clean = img
    if post == "upscale":
        import cv2

        y, clean = _resize(y, 1.5, cv2.INTER_CUBIC), _resize(img, 1.5, cv2.INTER_CUBIC)
        line_masks = [np.clip(_resize(m.astype(np.float32), 1.5, cv2.INTER_CUBIC), 0, 1).astype(np.float64)
                      for m in line_masks]
        M = np.max(line_masks, axis=0)
    truth = dict(layout=layout, lines=lines, font=f"{kind}:{Path(name).name.split('-')[0][:18]}", size=size,
                 thick=thick if kind == "hershey" else None, angle=round(angle, 1), alpha=round(alpha, 3),
                 color="white" if color.min() == 255 else "black" if color.max() == 0 else "colour",
                 near_border=near_border, post=post)
    return dict(y=y, clean=clean, M=M, line_masks=line_masks, truth=truth)


def save(path: Path, img: np.ndarray, post: str) -> None:
    """Write ``img`` as PNG, or as JPEG q 70 when ``post`` is 'jpeg70'."""
    from PIL import Image

    if post == "jpeg70":
        Image.fromarray(img).save(path, quality=70)
    else:
        Image.fromarray(img).save(path)


def load(path: Path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im)


def run_cli(inp: Path, out: Path, text: str, timeout: float = 600.0) -> dict:
    """Run ``odnn-sep unwatermark INP --text TEXT -o OUT --keep-partial --report`` as a user would."""
    rep = out.with_suffix(".json")
    for p in (out, rep):
        p.unlink(missing_ok=True)
    cmd = [sys.executable, "-c", "import sys; from odnn_sep.cli import main; sys.exit(main())", "unwatermark", str(inp), "--text", text, "-o", str(out),
           "--keep-partial", "--report", str(rep)]
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        rc, err = p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        rc, err = -9, "timeout"
    res = {"rc": rc, "stderr": err.strip().splitlines()[-1:] if err.strip() else [], "time": time.perf_counter() - t0,
           "traceback": "Traceback" in err, "report": json.loads(rep.read_text()) if rep.is_file() else {}}
    res["output"] = load(out) if out.is_file() else None
    return res


def _as3(a):
    a = np.asarray(a, dtype=np.float64)
    return a[:, :, None] if a.ndim == 2 else a[:, :, :3]


def psnr(a, b, region=None) -> float:
    d = _as3(a) - _as3(b)
    d = d[region] if region is not None else d
    mse = float(np.mean(d ** 2)) if d.size else 0.0
    return float(10 * np.log10(255.0 ** 2 / mse)) if mse > 0 else 99.0


def _across(d: np.ndarray, M: np.ndarray) -> float:
    """Energy of the gradient of ``d`` across the contours of ``M`` minus that along them."""
    import cv2

    mx = cv2.Sobel(cv2.GaussianBlur(M.astype(np.float32), (0, 0), 1.0), cv2.CV_32F, 1, 0, ksize=3)
    my = cv2.Sobel(cv2.GaussianBlur(M.astype(np.float32), (0, 0), 1.0), cv2.CV_32F, 0, 1, ksize=3)
    mag = np.hypot(mx, my)
    nx, ny = mx / np.maximum(mag, 1e-12), my / np.maximum(mag, 1e-12)
    tot = 0.0
    for c in range(d.shape[2]):
        ch = np.ascontiguousarray(d[:, :, c], dtype=np.float32)
        gx, gy = cv2.Sobel(ch, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(ch, cv2.CV_32F, 0, 1, ksize=3)
        tot += float(np.sum(mag ** 2 * ((gx * nx + gy * ny) ** 2 - (gy * nx - gx * ny) ** 2), dtype=np.float64))
    return tot


def score(out, y, clean, M, post) -> dict:
    """Oracle scores of ``out`` against ``clean`` with the true coverage ``M`` (see the module text)."""
    import cv2

    band = cv2.dilate((M > 0.05).astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    o, i, c = _as3(out), _as3(y), _as3(clean)
    floor = 0.0
    if post == "jpeg70":
        with tempfile.TemporaryDirectory() as td:
            save(Path(td) / "c.jpg", np.asarray(clean), "jpeg70")
            floor = float(np.sqrt(np.mean((_as3(load(Path(td) / "c.jpg")) - c)[band] ** 2)))
    d_out, d_in = (o - c)[band], (i - c)[band]
    rms_out = float(np.sqrt(np.mean(d_out ** 2)))
    left = float(np.sqrt(max(0.0, rms_out ** 2 - floor ** 2)))
    n_in = float(np.sum(d_in ** 2))
    proj = abs(float(np.sum(d_out * d_in)) / n_in) if n_in > 0 else 0.0
    e_in = _across(i - c, M)
    edge = max(0.0, _across(o - c, M) / e_in) if e_in > 0 else 0.0
    share = max(proj, edge)
    return dict(psnr=psnr(out, clean), psnr_band=psnr(out, clean, band), left=left, proj=proj, edge=edge,
                share=share, there=bool(left >= 4.0 and share >= 0.25), band=band)


def telea(y, band):
    import cv2

    return cv2.inpaint(np.ascontiguousarray(y), band.astype(np.uint8), 3, cv2.INPAINT_TELEA)


def run_population(seed: int, n_marked: int, n_clean: int, workdir: Path, log=print) -> list[dict]:
    """Draw ``n_marked`` marked and ``n_clean`` clean cases with ``seed`` and run the command on each."""
    rng = np.random.default_rng(seed)
    fonts, phs = font_sources(), photos()
    rows = []
    for k in range(n_marked + n_clean):
        name, img0 = phs[int(rng.integers(len(phs)))]
        img, pinfo = prepare_photo(img0, rng)
        marked = k < n_marked
        if marked:
            case = draw_case(img, rng, fonts)
        else:
            post = str(rng.choice(["none", "jpeg70", "upscale"]))
            clean = _resize(img, 1.5, __import__("cv2").INTER_CUBIC) if post == "upscale" else img
            lines = [str(rng.choice(SHORT + MEDIUM))]
            case = dict(y=clean, clean=clean, M=None, line_masks=[None], truth=dict(layout="clean", lines=lines,
                        post=post))
        t = case["truth"]
        inp = workdir / f"s{seed}_{k}_in.{'jpg' if t['post'] == 'jpeg70' else 'png'}"
        save(inp, case["y"], t["post"])
        y_in = load(inp)                           # what the command reads (JPEG decoded)
        cur, rcs, reps, times, errs = inp, [], [], [], []
        row = dict(seed=seed, case=k, photo=name, shape=list(y_in.shape), **pinfo, **t)
        line_rows = []
        for j, (text, Mi) in enumerate(zip(t["lines"], case["line_masks"])):
            out = workdir / f"s{seed}_{k}_out{j}.png"
            r = run_cli(cur, out, text)
            rcs.append(r["rc"])
            reps.append(r["report"].get("residual_mark"))
            times.append(r["time"])
            errs.append(r["stderr"])
            lr = dict(rc=r["rc"], traceback=r["traceback"], text=text,
                      reported=r["report"].get("residual_mark"), match=r["report"].get("match_score"),
                      font_used=Path(str(r["report"].get("font", ""))).name[:40] or None)
            prev = load(cur)
            if r["output"] is not None and marked:
                sc = score(r["output"], prev, case["clean"], Mi, t["post"])
                sc_in = score(prev, prev, case["clean"], Mi, t["post"])
                band = sc.pop("band")
                sc_in.pop("band")
                tl = score(telea(prev, band), prev, case["clean"], Mi, t["post"])
                tl.pop("band")
                lr.update(out=sc, inp=sc_in, telea=tl)
                cur = out
            elif r["output"] is not None:
                lr.update(out=dict(psnr=psnr(r["output"], case["clean"])))
                cur = out
            line_rows.append(lr)
        row.update(lines_run=line_rows, time=round(sum(times), 2), stderr_last=errs)
        rows.append(row)
        log(json.dumps(summary_line(row)), flush=True)
    return rows


def classify(lr: dict, marked: bool) -> str:
    """'removed-ok', 'dishonest', 'visible-ok', 'over-cautious', 'not found', 'false alarm', 'crash' or
    'clean-ok' for one run of the command."""
    rc = lr["rc"]
    if rc not in (0, 1, 3) or lr.get("traceback"):
        return "crash"
    if not marked:
        return "false alarm" if rc in (0, 3) else "clean-ok"
    if rc == 1:
        return "not found"
    there = lr.get("out", {}).get("there")
    if rc == 0:
        return "dishonest" if there else "removed-ok"
    return "visible-ok" if there else "over-cautious"


def summary_line(row: dict) -> dict:
    """A short dict of one case for the log."""
    marked = row["layout"] != "clean"
    out = {"case": f"{row['seed']}/{row['case']}", "photo": row["photo"], "shape": row["shape"], "layout": row["layout"],
           "font": row.get("font"), "alpha": row.get("alpha"), "post": row["post"], "time": row["time"]}
    out["runs"] = [{"text": lr["text"][:24], "rc": lr["rc"], "class": classify(lr, marked),
                    "in": round(lr["inp"]["psnr_band"], 1) if "inp" in lr else None,
                    "out": round(lr["out"]["psnr_band"], 1) if "out" in lr and "psnr_band" in lr["out"] else None,
                    "telea": round(lr["telea"]["psnr_band"], 1) if "telea" in lr else None,
                    "left": round(lr["out"]["left"], 1) if "out" in lr and "left" in lr["out"] else None,
                    "share": round(lr["out"]["share"], 2) if "out" in lr and "share" in lr["out"] else None,
                    "rep_vis": (lr.get("reported") or {}).get("visible")} for lr in row["lines_run"]]
    return out
