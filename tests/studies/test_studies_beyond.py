"""The studies beyond the paper (long_chain: self-contact; dish: the paraboloid) at the tiny size: they run, answer
the supplement's questions with numbers, round-trip through save/load, draw their figures and render their rows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from elastoactive.studies.paper import PAPER
from elastoactive.studies.self_contact import link_crossings


@pytest.fixture(scope="module")
def runs(tiny_studies):
    return tiny_studies("long_chain", "dish")


def test_link_crossings_geometry():
    straight = np.zeros((1, 5))
    links, particles = link_crossings(straight)
    assert links[0] == pytest.approx(1.0) and particles[0] == pytest.approx(2.0)  # links 1 and 3: 1 l apart
    crossed = np.array([[0.0, 2.0, -2.0]])  # link 3 comes back across link 1
    links, _ = link_crossings(crossed)
    assert links[0] < 1e-12


def test_long_chain_answers_the_speculation(runs):
    s = runs[1]["long_chain"].summary
    assert (s.n, s.sigma) == (PAPER.long_chain_n, PAPER.long_chain_sigma)
    at = {(r.contact, r.engine): r for r in s.runs if r.sigma == s.sigma}
    free, touch = at[False, "mujoco"], at[True, "mujoco"]
    assert s.passes_through and free.crossing_fraction > 0.3 and free.min_clearance <= -0.2 + 1e-9
    assert touch.crossing_fraction == 0.0 and touch.contact_fraction > 0.2 and -0.01 < touch.min_clearance < 0
    assert s.odd_harmonics_raised and touch.harmonics[2] > 2 * free.harmonics[2]
    assert max(touch.harmonics[1], touch.harmonics[3]) < 1e-2  # Theta's beat is odd-symmetric: no even harmonics
    conv = sorted(s.convergence, key=lambda c: -c.dt)
    assert conv[-1].overlap < 0.6 * conv[0].overlap  # the contact hardens as dt shrinks
    assert abs(conv[-1].amplitude / conv[0].amplitude - 1) < 0.005
    wind = {(w.contact, w.engine): w for w in s.winding}
    assert wind[True, "mujoco"].theta_span < 0.3 * wind[False, "mujoco"].theta_span
    red = wind[True, "reduced"]
    assert abs(red.frequency / wind[True, "mujoco"].frequency - 1) < 0.03


def test_dish_engines_and_states(runs):
    s = runs[1]["dish"].summary
    assert s.supplement_sigma == PAPER.dish_sigma
    assert s.engines_same_state and s.engines_max_rel_diff < 1e-3
    assert set(s.states) == {"rest", "spin", "orbit", "crawl", "beat", "irregular"}
    assert s.states["orbit"] >= 1 and s.states["spin"] >= 1 and s.states["beat"] >= 1
    assert math.isfinite(s.supplement_orbit_traps[0])


@pytest.mark.parametrize("name", ["long_chain", "dish"])
def test_round_trip_figures_and_rows(runs, name, round_trip):
    table = round_trip(runs, name)
    assert ("self-contact" in table) if name == "long_chain" else ("paraboloid" in table)
