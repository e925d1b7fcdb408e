"""docs/guides/ablations.md: building conditions in Python (``conditions.variant``) and its worked
example, run as written at a tiny budget."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import polars as pl
import pytest

from dart_reach.evolution.conditions import ConditionError, load_condition, variant

DOC = Path(__file__).resolve().parents[1] / "docs" / "guides" / "ablations.md"


def test_variant_changes_what_it_is_told_and_keeps_the_rest():
    std = load_condition("standard")
    v = variant(std, "sharp", phases={"pre": {"acuity": 1.0, "notation": "pre-sharp"}},
                generations_per_phase=7)
    assert v.name == "sharp" and [p.generations for p in v.phases] == [7, 7, 7]
    assert v.phase("pre").acuity == 1.0 and v.phase("pre").notation == "pre-sharp"
    g, g0 = v.phase("gross"), std.phase("gross")
    assert (g.acuity, g.reflexes, g.free_groups, g.notation, g.offset_sensors) == (
        g0.acuity, g0.reflexes, g0.free_groups, g0.notation, g0.offset_sensors)
    assert v.phase("pre").key != std.phase("pre").key
    same = variant(std, "same")
    assert same.keys == std.keys  # nothing changed: the phases are shared when trained together
    assert all(not p.reflexes for p in variant(std, "x", phases={"*": {"reflexes": False}}).phases)
    with pytest.raises(ConditionError, match="no phase"):
        variant(std, "x", phases={"prex": {"acuity": 1.0}})
    with pytest.raises(ConditionError, match="derived"):
        variant(std, "x", phases={"pre": {"generations": 3}})
    with pytest.raises(ConditionError, match="acuity"):
        variant(std, "x", phases={"pre": {"acuity": -1.0}})


#: (the guide's text, what the test runs instead): its budget, and the post-evaluation's best 1
#: robot of each replication instead of 5 (the one Fig. 10 compares; the 45 positions of 4
#: more robots of every replication, phase and run, 3240 trials, would prove nothing more)
TINY = (("GENERATIONS, REPLICATIONS, TRIALS, STEPS = 20, 4, 18, 200",
         "GENERATIONS, REPLICATIONS, TRIALS, STEPS = 1, 2, 1, 4"),
        ("        evaluate_run(out)  #", "        evaluate_run(out, robots=1)  #"))


def test_the_documented_sweep_runs_as_a_script(tmp_path):
    """Saved as a script and run by Python, as a reader would: the process pool's workers
    import the script, so without its ``__main__`` guard the run fails."""
    code = re.search(r"```python\n(.*?)```", DOC.read_text(), re.S).group(1)
    for original, tiny in TINY:
        assert code.count(original) == 1, f"the guide changed: update TINY for {original!r}"
        code = code.replace(original, tiny)
    code += ('if __name__ == "__main__":  # what it computed, for this test\n'
             '    statistics["summary"].write_parquet("summary.parquet")\n'
             '    statistics["pairs"].write_parquet("pairs.parquet")\n'
             '    figure.savefig("fig10.png")\n')
    (tmp_path / "sweep.py").write_text(code)
    result = subprocess.run([sys.executable, "sweep.py"], cwd=tmp_path, capture_output=True,
                            text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    runs = sorted(p.name for p in (tmp_path / "recordings/acuity-sweep").iterdir())
    assert runs == ["acuity-1", "acuity-2", "acuity-3"]
    summary = pl.read_parquet(tmp_path / "summary.parquet")
    assert summary["group"].to_list() == ["gross a=1", "gross a=2", "gross a=3"]
    assert (summary["replications"] == 2).all()
    assert pl.read_parquet(tmp_path / "pairs.parquet").height == 3
    assert (tmp_path / "fig10.png").stat().st_size > 0
