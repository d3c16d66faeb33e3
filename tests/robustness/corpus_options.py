"""Bad options and bad contents, per command (added to corpus.CASES on import)."""
from __future__ import annotations

from corpus import _i, _o, add, batch, denoise, mismatch, separate, simulate, unwatermark
from corpus_files import csv_special, giant_png, npz_special, truncated_png, valid, wav_special

# ---- denoise -----------------------------------------------------------------------------------------
for opt, values in {
    "--mains": ["abc", "-50", "0", "nan", "inf", "1e9", ""],
    "--harmonics": ["0", "-1", "abc", "1,,3", "1000000", "1.5", "nan"],
    "--tone": ["-5", "nan", "inf", "1e9"],
    "--block-s": ["0", "-1", "nan", "abc", "1e9", "inf"],
    "--max-hz": ["-1", "0", "nan", "abc", "inf"],
    "--subtype": ["FOO", "pcm_99"],
    "--solver": ["foo"],
}.items():
    for v in values:
        add(f"denoise{opt}={v or 'empty'}", lambda d, o=opt, v=v: denoise(d, o, v))
for kind in ("nan", "inf", "zero_frames", "one_sample"):  # 1e300 in a float WAV is valid audio data
    add(f"denoise-wav-{kind}", lambda d, k=kind: denoise(d, src=wav_special(k, _i(d) / "w.wav")))
add("denoise-out-ext", lambda d: ["denoise", valid("wav", _i(d) / "ok.wav"), "-o", _o(d) / "clean.xyz"])
add("denoise-plot-ext", lambda d: denoise(d, "--plot", str(_o(d) / "p.txt")))
add("denoise-no-output", lambda d: ["denoise", valid("wav", _i(d) / "ok.wav")])
add("denoise-unknown-option", lambda d: denoise(d, "--frobnicate"))
add("denoise-subtype-vs-format", lambda d: ["denoise", valid("wav", _i(d) / "ok.wav"), "-o", _o(d) / "c.ogg",
                                            "--subtype", "PCM_24"])

# ---- unwatermark -------------------------------------------------------------------------------------
TEXTS = {"empty": "", "newline": "A\nB", "tab-only": "\t", "control": "AB\x07C", "words2000": "word " * 2000,
         "chars5000": "x" * 5000, "spaces": "   "}
for name, text in TEXTS.items():
    add(f"unwatermark-text-{name}", lambda d, t=text: unwatermark(d, text=("--text", t)))
add("unwatermark-neither", lambda d: unwatermark(d, text=()))
for v in ("nan", "-5", "inf", "abc"):
    add(f"unwatermark-min-score={v}", lambda d, v=v: unwatermark(d, "--min-score", v))
add("unwatermark-font-missing", lambda d: unwatermark(d, "--font", str(_i(d) / "nofont.ttf")))
add("unwatermark-font-dir", lambda d: unwatermark(d, "--font", str(_i(d))))
add("unwatermark-font-garbage", lambda d: unwatermark(d, "--font", str(_garbage(_i(d) / "f.ttf"))))
add("unwatermark-font-unknown-name", lambda d: unwatermark(d, "--font", "NoSuchFontFamily-Bold"))
add("unwatermark-mask-wrong-size", lambda d: unwatermark(d, text=("--mask", _png(_i(d) / "m.png", (10, 10)))))
add("unwatermark-mask-black", lambda d: unwatermark(d, text=("--mask", _png(_i(d) / "m.png", (64, 64), 0))))
add("unwatermark-out-ext", lambda d: ["unwatermark", valid("png", _i(d) / "ok.png"), "--text", "A", "-o",
                                      _o(d) / "clean.gif"])
add("unwatermark-giant-png", lambda d: unwatermark(d, src=giant_png(_i(d) / "big.png")))
add("unwatermark-giant-mask", lambda d: unwatermark(d, text=("--mask", giant_png(_i(d) / "m.png"))))
add("unwatermark-truncated-png", lambda d: unwatermark(d, src=truncated_png(_i(d) / "t.png")))
add("unwatermark-tiny-image", lambda d: unwatermark(d, src=_png(_i(d) / "tiny.png", (1, 1))))
add("unwatermark-megapixel-limit", lambda d: unwatermark(d), env={"ODNN_SEP_MAX_MEGAPIXELS": "0.001"})
add("unwatermark-text-limit", lambda d: unwatermark(d, text=("--text", "ABCDEFGHIJ")), env={"ODNN_SEP_MAX_TEXT": "5"})

# ---- mismatch ----------------------------------------------------------------------------------------
for opts, cid in [
    (("--param", "k"), "param-no-value"), (("--param", "k=abc"), "param-text"), (("--param", "m=0"), "param-m0"),
    (("--param", "k=nan"), "param-nan"), (("--param", "k=inf"), "param-inf"), (("--param", "zz=1"), "param-unknown"),
    (("--param", "=1"), "param-no-name"), (("--param", "k=1e300"), "param-huge"), (("--param", "m=-1"), "param-m-neg"),
    (("--column", "5"), "column-range"), (("--column", "zzz"), "column-name"), (("--column", "-1"), "column-neg"),
    (("--column", "0"), "column-time"), (("--start", "1e6"), "start-beyond"), (("--duration", "0"), "duration-0"),
    (("--duration", "-1"), "duration-neg"), (("--start", "nan"), "start-nan"), (("--duration", "nan"), "duration-nan"),
    (("--start", "abc"), "start-text"), (("--effects", "nosuch"), "effects-unknown"), (("--effects", ","), "effects-empty"),
    (("--disturbance", "bad"), "disturbance-bad"), (("--model", "nosuch"), "model-unknown"),
]:
    add(f"mismatch-{cid}", lambda d, o=opts: mismatch(d, *o))
add("mismatch-no-model", lambda d: ["mismatch", valid("osc", _i(d) / "ok.csv")])
for kind in ("header_only", "one_row", "one_column", "ragged", "words", "nan", "inf", "huge", "neg_huge"):
    add(f"mismatch-csv-{kind}", lambda d, k=kind: mismatch(d, src=csv_special(k, _i(d) / "c.csv")))
for col in ("left", "right", "5", "-1", "ch1"):
    add(f"mismatch-wav-column-{col}", lambda d, c=col: mismatch(d, "--column", c, src=valid("wav", _i(d) / "w.wav"),
                                                                 model="hum"))
for kind in ("nan", "inf", "huge", "zero_frames", "one_sample"):
    add(f"mismatch-wav-{kind}", lambda d, k=kind: mismatch(d, src=wav_special(k, _i(d) / "w.wav"), model="hum"))
for kind in ("missing_z", "shape_mismatch", "object_array", "nan_field", "huge_values", "one_d_z", "truncated",
             "string_array", "giant_header"):
    add(f"mismatch-npz-{kind}", lambda d, k=kind: mismatch(d, src=npz_special(k, _i(d) / "f.npz"), model="heat2d"))
add("mismatch-row-limit", lambda d: mismatch(d), env={"ODNN_SEP_MAX_ROWS": "100"})
add("mismatch-heat2d-on-csv", lambda d: mismatch(d, model="heat2d"))
add("mismatch-hum-sources-bad", lambda d: mismatch(d, "--param", "sources=a:b", src=valid("npz", _i(d) / "f.npz"),
                                                   model="heat2d"))

# ---- separate ----------------------------------------------------------------------------------------
BASES = ["9**9**9", "x*2**2**40", "x*10**100000", "(" * 300 + "x" + ")" * 300, "-" * 200 + "x", "foo(x)", "...",
         "0<x<1", "__import__('os')", "x.real", "x[0]", "lambda: x", "'x'", "x if x else 1", "sin(x, x)",
         "sin(x=1)", "1e400*x", "x*1j", "log(x-10)", "1/0*x", "", "x\ny", "X", "t", "x @ x", "x // 2", "not x",
         "x and 1", "[x]", "{x}", "x" + "+x" * 1200, "sqrt(-1-x*x)", "exp(1000*x)", "y"]
for k, b in enumerate(BASES):
    add(f"separate-basis-{k:02d}", lambda d, b=b: separate(d, basis=b))
for spec in ("periodic:0", "periodic:-1", "periodic:abc", "band:5:1", "band:a:b", "band:1", "even:abc",
             "monotone:foo", "nosuch", "periodic", "convex:1", "", "periodic:nan", "periodic:inf", "band:-1:nan"):
    add(f"separate-disturbance={spec or 'empty'}", lambda d, s=spec: separate(d, "--disturbance", s))
for col in ("5", "zzz", "-1", "0", "1.5"):
    add(f"separate-column-{col}", lambda d, c=col: separate(d, "--column", c))
add("separate-names-count", lambda d: separate(d, "--name", "a", "--name", "b"))
add("separate-not-identifiable", lambda d: separate(d, "--disturbance", "periodic:0.5", basis="1+0*x"))
add("separate-even-not-identifiable", lambda d: separate(d, "--disturbance", "even", basis="x**2"))
add("separate-solver-bad", lambda d: separate(d, "--solver", "foo"))
add("separate-seed-text", lambda d: separate(d, "--seed", "abc"))
for kind in ("header_only", "one_row", "one_column", "ragged", "words", "nan", "inf", "huge", "neg_huge"):
    add(f"separate-csv-{kind}", lambda d, k=kind: separate(d, src=csv_special(k, _i(d) / "c.csv")))
for kind in ("missing_z", "shape_mismatch", "object_array", "nan_field", "huge_values", "one_d_z", "truncated",
             "string_array", "giant_header"):
    add(f"separate-npz-{kind}", lambda d, k=kind: separate(d, src=npz_special(k, _i(d) / "f.npz")))
add("separate-point-limit", lambda d: separate(d), env={"ODNN_SEP_MAX_POINTS": "50"})
add("separate-no-basis", lambda d: ["separate", valid("csv", _i(d) / "ok.csv")])

# ---- simulate ----------------------------------------------------------------------------------------
for cid, argv in [
    ("unknown", lambda d: simulate(d, name="nosuch")),
    ("wrong-suffix-1d", lambda d: simulate(d, out="fig.npz")),
    ("wrong-suffix-2d", lambda d: simulate(d, name="heat2d", out="h.csv")),
    ("seed-neg", lambda d: simulate(d, "--seed", "-1")),
    ("seed-text", lambda d: simulate(d, "--seed", "abc")),
    ("snr-nan", lambda d: simulate(d, "--snr-db", "nan")),
    ("snr-minus-inf", lambda d: simulate(d, "--snr-db=-inf")),     # +inf: noise-free data, accepted
    ("snr-text", lambda d: simulate(d, "--snr-db", "abc")),
    ("snr-huge", lambda d: simulate(d, "--snr-db", "1e300")),
    ("truth-is-output", lambda d: simulate(d, "--truth", str(_o(d) / "fig.csv"))),
    ("no-output", lambda d: ["simulate", "figure2"]),
]:
    add(f"simulate-{cid}", argv)

# ---- batch -------------------------------------------------------------------------------------------
for cid, fn in [
    ("missing-folder", lambda d: ["batch", "denoise", _i(d) / "nope", "-o", _o(d) / "res"]),
    ("file-not-folder", lambda d: ["batch", "denoise", valid("wav", _i(d) / "ok.wav"), "-o", _o(d) / "res"]),
    ("same-folder", lambda d: batch(d)[:3] + ["-o", _i(d)]),
    ("out-is-file", lambda d: batch(d)[:3] + ["-o", _i(d) / "ok.wav"]),
    ("jobs-0", lambda d: batch(d, "--jobs", "0")),
    ("jobs-neg", lambda d: batch(d, "--jobs", "-3")),
    ("jobs-text", lambda d: batch(d, "--jobs", "abc")),
    ("no-match", lambda d: batch(d, "--pattern", "*.xyz")),
    ("empty-pattern", lambda d: batch(d, "--pattern", ",")),
    ("summary-on-input", lambda d: batch(d, "--summary", str(_i(d) / "ok.wav"))),
    ("summary-devnull", lambda d: batch(d, "--summary", "/dev/null")),
    ("summary-folder", lambda d: batch(d, "--summary", str(_i(d)))),
    ("summary-missing-dir", lambda d: batch(d, "--summary", str(_o(d) / "a" / "b" / "s.json"))),
    ("unknown-target", lambda d: ["batch", "nosuch", _i(d), "-o", _o(d) / "res"]),
    ("dask-malformed", lambda d: batch(d, "--dask", "not an address")),
    ("dask-unreachable", lambda d: batch(d, "--dask", "tcp://127.0.0.1:9")),
    ("dask-bad-port", lambda d: batch(d, "--dask", "tcp://127.0.0.1:99999")),
    ("out-inside-in-collides", lambda d: [*batch(d)[:3], "-o", _sub_with_copy(d), "--recursive"]),
    ("passthrough-not-batch", lambda d: [*denoise(d), "--", "--mains", "50"]),
]:
    add(f"batch-{cid}", fn, env={"ODNN_SEP_DASK_TIMEOUT": "2"} if "dask" in cid else None)


def _sub_with_copy(d):
    sub = _i(d) / "sub"
    sub.mkdir(exist_ok=True)
    valid("wav", sub / "ok.wav")
    return sub


def _png(path, size, value=None):
    import cv2
    import numpy as np

    img = np.full((*size, 3), value if value is not None else 255, np.uint8)
    cv2.imwrite(str(path), img)
    return path


def _garbage(path):
    path.write_bytes(b"\x00\x01garbage font" * 50)
    return path
