"""Fill the README's generated blocks from the committed outputs, so that the README and the reports
have one source:

  <!-- generated: claims -->       the claims table of docs/reproduction/report.md (explanations left out)
  <!-- generated: validate -->     docs/generated/validate.md       (output of `elastoactive validate`)
  <!-- generated: convergence -->  docs/generated/convergence.md    (`elastoactive validate one-pinned --convergence`)

    .venv/bin/python scripts/update_readme.py            # rewrite README.md's blocks from those files
    .venv/bin/python scripts/update_readme.py --check    # exit 1 if README.md is out of date (tests/test_readme.py)
    .venv/bin/python scripts/update_readme.py --run      # first regenerate the two validate files (~1 min)

Each block ends at `<!-- end -->`.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
GENERATED = ROOT / "docs" / "generated"
REPORT = ROOT / "docs" / "reproduction" / "report.md"


def claims_table(report: str) -> str:
    """The report's claims table without its last (explanation) column."""
    section = report.split("## Claims", 1)[1]
    rows = [line for line in section.splitlines()[1:] if line.startswith("|")]
    rows = rows[: next((i for i, r in enumerate(rows[1:], 1) if not r.startswith("|")), len(rows))]
    out = []
    for row in rows:
        cells = re.split(r"(?<!\\)\|", row)[1:-1]  # '\|' inside a cell is not a separator
        out.append("|" + "|".join(cells[:-1]) + "|")
    return "\n".join(out)


def blocks() -> dict[str, str]:
    return {
        "claims": claims_table(REPORT.read_text()),
        "validate": (GENERATED / "validate.md").read_text().strip(),
        "convergence": (GENERATED / "convergence.md").read_text().strip(),
    }


def fill(text: str, content: dict[str, str]) -> str:
    for name, body in content.items():
        pattern = re.compile(rf"(<!-- generated: {name} -->\n)(?:(?!<!-- generated:).)*?(<!-- end -->)", re.S)
        if not pattern.search(text):
            raise SystemExit(f"README.md has no block <!-- generated: {name} --> ... <!-- end -->")
        text = pattern.sub(lambda m: m.group(1) + body + "\n" + m.group(2), text)
    return text


def regenerate() -> None:
    """Run validate and the one-pinned convergence study into docs/generated/ (atomically)."""
    sys.path.insert(0, str(ROOT))
    from elastoactive.outputs import write_text

    run = lambda *argv: subprocess.run([sys.executable, "-m", "elastoactive", *argv], capture_output=True, text=True,
                                       check=True).stdout.strip()
    write_text(GENERATED / "validate.md", run("validate", "--quiet") + "\n")
    # the convergence output opens with a heading paragraph naming the fixed dt and mass ratio: keep the table
    write_text(GENERATED / "convergence.md", run("validate", "one-pinned", "--convergence").split("\n\n", 1)[1] + "\n")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--check", action="store_true", help="only check; exit 1 if README.md is out of date")
    p.add_argument("--run", action="store_true", help="first regenerate docs/generated/validate.md and convergence.md")
    args = p.parse_args()
    if args.run:
        regenerate()
    text = README.read_text()
    new = fill(text, blocks())
    if args.check:
        if new != text:
            print("README.md is out of date: run scripts/update_readme.py", file=sys.stderr)
            return 1
        return 0
    README.write_text(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
