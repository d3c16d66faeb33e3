"""Generate the bundled samples (no third-party media): run `python samples/make_samples.py`.

- hum_demo.wav: a synthetic speech/music-like host with drifting mains hum and harmonics.
- watermark_demo.png: a procedurally generated photo-like image with a text watermark.
- oscillator_demo.csv: a damped oscillator recording whose damping law the simple model omits.
Outputs are deterministic; existing files are replaced atomically.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))


def main() -> None:
    import numpy as np

    from odnn_sep.io_utils import atomic_output

    made = []
    try:
        import soundfile as sf

        from odnn_sep.audio.synth import make_hum_demo

        y, sr, truth = make_hum_demo(duration_s=8.0, sr=16000, random_state=0)
        with atomic_output(HERE / "hum_demo.wav") as tmp:
            sf.write(tmp, y, sr, subtype="PCM_16", format="WAV")
        made.append("hum_demo.wav")
        (HERE / "hum_demo_truth.json").write_text(json.dumps(_plain(truth), indent=2) + "\n")
    except ImportError as exc:
        print(f"skipping audio sample: {exc}", file=sys.stderr)
    try:
        import cv2

        from odnn_sep.image.synth import make_watermark_demo

        marked, clean, truth = make_watermark_demo(random_state=0)
        with atomic_output(HERE / "watermark_demo.png") as tmp:
            cv2.imwrite(str(tmp), cv2.cvtColor(marked, cv2.COLOR_RGB2BGR))
        made.append("watermark_demo.png")
        truth = {**truth, "font": Path(str(truth.get("font", ""))).name}  # no machine-specific paths
        (HERE / "watermark_demo_truth.json").write_text(json.dumps(_plain(truth), indent=2) + "\n")
    except ImportError as exc:
        print(f"skipping image sample: {exc}", file=sys.stderr)
    t, y, truth = oscillator_demo()
    with atomic_output(HERE / "oscillator_demo.csv") as tmp:
        np.savetxt(tmp, np.c_[t, y], delimiter=",", header="t,x", comments="", fmt="%.6f")
    made.append("oscillator_demo.csv")
    (HERE / "oscillator_demo_truth.json").write_text(json.dumps(_plain(truth), indent=2) + "\n")
    print("made: " + ", ".join(made))


def oscillator_demo():
    """A mass on a spring with air drag (quadratic) that the linear model `oscillator` omits,
    plus a slow sensor drift and white noise."""
    import numpy as np
    from scipy.integrate import solve_ivp

    k, c, cq, x0 = 4.0, 0.05, 0.15, 1.0
    t = np.linspace(0, 30, 1500)
    sol = solve_ivp(lambda _, s: [s[1], -k * s[0] - c * s[1] - cq * s[1] * abs(s[1])], (0, 30), [x0, 0.0],
                    t_eval=t, rtol=1e-10, atol=1e-12)
    rng = np.random.default_rng(0)
    drift = 0.02 * np.sin(2 * np.pi * t / 60.0)
    y = sol.y[0] + drift + 0.01 * rng.normal(size=t.size)
    truth = {"model": "m x'' + c x' + c2 x'|x'| + k x = 0", "k": k, "c": c, "quadratic_drag": cq, "x0": x0,
             "v0": 0.0, "drift": "0.02 sin(2 pi t / 60)", "noise_sd": 0.01}
    return t, y, truth


def _plain(obj):
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist() if obj.size <= 64 else f"<array of shape {obj.shape}>"
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


if __name__ == "__main__":
    main()
