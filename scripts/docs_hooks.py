"""MkDocs hooks (mkdocs.yml): what the site builds from sources other than docs/*.md, at every build.

- ``index.md`` is the repository's README.md, its links made relative to docs/ (one front page for both).
- ``cli.md`` is written from the argparse parser (``elastoactive.cli.build_parser``): every subcommand, its usage,
  its options with their defaults and help, as ``elastoactive COMMAND --help`` prints them.
- ``api/parameters.md`` is written from the parameter table (``elastoactive.core.parameters``, grouped and ordered as
  ``help(ea.Physics)`` lists it: ``elastoactive.core.physics_doc``): every parameter of ``ea.Physics`` with its kind,
  default, units, range and the scenes that take it, and every setting of ``ea.Numerics`` with its default value.
- The generated pages are committed too (``docs/cli.md``, ``docs/api/parameters.md``), so that links to them work
  where the Markdown is read as it is; the site always uses the text generated at its build, and a test
  (tests/docs/test_docs_pages.py) checks that the committed copies are up to date. Rewrite them with
  ``bash scripts/docs.sh generate`` (``python scripts/docs_hooks.py``; ``--check`` only compares).
- ``NumericsDefaults``, a Griffe extension (mkdocs.yml's mkdocstrings options), shows ``ea.Numerics``' defaults as
  their values (``dt = 0.0025``) rather than the names of the constants that hold them.
- A pair of brackets in a docstring's plain text (``[I; M] [A, B]``, a matrix) reads to Markdown as a reference link;
  one whose target is no identifier (a cross-reference names a Python object or a heading: no spaces, no commas) is
  put back as the text it was, so that only a real cross-reference can fail the build.
- MathJax (the docs extra's ``django-static-mathjax`` package) is copied into ``assets/mathjax/``, so the built site
  typesets its maths without any network.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
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

PARAMETERS_PAGE = "api/parameters.md"
"""The reference of every Physics parameter and Numerics setting, written from the parameter table."""

USAGE_COLUMNS = 100
"""The width the command-line page's usage lines are wrapped to (argparse reads COLUMNS: the page must not depend on
the terminal it was written from)."""

MATHJAX_FILES = ("tex-svg.js",)
"""What the site needs of MathJax's es5 build: TeX to SVG in one file (glyphs as paths: no fonts to load)."""

_AUTOREF = re.compile(
    r'<autoref (?P<attrs>[^>]*?)identifier="(?P<identifier>[^"]*)"(?P<rest>[^>]*)>(?P<title>.*?)</autoref>', re.S
)
_IDENTIFIER = re.compile(r"[A-Za-z_][\w.:-]*")

_README_LINK = re.compile(r"(\]\(|src=\")(?!https?:|#|mailto:)([^)\"\s]+)")


_REPO_LINK = re.compile(r"\[([^\]]*)\]\((?!https?:|#|mailto:|docs/)([^)\s]+)\)")


SITE_PAGES = {"CITATION.cff": "citing.md"}
"""Files of the repository outside docs/ that a page of the site presents: a README link to one links to its page."""


def readme_for_site(text: str) -> str:
    """The README with its links made relative to docs/: ``docs/x`` becomes ``x``. A link to another file of the
    repository has no page in the site: it becomes a link to the page presenting it (SITE_PAGES: CITATION.cff, the
    page on citing), or else its text and the file's name (LICENSE); a link to a file that does not exist is refused,
    as the build refuses a broken link into docs/."""

    def repo_file(match: re.Match) -> str:
        target = match.group(2)
        if not (ROOT / target.split("#")[0]).exists():
            raise ValueError(f"README.md links to {target!r}, which is not a file of the repository")
        if target in SITE_PAGES:
            return f"[{match.group(1)}]({SITE_PAGES[target]})"
        return match.group(1) if match.group(1) == target else f"{match.group(1)} (`{target}`)"

    text = _REPO_LINK.sub(repo_file, text)
    return _README_LINK.sub(lambda m: m.group(1) + m.group(2).removeprefix("docs/"), text)


def _escape(text: str) -> str:
    """Plain text in Markdown: the characters that would start emphasis or a link escaped, those that would start
    HTML as entities (Python-Markdown does not take a backslash before them)."""
    text = re.sub(r"([\\`*_\[\]])", r"\\\1", text)
    return text.replace("<", "&lt;").replace(">", "&gt;")


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


def _package() -> None:
    """The checkout's package first on sys.path (the site documents this tree, whatever else is installed)."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))


def cli_reference() -> str:
    """The command-line reference as Markdown, from the parser ``elastoactive`` builds."""
    _package()
    from elastoactive.cli import build_parser

    columns = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(USAGE_COLUMNS)
    try:
        return _cli_page(build_parser())
    finally:
        if columns is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = columns


def _cli_page(parser: argparse.ArgumentParser) -> str:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    summaries = {choice.dest: choice.help or "" for choice in sub._choices_actions}
    lines = [
        "# Command-line reference",
        "",
        "Written from the parser (`scripts/docs_hooks.py`), so it is what `elastoactive COMMAND --help` prints for "
        "this version. Every subcommand's bad input stops with one line, `elastoactive: error: ...`, naming the "
        "option ([what the refusals mean](faq.md#a-setting-is-refused)).",
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


def _value(value) -> str:
    """A default as Python writes it (a float subclass or a str subclass as the plain value)."""
    for kind in (bool, int, float, str):
        if isinstance(value, kind):
            return repr(kind(value))
    return repr(value)


def _range(spec) -> str:
    """What values a parameter takes, in words a table cell holds."""
    if spec.kind is bool:
        return "true or false"
    if spec.choices:
        return ", ".join(f"`{c}`" for c in spec.choices)
    if spec.kind is str:
        return "text (see its meaning)"
    text = spec.range_text()
    return f"integer, {text}" if spec.kind is int else text


def _units(spec, systems) -> str:
    """A parameter's units in the unit systems of the scenes that take it (`1`: dimensionless)."""
    shown = {system.name: spec.units_in(system) for system in systems}
    if len(set(shown.values())) == 1:
        return f"`{next(iter(shown.values()))}`"
    return "; ".join(f"{name}: `{units}`" for name, units in shown.items())


def _scenes(taking: list[str], every: list[str], kinds: dict[str, list[str]]) -> str:
    """The scenes that take a parameter: all of them, all of one unit system's, or their names."""
    if taking == every:
        return "every scene"
    for kind, names in kinds.items():
        if taking == names:
            return f"every {kind} scene"
    return ", ".join(f"`{name}`" for name in taking) or "none registered"


def _meaning(spec, systems) -> str:
    helps = {system.name: spec.help_in(system) for system in systems}
    if len(set(helps.values())) == 1:
        text = _escape(next(iter(helps.values())))
    else:
        text = "; ".join(f"{name}: {_escape(help_text)}" for name, help_text in helps.items())
    if spec.needs:
        text += f" (acts with {_escape(spec.need_text)})"
    return _cell(text)


def parameters_reference() -> str:
    """Every parameter of ``ea.Physics`` and every setting of ``ea.Numerics`` as Markdown tables, from the parameter
    table: grouped and ordered as ``help(ea.Physics)`` lists them (``elastoactive.core.physics_doc``), each with its
    kind, default, units, range, the scenes that take it and its help."""
    _package()
    from elastoactive.core import registry
    from elastoactive.core.params import DEFAULT_SCENE, PRESETS, Numerics, parameter_fields, scene_parameters
    from elastoactive.core.physics_doc import _owners
    from elastoactive.core.units import SYSTEMS, scene_units

    owners = _owners()  # the registries' scenes and terms join the table first
    scenes = registry.scenes()
    every = [scene.name for scene in scenes]
    taken = {scene.name: set(scene_parameters(scene)) for scene in scenes}
    units = {scene.name: scene_units(scene) for scene in scenes}
    lines = [
        "# Parameters and numerical settings",
        "",
        "Every parameter `ea.Physics` takes and every setting of `ea.Numerics`, written from the parameter table "
        "(`elastoactive.core.parameters`, by `scripts/docs_hooks.py`): what `help(ea.Physics)` lists, with the "
        "range each value is checked against and the scenes that take it. On the command line each is an option "
        "of the same name, `-` for `_` (`--drag-ratio`; [the command line](../cli.md)). A value outside its "
        "range, or given to a scene without it, or while its switch is off, is refused in one line naming it "
        "([what the refusals mean](../faq.md#a-setting-is-refused)).",
        "",
        f"`scene` (default `{DEFAULT_SCENE!r}`) is one of the registered scenes ([Scenes](scenes.md)). Each speaks "
        "its own units; a unit `1` is dimensionless:",
        "",
    ]
    for system in SYSTEMS:
        users = ", ".join(f"`{name}`" for name in every if units[name] == system)
        lines.append(f"- {system.name} scenes ({users}): {_escape(system.text.removeprefix('Units: '))}")
    lines.append("")
    kinds = {system.name: [name for name in every if units[name] == system] for system in SYSTEMS}
    for owner, specs in owners:
        lines += [f"## Declared by {owner}", "", "| parameter | kind | default | units | range | scenes | meaning |"]
        lines.append("|---|---|---|---|---|---|---|")
        for spec in specs:
            taking = [name for name in every if spec.name in taken[name]]
            systems = list(dict.fromkeys(units[name] for name in taking)) or [SYSTEMS[0]]
            default = f"none: given instead of `{spec.instead_of}`" if spec.instead_of else f"`{_value(spec.default)}`"
            cells = [
                f"`{spec.name}`",
                spec.kind.__name__,
                default,
                _units(spec, systems),
                _range(spec),
                _scenes(taking, every, kinds),
                _meaning(spec, systems),
            ]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    lines += [
        "## Numerics",
        "",
        "The numerical settings of a run, `ea.Numerics(...)` (`elastoactive.core.params.Numerics`); times in tau. "
        "A setting left at its default may be chosen for the run (long chains, `sample_dt` of long runs: "
        "[the Numerics record](index.md#elastoactive.Numerics)).",
        "",
        "| setting | kind | default | choices | meaning |",
        "|---|---|---|---|---|",
    ]
    for field in parameter_fields(Numerics):
        choices = field.metadata.get("choices")
        kind = field.type if isinstance(field.type, str) else field.type.__name__
        shown = ", ".join(f"`{c}`" for c in choices) if choices else ""
        help_text = _cell(_escape(field.metadata.get("help", "")))
        lines.append(f"| `{field.name}` | {kind} | `{_value(field.default)}` | {shown} | {help_text} |")
    lines += ["", "Presets (`ea.Numerics.preset(name)`, `--preset`):", "", "| preset | settings |", "|---|---|"]
    for name, settings in PRESETS.items():
        lines.append(f"| `{name}` | " + ", ".join(f"`{k} = {_value(v)}`" for k, v in settings.items()) + " |")
    return "\n".join(lines) + "\n"


GENERATED = {CLI_PAGE: cli_reference, PARAMETERS_PAGE: parameters_reference}
"""The pages written from the code: docs/<page> committed, and written again at every build."""


def _mathjax_root() -> Path:
    import mathjax

    return Path(mathjax.__file__).parent / "static" / "mathjax" / "es5"


def on_files(files: Files, config) -> Files:
    """Add the generated pages (in place of their committed copies) and MathJax's files to the site."""
    for page, write in GENERATED.items():
        committed = files.get_file_from_path(page)
        if committed is not None:
            files.remove(committed)
        files.append(File.generated(config, page, content=write()))
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


try:  # the Griffe extension, when mkdocstrings (which brings Griffe) is installed
    import griffe
except ImportError:  # pragma: no cover - the docs extra is not installed: only the page writers are usable
    griffe = None

if griffe is not None:

    class NumericsDefaults(griffe.Extension):
        """Griffe extension: the records' defaults show as their values where the source names the constants that
        hold them: ``ea.Numerics``' fields (``dt: float = 0.0025``, not ``field(default=DEFAULT_DT)``) and
        ``ea.Physics``' scene (``scene: str = 'one-pinned'``, not ``DEFAULT_SCENE``), read from the classes."""

        NUMERICS = "elastoactive.core.params.Numerics"
        PHYSICS = "elastoactive.core.params.Physics"

        def on_class_members(self, *, cls, **kwargs) -> None:
            if cls.path not in (self.NUMERICS, self.PHYSICS):
                return
            _package()
            from elastoactive.core import params

            if cls.path == self.PHYSICS:
                init = cls.members.get("__init__")
                if init is not None and "scene" in init.parameters:
                    init.parameters["scene"].default = _value(params.DEFAULT_SCENE)
                return
            defaults = {f.name: _value(f.default) for f in dataclasses.fields(params.Numerics)}
            for name, member in cls.members.items():
                value = getattr(member, "value", None)
                if name not in defaults or not isinstance(value, griffe.ExprCall):
                    continue
                for argument in value.arguments:
                    if isinstance(argument, griffe.ExprKeyword) and argument.name == "default":
                        argument.value = defaults[name]


def write_pages(check: bool = False) -> list[str]:
    """Write the generated pages into docs/ (or, with `check`, only compare): the pages that were out of date."""
    stale = []
    for page, write in GENERATED.items():
        path = ROOT / "docs" / page
        text = write()
        if not path.is_file() or path.read_text() != text:
            stale.append(page)
            if not check:
                path.write_text(text)
    return stale


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Write the generated pages of the site into docs/ (" + ", ".join(GENERATED) + ")."
    )
    parser.add_argument("--check", action="store_true", help="only say which are out of date (exit status 1)")
    args = parser.parse_args(argv)
    stale = write_pages(check=args.check)
    for page in stale:
        print(f"docs/{page} {'is out of date' if args.check else 'written'}")
    return 1 if args.check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
