"""The cases of ``golden.py``: per group, ``{item: function returning its nested result}``.

Each function is deterministic (fixed seeds, fixed sizes) and returns plain data (dicts, lists,
arrays, numbers) that ``golden.flatten`` turns into fingerprints. Items that need
../shared/data are left out when the data are absent.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
ROOM = DATA / "pyenf_hum_recordings" / "room_audio_60hz_hum_8k.wav"


# ------------------------------------------------------------------------------------------ audio
def denoise_print(y, sr, **options) -> dict:
    """What ``denoise`` returns for ``y``: the cleaned signal and removed hum, the track, the lines."""
    from odnn_sep.audio import denoise

    r = denoise(y, sr, **options)
    return {"y": r.y, "hum": r.hum, "mains_hz": r.mains_hz, "nominal_hz": r.nominal_hz,
            "harmonics": list(r.harmonics), "tones": list(r.tones), "track_t": r.track_t, "track_hz": r.track_hz,
            "amplitudes": r.amplitudes, "phases": r.phases, "amplitude_overall": r.amplitude_overall,
            "line_names": list(r.line_names), "levels_before": r.levels_before, "levels_after": r.levels_after,
            "extra_combs": r.extra_combs, "report": r.as_dict()}


def audio_items() -> dict:
    from odnn_sep.audio import make_hum_mix

    def room():
        import soundfile as sf

        y, sr = sf.read(str(ROOM))
        return denoise_print(y, sr)

    def mix_stereo():
        y, sr, _ = make_hum_mix(12.0, 8000, channels=2, random_state=3)
        return denoise_print(y, sr)

    def case_speech_60():
        import _audio_cases as ac

        y, sr, _ = ac.make_case(ac.case_spec(4, ac.EVAL_SEED0, quick=True))   # speech, 60 Hz, ramp drift
        return denoise_print(y, sr, mains=60, tones=(1000.0,))

    out = {"room_recording": room} if ROOM.exists() else {}
    out.update({"mix_stereo_12s": mix_stereo, "case4_speech_60hz": case_speech_60})
    return out


# ------------------------------------------------------------------------------------------ image
def unwatermark_print(y, **options) -> dict:
    from odnn_sep.image import unwatermark

    r = unwatermark(y, **options)
    return {"image": r.image, "alpha": r.alpha, "color": np.asarray(r.color), "mask": r.mask,
            "lost": int(np.count_nonzero(r.lost)), "report": r.report}


def logo_case(seed: int):
    """A logo blended into a photo-like image as in ``bench_logo.py``: (image, logo RGBA)."""
    import bench_logo as bl

    from odnn_sep.image.synth import photo_like

    rng = np.random.default_rng(seed)
    clean = photo_like((240, 320), random_state=seed)
    logo = bl.make_logo(rng, coloured=bool(seed % 2))
    y, _, _, _ = bl.blend(clean, logo, rng, tiled=False)
    return y, logo


def image_items() -> dict:
    from odnn_sep.image import make_watermark_demo

    def text(seed):
        def run():
            y, _, truth = make_watermark_demo(random_state=seed)
            return unwatermark_print(y, text=truth["text"])      # the default font list
        return run

    def mask(seed):
        def run():
            y, _, truth = make_watermark_demo(random_state=seed)
            return unwatermark_print(y, mask=(truth["mask"] > 0.05).astype(np.uint8) * 255)
        return run

    def reference(seed, with_alpha):
        def run():
            import bench_logo as bl

            y, logo = logo_case(seed)
            return unwatermark_print(y, reference=logo if with_alpha else bl.flatten(logo))
        return run

    return {"text_default_font_0": text(0), "text_default_font_1": text(1), "mask_2": mask(2), "mask_3": mask(3),
            "reference_rgba_10": reference(10, True), "reference_flat_11": reference(11, False)}


# ---------------------------------------------------------------------------------------- mismatch
def with_explain_reports(run):
    """``run()``'s benchmark row plus the JSON report of every ``explain`` call it made (the row keeps
    only verdicts; the report has the fitted parameters, intervals and candidate scores)."""
    import _mismatch_population as mp
    import bench_mismatch as bm

    reports, original = [], bm.explain

    def explain(*args, **kwargs):
        res = original(*args, **kwargs)
        reports.append(res.as_dict())
        return res

    bm.explain = mp.explain = explain     # both benchmark modules call explain by this name
    try:
        row = run()
    finally:
        bm.explain = mp.explain = original
    return {"row": row, "explain": reports}


def mismatch_items() -> dict:
    """``bench_mismatch.py --quick``: its population jobs and its strength-sweep jobs, one item each."""
    import bench_mismatch as bm
    from _mismatch_population import population_jobs, run_population_case

    out = {}
    for job in population_jobs(["cooling/radiation", "freefall/quadratic_drag"],
                               lambda n: ["periodic", "spikes"], lambda n: [100]):
        out["population/" + "/".join(map(str, job))] = (
            lambda j=job: with_explain_reports(lambda: run_population_case(j)))
    for name in ["cooling/radiation", "freefall/quadratic_drag"]:
        strength = bm.design_strengths(bm.SYSTEMS[name])[-1]
        for with_effect in (True, False):
            job = (name, bm.SYSTEMS[name], strength, 0, with_effect)
            out[f"sweep/{name}/{'effect' if with_effect else 'null'}"] = (
                lambda j=job: with_explain_reports(lambda: bm.run_case(*j)))
    return out


# ------------------------------------------------------------------------------------------ table1
NETWORK_DATASETS = ("figure2", "population")


class _NoProgress:
    def update(self, n):
        pass


def table1_items() -> dict:
    """Table 1 at ``--quick`` size: exact solver, OLS, SINDy (2 trials) on every dataset; the network
    solver and the DNN baselines (1 trial, 60 epochs) on two; the noise sweep (1 draw per cell)."""
    import table1

    from odnn_sep.signals import GENERATORS

    def exact(k, name):
        return lambda: table1.run_dataset(name, trials=2, dnn_trials=0, network_trials=0, snr_db=30.0,
                                          net_epochs=60, dnn_epochs=60, seed0=1000 * k, progress=_NoProgress())

    def network(k, name):
        def run():
            r = table1.run_dataset(name, trials=1, dnn_trials=1, network_trials=1, snr_db=30.0, net_epochs=60,
                                   dnn_epochs=60, seed0=1000 * k, progress=_NoProgress())
            return {m: r["errs"][m] for m in ("odnn_network", "regular_dnn", "pinn_penalty")} | {
                "net_unconverged": r["net_unconverged"]}
        return run

    def sweep():
        names = [n for n in GENERATORS if n in table1.PAPER_ROW and GENERATORS[n](random_state=0).identified == "point"]
        return table1.snr_sweep(names, 1, (20.0, 40.0), 500_000)

    out = {f"exact/{name}": exact(k, name) for k, name in enumerate(GENERATORS)}
    out.update({f"network/{name}": network(list(GENERATORS).index(name), name) for name in NETWORK_DATASETS})
    out["noise_sweep"] = sweep
    return out
