"""The conformance kit: one fixed list of checks that every scene and every physical term passes, built-in or plug-in.

In the spirit of scikit-learn's ``check_estimator``: ``check_scene(name or class or instance)`` and
``check_term(name or class or instance)`` run each check of `SCENE_CHECKS` / `TERM_CHECKS` on the subject and raise
a `ConformanceError` naming the broken promise at the first that fails. A plug-in author calls them from their own
tests; the package's suite runs them over every registered scene and term (tests/testing/). The promises:

  declares                 its name, summary, parameters and observables are registered specs; its cases are its own
  engines agree            both engines run a short case and their states agree within the scene's `agreement`
  parameters act           every parameter it declares changes the result in every engine that takes it
  absurd values stop       sigma 1e6, duration 1e12, perturbation 1e9 (a term's rates at 1e6 per unit time) are
                           refused in one line naming the parameter, or announced and shown progressing, within
                           ABSURD_SECONDS of CPU, in every engine
  progress shows           a long run reports progress within PROGRESS_SECONDS of CPU, in every engine
  round trip               `run --out`, ea.load, `run --from` and `render` round-trip, bit-identical
  foreign start refused    another scene's state as its start is refused in one line naming `start` (or
                           `--start-from`) and both scenes
  observables defined      every observable it declares is measured at its parameters' defaults (a term's
                           occasional ones, Term.measured_at_rest False, while it acts)
  words fit                notes, summary fields, captions, labels, datasets and plots work on its results' shape

The checks drive the package from outside, as a user would (elastoactive.simulate, the command line,
elastoactive.io.progress's observers), so a promise is held whatever code path the subject takes.
"""

from .checks import (
    ABSURD_SECONDS,
    PROGRESS_SECONDS,
    SCENE_CHECKS,
    TERM_CHECKS,
    Check,
    ConformanceError,
    check_scene,
    check_term,
)
from .watch import Outcome, Stopped, watched

__all__ = [
    "ABSURD_SECONDS",
    "PROGRESS_SECONDS",
    "SCENE_CHECKS",
    "TERM_CHECKS",
    "Check",
    "ConformanceError",
    "Outcome",
    "Stopped",
    "check_scene",
    "check_term",
    "watched",
]
