"""The versioned header every command's JSON report carries, and the shipped JSON Schemas.

The CLI opens a :func:`run_context` for each run; :func:`odnn_sep.io_utils.write_json` then puts
``schema``, ``schema_version``, ``odnn_sep_version``, ``command`` and ``options`` in front of the
report's own keys and makes ``input`` a block with at least ``path``. Reports keep every key they had
before, so scripts reading them go on working. The schemas live in ``odnn_sep/report/schemas/``.
"""
from __future__ import annotations

import contextlib
import json
from importlib import resources

#: Bumped when a report's keys change meaning or are removed (adding keys keeps the version).
SCHEMA_VERSION = "1.0"

# Output paths are part of the run, not of the options.
_NOT_OPTIONS = {"func", "command", "passthrough"}

_CONTEXT: list[dict] = []


@contextlib.contextmanager
def run_context(command: str, options: dict):
    """Within the block, reports written with ``write_json`` get this run's header.

    Examples
    --------
    >>> with run_context("separate", {"solver": "exact"}):
    ...     head = with_header({"theta": [1.0]})
    >>> head["schema"], head["options"], head["theta"]
    ('odnn-sep/separate', {'solver': 'exact'}, [1.0])
    """
    _CONTEXT.append({"command": command, "options": _plain_options(options)})
    try:
        yield
    finally:
        _CONTEXT.pop()


def _plain_options(options: dict) -> dict:
    out = {}
    for k, v in options.items():
        if k in _NOT_OPTIONS or k.startswith("_"):
            continue
        if v is None or isinstance(v, (bool, int, float, str)):
            out[k] = v
        elif isinstance(v, (list, tuple)):
            out[k] = [w if isinstance(w, (bool, int, float, str)) or w is None else str(w) for w in v]
        else:
            out[k] = str(v)
    return out


def with_header(obj):
    """``obj`` with the current run's header in front (unchanged outside a CLI run).

    Examples
    --------
    >>> with_header({"theta": [1.0]})        # no run context: unchanged
    {'theta': [1.0]}
    """
    if not _CONTEXT or not isinstance(obj, dict):
        return obj
    ctx = _CONTEXT[-1]
    head = {"schema": f"odnn-sep/{ctx['command']}", "schema_version": SCHEMA_VERSION,
            "odnn_sep_version": _version(), "command": ctx["command"], "options": ctx["options"]}
    body = dict(obj)  # its own keys win: a batch summary's "command" stays the command run on each file
    inp = body.get("input")
    if isinstance(inp, (str, bytes)) or hasattr(inp, "__fspath__"):
        body["input"] = {"path": str(inp)}
    elif inp is None and ctx["command"] != "simulate":
        path = next((ctx["options"].get(k) for k in ("input", "data", "in_dir") if ctx["options"].get(k)), None)
        if path is not None:
            body["input"] = {"path": str(path)}
    return {**head, **body}


def _version() -> str:
    from odnn_sep import __version__

    return __version__


COMMANDS = ("denoise", "unwatermark", "mismatch", "separate", "simulate", "batch")


def load_schema(command: str) -> dict:
    """The JSON Schema (draft 2020-12) of ``command``'s report, as shipped in the package.

    Examples
    --------
    >>> load_schema("separate")["properties"]["schema"]["const"]
    'odnn-sep/separate'
    """
    from odnn_sep.errors import check_option

    check_option("command", command, COMMANDS)
    text = resources.files("odnn_sep.report").joinpath("schemas", f"{command}.schema.json").read_text()
    return json.loads(text)
