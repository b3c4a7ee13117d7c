"""Import directions between and inside the packages (a layer never imports those built on it, nor another
package's internals), read from the sources with `ast`, so nothing is imported and imports inside functions
count as much as those at the top."""

import ast
from pathlib import Path

import pytest
from checkout import ROOT

UTILS = "mobilemani_rl.utils"
ASSETS = "mobilemani_rl.assets"
RENDER = "mobilemani_rl.render"
ENVS = "mobilemani_rl.envs"
SCRIPTED = "mobilemani_rl.scripted"
SIMULATOR = (UTILS, ASSETS, RENDER, ENVS, SCRIPTED)
# PPO's one module for the other packages: finding, loading and running trained teachers
TEACHER = "mobilemani_rl.rl.teacher"
# the dataset's modules for the VLA: feature names, the frame builder, the exported metadata's readers
DATASET = ("mobilemani_data.schema", "mobilemani_data.frame", "mobilemani_data.metadata")
VLA_CONFIG, VLA_MODEL = "mobilemani_vla.config", "mobilemani_vla.model"

# (package, subpackage or module whose files are checked, the project's modules they may import besides their
# own); a rule for a package covers its subpackages, which may have rules of their own
LAYERS = [
    ("mobilemani_rl", ()),  # neither the dataset nor the VLA
    (UTILS, ()),
    (ASSETS, (UTILS,)),
    (f"{ASSETS}.robots", (UTILS, f"{ASSETS}.collision")),
    (f"{ASSETS}.objects", (UTILS, f"{ASSETS}.collision", f"{ASSETS}.stage", f"{ASSETS}.robots")),
    (f"{ASSETS}.scenes", (UTILS, f"{ASSETS}.objects", f"{ASSETS}.stage")),
    (RENDER, (UTILS, ASSETS)),
    (ENVS, (UTILS, ASSETS, RENDER)),
    (SCRIPTED, (UTILS, ASSETS, ENVS)),
    ("mobilemani_rl.rl", (UTILS, ASSETS, ENVS, SCRIPTED)),
    ("mobilemani_data", (*SIMULATOR, TEACHER)),
    ("mobilemani_vla", (*SIMULATOR, TEACHER, *DATASET)),
    (
        VLA_CONFIG,
        (
            UTILS,
            "mobilemani_data.schema",
            f"{ENVS}.config",
            f"{VLA_MODEL}.dit",
            "mobilemani_vla.data.augment",
        ),
    ),
    (VLA_MODEL, (UTILS, "mobilemani_data.schema", VLA_CONFIG)),
    ("mobilemani_vla.data", (UTILS, *DATASET, VLA_CONFIG, VLA_MODEL)),
    ("mobilemani_vla.checkpoint", (UTILS, VLA_CONFIG, VLA_MODEL)),
    (
        "mobilemani_vla.inference",
        (UTILS, "mobilemani_data.schema", VLA_CONFIG, VLA_MODEL, "mobilemani_vla.checkpoint"),
    ),
    (
        "mobilemani_vla.eval",
        (
            *SIMULATOR,
            TEACHER,
            *DATASET,
            VLA_CONFIG,
            VLA_MODEL,
            "mobilemani_vla.checkpoint",
            "mobilemani_vla.inference",
        ),
    ),
]


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def from_module(node: ast.ImportFrom, module: str, is_package: bool) -> str:
    """The module a `from ... import` reads from; a relative one resolved against the importing module's
    package."""
    base = node.module or ""
    if node.level:
        package = module.split(".")[: len(module.split(".")) - node.level + is_package]
        base = ".".join(package + ([base] if base else []))
    return base


def imported_modules(source: str, module: str, is_package: bool) -> list[tuple[int, str]]:
    """(line, module) for every import anywhere in the source; `from a import b` yields both a and a.b, since
    b may be a submodule."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = from_module(node, module, is_package)
            found.append((node.lineno, base))
            found += [(node.lineno, f"{base}.{alias.name}") for alias in node.names]
    return found


def within(name: str, prefixes: tuple[str, ...]) -> bool:
    return any(name == p or name.startswith(p + ".") for p in prefixes)


def is_module(name: str) -> bool:
    base = ROOT / Path(*name.split("."))
    return base.with_suffix(".py").is_file() or (base / "__init__.py").is_file()


def bad_imports(source: str, module: str, is_package: bool, package: str, allowed: tuple[str, ...]):
    """(line, module) of each of the project's modules the source imports that is neither `package`'s own nor
    `allowed`: `from a import b` names a.b when that is a module, else a."""
    bad = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = from_module(node, module, is_package)
            names = [f"{base}.{a.name}" if is_module(f"{base}.{a.name}") else base for a in node.names]
        else:
            continue
        bad += [
            (node.lineno, name)
            for name in names
            if name.split(".")[0] in ("mobilemani_rl", "mobilemani_data", "mobilemani_vla")
            and not within(name, (package, *allowed))
        ]
    return bad


def violations(package: str, allowed: tuple[str, ...]) -> list[str]:
    folder = ROOT / Path(*package.split("."))
    files = sorted(folder.rglob("*.py")) if folder.is_dir() else [folder.with_suffix(".py")]
    assert files and files[0].is_file(), f"no sources found for {package}"
    return sorted(
        f"{path.relative_to(ROOT)}:{line} imports {name}"
        for path in files
        for line, name in bad_imports(
            path.read_text(), module_name(path), path.name == "__init__.py", package, allowed
        )
    )


@pytest.mark.parametrize(("package", "allowed"), LAYERS, ids=[rule[0] for rule in LAYERS])
def test_imports_point_down_the_layers(package, allowed):
    assert violations(package, allowed) == []


def test_every_package_and_its_rooms_have_a_rule():
    """The three packages and each room inside them; folders deeper down (objects/generators,
    eval/policies) follow their room's rule."""
    packages = {
        module_name(init)
        for top in ("mobilemani_rl", "mobilemani_data", "mobilemani_vla")
        for init in (ROOT / top).rglob("__init__.py")
    }
    assert {p for p in packages if p.count(".") <= 1} <= {package for package, _ in LAYERS}


def test_the_check_sees_in_function_relative_and_from_package_imports():
    source = (
        "def f():\n    from ..envs import scene\n\n"
        "from mobilemani_rl import train\nimport mobilemani_vla.model\n"
    )
    names = {name for _, name in imported_modules(source, "mobilemani_rl.assets.stage", False)}
    assert {"mobilemani_rl.envs.scene", "mobilemani_rl.train", "mobilemani_vla.model"} <= names


def test_a_rule_names_what_it_does_not_allow():
    render = dict(LAYERS)[RENDER]
    source = "from mobilemani_rl.envs.scene import SceneIndex\nfrom mobilemani_rl.assets import stage\n"
    assert bad_imports(source, f"{RENDER}.segmentation", False, RENDER, render) == [
        (1, "mobilemani_rl.envs.scene")
    ]
    model = dict(LAYERS)[VLA_MODEL]
    source = "from mobilemani_data import schema\nfrom mobilemani_data import shards\n"
    assert bad_imports(source, f"{VLA_MODEL}.processor", False, VLA_MODEL, model) == [
        (2, "mobilemani_data.shards")
    ]
