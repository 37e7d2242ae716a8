"""MkDocs hooks (mkdocs.yml): what the site builds from sources other than docs/*.md, at every build.

- ``index.md`` is the repository's README.md, its links made relative to docs/ (one front page for both).
- ``cli.md`` is written from the argparse parser (``elastoactive.cli.build_parser``): every subcommand, its usage,
  its options with their defaults and help, as ``elastoactive COMMAND --help`` prints them.
- A pair of brackets in a docstring's plain text (``[I; M] [A, B]``, a matrix) reads to Markdown as a reference link;
  one whose target is no identifier (a cross-reference names a Python object or a heading: no spaces, no commas) is
  put back as the text it was, so that only a real cross-reference can fail the build.
- MathJax (the docs extra's ``django-static-mathjax`` package) is copied into ``assets/mathjax/``, so the built site
  typesets its maths without any network.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from mkdocs.structure.files import File, Files

ROOT = Path(__file__).resolve().parents[1]
"""The repository's root: README.md and the package live here."""

HOME = "index.md"
"""The site's home page, whose text is the README's."""

CLI_PAGE = "cli.md"
"""The command-line reference page, written from the parser."""

MATHJAX_FILES = ("tex-svg.js",)
"""What the site needs of MathJax's es5 build: TeX to SVG in one file (glyphs as paths: no fonts to load)."""

_AUTOREF = re.compile(
    r'<autoref (?P<attrs>[^>]*?)identifier="(?P<identifier>[^"]*)"(?P<rest>[^>]*)>(?P<title>.*?)</autoref>', re.S
)
_IDENTIFIER = re.compile(r"[A-Za-z_][\w.:-]*")

_README_LINK = re.compile(r"(\]\(|src=\")(?!https?:|#|mailto:)([^)\"\s]+)")


_REPO_LINK = re.compile(r"\[([^\]]*)\]\((?!https?:|#|mailto:|docs/)([^)\s]+)\)")


def readme_for_site(text: str) -> str:
    """The README with its links made relative to docs/: ``docs/x`` becomes ``x``. A link to another file of the
    repository (LICENSE, CITATION.cff) has no page in the site: it becomes its text and the file's name; a link to a
    file that does not exist is refused, as the build refuses a broken link into docs/."""

    def repo_file(match: re.Match) -> str:
        target = match.group(2)
        if not (ROOT / target.split("#")[0]).exists():
            raise ValueError(f"README.md links to {target!r}, which is not a file of the repository")
        return match.group(1) if match.group(1) == target else f"{match.group(1)} (`{target}`)"

    text = _REPO_LINK.sub(repo_file, text)
    return _README_LINK.sub(lambda m: m.group(1) + m.group(2).removeprefix("docs/"), text)


def _escape(text: str) -> str:
    """Plain text in Markdown: the characters that would start emphasis, a link or HTML escaped."""
    return re.sub(r"([\\`*_\[\]<>])", r"\\\1", text)


def _cell(text: str) -> str:
    """Text for one cell of a Markdown table: one line, pipes escaped."""
    return " ".join(str(text).split()).replace("|", "\\|")


def _option_row(action: argparse.Action, formatter: argparse.HelpFormatter) -> str:
    if action.option_strings:
        names = ", ".join(f"`{s}`" for s in action.option_strings)
        if action.nargs != 0:
            metavar = formatter._metavar_formatter(action, action.dest.upper())(1)[0]
            names += f" `{metavar}`"
    else:
        names = f"`{formatter._metavar_formatter(action, action.dest)(1)[0]}`"
    help_text = formatter._expand_help(action) if action.help else ""
    default = action.default
    shown = "" if default in (None, argparse.SUPPRESS, False) or action.nargs == 0 else f"`{default}`"
    return f"| {names} | {_cell(shown)} | {_cell(_escape(help_text))} |"


def _parser_section(parser: argparse.ArgumentParser, title: str, summary: str = "") -> list[str]:
    formatter = parser._get_formatter()
    lines = [f"## `{title}`", ""]
    if summary:
        lines += [_escape(summary[0].upper() + summary[1:]) + ".", ""]
    lines += ["```text", parser.format_usage().strip(), "```", ""]
    if parser.description:
        if issubclass(parser.formatter_class, argparse.RawDescriptionHelpFormatter):
            lines += ["```text", parser.description.strip(), "```", ""]
        else:  # argparse joins the lines into one paragraph, and so does the page
            lines += [_escape(" ".join(parser.description.split())), ""]
    for group in parser._action_groups:
        actions = [
            a
            for a in group._group_actions
            if a.help is not argparse.SUPPRESS
            and not isinstance(a, argparse._SubParsersAction)
            and not isinstance(a, argparse._HelpAction)
        ]
        if not actions:
            continue
        lines += [f"**{group.title}**", "", "| option | default | meaning |", "|---|---|---|"]
        lines += [_option_row(a, formatter) for a in actions]
        lines.append("")
    if parser.epilog:
        lines += ["```text", parser.epilog.strip(), "```", ""]
    return lines


def cli_reference() -> str:
    """The command-line reference as Markdown, from the parser ``elastoactive`` builds."""
    sys.path.insert(0, str(ROOT))
    from elastoactive.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    summaries = {choice.dest: choice.help or "" for choice in sub._choices_actions}
    lines = [
        "# Command-line reference",
        "",
        "Written from the parser at every build of this site, so it is what `elastoactive COMMAND --help` prints "
        "for this version. Every subcommand's bad input stops with one line, `elastoactive: error: ...`, "
        "naming the option.",
        "",
        "| command | what it does |",
        "|---|---|",
    ]
    lines += [
        f"| [`{name}`](#elastoactive-{name}) | {_cell(_escape(summaries.get(name, '')))} |" for name in sub.choices
    ]
    lines.append("")
    lines += _parser_section(parser, "elastoactive")
    for name, subparser in sub.choices.items():
        lines += _parser_section(subparser, f"elastoactive {name}", summaries.get(name, ""))
    return "\n".join(lines) + "\n"


def _mathjax_root() -> Path:
    import mathjax

    return Path(mathjax.__file__).parent / "static" / "mathjax" / "es5"


def on_files(files: Files, config) -> Files:
    """Add the generated CLI page and MathJax's files to the site."""
    files.append(File.generated(config, CLI_PAGE, content=cli_reference()))
    root = _mathjax_root()
    for name in MATHJAX_FILES:
        source = root / name
        for path in [source] if source.is_file() else sorted(p for p in source.rglob("*") if p.is_file()):
            rel = path.relative_to(root).as_posix()
            files.append(File.generated(config, f"assets/mathjax/{rel}", abs_src_path=str(path)))
    return files


def plain_brackets(html: str) -> str:
    """The page's HTML with every would-be cross-reference whose target is no identifier put back as its text."""

    def restore(match: re.Match) -> str:
        if _IDENTIFIER.fullmatch(match.group("identifier")):
            return match.group(0)
        return f"[{match.group('title')}] [{match.group('identifier')}]"

    return _AUTOREF.sub(restore, html)


def on_page_content(html: str, page, config, files) -> str:
    """Brackets in plain text stay text (plain_brackets)."""
    return plain_brackets(html)


def on_page_markdown(markdown: str, page, config, files) -> str:
    """The home page's text is the README's."""
    if page.file.src_uri == HOME:
        return readme_for_site((ROOT / "README.md").read_text())
    return markdown
