"""One JSON converter (elastoactive.io.jsonio) for summary.json, the studies' JSON and the sweep's journal."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from elastoactive.analysis.fits import Fit
from elastoactive.io.jsonio import from_jsonable, to_jsonable
from elastoactive.records import jsonable
from elastoactive.studies import SUMMARIES

ROOT = Path(__file__).resolve().parents[2]

VALUE = {
    "fit": Fit({"a": 1.5}, {"a": math.inf}, 0.9, 12),
    "z": complex(1.0, -math.nan),
    "theta": np.arange(3.0),
    "n": np.int64(7),
    "ok": np.bool_(True),
    "bad": float("nan"),
    3: (np.float32(0.5), -math.inf),
}


def test_summary_json_takes_every_value_the_studies_json_takes():
    """summary.json (records.jsonable) is the same converter with non-finite floats as null: dataclasses, arrays,
    complex numbers and non-text keys give valid JSON, not a TypeError at json.dumps."""
    text = json.dumps(jsonable(VALUE), allow_nan=False)
    assert json.loads(text) == {
        "fit": {"params": {"a": 1.5}, "errors": {"a": None}, "r2": 0.9, "n": 12, "extra": {}},
        "z": {"re": 1.0, "im": None},
        "theta": [0.0, 1.0, 2.0],
        "n": 7,
        "ok": True,
        "bad": None,
        "3": [0.5, None],
    }
    assert jsonable(VALUE) == to_jsonable(VALUE, nonfinite="null")
    studies = to_jsonable(VALUE)
    assert studies["bad"] == "nan" and studies["3"] == [0.5, "-inf"] and studies["fit"]["errors"] == {"a": "inf"}
    kept = to_jsonable(VALUE, nonfinite="keep")
    assert math.isnan(kept["bad"]) and kept["3"][1] == -math.inf
    with pytest.raises(ValueError, match="nonfinite"):
        to_jsonable(1.0, nonfinite="none")


def test_fit_reads_back_unchanged():
    fit = Fit({"a": 1.5, "b": math.nan}, {"a": math.inf, "b": 0.25}, -math.inf, 9, {"window": [1.0, math.nan]})
    back = from_jsonable(Fit, json.loads(json.dumps(to_jsonable(fit))))
    assert json.dumps(to_jsonable(back)) == json.dumps(to_jsonable(fit))
    assert back.n == 9 and math.isnan(back.params["b"]) and back.r2 == -math.inf


@pytest.mark.parametrize("path", sorted((ROOT / "docs" / "reproduction").glob("*.json")), ids=lambda p: p.stem)
def test_committed_study_json_is_written_byte_for_byte_again(path):
    """Each committed study's summary, read back and written again, gives the same bytes."""
    record = json.loads(path.read_text())
    if record.get("study") not in SUMMARIES:
        pytest.skip(f"{path.name} is not a study's summary")
    summary = from_jsonable(SUMMARIES[record["study"]], record["summary"])
    again = {**record, "summary": to_jsonable(summary), "wall_s": to_jsonable(from_jsonable(float, record["wall_s"]))}
    assert json.dumps(again, indent=2) + "\n" == path.read_text()
