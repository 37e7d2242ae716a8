"""Fill the documentation's generated blocks from the committed outputs, so that the pages and the reports have one
source:

  docs/reproduce.md
  <!-- generated: claims -->       the claims table (explanations left out), built through the study registry
                                   from the committed study data in docs/reproduction/ (as report.md's is)
  docs/accuracy.md
  <!-- generated: validate -->     docs/generated/validate.md       (output of `elastoactive validate`)
  <!-- generated: convergence -->  docs/generated/convergence.md    (`elastoactive validate one-pinned --convergence`)

    .venv/bin/python scripts/update_readme.py            # rewrite the pages' blocks from those files
    .venv/bin/python scripts/update_readme.py --check    # exit 1 if a page is out of date (tests/docs/test_readme.py)
    .venv/bin/python scripts/update_readme.py --run      # first regenerate the two validate files (~1 min)

Each block ends at `<!-- end -->`. (The README, the site's home page, holds no generated block.)
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GENERATED = DOCS / "generated"
REPRODUCTION = DOCS / "reproduction"

PAGES = {"claims": DOCS / "reproduce.md", "validate": DOCS / "accuracy.md", "convergence": DOCS / "accuracy.md"}
"""Each generated block and the page that holds it."""


def claims_table(folder: Path = REPRODUCTION) -> str:
    """The claims table of the studies saved in `folder`, without the explanation column: only that table (the
    report's other tables, sigma_c(N) and run times, stay in report.md)."""
    sys.path.insert(0, str(ROOT))
    from elastoactive.report import claims
    from elastoactive.studies import load_study, registry

    studies = {name: load_study(folder, name) for name in registry.names() if (folder / f"{name}.json").exists()}
    return claims.claims_table(claims.build_claims(studies), explanations=False)


def blocks() -> dict[str, str]:
    """Each block's content, by name."""
    return {
        "claims": claims_table(),
        "validate": (GENERATED / "validate.md").read_text().strip(),
        "convergence": (GENERATED / "convergence.md").read_text().strip(),
    }


def fill(text: str, content: dict[str, str], where: str = "the page") -> str:
    """`text` with each named block's body replaced by `content`'s; a block the text lacks is an error naming it."""
    for name, body in content.items():
        pattern = re.compile(rf"(<!-- generated: {name} -->\n)(?:(?!<!-- generated:).)*?(<!-- end -->)", re.S)
        if not pattern.search(text):
            raise SystemExit(f"{where} has no block <!-- generated: {name} --> ... <!-- end -->")
        text = pattern.sub(lambda m, body=body: m.group(1) + body + "\n" + m.group(2), text)
    return text


def filled() -> dict[Path, tuple[str, str]]:
    """Each page holding a block: its text now and its text with every block filled."""
    content = blocks()
    out = {}
    for page in dict.fromkeys(PAGES.values()):
        text = page.read_text()
        mine = {name: body for name, body in content.items() if PAGES[name] == page}
        out[page] = (text, fill(text, mine, str(page.relative_to(ROOT))))
    return out


def regenerate() -> None:
    """Run validate and the one-pinned convergence study into docs/generated/ (atomically)."""
    sys.path.insert(0, str(ROOT))
    from elastoactive.io.outputs import write_text

    def run(*argv: str) -> str:
        command = [sys.executable, "-m", "elastoactive", *argv]
        return subprocess.run(command, capture_output=True, text=True, check=True).stdout.strip()

    write_text(GENERATED / "validate.md", run("validate", "--quiet") + "\n")
    # the convergence output opens with a heading paragraph naming the fixed dt and mass ratio: keep the table
    write_text(GENERATED / "convergence.md", run("validate", "one-pinned", "--convergence").split("\n\n", 1)[1] + "\n")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--check", action="store_true", help="only check; exit 1 if a page is out of date")
    p.add_argument("--run", action="store_true", help="first regenerate docs/generated/validate.md and convergence.md")
    args = p.parse_args()
    if args.run:
        regenerate()
    pages = filled()
    stale = [page for page, (old, new) in pages.items() if old != new]
    if args.check:
        for page in stale:
            print(f"{page.relative_to(ROOT)} is out of date: run scripts/update_readme.py", file=sys.stderr)
        return 1 if stale else 0
    for page in stale:
        page.write_text(pages[page][1])
    return 0


if __name__ == "__main__":
    sys.exit(main())
