"""The post-evaluation's tables as results (results.py): float32 storage read as float64, the
baseline in its own table, provenance per session, and a table of an older format migrated
once."""

from __future__ import annotations

import shutil
from pathlib import Path

import polars as pl
import pytest

from dart_reach import integrity
from dart_reach.evolution.rundir import RunError
from dart_reach.postevaluation import results
from dart_reach.postevaluation.systematic import evaluate_run, load_evaluation

TRIALS = 45


def test_tables_are_float32_apart_and_say_who_wrote_them(trained, tmp_path):
    out = tmp_path / "run"
    shutil.copytree(trained, out)
    evaluate_run(out, senses=["normal"], robots=1, baseline=1, record="none", workers=1,
                 progress=False)
    raw = pl.read_parquet(out / results.EVALUATION)
    chance = pl.read_parquet(out / results.BASELINE)
    assert not raw["baseline"].any() and chance["baseline"].all()
    assert (raw.height, chance.height) == (3 * 2 * TRIALS, 3 * TRIALS)  # phases x robots
    for table in (raw, chance):
        assert pl.Float64 not in table.schema.dtypes() and pl.Float32 in table.schema.dtypes()
        assert (table["session"] == 0).all()
    loaded = load_evaluation(out, baseline=None)
    assert pl.Float32 not in loaded.schema.dtypes()
    assert loaded.filter(~pl.col("baseline")).equals(
        raw.with_columns(pl.col(pl.Float32).cast(pl.Float64)))
    (first,) = results.sessions(out / results.EVALUATION)
    assert first["rows"] == raw.height and first["version"]
    assert "revision" in first and first["command"]
    assert results.is_current(out / results.EVALUATION)
    path = str(out / results.EVALUATION)  # as a user types it
    assert results.read_table(path).equals(raw.with_columns(pl.col(pl.Float32).cast(pl.Float64)))
    assert results.sessions(path) == [first] and results.is_current(path)

    # a second session appends its entry; rows keep the index of the session that added them
    evaluate_run(out, senses=["no-ball"], robots=1, record="none", workers=1, progress=False)
    entries = results.sessions(out / results.EVALUATION)
    table = pl.read_parquet(out / results.EVALUATION)
    assert len(entries) == 2 and [e["rows"] for e in entries] == [raw.height] * 2
    assert table.group_by("senses", "session").len().sort("senses").rows() == [
        ("no-ball", 1, raw.height), ("normal", 0, raw.height)]
    assert table.filter(pl.col("senses") == "normal").equals(raw)  # nothing rewritten
    assert len(results.sessions(out / results.BASELINE)) == 1  # no baseline rows added


def test_a_table_of_an_older_format_is_refused_in_one_line_and_migrated_once(trained, tmp_path):
    """A float64 evaluation.parquet holding the baseline too (written before results.py, and
    before the measures' version 2) is not read: one line names the command that rewrites
    it; ``dart-reach evaluate RUN --migrate`` (``migrate``) rewrites it once, with the
    provenance given, and the same rows read back; the committed tables are all current."""
    out = tmp_path / "run"
    shutil.copytree(trained, out)
    evaluate_run(out, senses=["normal"], robots=1, baseline=1, record="none", workers=1,
                 progress=False)
    every = load_evaluation(out, baseline=None).drop("session")
    migrated = tmp_path / "migrated"
    shutil.copytree(out, migrated)
    (migrated / results.BASELINE).unlink()
    integrity.write(migrated / results.EVALUATION,  # the old format, as a run records it
                    lambda p: every.drop("measures_version").write_parquet(p))
    assert not results.is_current(migrated / results.EVALUATION)
    with pytest.raises(RunError) as refused:
        load_evaluation(migrated, None)
    message = str(refused.value)
    assert "\n" not in message and f"dart-reach evaluate {migrated} --migrate" in message

    entry = {"revision": "abc", "command": "dart-reach evaluate run"}
    assert sorted(p.name for p in results.migrate(migrated, entry)) == [
        results.BASELINE, results.EVALUATION]
    assert results.sessions(migrated / results.BASELINE) == [dict(entry, rows=3 * 45)]
    back = load_evaluation(migrated, None).drop("session")
    assert back.drop("measures_version").equals(every.drop("measures_version"))
    assert (back["measures_version"] == 1).all()  # measured before version 2
    assert results.migrate(migrated, entry) == []  # current: left alone
    with pytest.raises(RunError, match="not a run directory"):  # not said to be current
        results.migrate(tmp_path)

    committed = [folder / name for folder in (Path(__file__).parents[2] / "recordings").iterdir()
                 for name in (results.EVALUATION, results.BASELINE, results.DEVELOPMENT)
                 if results.exists(folder / name)]
    assert committed and all(results.is_current(path) for path in committed)


def test_a_large_table_is_stored_in_parts_and_read_as_one(tmp_path, monkeypatch):
    """Over PART_BYTES a table is written in parts (each at most PART_BYTES), read back as the
    one table it is with its provenance; written again small, it is one file and the parts go;
    and the committed tables are each under 5 MB (a tracked file's limit)."""
    import numpy as np

    rng = np.random.default_rng(0)
    table = pl.DataFrame({"notation": np.repeat(["pre", "gross", "fine"], 20_000),
                          "trial": np.arange(60_000),
                          "speed": rng.normal(size=60_000)})
    path = tmp_path / results.DEVELOPMENT
    entry = {"command": "test", "rows": table.height}
    monkeypatch.setattr(results, "PART_BYTES", 200_000)
    results.write_table(path, table, [entry])
    parts = results.stored_files(path)
    assert not path.exists() and len(parts) >= 2
    assert all(p.parent == results.parts_folder(path) and p.stat().st_size <= 200_000
               for p in parts)
    assert results.exists(path) and results.is_current(path)
    assert results.read_table(path).equals(results.quantised(table))
    assert results.sessions(path) == [entry] and results.rows(path) == table.height
    monkeypatch.setattr(results, "PART_BYTES", 50_000_000)
    results.write_table(path, table.head(10), [entry])
    assert results.stored_files(path) == [path] and not results.parts_folder(path).exists()
    assert results.read_table(path).equals(results.quantised(table.head(10)))
    assert results.read_table(tmp_path / "none.parquet") is None
    assert not results.exists(tmp_path / "none.parquet")
    assert results.rows(path) == 10 and results.rows(tmp_path / "none.parquet") == 0


def test_a_growing_table_keeps_its_full_parts_and_writes_only_what_is_new(tmp_path, monkeypatch):
    """A table in parts that grows (a snapshot's trials at a time, through ``save_table``)
    keeps the parts it has, byte for byte, and writes only its new rows, the last part joining
    them while it is small; the last part holds every session's provenance; a row replaced in
    the first part rewrites the parts from there on; read back, it is always the one table."""
    import numpy as np

    rng = np.random.default_rng(1)
    monkeypatch.setattr(results, "PART_BYTES", 200_000)
    path, key = tmp_path / results.DEVELOPMENT, ("generation", "trial")

    def snapshot(generation: int, n: int, start: int = 0) -> list[dict]:
        return [{"generation": generation, "trial": start + t, "speed": float(x)}
                for t, x in enumerate(rng.normal(size=n))]

    def stored() -> dict[str, bytes]:
        return {p.name: p.read_bytes() for p in results.stored_files(path)}

    def entry(n: int) -> dict:
        return {"pid": n, "started": str(n), "rows": 0}

    everything = snapshot(1, 60_000)
    table = results.save_table(path, None, everything, key, entry(1))
    first = stored()
    assert not path.exists() and len(first) >= 2
    for n in (2, 3, 4):
        rows = snapshot(n, 1_000)
        everything += rows
        table = results.save_table(path, table, rows, key, entry(n))
        now = stored()
        assert {k: v for k, v in now.items() if k in first and k != max(first)} == {
            k: v for k, v in first.items() if k != max(first)}  # the full parts: untouched
        assert len(now) <= len(first) + 1  # the small new rows share one part
        assert results.read_table(path).drop("session").equals(
            results.quantised(pl.DataFrame(everything)))
        assert [e["pid"] for e in results.sessions(path)] == list(range(1, n + 1))
        assert all(p.stat().st_size <= 200_000 for p in results.stored_files(path))
    again = snapshot(1, 1, start=5)  # trial 5 of generation 1 measured again
    table = results.save_table(path, table, again, key, entry(5))
    now = stored()
    assert now[min(now)] != first[min(first)]  # the first part lost a row: written again
    assert sorted(now) == [f"part-{i:03d}.parquet" for i in range(len(now))]  # none stale
    expected = [r for r in everything if (r["generation"], r["trial"]) != (1, 5)] + again
    assert results.read_table(path).drop("session").equals(
        results.quantised(pl.DataFrame(expected)))


def test_every_committed_table_file_is_under_5_mb():
    from pathlib import Path

    recordings = Path(__file__).resolve().parents[2] / "recordings"
    files = list(recordings.glob("**/*.parquet"))
    assert files
    assert max(f.stat().st_size for f in files) < 5_000_000, \
        [f for f in files if f.stat().st_size >= 5_000_000]


def test_two_sessions_of_one_process_in_the_same_second_are_two_entries(tmp_path):
    """A session adds its rows to its own entry however many times it saves; another session
    of the same process, started in the same second, gets an entry of its own (which the
    start time, to the second, and the pid alone would not tell apart)."""
    path, key = tmp_path / results.EVALUATION, ("trial",)
    first, second = results.session("one"), results.session("two")
    second["started"] = first["started"]
    table = results.save_table(path, None, [{"trial": 0, "speed": 1.0}], key, first)
    table = results.save_table(path, table, [{"trial": 1, "speed": 2.0}], key, first)
    table = results.save_table(path, table, [{"trial": 2, "speed": 3.0}], key, second)
    assert [(e["command"], e["rows"]) for e in results.sessions(path)] == [("one", 2), ("two", 1)]
    assert table["session"].to_list() == [0, 0, 1]
