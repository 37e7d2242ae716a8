"""The linear-stability bracket of a network whose units have their own force f_u and alignment length l_u: the
weighted operator -D + Pi Q_w (w_u = f_u l_a / l_u) against today's numbers (every weight 1), a scaling of the
forces, the reduced engine's full Jacobian at the nonlinear fixed point, and a passive unit (f_u = 0)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import HAND_WRITTEN
from scipy.optimize import brentq

from elastoactive.analysis.network import NetworkState, hexagonal_patch
from elastoactive.analysis.network import stability as st
from elastoactive.networks.geometry import make_network
from elastoactive.reduced import network as m

NODES, BONDS, PINNED, UNITS = (HAND_WRITTEN[key] for key in ("nodes", "bonds", "pinned", "units"))
FORCE = [1.0, 0.6, 1.5, 0.8, 1.2]
LENGTH = [0.1, 0.15, 0.08, 0.12, 0.1]
LA = 0.1
"""docs/network.md's hand-written 12-node network (3 pinned, 5 units) with unequal units, in the order of UNITS."""


def hand(force=FORCE, length=LENGTH, units=UNITS):
    return make_network(NODES, BONDS, pinned=PINNED, units=units, unit_force=force, unit_alignment_length=length)


def bracket(network, alignment_length=None):
    return (
        st.stable_below(network, alignment_length),
        st.interlacing_ceiling(network, alignment_length),
        st.unit_ceiling(network, alignment_length),
        st.coupling_ceiling(network, alignment_length),
    )


@pytest.mark.parametrize("rings", [None, 2], ids=["hand", "R2"])
def test_every_weight_one_gives_todays_numbers_to_the_bit(rings):
    """A network whose units all have factor 1 and the run's l_a: every number as without the fields, exactly."""
    plain = hexagonal_patch(rings) if rings else hand(None, None)
    count = int(plain.active.sum())
    ones = plain._replace(unit_force=np.ones(count), unit_alignment_length=np.full(count, LA))
    assert np.array_equal(st.unit_weights(ones, LA), np.ones(count))
    before, after = (
        st.threshold(plain, starts=2, samples=5),
        st.threshold(ones, starts=2, samples=5, alignment_length=LA),
    )
    for field in before._fields:
        assert np.array_equal(getattr(before, field), getattr(after, field)), field
    assert bracket(plain) == bracket(ones, LA)
    psi = np.random.default_rng(2).uniform(0, 2 * np.pi, count)
    assert st.critical_coupling(plain, psi) == st.critical_coupling(ones, psi, LA)
    assert st.least_stable_growth(plain, 1.5) == st.least_stable_growth(ones, 1.5, LA)


def test_scaling_every_force_divides_the_bracket():
    """f_u -> c f_u multiplies Q_w by c: every Pi_c, both ceilings and the lower bound divide by c."""
    c = 2.5
    network, scaled = hand(), hand([c * f for f in FORCE])
    for one, other in zip(bracket(network, LA), bracket(scaled, LA)):
        assert other == pytest.approx(one / c, rel=1e-12)
    found = st.threshold(network, starts=2, samples=5, alignment_length=LA)
    assert st.critical_coupling(scaled, found.polarities, LA) == pytest.approx(found.coupling / c, rel=1e-9)
    assert st.threshold(scaled, starts=2, samples=5, alignment_length=LA).coupling == pytest.approx(
        found.coupling / c, rel=1e-6
    )


def test_a_passive_unit_is_a_removed_unit():
    """A unit of force 0 pushes nothing: the bracket and the search are those of the network without it."""
    passive = hand([1.0, 0.6, 1.5, 0.0, 1.2])
    removed = hand([1.0, 0.6, 1.5, 1.2], [0.1, 0.15, 0.08, 0.1], [5, 6, 9, 1])
    assert bracket(passive, LA) == bracket(removed, LA)
    with_it = st.threshold(passive, starts=2, samples=5, alignment_length=LA)
    without = st.threshold(removed, starts=2, samples=5, alignment_length=LA)
    keep = np.flatnonzero(passive.active) != 10
    assert with_it.coupling == without.coupling and with_it.typical == without.typical
    assert np.array_equal(with_it.polarities[keep], without.polarities)
    psi = np.random.default_rng(4).uniform(0, 2 * np.pi, 5)
    assert st.critical_coupling(passive, psi, LA) == pytest.approx(st.critical_coupling(removed, psi[keep], LA))
    with pytest.raises(Exception, match="every unit has force 0"):
        st.threshold(hand([0.0] * 5), alignment_length=LA)


def _top_growth(network, psi, coupling, la):
    """The largest real part of the full Jacobian's (model.jacobian) eigenvalues at the nonlinear fixed point of
    polarities psi (sigma = Pi l_a) other than its A zero ones along the family of fixed points: J's kernel K (its A
    null right singular vectors) is invariant, so in an orthonormal basis [K, C] J is block triangular and its other
    eigenvalues are those of C^T J C (the zero eigenvalue is defective where another one crosses it: J's own
    eigenvalues split there by the square root of round-off)."""
    system = m.network_system(network, coupling * la, la)
    free, dofs = ~network.pinned, m.free_dofs(system)
    positions = network.positions.copy()
    for _ in range(4):  # Newton on the node velocities (the springs balancing the active forces)
        step = np.linalg.solve(
            m.force_jacobian(system, positions)[np.ix_(dofs, dofs)],
            m.velocities(system, positions, psi)[free].reshape(-1),
        )
        positions[free] -= step.reshape(-1, 2)
    assert np.abs(m.velocities(system, positions, psi)).max() < 1e-15
    y = m.pack(system, NetworkState(positions, psi))
    jacobian = m.jacobian(system, y)
    _, singular, right = np.linalg.svd(jacobian)
    count = psi.size
    assert singular[-count - 1] > 1e6 * singular[-count]  # a kernel of dimension A, well apart
    rest = right[:-count].T
    return float(np.linalg.eigvals(rest.T @ jacobian @ rest).real.max())


def test_the_threshold_is_where_the_full_jacobian_crosses_zero():
    """At the best fixed point found, the reduced engine's Jacobian at the nonlinear fixed point has its largest
    non-zero eigenvalue cross zero at the predicted Pi_c within 1e-6 (lengths scaled by 1e-6: displacements ~ sigma =
    Pi l_a ~ 1e-7, the linear-elastic limit H = -D; the weights are unchanged), inside the proved bracket."""
    scale = 1e-6
    network, la = hand(length=[scale * length for length in LENGTH]), scale * LA
    found = st.threshold(network, starts=2, samples=20, alignment_length=la)
    predicted = found.coupling
    assert _top_growth(network, found.polarities, found.softest, la) < 0
    assert _top_growth(network, found.polarities, found.ceiling, la) > 0
    crossing = brentq(lambda p: _top_growth(network, found.polarities, p, la), found.softest, found.ceiling, xtol=1e-12)
    assert crossing == pytest.approx(predicted, rel=1e-6)
    assert found.softest < found.typical <= predicted <= found.ceiling


def test_each_bound_holds_for_unequal_units():
    """Every fixed point (random polarities, the search's best) has lambda_1 / max w <= Pi_c <= both ceilings; the
    least stable fixed point's growth lambda_max(-D + Pi P_w) is the max over the polarities, reached by turning each
    n_perp along the top vector; the interlacing bound's weighted argument: Q_w >= w_+ Q_+."""
    network = hand()
    rng = np.random.default_rng(5)
    found = st.threshold(network, starts=2, samples=20, alignment_length=LA)
    couplings = [st.critical_coupling(network, rng.uniform(0, 2 * np.pi, 5), LA) for _ in range(50)]
    couplings.append(found.coupling)
    low, interlacing, unit, ceiling = bracket(network, LA)
    assert low * (1 - 1e-12) <= min(couplings) and max(couplings) <= min(interlacing, unit) * (1 + 1e-12)
    assert ceiling == min(interlacing, unit) and found.ceiling == ceiling and found.softest == low
    weights = st.unit_weights(network, LA)
    np.testing.assert_allclose(weights, np.array(FORCE)[np.argsort(UNITS)] * LA / np.array(LENGTH)[np.argsort(UNITS)])
    growth = st.least_stable_growth(network, 3.0, LA)
    d = m.dynamical_matrix(network)
    slots = st.unit_slots(network)
    on_nodes = np.zeros(d.shape[0] // 2)
    on_nodes[slots] = weights
    top = np.linalg.eigh(-d + 3.0 * np.diag(np.repeat(on_nodes, 2)))[1][:, -1].reshape(-1, 2)
    psi = np.arctan2(-top[slots, 0], top[slots, 1])  # n_perp_u = (-sin, cos) along v_u
    assert np.linalg.eigvalsh(st.coupling_operator(network, psi, 3.0, LA))[-1] == pytest.approx(growth, rel=1e-10)
    for _ in range(20):
        other = np.linalg.eigvalsh(st.coupling_operator(network, rng.uniform(0, 2 * np.pi, 5), 3.0, LA))[-1]
        assert other <= growth + 1e-12
    n = st.weighted_perpendiculars(network, rng.uniform(0, 2 * np.pi, 5), d.shape[0] // 2, LA)
    projector = (n / np.sqrt(weights)) @ (n / np.sqrt(weights)).T  # Q: every unit pushes here
    assert np.linalg.eigvalsh(n @ n.T - weights.min() * projector)[0] > -1e-12


def test_stability_command_prints_the_bracket_of_unequal_units(tmp_path, capsys, monkeypatch):
    """`elastoactive stability network --geometry FILE` on a file with unit_force and unit_alignment_length: the
    bracket (in Pi = sigma / l_a, the run's l_a the reference), not a refusal."""
    from elastoactive.cli import main

    path = tmp_path / "hand.json"
    data = {"nodes": NODES, "bonds": BONDS, "pinned": PINNED, "units": UNITS}
    path.write_text(json.dumps(data | {"unit_force": FORCE, "unit_alignment_length": LENGTH}))
    monkeypatch.setattr(st, "search_starts", lambda units: 2)
    assert main(["stability", "network", "--geometry", str(path), "--alignment-length", "0.1", "--sigma", "0.1"]) == 0
    out = capsys.readouterr().out
    low, _, _, ceiling = bracket(hand(), LA)
    assert f"every fixed point is stable below Pi = {low:.6g}" in out
    assert f"no fixed point is stable above Pi = {ceiling:.6g}" in out
    assert f"growth rate {st.least_stable_growth(hand(), 1.0, LA):+.6g}" in out
    assert "equal units only" not in out


def test_a_large_network_of_unequal_units_stays_sparse(monkeypatch):
    """Above DENSE_MODES free coordinates the weighted bracket (lambda_1 / max w_u, the ceilings with the weights)
    builds no dense matrix, and holds Pi_c of random polarities computed densely afterwards."""
    from elastoactive.networks.lattices import generate

    plain = generate("triangular", "hexagonal", 17, "pinned", 0.0, 0)
    rng = np.random.default_rng(6)
    count = int(plain.active.sum())
    force = rng.uniform(0.5, 1.5, count)
    force[::50] = 0.0  # some passive units
    network = plain._replace(unit_force=force, unit_alignment_length=rng.uniform(0.08, 0.12, count))
    assert m.is_large(network)

    def refuse(*args, **kwargs):
        raise AssertionError("a dense N x N matrix was built for a large network")

    with monkeypatch.context() as patch:
        patch.setattr(st, "dynamical_matrix", refuse)
        found = st.threshold(network, alignment_length=LA)
        growth = st.least_stable_growth(network, 1.0, LA)
    weights = st.unit_weights(network, LA)
    assert found.starts == 0 and found.softest == pytest.approx(st.softest(plain) / weights.max(), rel=1e-12)
    assert found.softest < found.ceiling and growth == pytest.approx(weights.max() - st.softest(plain), rel=1e-12)
    pi_c = st.critical_coupling(network, rng.uniform(0, 2 * np.pi, count), LA)
    assert found.softest * (1 - 1e-9) <= pi_c <= found.ceiling
