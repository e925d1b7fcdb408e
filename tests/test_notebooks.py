"""The figures of section IV (``dart_reach.analysis.figures``) and the six analysis notebooks, on
a tiny real run (trained and post-evaluated through the library): every figure function returns
a figure with its panels, renders with degenerate data, and every notebook runs in a real
Jupyter kernel of this environment and shows at least one image."""

from __future__ import annotations

import ast
import io
import json
import math
import shutil
import sys
from pathlib import Path

import nbclient
import nbformat
import polars as pl
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text

from dart_reach.analysis import figures, stats, summaries, tables
from dart_reach.evolution.conditions import load_condition, scaled
from dart_reach.postevaluation.systematic import SENSES, evaluate_run, load_evaluation, run_phases
from dart_reach.evolution.rundir import RunDirectory
from dart_reach.evolution.settings import Settings
from dart_reach.evolution.trainer import train
from dart_reach.postevaluation.snapshots import load_development

NOTEBOOKS_DIR = Path(__file__).resolve().parents[1] / "notebooks"
NOTEBOOKS = ("fig5_performance.ipynb", "fig6_distances_variability.ipynb",
             "fig7_sector_maps.ipynb", "fig8_trajectories.ipynb",
             "fig9_sensory_deprivation.ipynb", "fig10_conditions.ipynb")
ABLATION = "ablation.ipynb"
STRATEGIES = "strategies.ipynb"  # reads the committed full-budget run, not the tiny one
PHASES = ["pre", "gross", "fine"]


@pytest.fixture(scope="module")
def tiny_run(built_once):
    """The standard condition, 1 generation per phase, 2 replications, trials of 6 steps, then
    post-evaluated: 2 robots per replication, every sensory condition, the best robot of the
    best replication of each phase recorded. Built once for the session (35 CPU-s), read by
    every test and notebook."""
    def build(root):
        out = root / "tiny"
        train([scaled(load_condition("standard"), 1)],
              Settings(replications=2, trials=1, steps=6, seed=1), out, workers=1)
        evaluate_run(out, senses=SENSES, robots=2, workers=1)

    return built_once("notebooks", build) / "tiny"


@pytest.fixture(scope="module")
def table(tiny_run):
    return load_evaluation(tiny_run)


def _render(fig: Figure) -> Figure:
    """Draw the figure to PNG bytes (runs the layout and every artist)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=40)
    assert buf.getvalue()[:8] == b"\x89PNG\r\n\x1a\n"
    return fig


# ------------------------------------------------------------------------------ figures

def test_phase_order_and_run_settings(tiny_run):
    assert tables.phase_order(tiny_run) == PHASES
    assert tables.phase_order(tiny_run, condition="not-there") == PHASES
    assert tables.sector_config(tiny_run).azimuth_edges[0] == 0.0
    assert tables.ball_radius(tiny_run) > 0


def test_every_figure_has_its_panels(tiny_run, table):
    stats_table = RunDirectory.open(tiny_run).stats
    counts = {
        "training": (figures.training_curves(stats_table, run_phases(tiny_run)), 1),
        "fig5": (figures.fig5_performance(table, PHASES), 4),
        # top: distances; bottom: elbow, shoulder, trunk, elbow freezing
        "fig6": (figures.fig6_distances_variability(table, tiny_run, PHASES), 5),
        # 2 rows x 3 phases + colour bar
        "fig7": (figures.fig7_sector_maps(table, PHASES), 7),
        "fig7 regression": (figures.fig7_reach_regression(table), 2),
        # 4 senses and the ball-absent test x 3 phases + colour bar
        "fig8": (figures.fig8_trajectories(table, tiny_run, PHASES), 16),
        "fig8 side": (figures.fig8_trajectories(table, tiny_run, PHASES, senses=["normal"],
                                                view="side"), 4),
        "fig8 babbling": (figures.fig8_babbling(table, PHASES), 2),
        # bars, significance matrix, bars grouped by senses
        "fig9": (figures.fig9_sensory_deprivation(table, PHASES), 3),
        "fig10": (figures.fig10_conditions(summaries.replication_performance(
            tables.load_runs([tiny_run]), by=("group",))), 2),
    }
    for name, (fig, n_axes) in counts.items():
        assert isinstance(fig, Figure), name
        assert len(fig.axes) == n_axes, name
        _render(fig)
    with pytest.raises(ValueError, match="view"):
        figures.fig8_trajectories(table, tiny_run, view="below")


def test_figure_tables(tiny_run, table):
    summary = stats.performance_summary(table, ["reached", "speed"], PHASES)
    assert summary["phase"].to_list() == ["pre", "pre", "gross", "gross", "fine", "fine"]
    assert summary.filter(pl.col("measure") == "reached")["n"].to_list() == [4, 4, 4]
    pairs = stats.phase_statistics(table, ["reached", "speed"], PHASES)
    assert pairs.columns == ["measure", "a", "b", "n_a", "n_b", "U", "p", "significant"]
    assert pairs.height == 2 * 3
    st = stats.fig9_statistics(table, PHASES)
    assert st["robots"].height == 3 * 4 * 2 * 2  # phases x senses x replications x robots
    assert st["kruskal"]["phase"].to_list() == PHASES
    assert st["matrix"].width == 1 + 12 and st["pairs"].height == 12 * 11 // 2
    robot = tables.recorded_robot(table, "pre")
    assert robot.height == 45 and robot["rank"].unique().to_list() == [0]
    assert robot["trial"].to_list() == list(range(45))
    # the recorded robot is the best robot of the best replication (evaluate_run's choice)
    pre = table.filter((pl.col("phase") == "pre") & (pl.col("rank") == 0))
    best = pre.sort("lifetime_fitness", descending=True)["replication"][0]
    assert robot["replication"][0] == best


def test_load_runs_labels_groups(tiny_run, tmp_path):
    one = tables.load_runs([tiny_run])
    assert one.schema["group"] == pl.Enum(PHASES)
    assert set(one["run"].unique()) == {"tiny"}
    reps = summaries.replication_performance(one, by=("group",))
    assert reps["group"].cast(pl.Utf8).to_list() == ["pre", "pre", "gross", "gross", "fine",
                                                     "fine"]
    st = stats.fig10_statistics(reps)
    assert st["summary"]["group"].to_list() == PHASES
    assert st["summary"]["replications"].to_list() == [2, 2, 2]
    # a run given twice is read once
    assert tables.load_runs([tiny_run, tiny_run]).height == one.height
    # two runs of the same name: every notation comes from both, so groups name the run
    other = tmp_path / "copy" / "tiny"
    shutil.copytree(tiny_run, other)
    two = tables.load_runs([tiny_run, other])
    groups = two.schema["group"].categories.to_list()
    assert groups[:3] == [f"{p} [{tiny_run}]" for p in PHASES]
    assert groups[3:] == [f"{p} [{other}]" for p in PHASES]
    reps = summaries.replication_performance(two, by=("group",))
    assert reps.height == 2 * 3 * 2
    with pytest.raises(ValueError):
        tables.load_runs([])


def test_figures_survive_missing_and_degenerate_data(tiny_run, table):
    """One phase only, no reach at all (speed and straightness NaN), zero fitness, one sensory
    condition, no recordings: every figure still renders, with empty slots."""
    nan = float("nan")
    pre = (table.filter((pl.col("phase") == "pre") & (pl.col("senses") == "normal"))
           .with_columns(pl.lit(nan).alias("speed"), pl.lit(nan).alias("straightness"),
                         pl.lit(0.0).alias("fitness"), pl.lit(False).alias("reached"),
                         pl.lit(None, pl.Utf8).alias("recording")))
    _render(figures.fig5_performance(pre, PHASES))
    summary = stats.performance_summary(pre, ["speed", "reached"], PHASES)
    speed = summary.filter(pl.col("measure") == "speed")
    assert speed["n"].to_list() == [0] and math.isnan(speed["mean"][0])
    assert stats.phase_statistics(pre, ["speed"], PHASES).height == 0
    assert len(_render(figures.fig6_distances_variability(pre, tiny_run, PHASES)).axes) == 5
    assert len(_render(figures.fig7_sector_maps(pre, PHASES)).axes) == 7
    assert len(_render(figures.fig7_reach_regression(pre)).axes) == 2  # no "gross": a message
    assert len(_render(figures.fig8_trajectories(pre, tiny_run, PHASES)).axes) == 16
    _render(figures.fig8_babbling(pre, PHASES))
    st = stats.fig9_statistics(pre, PHASES)
    assert math.isnan(st["kruskal"]["p"][0]) and st["pairs"].height == 0
    _render(figures.fig9_sensory_deprivation(pre, PHASES))
    _render(figures.fig9_sensory_deprivation(table.head(0), PHASES))
    reps = summaries.replication_performance(
        tables.load_runs([tiny_run]).with_columns(pl.lit(0.0).alias("fitness")), by=("group",))
    st = stats.fig10_statistics(reps)
    assert st["pairs"]["p"].to_list() == [1.0, 1.0, 1.0]  # all zero: no difference
    _render(figures.fig10_conditions(reps))
    _render(figures.fig10_conditions(reps.filter(pl.col("group") == "pre")))


def test_fig10s_titles_neither_overlap_nor_leave_the_figure():
    """Fig. 10 of the committed runs (18 groups with long names, as in the report and the
    notebook): every title and label is inside the figure and no two titles overlap."""
    runs = [NOTEBOOKS_DIR.parent / "recordings" / r
            for r in ("replication-50", "replication-10", "replication-50x10")]
    reps = summaries.replication_performance(tables.load_runs(runs), by=("group",))
    fig = figures.fig10_conditions(reps)
    fig.set_dpi(100)  # the report's resolution
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    page = fig.bbox
    ticks = {id(t) for ax in fig.axes for t in ax.get_xticklabels() + ax.get_yticklabels()}
    texts = [t for t in fig.findobj(Text) if t.get_text() and t.get_visible()
             and id(t) not in ticks]  # titles, axis labels
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in texts]
    assert len(boxes) >= 4  # the figure's title, the box plots' and the matrix's, the y label
    for i, (text, a) in enumerate(boxes):
        assert page.x0 <= a.x0 and a.x1 <= page.x1 and page.y0 <= a.y0 and a.y1 <= page.y1, text
        for other, b in boxes[i + 1:]:
            assert not a.overlaps(b), (text, other)
    labels = [t for ax in fig.axes for t in ax.get_xticklabels() + ax.get_yticklabels()
              if t.get_text()]
    assert len(labels) >= 3 * 18
    for t in labels:
        box = t.get_window_extent(renderer)
        assert page.x0 - 1 <= box.x0 and box.x1 <= page.x1 + 1 and page.y0 - 1 <= box.y0, (
            t.get_text())


# ------------------------------------------------------------------------------ notebooks

def test_the_notebooks_are_saved_without_outputs():
    every = (*NOTEBOOKS, ABLATION, STRATEGIES)
    assert sorted(p.name for p in NOTEBOOKS_DIR.glob("*.ipynb")) == sorted(every)
    assert (NOTEBOOKS_DIR / "README.md").is_file()
    for name in every:
        nb = nbformat.read(NOTEBOOKS_DIR / name, as_version=4)
        nbformat.validate(nb)
        assert nb.cells[0].cell_type == "markdown" and "Savastano" in nb.cells[0].source
        code = [c for c in nb.cells if c.cell_type == "code"]
        assert all(c.outputs == [] and c.execution_count is None for c in code), name
        params = [c for c in code if "parameters" in c.metadata.get("tags", [])]
        assert len(params) == 1, name
        env = {"fig10_conditions.ipynb": "DART_REACH_RUNS", ABLATION: "DART_REACH_ABLATION",
               STRATEGIES: "DART_REACH_COURSE_RUN"}.get(name, "DART_REACH_RUN")
        assert f'os.environ.get("{env}"' in params[0].source, name


def _code(cell) -> str:
    return "\n".join(line for line in cell.source.splitlines() if not line.startswith("%"))


def _literal(node) -> bool:
    try:
        ast.literal_eval(node)
        return True
    except ValueError:
        return False


@pytest.mark.parametrize("name", (*NOTEBOOKS, ABLATION, STRATEGIES))
def test_parameters_in_the_parameters_cell_and_no_unused_import(name):
    """Papermill-style: every setting a reader may change (an upper-case name given a literal)
    is in the parameters cell, so that a cell injected after it overrides it; and every
    import is used."""
    nb = nbformat.read(NOTEBOOKS_DIR / name, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    for cell in code:
        if "parameters" in cell.metadata.get("tags", []):
            continue
        for node in ast.walk(ast.parse(_code(cell))):
            if isinstance(node, ast.Assign) and _literal(node.value):
                names = [t.id for t in node.targets if isinstance(t, ast.Name)] + [
                    e.id for t in node.targets if isinstance(t, ast.Tuple) for e in t.elts]
                assert not [n for n in names if n.isupper()], (name, ast.unparse(node))
    tree = ast.parse("\n".join(_code(c) for c in code))
    imported = {(a.asname or a.name).split(".")[0] for node in ast.walk(tree)
                if isinstance(node, (ast.Import, ast.ImportFrom)) for a in node.names}
    used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    assert imported <= used, (name, imported - used)


def test_run_paths_resolve_from_the_repository_root(tmp_path, monkeypatch):
    root = NOTEBOOKS_DIR.parent
    monkeypatch.chdir(NOTEBOOKS_DIR)
    assert tables.repository_path("recordings/x") == root / "recordings/x"
    monkeypatch.chdir(tmp_path)  # outside the repository: the checkout of the package
    assert tables.repository_path("recordings/x") == root / "recordings/x"
    assert tables.repository_path(tmp_path / "r") == tmp_path / "r"
    (tmp_path / "pyproject.toml").write_text("")
    (tmp_path / "dart_reach").mkdir()
    (tmp_path / "notebooks").mkdir()
    monkeypatch.chdir(tmp_path / "notebooks")  # in another clone: that clone's root
    assert tables.repository_path("recordings/x") == tmp_path / "recordings/x"


def _execute(nb, last_cell: str, timeout: int = 300) -> tuple[list, dict]:
    """Run notebook ``nb`` with ``last_cell`` appended (it prints one JSON line) in a real
    kernel of this environment from notebooks/: every output, none an error, and the JSON."""
    nb.cells.append(nbformat.v4.new_code_cell(last_cell))
    client = nbclient.NotebookClient(nb, timeout=timeout, kernel_name="python3",
                                     resources={"metadata": {"path": str(NOTEBOOKS_DIR)}})
    client.execute()  # raises CellExecutionError on any error
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    return outputs, json.loads(nb.cells[-1].outputs[0]["text"])


def _images(outputs: list) -> int:
    return len([o for o in outputs if "image/png" in o.get("data", {})])


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_notebook_runs(name, tiny_run, monkeypatch):
    monkeypatch.setenv("DART_REACH_RUN", str(tiny_run))
    monkeypatch.setenv("DART_REACH_RUNS", str(tiny_run))
    monkeypatch.setenv("MPLBACKEND", "Agg")  # the notebooks switch to inline themselves
    outputs, last = _execute(nbformat.read(NOTEBOOKS_DIR / name, as_version=4),
                             "import json, sys\nprint(json.dumps({'prefix': sys.prefix, 'run': "
                             "[str(d) for d in RUN_DIRS] if 'RUN_DIRS' in globals() "
                             "else str(RUN_DIR)}))")
    assert _images(outputs), f"{name} shows no image"
    # the kernel is this environment's Python, and read the run of the environment variable
    assert last["prefix"] == sys.prefix
    assert last["run"] in (str(tiny_run), [str(tiny_run)])


def test_the_ablation_notebook_builds_trains_evaluates_and_compares(tmp_path, monkeypatch):
    """notebooks/ablation.ipynb as a user runs it, at a tiny budget set the way papermill
    does (a cell after the parameters cell): a condition built in Python beside the standard
    one, trained, post-evaluated, compared phase by phase and reported."""
    out = tmp_path / "ablation"
    monkeypatch.setenv("DART_REACH_ABLATION", str(out))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(NOTEBOOKS_DIR / ABLATION, as_version=4)
    params = next(i for i, c in enumerate(nb.cells) if "parameters" in c.metadata.get("tags", []))
    nb.cells.insert(params + 1, nbformat.v4.new_code_cell(
        "GENERATIONS, REPLICATIONS, TRIALS, STEPS = 1, 2, 1, 4"))
    outputs, last = _execute(nb, "import json\nprint(json.dumps({'pairs': statistics['pairs']"
                             ".filter(same_phase)[['a', 'b']].rows(), 'groups': "
                             "statistics['summary']['group'].to_list()}))", timeout=600)
    assert _images(outputs) >= 2  # training, Fig. 10
    assert last["groups"] == ["pre", "gross", "fine", "gross (no reflexes)",
                              "fine (no reflexes)"]
    assert sorted(map(sorted, last["pairs"])) == [["fine", "fine (no reflexes)"],
                                                  ["gross", "gross (no reflexes)"]]
    # one shared pre-reaching phase, two conditions, each replication's best robot evaluated
    run = RunDirectory.open(out)
    assert sorted(c.name for c in run.conditions) == ["reflexes-withdrawn", "standard"]
    assert run_phases(out)["phase_key"].n_unique() == 5
    table = load_evaluation(out)
    assert table.height == 5 * 2 * 45 and (table["rank"] == 0).all()
    assert (tmp_path / "ablation-report.html").is_file()  # beside, never in, the run
    assert not (out / "report.html").exists()


def test_the_strategies_notebook_follows_the_committed_full_budget_run(monkeypatch):
    """notebooks/strategies.ipynb on the run it defaults to, committed with the repository:
    the course, both figures and Eq. 5's snapshots taken apart, in a real kernel."""
    monkeypatch.delenv("DART_REACH_COURSE_RUN", raising=False)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    outputs, last = _execute(nbformat.read(NOTEBOOKS_DIR / STRATEGIES, as_version=4),
                             "import json\nprint(json.dumps({'run': str(RUN_DIR), 'rows': "
                             "course.height, 'taken_apart': list(taken_apart)}))")
    assert _images(outputs) == 2
    run = NOTEBOOKS_DIR.parent / "recordings" / "standard-500x10"
    development = load_development(run)
    assert last["run"] == str(run)
    assert last["rows"] == development.select("replication", "generation").n_unique()
    terms = pl.read_parquet(run / "fitness-terms.parquet")
    assert last["taken_apart"] == sorted(terms["generation"].unique().to_list())


def test_condition_trials_keeps_same_named_phases_of_other_conditions_apart(tmp_path):
    """A user condition whose first phase is also called "pre" (but differs) must not be
    mixed into the standard condition's figures: rows are chosen by phase key."""
    text = (Path(load_condition("standard").source).read_text()
            .replace('name = "standard"', 'name = "sharp"').replace("acuity = 3.0", "acuity = 1.0"))
    sharp = tmp_path / "sharp.toml"
    sharp.write_text(text)
    run = tmp_path / "two"
    conditions = [scaled(load_condition(c), 1) for c in ("standard", str(sharp))]
    train(conditions, Settings(replications=1, trials=1, steps=2, seed=2), run, workers=1)
    evaluate_run(run, robots=1, record="none", workers=1)
    everything = load_evaluation(run)
    assert everything.filter(pl.col("phase") == "pre")["phase_key"].n_unique() == 2
    for name in ("standard", "sharp"):
        table, phases = tables.condition_trials(run, name)
        assert phases == ["pre", "gross", "fine"]
        keys = run_phases(run).filter(pl.col("condition") == name)["phase_key"]
        assert set(table["phase_key"]) == set(keys)
        assert table.height == 3 * 45
