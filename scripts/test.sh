#!/usr/bin/env bash
# The test command: set up (idempotent), then lint and run the whole suite.
# The main job's set-up (scripts/setup.sh) stays lean: what only the tests need (the documentation site's builder
# and a headless Chromium for its browser test) is installed here, by scripts/docs_setup.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/docs_setup.sh
.venv/bin/ruff check .
.venv/bin/ruff format --check .
# one BLAS thread per test process: the workers already fill every core, and a multi-threaded OpenBLAS in each of
# them spins against the others (elastoactive/reduced/blas.py measured 65x on one LU on 2 shared cores)
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}" OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}" MKL_NUM_THREADS="${MKL_NUM_THREADS:-1}"
# the suite on every core (pytest-xdist; tests are spread one by one, an idle worker taking over another's queue)
# --durations: the slowest tests, printed at the end, so that a slower suite names what grew
exec .venv/bin/python -m pytest -n auto --dist worksteal --durations=25 "$@"
