"""Audio front-end: remove mains hum (tracked fundamental and harmonics) and tones from sound.

``denoise(y, sr)`` works on arrays, ``denoise_file(in, out)`` streams files; both return a
:class:`DenoiseResult`. ``odnn-sep denoise`` is the command-line form. Names are loaded lazily so
importing the subcommand module (for ``odnn-sep --help``) stays light.
"""
_EXPORTS = {
    "denoise": "odnn_sep.audio.api",
    "denoise_file": "odnn_sep.audio.api",
    "DenoiseResult": "odnn_sep.audio.result",
    "make_hum_demo": "odnn_sep.audio.synth",
    "make_hum_mix": "odnn_sep.audio.synth",
}

__all__ = list(_EXPORTS)


def __getattr__(name):
    if name in _EXPORTS:
        import importlib

        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'odnn_sep.audio' has no attribute {name!r}")
