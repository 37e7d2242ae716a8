"""The studies behind the paper's figures and claims, shared by `elastoactive reproduce` and the
scenario scripts in scripts/.

Each study is one module holding its run, its typed summary, its figures and its claim rows,
registered together in `registry` (see there for the decorators). Its run function
``name_study(size="quick", workers=None, progress=True) -> Study``
chooses its parameter grid and run lengths from ``size`` ("tiny" for tests, "quick" for the default
reproduce run, "full" for publication resolution), runs its simulations through
`elastoactive.batch.run_cases` (a process pool) and returns the arrays behind the figure
(`Study.data`, saved as NPZ) and the numbers the report quotes (`Study.summary`, a typed dataclass,
saved as JSON). MuJoCo ("mujoco") and the reduced overdamped model ("reduced") run the same cases
from the same initial state. The mathematics they use lives in `elastoactive.analysis`; the paper's
numbers they are set against in `elastoactive.studies.paper`.

    linear        stability (sigma_c(N), N^-3, continuum), growth (linear rates seen by both engines)
    hopf          the Hopf bifurcation of N = 7
    normal_form   the N = 2 Landau-Stuart coefficient
    snapping      self-snapping with both ends pinned
    rotation      the freely rotating pin
    sync          the coupled pair (Fig. 5); tongue: its Arnold tongue; sync_n2: kappa_c of N = 2
    noise         multiplicative noise and anisotropic drag (N = 2)
    inertia       the overdamped idealisation: sigma_c(mass ratio), Ziegler's column, the experiment's mass ratio
    noise_readings  claim 21 under Ito, Stratonovich and coloured noise; the experiment's noise regime
    long_chain    the supplement's N = 17 chain with and without self-contact; contact convergence; winding
    dish          the supplement's chain in a paraboloid dish: the (sigma, trap) phase diagram of N = 7
    skin          the outlook: mode localisation, spectral winding and transient gain of the non-Hermitian chain
    response      the outlook: a periodic tip force below onset (gain, phase, resonance width) and entrainment above
    ring          the outlook: rings of N = 7 and 24, pinned or free (rigid turning, beating)
    self_aligning the outlook: the one-pinned chain with self-aligning units over (sigma, l_a)
    star          the outlook: k arms on one hub against the hub's stiffness (in phase, antiphase, spinning)
    clamp_tongue  the outlook: the beat locking to a moving clamp (phase response, Adler's tongue)
    lattice       the outlook: the active solid (the pinned hexagon's collective actuation, mode selection, the
                  trapped unit)
    hysteresis    the outlook: the active solid's hysteresis loop (Pi up, then down) on the triangular hexagon and a
                  kagome patch, with the named states
    noise_threshold  the outlook: where the active solid's units start turning (up and down) against the rotational
                  noise on their polarities
    disorder      the outlook: the active solid's actuation on diluted triangular patches and Delaunay networks,
                  against each network's linear bracket
    states3d      beyond the paper: the clamped chain in 3D, the state reached (planar beat, whirl) against the load,
                  the start and the drag ratio; the beat's out-of-plane Floquet multipliers, the whirl's stability
    fluid_onset, cilium_states, cilia_pair_sync, cilia_row_waves
                  beyond the paper, through the fluid (docs/fluid_studies.md): the onset against the bead radius in
                  free space and on a wall, a cilium's beat or whirl, a pair's locks, a row's waves and flux

and what they share: `registry` (the studies by name), `base` (sizes, the Study container, running a
batch of cases), `plotting` (figure style and helpers), `claim_rows` (the claim row and its number
formatting). docs/studies.md describes the contract and the diff a new study needs.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path

from . import registry
from .base import ENGINES, SIZES, Study, Summary
from .cilia_pair_sync import PairSyncSummary, cilia_pair_sync_study
from .cilia_row_waves import RowWavesSummary, cilia_row_waves_study
from .cilium_states import CiliumStatesSummary, cilium_states_study
from .clamp_tongue import ClampTongueSummary, clamp_tongue_study
from .dish import DishSummary, dish_study
from .disorder import DisorderSummary, disorder_study
from .fluid_onset import FluidOnsetSummary, fluid_onset_study
from .hopf import HopfSummary, hopf_study
from .hysteresis import HysteresisSummary, hysteresis_study
from .inertia import InertiaSummary, inertia_study
from .lattice import ActiveSolidSummary, active_solid_study
from .linear import GrowthSummary, StabilitySummary, growth_study, stability_study
from .noise import (
    AnisotropySummary,
    NoiseReadingsSummary,
    NoiseSummary,
    anisotropy_study,
    noise_readings_study,
    noise_study,
)
from .noise_threshold import NoiseThresholdSummary, noise_threshold_study
from .normal_form import NormalFormSummary, normal_form_study
from .response import EntrainmentSummary, ResponseSummary, entrainment_study, response_study
from .ring import RingSummary, ring_study
from .rotation import RotationSummary, rotation_study
from .self_aligning import SelfAligningSummary, self_aligning_study
from .self_contact import LongChainSummary, long_chain_study
from .skin import SkinSummary, skin_study
from .snapping import SnappingSummary, snapping_study
from .star import StarSummary, star_study
from .states3d import States3DSummary, states3d_study
from .sync import SyncSummary, sync_study
from .sync_n2 import SyncN2Summary, sync_n2_study
from .tongue import TongueSummary, tongue_study

__all__ = [
    "ENGINES",
    "SIZES",
    "STUDIES",
    "SUMMARIES",
    "Study",
    "Summary",
    "load_study",
    "registry",
    "stability_study",
    "growth_study",
    "hopf_study",
    "normal_form_study",
    "snapping_study",
    "rotation_study",
    "sync_study",
    "tongue_study",
    "sync_n2_study",
    "noise_study",
    "anisotropy_study",
    "inertia_study",
    "noise_readings_study",
    "long_chain_study",
    "dish_study",
    "DishSummary",
    "HopfSummary",
    "InertiaSummary",
    "GrowthSummary",
    "StabilitySummary",
    "AnisotropySummary",
    "NoiseReadingsSummary",
    "NoiseSummary",
    "NormalFormSummary",
    "RotationSummary",
    "LongChainSummary",
    "SnappingSummary",
    "SyncN2Summary",
    "SyncSummary",
    "TongueSummary",
    "ClampTongueSummary",
    "clamp_tongue_study",
    "ActiveSolidSummary",
    "active_solid_study",
    "HysteresisSummary",
    "hysteresis_study",
    "NoiseThresholdSummary",
    "noise_threshold_study",
    "DisorderSummary",
    "disorder_study",
    "EntrainmentSummary",
    "ResponseSummary",
    "entrainment_study",
    "response_study",
    "RingSummary",
    "ring_study",
    "SelfAligningSummary",
    "self_aligning_study",
    "SkinSummary",
    "skin_study",
    "StarSummary",
    "star_study",
    "States3DSummary",
    "states3d_study",
    "FluidOnsetSummary",
    "fluid_onset_study",
    "CiliumStatesSummary",
    "cilium_states_study",
    "PairSyncSummary",
    "cilia_pair_sync_study",
    "RowWavesSummary",
    "cilia_row_waves_study",
]


class _View(Mapping):
    """A read-only view of the registry: study name -> one attribute of its entry, in reproduce's order."""

    def __init__(self, pick: Callable[[registry.StudyEntry], object]):
        self._pick = pick

    def __getitem__(self, name: str):
        return self._pick(registry.get(name))  # an unknown name: registry.UnknownStudy, a KeyError listing the names

    def __iter__(self):
        return iter(registry.names())

    def __len__(self) -> int:
        return len(registry.names())

    def __repr__(self) -> str:
        return f"{{{', '.join(f'{k!r}: {v!r}' for k, v in self.items())}}}"


STUDIES: Mapping[str, Callable[..., Study]] = _View(lambda e: e.run_fn)
"""Every registered study's run function by name, in the order reproduce runs them."""

SUMMARIES: Mapping[str, type[Summary]] = _View(lambda e: e.summary)
"""The summary type of each registered study."""


def load_study(folder: Path, name: str) -> Study:
    """Read back a study saved by Study.save (NPZ + JSON), its summary typed."""
    if name not in registry.names():
        raise ValueError(f"unknown study {name!r}; choose from {', '.join(registry.names())}")
    return Study.load(folder, name, registry.get(name).summary)
