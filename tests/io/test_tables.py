"""io.tables prints a run's results by one rule: a table of name, value and units, its rows on one line, or the record
as JSON; the beat's details and the notes stay out of the table and the line."""

import json
import math

from elastoactive.io import tables

RESULTS = {
    "amplitude": [2.9049182748, 2.87],
    "frequency": None,
    "periodic": True,
    "period_spread": 1e-7,
    "notes": ["frequency not measured"],
    "harmonics": [1.0, 0.1],
    "tip_aspect": math.nan,
    "motion_state": "whirl",
}
UNITS = {"amplitude": "rad", "frequency": "1/tau", "tip_aspect": "1"}


def test_rows_show_a_person_s_values_with_units():
    assert tables.rows(RESULTS, UNITS) == [
        ("amplitude", "2.905, 2.87", "rad"),
        ("frequency", "-", "1/tau"),
        ("periodic", "yes", ""),
        ("tip_aspect", "-", ""),
        ("motion_state", "whirl", ""),
    ]


def test_the_table_aligns_its_columns_under_its_title():
    text = tables.table(RESULTS, UNITS, "one-pinned, mujoco")
    lines = text.splitlines()
    assert lines[0] == "one-pinned, mujoco" and len(lines) == 6
    assert lines[1] == "  amplitude     2.905, 2.87  rad"
    assert {line.index(line.split()[1]) for line in lines[1:]} == {16}  # the values in one column


def test_quiet_is_one_line_and_json_is_the_record():
    line = tables.results_text({}, RESULTS, UNITS, as_json=False, quiet=True)
    assert line == "amplitude 2.905, 2.87 rad, frequency - 1/tau, periodic yes, tip_aspect -, motion_state whirl"
    record = {"wall_time_s": 1.5, "notes": ["x"]}
    assert json.loads(tables.results_text(record, RESULTS, UNITS, as_json=True, quiet=True)) == record
