#!/usr/bin/env bash
# Set up what only the documentation needs, after scripts/setup.sh: the `docs` extra of pyproject.toml (MkDocs, the
# Material theme, mkdocstrings, MathJax) into .venv, and, when root with apt, Debian's `chromium` for the test that
# opens the built site in a real headless browser (tests/docs/test_docs_site.py).
# The extra's packages are installed at the versions in scripts/constraints.txt, as scripts/setup.sh installs the rest.
# Idempotent and quick when done: the pip install is skipped while the extra's list and the constraints are as at the
# last install (stamp in .venv/.elastoactive-docs-stamp), apt-get runs (with one `apt-get update` first) only while
# chromium is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x .venv/bin/python ] || { echo "docs_setup: no .venv: run scripts/setup.sh first" >&2; exit 1; }
extra=$(.venv/bin/python -c 'import tomllib
print("\n".join(tomllib.load(open("pyproject.toml", "rb"))["project"]["optional-dependencies"]["docs"]))')
constraints=scripts/constraints.txt
stamp=$( (printf '%s\n' "$extra"; cat "$constraints") | sha256sum | cut -d' ' -f1)
if [ "$(cat .venv/.elastoactive-docs-stamp 2>/dev/null)" != "$stamp" ] \
   || ! .venv/bin/python -c "import mkdocs, material, mkdocstrings_handlers.python, mathjax" 2>/dev/null; then
  # the extra's requirements alone: the package itself is installed (editable) by scripts/setup.sh
  mapfile -t requirements <<< "$extra"
  .venv/bin/python -m pip install -q -c "$constraints" "${requirements[@]}"
  echo "$stamp" > .venv/.elastoactive-docs-stamp
fi
if ! command -v chromium >/dev/null 2>&1; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null) \
      || echo "docs_setup: could not install chromium; the browser test of the site will fail" >&2
  else
    echo "docs_setup: chromium is not installed and this is not root with apt: the browser test of the site skips" >&2
  fi
fi
