#!/usr/bin/env bash
# Set up everything on a fresh machine: system libraries for off-screen rendering (when root and
# apt is available), a virtual environment in .venv, and elastoactive with its test extras.
# Needs Python >= 3.11 with venv, a C compiler and the Python headers (the follower-force callback is
# compiled at install), network access to PyPI, and about 1.1 GB of disk for .venv.
# Every package (pip included) is installed at the version in scripts/constraints.txt, what CI tested (the file says
# how to refresh it); the MuJoCo the callback is compiled against too (--build-constraint).
# Idempotent and quick when nothing changed: the install is skipped while pyproject.toml, setup.py, the C callback
# and the constraints are as they were at the last install (stamp in .venv/.elastoactive-stamp), and the
# numba kernels are compiled ahead (elastoactive.cli.warm) only after an install or a change of the sources.
set -euo pipefail
cd "$(dirname "$0")/.."
say() { echo "setup: $*"; }  # one line per stage that does work; the tools' own output stays quiet
if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
  need=""
  for pkg in libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libgl1 libosmesa6; do
    dpkg -s "$pkg" >/dev/null 2>&1 || need="$need $pkg"
  done
  if [ -n "$need" ]; then
    say "installing system libraries for off-screen rendering:$need (apt)"
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $need >/dev/null) \
      || echo "setup: could not install$need; off-screen rendering may be unavailable" >&2
  fi
fi
if [ ! -x .venv/bin/python ]; then
  say "creating the virtual environment .venv"
  python3 -m venv .venv
fi
# bytecode of the package's sources (an editable install leaves it to the first import, which cannot write it
# where PYTHONDONTWRITEBYTECODE is set: every process would compile ~100 modules, ~0.04 s); quick when up to date
.venv/bin/python -m compileall -q elastoactive analysis controllers >/dev/null
constraints=scripts/constraints.txt
stamp=$(cat pyproject.toml setup.py controllers/follower.c "$constraints" | sha256sum | cut -d' ' -f1)
if [ "$(cat .venv/.elastoactive-stamp 2>/dev/null)" != "$stamp" ] || ! .venv/bin/python -c "import elastoactive.controllers" 2>/dev/null; then
  say "installing elastoactive and its test extras into .venv (pip, the versions of $constraints; a few minutes)"
  .venv/bin/python -m pip install -q --upgrade -c "$constraints" pip
  .venv/bin/python -m pip install -q -c "$constraints" --build-constraint "$constraints" -e '.[test]'
  echo "$stamp" > .venv/.elastoactive-stamp
fi
# the reduced model's numba kernels, compiled into numba's on-disk cache here (~2 min on 2 cores) rather than by the
# first run; again after an install or when a source changed since (~2 s when the cache is still valid)
kernels=.venv/.elastoactive-kernels
if [ ! -f "$kernels" ] || [ .venv/.elastoactive-stamp -nt "$kernels" ] \
   || [ -n "$(find elastoactive analysis -name '*.py' -newer "$kernels" 2>/dev/null | head -1)" ]; then
  say "compiling the reduced model's numba kernels ahead (about 2 min on 2 cores)"
  if .venv/bin/python -m elastoactive.cli.warm; then
    touch "$kernels"
  else
    echo "setup: could not compile the kernels ahead; the first run compiles them" >&2
  fi
fi
say "ready: .venv/bin/elastoactive (or \`source .venv/bin/activate\` to call it as elastoactive)"
