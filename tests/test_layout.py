"""Architecture rules, checked on the source tree with :mod:`ast` (nothing is imported).

* ``chaoskit`` never imports ``mechanism``;
* no import cycle among the modules of one package (module-level imports, ``TYPE_CHECKING``
  blocks excluded, package ``__init__`` files included);
* no import inside a function, except the lazy imports of heavy optional libraries listed in
  ``LAZY_IMPORTS`` (an import moved into a function to dodge a cycle fails here);
* no private module of another package (``mechanism`` importing ``chaoskit._x``);
* ``mechanism.core`` never imports ``mechanism.studies`` (nor the ``mechanism`` package or its
  CLI), and studies use only the core's public modules (no ``mechanism.core..._x``).

The checks are plain functions run on the real tree and, in ``test_checks_catch_*``, on small
synthetic trees that break each rule, so a check that stopped finding anything fails too.
"""

from __future__ import annotations

import ast
import importlib
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.conftest import REPO

PACKAGES = ("chaoskit", "mechanism")

#: Third-party libraries a function may import lazily, and why.
LAZY_IMPORTS = {
    "matplotlib": "plotting is optional; numerics never import it (house style)",
    "jinja2": "only report rendering needs the templates",
    "distributed": "dask is the optional parallel backend of sweeps",
    "dask": "the scheduler is configured only where a write may run inside a dask worker",
    "tqdm": "progress bars are opt-in",
    "nolds": "only sample entropy, DFA and the Hurst exponent call it; its import is slow",
    "scipy": "scipy.stats/integrate/interpolate load only on the paths that use them",
}


@dataclass(frozen=True)
class Import:
    """One import statement, resolved to absolute module names."""

    module: str  # the importing module
    path: Path
    line: int
    targets: tuple[str, ...]  # absolute names, most specific first (see _targets)
    local: bool  # inside a function body
    type_only: bool  # inside ``if TYPE_CHECKING:``


def module_name(root: Path, path: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def source_files(root: Path, packages: tuple[str, ...] = PACKAGES) -> dict[str, Path]:
    return {
        module_name(root, p): p
        for pkg in packages
        for p in sorted((root / pkg).rglob("*.py"))
        if "__pycache__" not in p.parts
    }


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _walk(node: ast.AST, *, local: bool, type_only: bool):  # type: ignore[no-untyped-def]
    for child in ast.iter_child_nodes(node):
        if isinstance(child, (ast.Import, ast.ImportFrom)):
            yield child, local, type_only
        elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            yield from _walk(child, local=True, type_only=type_only)
        elif isinstance(child, ast.If) and _is_type_checking(child):
            yield from _walk(child, local=local, type_only=True)
        else:
            yield from _walk(child, local=local, type_only=type_only)


def _targets(node: ast.Import | ast.ImportFrom, module: str, is_pkg: bool, known: set[str]):  # type: ignore[no-untyped-def]
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if node.level:
        base = module.split(".") if is_pkg else module.split(".")[:-1]
        base = base[: len(base) - (node.level - 1)]
        stem = ".".join(base + ([node.module] if node.module else []))
    else:
        stem = node.module or ""
    # ``from pkg import name`` imports the module pkg.name when there is one, else pkg itself
    out = [f"{stem}.{a.name}" for a in node.names if f"{stem}.{a.name}" in known]
    return out if len(out) == len(node.names) else [*out, stem]


def imports(root: Path, packages: tuple[str, ...] = PACKAGES) -> list[Import]:
    files = source_files(root, packages)
    known = set(files)
    out = []
    for module, path in files.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        is_pkg = path.name == "__init__.py"
        for node, local, type_only in _walk(tree, local=False, type_only=False):
            targets = _targets(node, module, is_pkg, known)
            out.append(Import(module, path, node.lineno, tuple(targets), local, type_only))
    return out


def _ancestors(module: str) -> set[str]:
    parts = module.split(".")
    return {".".join(parts[:k]) for k in range(1, len(parts))}


def import_graph(found: list[Import], known: set[str]) -> dict[str, set[str]]:
    """Module → first-party modules its module-level imports name, type-only ones included.

    Importing ``a.b.c`` runs the ``__init__`` of ``a.b`` too, unless that package is one of
    the importer's own ancestors (already being initialised); the named module itself is
    always an edge, so ``from chaoskit import analyze`` inside chaoskit is a cycle. An
    import under ``if TYPE_CHECKING:`` is an edge as well: two modules that need each
    other's types belong to one concern, or the type belongs below both.
    """
    graph: dict[str, set[str]] = {m: set() for m in known}
    for imp in found:
        if imp.local:
            continue
        own = _ancestors(imp.module)
        for target in imp.targets:
            if target in known and target != imp.module:
                graph[imp.module].add(target)
            for prefix in _ancestors(target):
                if prefix in known and prefix not in own and prefix != imp.module:
                    graph[imp.module].add(prefix)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def _first_party(name: str) -> bool:
    return name.split(".")[0] in PACKAGES


def _private(name: str) -> bool:
    return any(part.startswith("_") and not part.startswith("__") for part in name.split("."))


def _where(imp: Import, root: Path) -> str:
    return f"{imp.path.relative_to(root)}:{imp.line}"


def cycle_problems(root: Path) -> list[str]:
    found = imports(root)
    known = set(source_files(root))
    return [
        "import cycle: " + " <-> ".join(component)
        for component in cycles(import_graph(found, known))
    ]


def _pairs(root: Path):  # type: ignore[no-untyped-def]
    """(import, one of its targets, "file:line") for every import of the tree."""
    for imp in imports(root):
        for target in imp.targets:
            yield imp, target, _where(imp, root)


def _top(name: str) -> str:
    return name.split(".")[0]


def local_import_problems(root: Path) -> list[str]:
    return [
        f"{where}: {target!r} is imported inside a function; import it at module level (or "
        "add a heavy optional library to LAZY_IMPORTS)"
        for imp, target, where in _pairs(root)
        if imp.local and _top(target) not in LAZY_IMPORTS
    ]


def _private_owner(target: str) -> str | None:
    """The folder (package) that owns the first private part of ``target``, if any."""
    parts = target.split(".")
    for i, part in enumerate(parts):
        if part.startswith("_") and not part.startswith("__"):
            return ".".join(parts[:i])
    return None


def private_import_problems(root: Path) -> list[str]:
    """A ``_module`` is imported only from its own folder or below it."""
    problems = []
    for imp, target, where in _pairs(root):
        owner = _private_owner(target) if _first_party(target) else None
        if owner is None:
            continue
        package = imp.module if imp.path.name == "__init__.py" else imp.module.rpartition(".")[0]
        if package != owner and not package.startswith(owner + "."):
            problems.append(
                f"{where}: {imp.module} imports {target!r}, private to {owner}; import "
                f"what {owner} exports instead"
            )
    return problems


def _module_aliases(tree: ast.Module, module: str, is_pkg: bool) -> dict[str, str]:
    """Names bound to first-party modules by the imports of a file."""
    aliases = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if _first_party(a.name):
                    aliases[a.asname or a.name.split(".")[0]] = a.name
        elif isinstance(node, ast.ImportFrom):
            stem = _stem(node, module, is_pkg)
            if _first_party(stem):
                for a in node.names:
                    aliases[a.asname or a.name] = f"{stem}.{a.name}"
    return aliases


def _stem(node: ast.ImportFrom, module: str, is_pkg: bool) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".") if is_pkg else module.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def private_name_problems(root: Path, packages: tuple[str, ...] = PACKAGES) -> list[str]:
    """An ``_name`` (function, class, constant) never crosses files: neither imported
    (``from .m import _f``) nor reached through a module (``m._f``)."""
    files = source_files(root, packages)
    known = set(files)
    problems = []
    for module, path in files.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        is_pkg = path.name == "__init__.py"
        where = path.relative_to(root)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                stem = _stem(node, module, is_pkg)
                for a in node.names:
                    name = f"{stem}.{a.name}"
                    if _first_party(stem) and _private(a.name) and name not in known:
                        problems.append(f"{where}:{node.lineno}: imports the private {name!r}")
        aliases = _module_aliases(tree, module, is_pkg)
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in aliases
                and aliases[node.value.id] in known
                and _private(node.attr)
            ):
                problems.append(
                    f"{where}:{node.lineno}: reaches the private "
                    f"{aliases[node.value.id] + '.' + node.attr!r}"
                )
    return problems


def _layer_problem(module: str, target: str) -> str | None:
    if _top(module) == "chaoskit" and _top(target) == "mechanism":
        return f"chaoskit imports {target!r}"
    upward = target in ("mechanism", "mechanism.cli") or target.startswith(
        ("mechanism.studies", "mechanism.cli.")
    )
    if module.startswith("mechanism.core") and upward:
        return (
            f"the core module {module} imports {target!r}; the core never imports upward "
            "(studies, the package, the CLI)"
        )
    if module.startswith("mechanism.studies") and target.startswith("mechanism.core"):
        if _private(target):
            return (
                f"the study {module} imports the core's private {target!r}; studies use "
                "mechanism.core's public names"
            )
    return None


def layer_problems(root: Path) -> list[str]:
    return [
        f"{where}: {problem}"
        for imp, target, where in _pairs(root)
        if (problem := _layer_problem(imp.module, target)) is not None
    ]


#: Lines above which a module (other than a numba kernel module) is split by concern.
MAX_MODULE_LINES = 800
#: Parameters (``self`` included) above which a public function wants an options object.
MAX_PARAMETERS = 12


def long_module_problems(root: Path, packages: tuple[str, ...] = PACKAGES) -> list[str]:
    """Modules over ``MAX_MODULE_LINES`` lines; the numba kernel modules (``*_kernels.py``)
    are exempt (a compiled loop is one long function by design)."""
    problems = []
    for path in source_files(root, packages).values():
        if path.name.endswith("_kernels.py"):
            continue
        lines = len(path.read_text(encoding="utf-8").splitlines())
        if lines > MAX_MODULE_LINES:
            problems.append(
                f"{path.relative_to(root)}: {lines} lines, more than {MAX_MODULE_LINES}; split "
                "it into modules of one concern each"
            )
    return problems


def _all_names(tree: ast.Module) -> set[str]:
    """The names of a module's ``__all__`` (``=`` or ``+=``, through the per-topic lists it
    is assembled from)."""
    lists = {
        node.targets[0].id: node.value
        for node in tree.body
        if isinstance(node, ast.Assign)
        and len(node.targets) == 1
        and isinstance(node.targets[0], ast.Name)
    }
    values = [lists["__all__"]] if "__all__" in lists else []
    values += [
        node.value
        for node in tree.body
        if isinstance(node, ast.AugAssign)
        and isinstance(node.target, ast.Name)
        and node.target.id == "__all__"
    ]
    names: set[str] = set()
    while values:
        for node in ast.walk(values.pop()):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                names.add(node.value)
            elif isinstance(node, ast.Name) and node.id in lists and node.id != "__all__":
                values.append(lists.pop(node.id))
    return names


def _parameters(func: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    a = func.args
    return (
        len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs)
        + (a.vararg is not None) + (a.kwarg is not None)
    )  # fmt: skip


def _is_command(func: ast.FunctionDef) -> bool:
    """A command-line command (``@app.command(...)``): one parameter per option, by design."""
    return any(
        isinstance(d, ast.Call) and isinstance(d.func, ast.Attribute) and d.func.attr == "command"
        for d in func.decorator_list
    )


def long_signature_problems(root: Path, packages: tuple[str, ...] = PACKAGES) -> list[str]:
    """Public functions and public methods of public classes (a name of some ``__all__``)
    with more than ``MAX_PARAMETERS`` parameters; command-line commands are left out."""
    trees = {
        path: ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for path in source_files(root, packages).values()
    }
    public = set().union(*(_all_names(tree) for tree in trees.values()))
    problems = []
    for path, tree in trees.items():
        for node in tree.body:
            if not isinstance(node, ast.FunctionDef | ast.ClassDef) or node.name not in public:
                continue
            if isinstance(node, ast.FunctionDef) and _is_command(node):
                continue
            funcs = [node] if isinstance(node, ast.FunctionDef) else [
                f for f in node.body
                if isinstance(f, ast.FunctionDef) and not f.name.startswith("_")
            ]  # fmt: skip
            for func in funcs:
                if (count := _parameters(func)) > MAX_PARAMETERS:
                    name = func.name if func is node else f"{node.name}.{func.name}"
                    problems.append(
                        f"{path.relative_to(root)}:{func.lineno}: {name} takes {count} "
                        f"parameters, more than {MAX_PARAMETERS}; group the options that "
                        "belong together in a frozen settings object"
                    )
    return problems


# --------------------------------------------------------------------------- the real tree


def test_no_import_cycles() -> None:
    assert cycle_problems(REPO) == []


def test_no_imports_inside_functions() -> None:
    assert local_import_problems(REPO) == []


def test_private_modules_stay_in_their_folder() -> None:
    assert private_import_problems(REPO) == []


def test_private_names_stay_in_their_file() -> None:
    assert private_name_problems(REPO) == []


def test_layers_point_down() -> None:
    assert layer_problems(REPO) == []


def test_modules_stay_small() -> None:
    assert long_module_problems(REPO) == []


def test_public_signatures_stay_short() -> None:
    assert long_signature_problems(REPO) == []


def test_mechanism_is_core_and_studies() -> None:
    top = {p.name for p in (REPO / "mechanism").iterdir() if not p.name.startswith("__")}
    assert top == {"cli", "core", "studies"}


def test_importing_chaoskit_does_not_load_mechanism() -> None:
    code = "import sys, chaoskit, chaoskit.cli; sys.exit('mechanism' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], check=False).returncode == 0


# --------------------------------------------------------------------------- the checks fail


def _tree(tmp_path: Path, files: dict[str, str]) -> Path:
    # a synthetic tree written over the repository would clobber its packages
    assert tmp_path.resolve() != REPO and REPO not in tmp_path.resolve().parents
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    for pkg in PACKAGES:
        (tmp_path / pkg).mkdir(exist_ok=True)
        (tmp_path / pkg / "__init__.py").touch()
    return tmp_path


def test_checks_catch_a_cycle(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "chaoskit/a.py": "from .b import f\n",
            "chaoskit/b.py": "from typing import TYPE_CHECKING\nfrom . import c\n",
            "chaoskit/c.py": "from chaoskit.a import g\n",
            "chaoskit/d.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
            "    from .a import f\n",
            "chaoskit/e.py": "from .d import f\n",
        },
    )
    assert cycle_problems(root) == ["import cycle: chaoskit.a <-> chaoskit.b <-> chaoskit.c"]


def test_checks_catch_a_cycle_through_a_package_init(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "mechanism/core/__init__.py": "from .x import f\n",
            "mechanism/core/x.py": "from mechanism import g\n",
            "mechanism/__init__.py": "from .core import f\n",
        },
    )
    assert cycle_problems(root) == [
        "import cycle: mechanism <-> mechanism.core <-> mechanism.core.x"
    ]


def test_checks_catch_a_function_local_import(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "chaoskit/a.py": "def f():\n    from .b import g\n    import matplotlib.pyplot\n",
            "chaoskit/b.py": "class K:\n    def m(self):\n        import json\n",
        },
    )
    problems = local_import_problems(root)
    assert len(problems) == 2
    assert problems[0].startswith("chaoskit/a.py:2: 'chaoskit.b'")
    assert problems[1].startswith("chaoskit/b.py:3: 'json'")


def test_checks_catch_private_and_upward_imports(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "chaoskit/_x.py": "",
            "chaoskit/m.py": "import mechanism\n",
            "mechanism/core/__init__.py": "",
            "mechanism/core/_k.py": "from mechanism.studies import s\n",
            "mechanism/studies/__init__.py": "from mechanism.core._k import f\n",
            "mechanism/studies/s.py": "from chaoskit._x import y\nfrom chaoskit import z\n",
        },
    )
    assert [p.split(": ", 1)[0] for p in private_import_problems(root)] == [
        "mechanism/studies/__init__.py:1",
        "mechanism/studies/s.py:1",
    ]
    layers = layer_problems(root)
    assert [p.split(": ", 1)[0] for p in layers] == [
        "chaoskit/m.py:1",
        "mechanism/core/_k.py:1",
        "mechanism/studies/__init__.py:1",
    ]


def test_checks_catch_a_private_module_of_a_sibling_folder(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "chaoskit/b/__init__.py": "from ._k import f\n",
            "chaoskit/b/_k.py": "def f(): pass\n",
            "chaoskit/b/c/__init__.py": "",
            "chaoskit/b/c/y.py": "from chaoskit.b._k import f\n",
            "chaoskit/a/__init__.py": "",
            "chaoskit/a/x.py": "from chaoskit.b import _k\nfrom ..b._k import f\n",
            "chaoskit/z.py": "from chaoskit.b import f\n",
        },
    )
    assert [p.split(": ", 1)[0] for p in private_import_problems(root)] == [
        "chaoskit/a/x.py:1",
        "chaoskit/a/x.py:2",
    ]


def test_checks_catch_a_private_name_crossing_files(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "chaoskit/m.py": "_F = 1\ndef _g(): pass\nG = 2\n",
            "chaoskit/n.py": "from .m import _F, G\nfrom . import m\nx = m._g() + m.G\n",
            "chaoskit/o.py": "from chaoskit import m as k\ny = k._F\n__all__ = []\n",
        },
    )
    assert [p.split(": ", 1)[0] for p in private_name_problems(root)] == [
        "chaoskit/n.py:1",
        "chaoskit/n.py:3",
        "chaoskit/o.py:2",
    ]


def test_checks_catch_a_long_module(tmp_path: Path) -> None:
    body = "x = 1\n" * MAX_MODULE_LINES
    root = _tree(
        tmp_path,
        {
            "mechanism/core/long.py": body + "y = 2\n",
            "mechanism/core/just.py": body,
            "mechanism/core/_long_kernels.py": body * 2,
        },
    )
    assert long_module_problems(root) == [
        f"mechanism/core/long.py: {MAX_MODULE_LINES + 1} lines, more than {MAX_MODULE_LINES}; "
        "split it into modules of one concern each"
    ]


def test_checks_catch_a_long_signature(tmp_path: Path) -> None:
    many = ", ".join(f"p{i}" for i in range(MAX_PARAMETERS))
    root = _tree(
        tmp_path,
        {
            "chaoskit/a.py": "__all__ = ['f', 'g', 'K']\n"
            f"def f({many}, extra): ...\n"
            f"def g({many}): ...\n"
            f"def _h({many}, extra): ...\n"
            f"class K:\n    def m(self, {many}): ...\n    def _p(self, {many}): ...\n",
            "chaoskit/b.py": "_topic = ['r']\n__all__ = _topic\n__all__ += ['s', 'c']\n"
            f"def r(*, {many}, **extra): ...\ndef s(*args, {many}): ...\n"
            f"@app.command('c')\ndef c({many}, extra): ...\n",
        },
    )
    assert [p.split(": ", 1)[1].split(" takes")[0] for p in long_signature_problems(root)] == [
        "f",
        "K.m",
        "r",
        "s",
    ]


def test_checks_catch_a_type_only_cycle(tmp_path: Path) -> None:
    root = _tree(
        tmp_path,
        {
            "chaoskit/a.py": "from .b import f\n",
            "chaoskit/b.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
            "    from .a import A\n",
        },
    )
    assert cycle_problems(root) == ["import cycle: chaoskit.a <-> chaoskit.b"]


# --------------------------------------------------------------------------- repository


@pytest.mark.parametrize(
    "name",
    [
        "pyproject.toml",
        "README.md",
        "chaoskit",
        "mechanism",
        "tests",
        "data",
        "notebooks",
        "benchmarks",
        "docs",
        ".ci/run",
        "constraints.txt",
    ],
)
def test_top_level_layout(name: str) -> None:
    assert (REPO / name).exists()


def test_public_api_is_curated() -> None:
    import chaoskit
    import mechanism

    for pkg in (chaoskit, mechanism):
        assert pkg.__all__, pkg.__name__
        for name in pkg.__all__:
            assert not name.startswith("_") or name == "__version__"
            assert hasattr(pkg, name), f"{pkg.__name__}.{name} is listed but missing"


def test_constraints_pin_exact_versions() -> None:
    lines = [
        ln.strip()
        for ln in (REPO / "constraints.txt").read_text().splitlines()
        if ln.strip() and not ln.startswith("#")
    ]
    assert lines and all("==" in ln for ln in lines)
    names = {ln.split("==")[0].lower() for ln in lines}
    for required in ("numpy", "scipy", "numba", "xarray", "h5netcdf", "nolds", "pytest"):
        assert required in names


def _public_prefixes(module: str) -> list[str]:
    """The public packages above the first private part of ``module``, nearest first."""
    parts = module.split(".")
    public = []
    for part in parts:
        if part.startswith("_") and not part.startswith("__"):
            break
        public.append(part)
    return [".".join(public[:k]) for k in range(len(public), 0, -1)]


def private_test_imports(tests: Path) -> list[str]:
    """Imports of a private module by a test for a name a public package exports."""
    problems = []
    for path in sorted(tests.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            if not (isinstance(node, ast.ImportFrom) and node.module and not node.level):
                continue
            if not (_first_party(node.module) and _private(node.module)):
                continue
            for alias in node.names:
                for public in _public_prefixes(node.module):
                    if alias.name in getattr(importlib.import_module(public), "__all__", ()):
                        problems.append(
                            f"{path.relative_to(tests.parent)}:{node.lineno}: "
                            f"{alias.name} from {node.module}; {public} exports it"
                        )
                        break
    return problems


def test_tests_use_public_names() -> None:
    assert private_test_imports(REPO / "tests") == []


#: Words that date a text by the work that produced it, instead of naming its concept.
WORK_ITEM = re.compile(r"\b(issue|ticket|work item)s?\s+#?\d+", re.IGNORECASE)


def work_item_mentions(root: Path) -> list[str]:
    found = []
    for folder in ("chaoskit", "mechanism", "docs", "notebooks", "benchmarks", "tests"):
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".py", ".md", ".toml") or "_build" in path.parts:
                continue
            for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if WORK_ITEM.search(line):
                    found.append(f"{path.relative_to(root)}:{n}: {line.strip()[:80]}")
    for name in ("README.md",):
        text = (root / name).read_text(encoding="utf-8")
        found += [f"{name}: {m.group(0)}" for m in WORK_ITEM.finditer(text)]
    return found


def test_no_work_item_words() -> None:
    assert work_item_mentions(REPO) == []


def test_work_item_check_finds_one(tmp_path: Path) -> None:
    root = _tree(tmp_path, {"chaoskit/a.py": '"""Fixes issue' + ' 12."""\n', "README.md": "ok\n"})
    for folder in ("mechanism", "docs", "notebooks", "benchmarks", "tests"):
        (root / folder).mkdir(exist_ok=True)
    assert work_item_mentions(root) == ['chaoskit/a.py:1: """Fixes issue' + ' 12."""']
