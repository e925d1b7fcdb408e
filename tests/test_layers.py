"""The package's architecture, read from its imports with ``ast``: subpackages follow the data
flow and import only those before them; no module imports a private name of another; no module
grows past about 600 lines; imports sit at the top of a module except where deferring them is
stated (an optional extra, or the CLI's start-up time); no two modules import each other."""

from __future__ import annotations

import ast
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "dart_reach"

#: Each layer may import itself and the layers before it. ``errors``, ``files``, ``pinning``
#: (the kernels' pin, which ``import dart_reach`` runs first) and ``progress`` are shared
#: utilities every layer may use.
#: ``envs`` (the Gymnasium environment) wraps the model's trial, takes its phases from
#: evolution's conditions and draws its frames with ``viewing.episode`` (which takes a trial's
#: record, not the environment): it sits after viewing, and bench (studies) measures it.
LAYERS = ("model", "measures", "recording", "evolution", "postevaluation", "analysis",
          "robots", "viewing", "envs", "studies", "cli")
SHARED = {"errors", "files", "integrity", "pinning", "progress", "skeletons", ""}

MAX_LINES = 600

#: Modules allowed to import inside functions, and why (checked to still need it).
DEFERRED = {
    "model.task": "Numba takes about 0.4 s to import and compiles (or loads from its cache) "
                  "on first use; only model version 2's trial and network need it",
    "cli": "start-up: 'dart-reach --help' and every command load only what they run",
    "__init__": "the public names are loaded on first use (PEP 562)",
    "envs": "a render mode alone loads its renderer (human: rerun and polars, about a "
            "second), which every process of a vector environment would pay",
    "progress": "start-up: tqdm.auto takes 60 ms to import and is needed only to draw a bar; "
                "the CLI imports progress for every command",
    "pinning": "it runs before numpy loads, to set the variables numpy and OpenBLAS read when "
               "they load; numpy is imported only to read the kernels a process runs",
    "files": "start-up: pyarrow takes about 0.2 s to import and only writing a parquet file "
             "needs it; the CLI and every reader of a run import files",
    "integrity": "pyarrow and rerun read a table or a recording whole only when 'migrate' "
                 "checks an old run's files; every command verifies runs through integrity",
    "measures.kinematics": "start-up: scipy.signal takes 0.6 s to import and only "
                           "movement_units needs it; every 'dart-reach train' loads the measures "
                           "(its recordings do)",
}
#: Optional extras imported where they are used: ray (cluster), imageio (video), pinocchio,
#: the Gymnasium environment (``envs``: the gym extra).
OPTIONAL = {"ray", "imageio", "imageio_ffmpeg", "imageio.v2", "pinocchio", "IPython",
            "ipywidgets", "icub_models", "envs"}


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        yield path, parts, ast.parse(path.read_text(), str(path))


def _target(parts: tuple[str, ...], node: ast.ImportFrom, is_init: bool) -> list[str]:
    """The package-relative dotted names an import refers to ('' for the package itself)."""
    if node.level == 0:
        if not (node.module or "").startswith("dart_reach"):
            return []
        base = (node.module or "").split(".")[1:]
    else:
        here = list(parts if is_init else parts[:-1])
        if is_init:
            here = here[:-1]
        base = (here[: len(here) - (node.level - 1)]
                + (node.module.split(".") if node.module else []))
    if node.module is None or node.level and not node.module:
        return [".".join([*base, a.name]) for a in node.names]
    return [".".join(base)]


def _layer(dotted: str) -> str:
    return dotted.split(".")[0] if dotted else ""


def _layer_violations(modules) -> list[str]:
    """Each import of a later layer by an earlier one, as 'path:line layer imports layer'."""
    wrong = []
    for path, parts, tree in modules:
        is_init = parts[-1] == "__init__"
        mine = _layer(".".join(parts)) if len(parts) > 1 else ""
        if mine in SHARED or mine == "__init__":
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                for target in _target(parts, node, is_init):
                    theirs = _layer(target)
                    if theirs in SHARED or theirs not in LAYERS:
                        continue
                    if LAYERS.index(theirs) > LAYERS.index(mine):
                        wrong.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {mine} imports "
                                     f"{theirs}")
    return wrong


def test_subpackages_import_only_those_before_them():
    wrong = _layer_violations(_modules())
    assert not wrong, "\n".join(wrong)


def test_every_module_is_in_a_layer():
    for path in PACKAGE.iterdir():
        if path.is_dir() and (path / "__init__.py").exists():
            assert path.name in LAYERS or path.name in SHARED, path.name
        elif path.suffix == ".py":
            assert path.stem in SHARED or path.stem == "__init__", path.name


def test_no_private_name_is_imported_from_another_module():
    wrong = []
    for path, parts, tree in _modules():
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and _target(parts, node, parts[-1] == "__init__"):
                wrong += [f"{path.relative_to(PACKAGE)}:{node.lineno} {a.name}"
                          for a in node.names if a.name.startswith("_") and a.name != "__version__"]
    assert not wrong, "\n".join(wrong)


#: The subpackages whose modules read no private attribute of another object: a module reads
#: ``self._name``, never ``world._name``, ``self.world._name`` or ``module._name``.
PRIVATE_CHECKED = ("model", "envs", "evolution", "studies")
#: Underscore attributes outside the package that are public by their owner's documentation.
PRIVATE_ALLOWED = {"os._exit": "Python's exit of a child process without clean-up "
                               "(documented in the os module)"}


def _private_reads(tree: ast.AST) -> list[str]:
    """``line: expression`` of every read of an underscore attribute (dunders aside) of
    anything but ``self`` or ``cls``."""
    found = []
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                and not (node.attr.startswith("__") and node.attr.endswith("__"))
                and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))
                and ast.unparse(node) not in PRIVATE_ALLOWED):
            found.append(f"{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_module_reads_a_private_attribute_of_another_object():
    checked, wrong = 0, []
    for path, parts, tree in _modules():
        if parts[0] in PRIVATE_CHECKED:
            checked += 1
            wrong += [f"{path.relative_to(PACKAGE)}:{r}" for r in _private_reads(tree)]
    assert checked > 40 and not wrong, "\n".join(wrong)


def test_the_private_attribute_rule_can_fail():
    source = ("other._x\nself._y\nself.world._z\nnp._core.f\nx.__dict__\ncls._w\n"
              "os._exit(1)\n")
    assert _private_reads(ast.parse(source)) == ["1: other._x", "3: self.world._z",
                                                  "4: np._core"]


def test_no_module_is_too_long():
    long = [f"{p.relative_to(PACKAGE)}: {n} lines" for p, _, _ in _modules()
            if (n := len(p.read_text().splitlines())) > MAX_LINES]
    assert not long, "\n".join(long)


def test_imports_are_at_the_top_unless_deferral_is_stated():
    wrong = []
    for path, parts, tree in _modules():
        if parts[0] in DEFERRED or parts[-1] in DEFERRED and len(parts) == 1 \
                or ".".join(parts) in DEFERRED:
            continue
        top = {id(n) for n in tree.body}
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in top:
                names = [a.name for a in node.names] if isinstance(node, ast.Import) \
                    else [node.module or ""]
                if any(n.split(".")[0] in OPTIONAL or n in OPTIONAL for n in names):
                    continue
                wrong.append(f"{path.relative_to(PACKAGE)}:{node.lineno} "
                             f"{ast.unparse(node)}")
    assert not wrong, f"{len(wrong)} imports inside functions:\n" + "\n".join(wrong)


def test_the_layer_test_sees_a_wrong_import():
    """The rule can fail: the model importing the analysis is caught (relative and absolute),
    the analysis importing the model and anything importing a shared utility are not."""
    sources = {("model", "world"): "from ..analysis import figures\n"
                                   "from dart_reach.analysis.figures import fig5\n",
               ("analysis", "figures"): "from ..model import world\nfrom ..files import x\n",
               ("model", "task"): "from ..progress import bar\n"}
    modules = [(PACKAGE.joinpath(*parts).with_suffix(".py"), parts, ast.parse(source))
               for parts, source in sources.items()]
    assert _layer_violations(modules) == ["model/world.py:1 model imports analysis",
                                          "model/world.py:2 model imports analysis"]


def _import_graph() -> dict[str, set[str]]:
    """Module -> the package's modules it imports (at the top or deferred; a package's
    ``__init__`` stands for the package)."""
    modules = {".".join(parts[:-1] if parts[-1] == "__init__" else parts)
               for _, parts, _ in _modules()}
    graph: dict[str, set[str]] = {}
    for _, parts, tree in _modules():
        is_init = parts[-1] == "__init__"
        me = ".".join(parts[:-1] if is_init else parts)
        edges = graph.setdefault(me, set())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                for target in _target(parts, node, is_init):
                    while target and target not in modules:  # a name of a module
                        target = target.rpartition(".")[0]
                    if target and target != me:
                        edges.add(target)
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every import circle between two modules of one subpackage (A imports B, B imports A,
    deferred or not): a package's ``__init__`` importing its own modules is not one."""
    return sorted([a, b] for a in graph for b in graph[a]
                  if a < b and a in graph.get(b, ()) and a.split(".")[0] == b.split(".")[0]
                  and "." in a and "." in b)


def test_no_two_modules_import_each_other():
    circles = _circles(_import_graph())
    assert not circles, f"import circles: {circles}"
    # the rule can fail
    assert _circles({"envs.a": {"envs.b"}, "envs.b": {"envs.a"}}) == [["envs.a", "envs.b"]]


#: The repository's root: the project's committed runs (folders under recordings/) and its
#: studies of them (reports/, beside the package, never installed).
ROOT = PACKAGE.parent
REPORTS = ROOT / "reports"


def committed_runs() -> list[str]:
    """The names of the committed runs: the folders under recordings/."""
    return sorted(p.name for p in (ROOT / "recordings").iterdir() if p.is_dir())


def _code_strings(tree: ast.AST) -> list[ast.Constant]:
    """The string constants of a module's code, its docstrings left out (they may name a
    page a reader opens; code that reads one is what the rule is about)."""
    docs = {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef,
                                 ast.AsyncFunctionDef))
            and node.body and isinstance(node.body[0], ast.Expr)
            and isinstance(node.body[0].value, ast.Constant)}
    return [n for n in ast.walk(tree) if isinstance(n, ast.Constant)
            and isinstance(n.value, str) and id(n) not in docs]


def run_and_docs_mentions(text: str, tree: ast.AST, runs: list[str]) -> list[str]:
    """What in a module names a committed run or reads docs/: a run's name with a digit in it
    (``replication-50``) anywhere in its text, comments and docstrings included; a run's name as
    a path part of a string in code that also names ``recordings``; a string in code that is
    ``docs`` or starts with ``docs/``."""
    found = [f"names {run}" for run in runs if any(c.isdigit() for c in run)
             and re.search(rf"(?<![\w-]){re.escape(run)}(?!\w)", text)]
    strings = [n.value for n in _code_strings(tree)]
    parts = {part for s in strings for part in s.split("/")}
    if "recordings" in parts:
        found += [f"names {run} under recordings/" for run in runs if run in parts]
    found += [f"reads {s!r}" for s in strings if s.strip() == "docs" or s.startswith("docs/")]
    return found


def test_no_module_of_the_package_names_a_committed_run_or_reads_docs():
    """The package is the model and its generic tools: what it computes takes a run and
    parameters; the pages of the project's own runs live in reports/."""
    runs = committed_runs()
    assert {"replication-50x10", "standard-500x10"} <= set(runs)
    wrong = [f"{path.relative_to(PACKAGE)}: {what}" for path, _, tree in _modules()
             for what in run_and_docs_mentions(path.read_text(), tree, runs)]
    assert not wrong, "\n".join(wrong)
    # the rule can fail
    code = 'TEN = "replication-50x10"\nPAGE = Path("docs/results/x.md")\n' \
           'T = ROOT / "recordings" / "calibration" / "t.parquet"\n'
    assert run_and_docs_mentions(code, ast.parse(code), runs) == [
        "names replication-50x10", "names calibration under recordings/",
        "names replication-50x10 under recordings/", "reads 'docs/results/x.md'"]
    code = '"""See docs/results/replication.md."""\nd["levers"] = 1\n'
    assert run_and_docs_mentions(code, ast.parse(code), runs) == []


#: A date as the docs write one (2026-11-24).
DATE = re.compile(r"\b20\d\d-[01]\d-[0-3]\d\b")


def test_no_module_of_the_package_carries_a_dated_measurement():
    """A measured figure belongs in docs/results (or a guide) with the date and the command
    that made it; the package may take one as an argument or read it from a file a user's
    benchmark wrote, never carry a date-stamped one."""
    dated = [f"{path.relative_to(PACKAGE)}:{n}: {line.strip()}"
             for path, _, _ in _modules()
             for n, line in enumerate(path.read_text().splitlines(), 1) if DATE.search(line)]
    assert not dated, "\n".join(dated)


def _imported(tree: ast.AST) -> set[str]:
    """The top-level names of the modules a module imports by absolute name."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names


def test_reports_import_the_package_one_way_and_are_never_installed():
    """reports/ imports dart_reach; dart_reach never imports reports; the wheel ships no
    reports (pyproject's package list)."""
    pyproject = (ROOT / "pyproject.toml").read_text()
    listed = re.search(r"^packages = \[(.*?)\]", pyproject, re.M | re.S).group(1)
    shipped = set(re.findall(r'"([\w.]+)"', listed))
    assert "dart_reach" in shipped and not any(p.split(".")[0] == "reports" for p in shipped)
    backwards = [str(path.relative_to(PACKAGE)) for path, _, tree in _modules()
                 if "reports" in _imported(tree)]
    assert not backwards, f"the package imports reports: {backwards}"
    studies = sorted(REPORTS.glob("*.py"))
    assert len(studies) > 2
    assert any("dart_reach" in _imported(ast.parse(p.read_text())) for p in studies)
