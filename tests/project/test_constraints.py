"""The test environment is reproducible: scripts/constraints.txt pins every package the install brings (elastoactive,
its test and docs extras, and theirs, transitively) to one version, the set-up scripts install under it, and a change
of it re-installs (it is part of their stamps)."""

import re
from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[2]
CONSTRAINTS = ROOT / "scripts" / "constraints.txt"
EXTRAS = ("test", "docs")
"""The extras the set-up installs: scripts/setup.sh the test extra, scripts/docs_setup.sh the docs extra."""


def pins() -> dict[str, str]:
    pinned = {}
    for line in CONSTRAINTS.read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        match = re.fullmatch(r"([A-Za-z0-9][A-Za-z0-9._-]*)==([^\s;]+)", line.strip())
        assert match, f"scripts/constraints.txt: {line!r} is not NAME==VERSION"
        name = canonicalize_name(match.group(1))
        assert name not in pinned, f"scripts/constraints.txt pins {name} twice"
        pinned[name] = match.group(2)
    return pinned


def installed_requirements() -> dict[str, str]:
    """Every distribution the install of elastoactive[test,docs] brings that is installed here, with its version: its
    requirements (their markers evaluated here), then theirs."""
    found: dict[str, str] = {}
    queue = [(canonicalize_name("elastoactive"), EXTRAS)]
    seen = set()
    while queue:
        name, extras = queue.pop()
        if (name, extras) in seen:
            continue
        seen.add((name, extras))
        try:
            dist = distribution(name)
        except PackageNotFoundError:
            continue  # an extra not installed here (the docs extra before scripts/docs_setup.sh)
        if name != "elastoactive":
            found[name] = dist.version
        for text in dist.requires or []:
            requirement = Requirement(text)
            environments = [{"extra": extra} for extra in extras] or [{"extra": ""}]
            if requirement.marker and not any(requirement.marker.evaluate(env) for env in environments):
                continue
            queue.append((canonicalize_name(requirement.name), tuple(sorted(requirement.extras))))
    return found


def test_every_package_installed_is_pinned_at_its_version():
    pinned = pins()
    needed = installed_requirements()
    assert {"numpy", "scipy", "mujoco", "pytest"} <= set(needed)
    missing = sorted(name for name in needed if name not in pinned)
    assert not missing, f"not pinned in scripts/constraints.txt: {', '.join(missing)}"
    other = {name: (pinned[name], version) for name, version in needed.items() if pinned[name] != version}
    assert not other, f"installed at other versions than scripts/constraints.txt pins (pinned, installed): {other}"
    assert "pip" in pinned and "elastoactive" not in pinned


def _stamp(script: str) -> str:
    return next(line for line in script.splitlines() if line.startswith("stamp="))


def test_the_set_up_installs_under_the_constraints_and_reinstalls_when_they_change():
    for name in ("setup.sh", "docs_setup.sh"):
        script = (ROOT / "scripts" / name).read_text()
        assert "constraints=scripts/constraints.txt" in script, name
        installs = [line for line in script.splitlines() if "pip install" in line and not line.lstrip().startswith("#")]
        assert installs and all('-c "$constraints"' in line for line in installs), (name, installs)
        assert '"$constraints"' in _stamp(script), (name, _stamp(script))
    setup = (ROOT / "scripts" / "setup.sh").read_text()
    assert '--build-constraint "$constraints"' in setup  # the MuJoCo headers the callback is built against
