"""Every command's JSON report carries the versioned header and validates against the schema
shipped in the package; the JSON is strict (no NaN or Infinity)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from robustness_helpers import write_oscillator_csv, write_wav

from odnn_sep import __version__
from odnn_sep.cli import main
from odnn_sep.io_utils import to_jsonable, write_json
from odnn_sep.report.schema import COMMANDS, load_schema

jsonschema = pytest.importorskip("jsonschema", reason="report validation needs jsonschema")


def _strict_load(path):
    def refuse(token):
        raise ValueError(f"non-standard JSON token {token}")

    return json.loads(Path(path).read_text(), parse_constant=refuse)


def _marked_image(d: Path):
    import cv2

    # a smooth photo with mild noise: on i.i.d. noise of sigma 20 the filled rectangle's edge statistic
    # (12 px patches) stays below what chance shapes in boxes reach on real photos
    rng = np.random.default_rng(0)
    yy, xx = np.mgrid[0:96, 0:128]
    img = np.clip((90 + 0.5 * xx + 0.3 * yy)[..., None] + rng.normal(0, 3, (96, 128, 3)), 0, 255).astype(np.uint8)
    img[40:50, 30:90] = (0.6 * img[40:50, 30:90] + 0.4 * 255).astype(np.uint8)
    mask = np.zeros((96, 128), np.uint8)
    mask[35:55, 25:95] = 255
    cv2.imwrite(str(d / "w.png"), img)
    cv2.imwrite(str(d / "m.png"), mask)
    return d / "w.png", d / "m.png"


def _reports(d: Path) -> dict:
    wav = write_wav(d / "hum.wav", seconds=2.0)
    osc = write_oscillator_csv(d / "osc.csv", n=200)
    out = {}
    assert main(["denoise", str(wav), "-o", str(d / "c.wav"), "--report", str(d / "denoise.json"), "--quiet"]) == 0
    img, mask = _marked_image(d)
    assert main(["unwatermark", str(img), "--mask", str(mask), "-o", str(d / "c.png"), "--report",
                 str(d / "unwatermark.json"), "--quiet"]) == 0
    assert main(["mismatch", str(osc), "--model", "oscillator", "--effects", "quadratic_drag", "--report",
                 str(d / "mismatch.json"), "--quiet"]) == 0
    assert main(["simulate", "figure2", "-o", str(d / "f.csv"), "--truth", str(d / "simulate.json"),
                 "--quiet"]) == 0
    assert main(["separate", str(d / "f.csv"), "--basis", "x**2*sin(5*x)", "--disturbance", "even",
                 "--report", str(d / "separate.json"), "--quiet"]) == 0
    (d / "in").mkdir()
    write_wav(d / "in" / "a.wav", seconds=2.0)
    assert main(["batch", "denoise", str(d / "in"), "-o", str(d / "out"), "--jobs", "1", "--summary",
                 str(d / "batch.json"), "--quiet"]) == 0
    for c in COMMANDS:
        out[c] = _strict_load(d / f"{c}.json")
    return out


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    return _reports(tmp_path_factory.mktemp("reports"))


@pytest.mark.parametrize("command", COMMANDS)
def test_report_validates_against_shipped_schema(reports, command):
    rep = reports[command]
    jsonschema.validate(rep, load_schema(command))
    assert rep["schema"] == f"odnn-sep/{command}" and rep["odnn_sep_version"] == __version__
    assert isinstance(rep["options"], dict) and "func" not in rep["options"]
    if command != "simulate":
        assert isinstance(rep["input"]["path"], str)


def test_schemas_are_valid_json_schemas():
    for c in COMMANDS:
        jsonschema.Draft202012Validator.check_schema(load_schema(c))


def test_report_keeps_its_own_keys(reports):
    assert reports["batch"]["command"] == "denoise"  # the command run on each file, as before
    assert "parameters" in reports["separate"] and "verdict" in reports["mismatch"]


def test_non_finite_numbers_become_null(tmp_path):
    obj = {"a": float("nan"), "b": np.array([1.0, np.inf, -np.inf]), "c": np.float32("nan"), "d": (1, 2.5)}
    assert to_jsonable(obj) == {"a": None, "b": [1.0, None, None], "c": None, "d": [1, 2.5]}
    write_json(tmp_path / "r.json", obj)
    back = _strict_load(tmp_path / "r.json")
    assert back["a"] is None and not any(isinstance(v, float) and not math.isfinite(v) for v in back["b"] if v)
