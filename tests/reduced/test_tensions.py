"""The links' tensions (elastoactive.reduced.tensions): D lambda = z by its chain-pair blocks."""

import numpy as np

from elastoactive.reduced import tensions


def spd_blocks(chains, n, coupled, seed=0):
    """db (C, C, n, n): blocks of a symmetric positive definite D, chain c's with chain c' at slot c' (all chains
    listed); zero between chains unless `coupled`."""
    rng = np.random.default_rng(seed)
    b = chains * n
    a = rng.normal(size=(b, b))
    d = a @ a.T / b + np.eye(b)
    if not coupled:
        for c in range(chains):
            for c2 in range(chains):
                if c2 != c:
                    d[c * n : c * n + n, c2 * n : c2 * n + n] = 0.0
    return d, np.ascontiguousarray(d.reshape(chains, n, chains, n).transpose(0, 2, 1, 3))


def everyone(chains):
    nbr = np.tile(np.arange(chains, dtype=np.int64), (chains, 1))
    return nbr, np.full(chains, chains, dtype=np.int64), np.arange(chains, dtype=np.int64)


def test_chain_by_chain_is_the_whole_cholesky_without_coupling_to_the_bit():
    """own_tensions on each chain's block alone gives the whole matrix's Cholesky solve bit for bit (its blocks
    between chains are zeros, which subtract nothing), and conjugate gradients' answer beyond DIRECT_UP_TO."""
    for chains, n in ((4, 10), (13, 10)):  # 40 links: Cholesky; 130: conjugate gradients
        d, db = spd_blocks(chains, n, coupled=False, seed=chains)
        z = np.random.default_rng(1).normal(size=chains * n)
        nbr, count, self_slot = everyone(chains)
        whole = z.copy()
        tensions.tensions(db, whole, n, nbr, count, self_slot)
        own = z.copy()
        tensions.own_tensions(np.ascontiguousarray(db[np.arange(chains), np.arange(chains)][:, None]), own, n)
        np.testing.assert_allclose(own, np.linalg.solve(d, z), rtol=1e-12)
        if chains * n <= tensions.DIRECT_UP_TO:
            np.testing.assert_array_equal(own, whole)
        else:
            np.testing.assert_allclose(own, whole, rtol=1e-13)


def test_coupled_chains_solve_the_whole_system():
    for chains, n in ((4, 10), (13, 10)):
        d, db = spd_blocks(chains, n, coupled=True, seed=chains + 7)
        z = np.random.default_rng(2).normal(size=chains * n)
        nbr, count, self_slot = everyone(chains)
        lam = z.copy()
        assert tensions.tensions(db, lam, n, nbr, count, self_slot) >= 0
        np.testing.assert_allclose(lam, np.linalg.solve(d, z), rtol=1e-10)
