#!/usr/bin/env bash
# Build or serve the documentation site (mkdocs.yml; docs/site.md), offline, with warnings as errors.
#   bash scripts/docs.sh build [DIR]      # the static site into DIR (default site/); open DIR/index.html
#   bash scripts/docs.sh serve [ADDR]     # serve it at ADDR (default 127.0.0.1:8000), rebuilt on every edit
#   bash scripts/docs.sh generate [--check]  # rewrite (or check) the committed generated pages: docs/cli.md,
#                                            # docs/api/parameters.md (scripts/docs_hooks.py)
# Run scripts/setup.sh and scripts/docs_setup.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
export NO_MKDOCS_2_WARNING=1  # the theme's banner about its successor, printed at every build
case "${1:-build}" in
  build) exec .venv/bin/mkdocs build --strict --site-dir "${2:-site}" ;;
  serve) exec .venv/bin/mkdocs serve --strict --dev-addr "${2:-127.0.0.1:8000}" ;;
  generate) shift; exec .venv/bin/python scripts/docs_hooks.py "$@" ;;
  *) echo "usage: bash scripts/docs.sh build [DIR] | serve [ADDR] | generate [--check]" >&2; exit 2 ;;
esac
