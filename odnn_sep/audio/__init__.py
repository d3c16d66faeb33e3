"""Audio front-end: remove mains hum (tracked fundamental and harmonics) and tones from sound.

``denoise(y, sr)`` works on arrays, ``denoise_file(in, out)`` streams files; both return a
:class:`DenoiseResult`. ``odnn-sep denoise`` is the command-line form.
"""
from odnn_sep.audio.denoise import DenoiseResult, denoise, denoise_file
from odnn_sep.audio.synth import make_hum_demo, make_hum_mix

__all__ = ["denoise", "denoise_file", "DenoiseResult", "make_hum_demo", "make_hum_mix"]
