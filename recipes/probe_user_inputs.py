"""Inputs a new user brings that no generator of the project draws: what each command says about them.

Each case is one plain record or file as a user would hand it over, and the row gives what the tool
answered (named effects, notes, exit code, gain). Run it with another version on ``PYTHONPATH`` to
compare; cases whose options that version lacks print ``n/a``.

- noise-free records (a simulation compared with a simulation): five presets, with and without a
  missing effect; a constant column;
- a pendulum's angles in degrees; a free fall measured downwards (distance fallen);
- a Duffing oscillator whose motion is 1e-7 or 1e-9 in the record's unit (nanometres in metres);
- a CSV written by pandas (its row index first, unnamed);
- audio: a Vorbis (OGG) input written back as OGG;
- images: a text mark of two lines; a text in a script the fonts do not cover.

    python recipes/probe_user_inputs.py                 # prints the table
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np


def _mismatch(preset, t, y, **kw):
    from odnn_sep.mismatch import explain
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            r = explain(preset, t, y, **kw)
        except Exception as exc:  # noqa: BLE001 - the answer is the row
            return f"error: {str(exc)[:90]}"
    named = "+".join(r.effects) or "nothing"
    dist = "+".join(d.get("effect", "?") for d in r.disturbances)
    failed = len(r.failed)
    notes = "; ".join(n.split(":")[0][:60] for n in r.notes if "time analysed" not in n)
    return f"named {named}" + (f", disturbances {dist}" if dist else "") + \
        (f", {failed} fit(s) failed" if failed else "") + (f" | notes: {notes}" if notes else "")


def mismatch_cases():
    from odnn_sep.mismatch import make_model
    rng = np.random.default_rng(0)
    rows = []
    ff = np.linspace(0, 0.6, 120)
    cases = [
        ("noise-free free fall", "freefall", ff, make_model("freefall", {"g": 9.81, "h0": 2.0}), None),
        ("noise-free free fall + drag", "freefall", ff, make_model("freefall", {"g": 9.81, "h0": 2.0}),
         ("quadratic_drag", {"q_drag": 0.02})),
        ("noise-free cooling", "cooling", np.linspace(0, 300, 300), make_model("cooling", {"h": 0.01}), None),
        ("noise-free cooling + radiation", "cooling", np.linspace(0, 300, 300), make_model("cooling", {"h": 0.01}),
         ("radiation", {"r_rad": 0.003})),
        ("noise-free oscillator + cubic", "oscillator", np.linspace(0, 20, 400),
         make_model("oscillator", {"k": 4.0, "c": 0.1}), ("cubic_stiffness", {"beta": 0.5})),
        ("noise-free pendulum + large angle", "pendulum", np.linspace(0, 20, 400),
         make_model("pendulum", {"w2": 9.0, "theta0": 0.8}), ("large_angle", {"s_angle": 1.0})),
    ]
    for label, preset, t, m, eff in cases:
        mm = m.with_effect(*eff) if eff else m
        rows.append((label, "truth: " + (eff[0] if eff else "nothing"), _mismatch(preset, t, mm.predict(t))))
    t = np.arange(200) * 0.1
    rows.append(("constant column", "truth: nothing to explain", _mismatch("cooling", t, np.full(200, 20.0))))
    t = np.linspace(0, 20, 500)
    m = make_model("pendulum", {"w2": 9.0, "c": 0.05, "theta0": 0.6}).with_effect("large_angle", {"s_angle": 1.0})
    y = np.degrees(m.predict(t))
    rows.append(("pendulum, 34 deg swing given in degrees", "truth: large_angle",
                 _mismatch("pendulum", t, y + 0.002 * np.abs(y).max() * rng.normal(size=t.size))))
    t = np.linspace(0, 0.6, 120)
    h = make_model("freefall", {"g": 9.81, "h0": 2.0}).with_effect("quadratic_drag", {"q_drag": 0.05}).predict(t)
    rows.append(("free fall given as distance fallen", "truth: quadratic_drag",
                 _mismatch("freefall", t, 2.0 - h + 0.001 * rng.normal(size=t.size))))
    t = np.linspace(0, 20, 400)
    m = make_model("oscillator", {"k": 4.0, "c": 0.1, "x0": 1.0}).with_effect("cubic_stiffness", {"beta": 0.5})
    y = m.predict(t) + 0.01 * np.random.default_rng(1).normal(size=t.size)
    for s in (1e-7, 1e-9):
        rows.append((f"Duffing oscillator, values x {s:g}", "truth: cubic_stiffness", _mismatch("oscillator", t, y * s)))
    return rows


def cli(args, cwd):
    p = subprocess.run([sys.executable, "-m", "odnn_sep.cli", *args], capture_output=True, text=True, cwd=cwd,
                       timeout=600)
    out = (p.stdout + p.stderr).strip().splitlines()
    return p.returncode, out


def file_cases(d: Path):
    import soundfile as sf
    rows = []
    t = np.linspace(0, 300, 200)
    T = 20 + 60 * np.exp(-0.01 * t) + 0.05 * np.random.default_rng(0).normal(size=t.size)
    (d / "pd.csv").write_text(",t,T\n" + "".join(f"{k},{a},{b}\n" for k, (a, b) in enumerate(zip(t, T, strict=True))))
    code, out = cli(["mismatch", "pd.csv", "--model", "cooling", "--report", "pd.json"], d)
    import json
    h = json.loads((d / "pd.json").read_text())["calibration"]["parameters"]["h"]["value"] if code == 0 else None
    rows.append(("CSV from pandas (index first), cooling h = 0.01", "truth: h = 0.01",
                 f"exit {code}, h = {h:.4g}" if h is not None else f"exit {code}: {out[-1][:90]}"))
    sr = 44100
    tt = np.arange(12 * sr) / sr
    rng = np.random.default_rng(0)
    host = 0.05 * rng.normal(size=tt.size)
    hum = 0.05 * np.sin(2 * np.pi * 60.02 * tt) + 0.03 * np.sin(2 * np.pi * 180.06 * tt + 1)
    sf.write(d / "in.ogg", host + hum, sr, subtype="VORBIS")
    code, out = cli(["denoise", "in.ogg", "-o", "out.ogg"], d)
    x, _ = sf.read(d / "in.ogg")
    yo, _ = sf.read(d / "out.ogg")
    err = float(np.sqrt(np.mean((x - yo - hum) ** 2)))
    warned = any("lossy" in ln for ln in out)
    rows.append(("OGG/Vorbis in and out, 43 dB removal in memory", "removed hum minus the true hum",
                 f"exit {code}, RMS error {err:.4f} ({20 * np.log10(np.sqrt(np.mean(hum ** 2)) / err):.1f} dB "
                 f"under the hum), lossy warning: {'yes' if warned else 'no'}"))
    from PIL import Image

    from odnn_sep.image.render import render_text
    from odnn_sep.image.synth import photo_like
    photo = photo_like((260, 380), random_state=3).astype(float)
    M = np.zeros(photo.shape[:2])
    for text, (r, c) in (("Studio 2024", (70, 60)), ("John Doe", (118, 90))):
        g = render_text(text, "DejaVuSans-Bold", 30)
        M[r:r + g.shape[0], c:c + g.shape[1]] = np.maximum(M[r:r + g.shape[0], c:c + g.shape[1]], g)
    y = np.clip(np.round((1 - 0.5 * M[..., None]) * photo + 0.5 * M[..., None] * 255), 0, 255).astype(np.uint8)
    Image.fromarray(y).save(d / "two.png")
    psnr = lambda f: 10 * np.log10(255 ** 2 / np.mean((np.asarray(Image.open(d / f), float) - photo) ** 2))  # noqa: E731
    for label, text in (("two-line mark, both lines given", "Studio 2024\nJohn Doe"),
                        ("two-line mark, first line only", "Studio 2024")):
        out_png = d / "o.png"
        out_png.unlink(missing_ok=True)
        code, out = cli(["unwatermark", "two.png", "-o", "o.png", "--text", text], d)
        res = f"exit {code}, " + (f"PSNR {psnr('o.png'):.1f} dB" if out_png.exists() else "no output") + \
            f" (input {psnr('two.png'):.1f} dB): {out[-1][:70] if out else ''}"
        rows.append((label, "two lines, DejaVu Sans Bold 30 px", res))
    code, out = cli(["unwatermark", "two.png", "-o", "o2.png", "--text", "水印 2024"], d)
    rows.append(("text in Chinese (no font tried covers it)", "a clear error", f"exit {code}: {out[-1][:110]}"))
    return rows


def print_rows(rows, header, t0) -> None:
    """The rows as a Markdown table under ``header`` (three column names), and the time on stderr."""
    print("| " + " | ".join(header) + " |")
    print("|---|---|---|")
    for a, b, c in rows:
        print(f"| {a} | {b} | {c.replace('|', '/')} |")
    print(f"\n{len(rows)} cases in {time.time() - t0:.0f} s", file=sys.stderr)


def main() -> int:
    t0 = time.time()
    rows = mismatch_cases()
    with tempfile.TemporaryDirectory() as d:
        rows += file_cases(Path(d))
    print_rows(rows, ("input", "truth", "what the tool says"), t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
