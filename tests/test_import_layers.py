"""Import directions between and inside the packages (a layer never imports those built on it), read from the
sources with `ast`, so nothing is imported and imports inside functions count as much as those at the top."""

import ast
from pathlib import Path

import pytest
from checkout import ROOT

# (package or subpackage whose files are checked, module prefixes none of them may import)
RULES = [
    ("mobilemani_rl", ("mobilemani_data", "mobilemani_vla")),
    # PPO's public module for other packages is mobilemani_rl.rl.teacher (finding and loading teachers)
    (
        "mobilemani_data",
        (
            "mobilemani_vla",
            *(f"mobilemani_rl.rl.{m}" for m in ("train", "eval", "runner", "factory", "run_dir")),
        ),
    ),
    ("mobilemani_rl.assets", ("mobilemani_rl.envs", "mobilemani_rl.render")),
    ("mobilemani_rl.render", ("mobilemani_rl.envs",)),
]


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(source: str, module: str, is_package: bool) -> list[tuple[int, str]]:
    """(line, module) for every import anywhere in the source; `from a import b` yields both a and a.b, since
    b may be a submodule."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:  # relative: resolved against the importing module's package
                package = module.split(".")[: len(module.split(".")) - node.level + is_package]
                base = ".".join(package + ([base] if base else []))
            found.append((node.lineno, base))
            found += [(node.lineno, f"{base}.{alias.name}") for alias in node.names]
    return found


def violations(package: str, forbidden: tuple[str, ...]) -> list[str]:
    files = sorted((ROOT / Path(*package.split("."))).rglob("*.py"))
    assert files, f"no sources found for {package}"
    bad = []
    for path in files:
        module = module_name(path)
        for line, name in imported_modules(path.read_text(), module, path.name == "__init__.py"):
            if any(name == f or name.startswith(f + ".") for f in forbidden):
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {name}")
    return sorted(set(bad))


@pytest.mark.parametrize(("package", "forbidden"), RULES, ids=[rule[0] for rule in RULES])
def test_imports_point_down_the_layers(package, forbidden):
    assert violations(package, forbidden) == []


def test_the_check_sees_in_function_relative_and_from_package_imports():
    source = (
        "def f():\n    from ..envs import scene\n\n"
        "from mobilemani_rl import train\nimport mobilemani_vla.model.network\n"
    )
    names = {name for _, name in imported_modules(source, "mobilemani_rl.assets.stage", False)}
    assert {"mobilemani_rl.envs.scene", "mobilemani_rl.train", "mobilemani_vla.model.network"} <= names
