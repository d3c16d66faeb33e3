"""What happened to each file of a batch, in a few words, read from the command's own report.

The commands run ``--quiet`` in a batch (one progress bar for all files), which also silences
their summary lines and warnings: a file where no hum was found, or whose output is lossy, looked
the same in the summary as a file cleaned well. Each command writes its JSON report (to a
temporary file, for ``denoise`` and ``unwatermark``), and the summary takes its outcome and warnings.
"""
from __future__ import annotations

import json
from pathlib import Path

#: Parameters of a ``separate`` fit written into the batch summary's one-line outcome (the report has all).
_SHOWN_PARAMETERS = 4


def outcome(target: str, report_path) -> dict:
    """``{"outcome": str, "warnings": [str]}`` from a command's report (empty when it cannot be read).

    Parameters
    ----------
    target : str
        ``"denoise"``, ``"unwatermark"``, ``"mismatch"`` or ``"separate"``.
    report_path : path-like
        The command's JSON report.

    Returns
    -------
    dict

    Examples
    --------
    >>> import json, os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "r.json")
    >>> _ = open(p, "w").write(json.dumps({"lines": [], "clipping": None}))
    >>> outcome("denoise", p)
    {'outcome': 'no hum found: written unchanged', 'warnings': []}
    >>> outcome("denoise", p + ".missing")
    {}
    """
    try:
        d = json.loads(Path(report_path).read_text())
    except (OSError, ValueError):
        return {}
    if target == "denoise":
        return _denoise(d)
    if target == "unwatermark":
        return {"outcome": str(d.get("outcome", "")), "warnings": []}
    if target == "separate":
        return _separate(d)
    v = d.get("verdict") or {}
    effects = v.get("effects") or []
    text = ("missing: " + ", ".join(e.get("effect", "?") for e in effects)) if effects else str(v.get("description", ""))
    return {"outcome": text, "warnings": list(v.get("warnings") or [])}


def _separate(d: dict) -> dict:
    """The fitted parameters with their intervals (the first few), and the command's warnings.

    Examples
    --------
    >>> _separate({"parameters": {"a": {"value": 2.0, "interval": [1.9, 2.1]}, "b": {"value": 0.5,
    ...            "interval": None}}, "identified": "point", "warnings": ["w"]})
    {'outcome': 'fitted: a = 2 [1.9, 2.1], b = 0.5 (no interval)', 'warnings': ['w']}
    """
    params = d.get("parameters") or {}
    shown = []
    for name, p in list(params.items())[:_SHOWN_PARAMETERS]:
        iv = p.get("interval")
        band = f" [{iv[0]:.4g}, {iv[1]:.4g}]" if iv else " (no interval)"
        shown.append(f"{name} = {p.get('value', float('nan')):.4g}{band}")
    more = f", and {len(params) - _SHOWN_PARAMETERS} more" if len(params) > _SHOWN_PARAMETERS else ""
    # convex and monotone classes give identified sets, not confidence intervals (core/cone.py)
    kind = "" if d.get("identified", "point") == "point" else " (intervals are identified sets)"
    return {"outcome": "fitted: " + ", ".join(shown) + more + kind, "warnings": list(d.get("warnings") or [])}


def _denoise(d: dict) -> dict:
    lines = d.get("lines") or []
    warnings = [str(d[k]) for k in ("clipping", "requantisation", "lossy_output") if d.get(k)]
    if not lines:
        return {"outcome": "no hum found: written unchanged", "warnings": warnings}
    f0 = (d.get("mains") or {}).get("fundamental_hz")
    names = ", ".join(str(ln.get("name")) for ln in lines)
    text = f"removed hum: fundamental {f0:.4f} Hz, lines {names}" if f0 else f"removed lines {names}"
    spans = d.get("hum_spans") or []
    if spans:
        text += "; only over " + ", ".join(f"{s['start_s']:.1f}-{s['end_s']:.1f} s" for s in spans)
    return {"outcome": text, "warnings": warnings}
