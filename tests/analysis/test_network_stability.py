"""Linear stability of the network's fixed points (analysis.network.stability) against the full Jacobian and the
trapped unit's exact threshold."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.optimize import fsolve

from elastoactive.analysis.network import NetworkState, hexagonal_patch, trap_unit
from elastoactive.analysis.network import stability as st
from elastoactive.reduced import network as m


def test_trap_threshold_is_one_in_the_traps_units():
    for k in (0.3, 1.0, 2.5):
        for psi in (0.0, 1.3, 4.0):
            assert st.critical_coupling(trap_unit(k), np.array([psi])) == pytest.approx(k, rel=1e-12)


def test_single_free_node_of_the_pinned_hexagon():
    """R = 1 pinned: D = 3 I, so Pi_c = 3 whatever the polarity."""
    th = st.threshold(hexagonal_patch(1), starts=2, samples=20)
    assert th.softest == pytest.approx(3.0) and th.coupling == pytest.approx(3.0) and th.typical == pytest.approx(3.0)


def test_growth_rates_are_those_of_the_full_jacobian_at_a_fixed_point():
    """At a fixed point of the nonlinear model (springs balancing sigma n), model.jacobian's non-zero eigenvalues
    are those of H + Pi Q, and there are A zero ones; in the linear-elastic limit H -> -D."""
    network = hexagonal_patch(2)
    sigma, la = 0.02, 0.01  # Pi = 2, displacements ~ sigma << a
    system = m.network_system(network, sigma, la)
    psi = np.random.default_rng(1).uniform(0, 2 * np.pi, 7)
    free = ~network.pinned

    def residual(q):
        pos = network.positions.copy()
        pos[free] = q.reshape(-1, 2)
        return m.velocities(system, pos, psi)[free].reshape(-1)

    q = fsolve(residual, network.positions[free].reshape(-1), xtol=1e-14)
    y = m.pack(system, NetworkState(np.where(free[:, None], 0, network.positions), psi))
    y[: q.size] = q
    assert np.abs(m.rhs(system)(0, y)).max() < 1e-12
    full = np.sort_complex(np.linalg.eigvals(m.jacobian(system, y)))
    nonzero = full[np.abs(full) > 1e-9]
    assert len(full) - len(nonzero) == 7
    pos = m.unpack(system, y).positions
    h = m.force_jacobian(system, pos)[np.ix_(m.free_dofs(system), m.free_dofs(system))]
    n = st.perpendiculars(psi, st.unit_slots(network), 7)
    np.testing.assert_allclose(nonzero, np.sort_complex(np.linalg.eigvals(h + (sigma / la) * n @ n.T)), atol=1e-9)
    linear = np.linalg.eigvalsh(st.coupling_operator(network, psi, sigma / la))
    np.testing.assert_allclose(np.sort(nonzero.real), linear, atol=0.05)  # geometric corrections O(sigma / a)


@pytest.mark.slow
def test_pinned_hexagon_threshold_lies_between_the_softest_mode_and_every_random_polarity():
    th = st.threshold(hexagonal_patch(2), starts=2, samples=100)
    assert th.softest == pytest.approx(1.1358, abs=1e-4)
    assert th.softest < th.typical < th.coupling < 1.9
    assert st.critical_coupling(hexagonal_patch(2), th.polarities) == pytest.approx(th.coupling)


@pytest.mark.parametrize(
    "network",
    [hexagonal_patch(1), hexagonal_patch(2), hexagonal_patch(3), trap_unit(0.7)],
    ids=["R=1", "R=2", "R=3", "trap"],
)
def test_each_ceiling_bounds_every_fixed_points_threshold(network):
    """No fixed point is stable above either proved ceiling: random polarities and the search's best stay below both;
    the interlacing argument's vector (in the span of the 2F - A + 1 softest modes and of the units' n_perp) has
    Rayleigh quotient <= lambda_{2F-A+1} on D and 1 on Q; one unit in a trap (D = k I) makes both exact."""
    rng = np.random.default_rng(3)
    units = len(st.unit_slots(network))
    found = st.threshold(network, starts=1, samples=1)
    couplings = [st.critical_coupling(network, rng.uniform(0, 2 * np.pi, units)) for _ in range(30)]
    couplings.append(st.critical_coupling(network, found.polarities))
    for ceiling in (st.interlacing_ceiling(network), st.unit_ceiling(network)):
        assert max(couplings) <= ceiling * (1 + 1e-12)
    assert found.ceiling == min(st.interlacing_ceiling(network), st.unit_ceiling(network))
    d = m.dynamical_matrix(network)
    values, vectors = np.linalg.eigh(d)
    n = st.perpendiculars(rng.uniform(0, 2 * np.pi, units), st.unit_slots(network), d.shape[0] // 2)
    soft = vectors[:, : d.shape[0] - units + 1]
    _, singular, right = np.linalg.svd(np.hstack([soft, -n]))  # soft a = n b: a null vector of [soft, -n]
    v = soft @ right[-1, : soft.shape[1]]
    assert singular.size < soft.shape[1] + units or singular[-1] < 1e-9
    assert v @ d @ v <= st.interlacing_ceiling(network) * (v @ v) * (1 + 1e-9)
    assert v @ (n @ n.T) @ v == pytest.approx(v @ v)
    if network.trap:
        assert st.interlacing_ceiling(network) == pytest.approx(0.7) and st.unit_ceiling(network) == pytest.approx(0.7)


def test_the_search_reaches_past_the_kink_of_the_top_eigenvalue():
    """Pi_c peaks where mu_max's top eigenvalues cross, where a plain descent stalls (R = 3: 0.968 from 6 plain
    starts); the smoothed search reaches the fixed point stable to Pi = 0.9914 from 2 starts."""
    network = hexagonal_patch(3)
    found = st.threshold(network, starts=2, samples=1)
    assert found.coupling > 0.99 and found.reached >= 1
    assert st.critical_coupling(network, found.polarities) == pytest.approx(found.coupling, rel=1e-9)


def test_stability_command_reports_the_lattices_bracket(capsys, monkeypatch):
    """`elastoactive stability lattice`: the fixed points form a family, so the onset is what is proved (every one
    stable below lambda_1, none above the ceiling) apart from what the search found (one stable up to at least its
    Pi, printed as such and never as 'none above'), in Pi and sigma = Pi l_a, with the least stable fixed point's
    growth rate Pi - lambda_1 at --sigma."""
    import re

    from elastoactive.cli import main

    monkeypatch.setattr(st, "search_starts", lambda units: 4)  # the report, not the search's reach (tested above)
    assert main(["stability", "lattice", "--rings", "2", "--alignment-length", "0.1", "--sigma", "0.15"]) == 0
    out = capsys.readouterr().out
    assert "every fixed point is stable below Pi = 1.13584, sigma = 0.113584 (lambda_1, proved)" in out
    assert "growth rate +0.364164 k/gamma (unstable; some fixed point is stable)" in out
    found = float(re.search(r"some fixed point is stable up to at least Pi = ([\d.]+)", out).group(1))
    ceiling = float(re.search(r"no fixed point is stable above Pi = ([\d.]+), sigma = [\d.]+ \(proved", out).group(1))
    network = hexagonal_patch(2)
    assert 1.7 < found <= 1.7550  # 1.7549 from the default 16 starts (docs/network.md)
    assert ceiling == pytest.approx(st.coupling_ceiling(network), rel=1e-5) and found < ceiling
    assert "none above" not in out and "lower bound" not in out
    assert main(["stability", "lattice", "--rings", "2", "--alignment-length", "0.1", "--sigma", "0.3"]) == 0
    assert "(unstable; no fixed point is stable)" in capsys.readouterr().out
    assert main(["stability", "lattice", "--boundary", "centre"]) != 0
    assert "needs a patch held in place, and --boundary centre lets it turn" in capsys.readouterr().err


def test_a_network_file_held_by_one_pin_is_refused_in_its_own_words(tmp_path, capsys):
    """A file has no --boundary: the refusal says what the file pins, not a boundary the user never gave."""
    from elastoactive.cli import main

    path = tmp_path / "one_pin.json"
    path.write_text(
        json.dumps({"nodes": [[0, 0], [1, 0], [0.5, 0.9]], "bonds": [[0, 1], [1, 2], [0, 2]], "pinned": [0]})
    )
    assert main(["stability", "network", "--geometry", str(path)]) != 0
    err = capsys.readouterr().err
    assert "one_pin.json pins 1 node, which lets it turn about its pinned node" in err and "boundary" not in err


def test_the_coupling_is_the_scenes_own(capsys):
    """Pi = l_e / l_a with the scene's own spring: sigma / l_a on the lattice (k = 1), sigma / (trap l_a) for the
    trapped unit (its onset Pi_c = 1 had been printed as 0.1 at trap 0.1); the caption draws the same number."""
    import elastoactive as ea
    from elastoactive.cli import main

    assert main(["stability", "trapped-unit", "--sigma", "0.8", "--trap", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "(Pi_c = 1)" in out and "(Pi = 8)" in out
    physics = ea.Physics(scene="trapped-unit", sigma=0.8, trap=0.1)
    assert physics.scene_def.coupling(physics) == 8.0 and "Π = σ / (k_t l_a) = 8" in physics.scene_def.caption(physics)
    lattice = ea.Physics(scene="lattice", sigma=0.15, alignment_length=0.1)
    assert lattice.scene_def.coupling(lattice) == pytest.approx(1.5)


@pytest.mark.parametrize(
    "network",
    [hexagonal_patch(2), hexagonal_patch(3), trap_unit(0.7)],
    ids=["R2", "R3", "trap"],
)
def test_sparse_bracket_is_the_dense_one(network):
    """The sparse path (every unit's compliance block by sparse solves, the softest eigenvalue by shift-invert
    Lanczos) equals the dense analysis to round-off."""
    assert st.unit_ceiling_sparse(network) == pytest.approx(st.unit_ceiling(network), rel=1e-12)
    if 2 * int((~network.pinned).sum()) > 2:
        lowest = m.lowest_eigenvalues(network, 1, sparse=True)[0]
        assert lowest == pytest.approx(np.linalg.eigvalsh(m.dynamical_matrix(network))[0], rel=1e-10)


def test_a_subset_of_units_gives_a_weaker_ceiling():
    """Each unit's bound holds alone: the ceiling from some units is >= the one from all of them."""
    network = hexagonal_patch(3)
    every = st.unit_ceiling_sparse(network)
    for units in ([0], [0, 5, 9], list(range(0, 19, 2))):
        assert st.unit_ceiling_sparse(network, np.array(units)) >= every * (1 - 1e-12)


def test_large_bracket_brackets_the_dense_search():
    """A large network's sparse bracket [lambda_1, ceiling] (no search) contains Pi_c of random polarities, computed
    densely: every fixed point is stable below lambda_1 and none above the ceiling."""
    from elastoactive.networks.lattices import generate

    network = generate("triangular", "hexagonal", 17, "pinned", 0.0, 0)
    bracket = st.threshold(network)
    assert bracket.starts == 0 and np.isnan(bracket.typical)
    rng = np.random.default_rng(1)
    for _ in range(2):
        pi_c = st.critical_coupling(network, rng.uniform(0, 2 * np.pi, int(network.active.sum())))
        assert bracket.softest * (1 - 1e-9) <= pi_c <= bracket.ceiling
