"""The command line as a user meets it: --version, a bare ``dart-reach``, help text and
defaults of every command and option, the README's command list, and bad input as one line and
exit code 2 (a physics step, too many workers, a report without post-evaluation or into a
missing directory, a resume with another budget); the size of a long run before it starts."""

from __future__ import annotations

import argparse
import os
import re
import select
import subprocess
import sys
from pathlib import Path

import pytest

from dart_reach import __version__
from dart_reach.cli import build_parser
from dart_reach.cli.arguments import cores

README = Path(__file__).resolve().parents[1] / "README.md"
TINY = ["--replications", "1", "--trials", "1", "--steps", "2", "--workers", "1",
        "--record-every", "0"]


def _cli(*args, timeout=300):
    """The command line as a script runs it: stdin is not a terminal."""
    return subprocess.run([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)


def _in_terminal(*args, answer: str | None = None, timeout=300) -> tuple[int, str]:
    """The command line run by a person at a terminal (a real pseudo-terminal as its stdin,
    stdout and stderr): its exit code and what the terminal showed; ``answer`` is typed when
    it asks [y/N]."""
    master, slave = os.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "dart_reach.cli", *map(str, args)],
                            stdin=slave, stdout=slave, stderr=slave, close_fds=True)
    os.close(slave)
    shown = b""
    try:
        while select.select([master], [], [], timeout)[0]:
            try:
                chunk = os.read(master, 4096)
            except OSError:  # EIO: the process ended and closed the terminal
                break
            if not chunk:
                break
            shown += chunk
            if answer is not None and b"[y/N]" in shown:
                os.write(master, answer.encode() + b"\n")
                answer = None
        return proc.wait(timeout=timeout), shown.decode(errors="replace")
    finally:
        if proc.poll() is None:
            proc.kill()
        os.close(master)


def _commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _one_line_exit_2(result, *fragments):
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr, result.stderr
    for f in fragments:
        assert f in result.stderr, (f, result.stderr)


def test_version_and_a_bare_command_list_the_commands():
    result = _cli("--version")
    assert result.returncode == 0 and result.stdout.strip() == f"dart-reach {__version__}"
    bare = _cli()
    assert bare.returncode == 2
    for name in _commands():
        assert re.search(rf"^\s+{name}\b", bare.stdout, re.M), name


def test_every_command_and_option_is_explained_with_its_default():
    for name, parser in _commands().items():
        assert parser.description and len(parser.description) > 15, name
        text = parser.format_help()
        assert parser.description.split()[0] in text
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            assert action.help, (name, action.dest)
            if action.option_strings and action.nargs != 0:
                shown = parser._get_formatter()._get_help_string(action)
                assert "default" in shown, (name, action.option_strings)


def test_the_readme_lists_every_command_once_and_points_to_help():
    text = README.read_text()
    section = text[text.index("## Command line"):]
    section = section[:section.index("\n## ", 1)]
    block = section[section.index("```sh"):section.index("```", section.index("```sh") + 5)]
    for name in _commands():
        lines = [line for line in block.splitlines() if re.match(rf"dart-reach {name}\b", line)]
        assert len(lines) == 1, f"README's command list: 'dart-reach {name}' on {len(lines)} lines"
        assert "#" in lines[0], f"README's command list: 'dart-reach {name}' says what it does"
    assert "dart-reach COMMAND --help" in section


@pytest.mark.parametrize("dt, fragment", [("0", "positive"), ("nan", "positive"),
                                          ("-0.02", "positive"), ("inf", "positive"),
                                          ("0.03", "divide"), ("0.2", "divide"),
                                          ("x", "positive")])
def test_physics_step_must_divide_the_control_step(dt, fragment, tmp_path):
    _one_line_exit_2(_cli("train", "standard", "--physics-dt", dt, "--out", tmp_path / "r"),
                     "--physics-dt", fragment)
    assert not (tmp_path / "r").exists()


def test_workers_above_the_cores_are_refused():
    for command in (["train", "standard"], ["evaluate", "somewhere"], ["bench", "--physics"]):
        _one_line_exit_2(_cli(*command, "--workers", cores() + 1), "--workers",
                         f"{cores()} cores")


def test_report_needs_a_post_evaluation_and_an_existing_directory(tmp_path, monkeypatch,
                                                                   in_process):
    run = tmp_path / "run"
    assert in_process("train", "standard", "--generations", "1", *TINY,
                      "--out", run).returncode == 0
    _one_line_exit_2(_cli("report", run), "not post-evaluated",
                     f"dart-reach evaluate {run} --sensors all")
    assert not (run / "report.html").exists()
    # with a post-evaluation, an --out in a directory that does not exist is refused
    assert in_process("evaluate", run, "--robots", "1", "--record", "none",
                      "--workers", "1").returncode == 0
    _one_line_exit_2(in_process("report", run, "--out", tmp_path / "nowhere" / "r.html"),
                     "no such directory", "--out")
    assert not (tmp_path / "nowhere").exists()
    # a post-evaluation stored in parts (a large table) is one too
    from dart_reach.postevaluation import results

    table = run / "evaluation.parquet"
    frame, entries = results.read_table(table), results.sessions(table)
    monkeypatch.setattr(results, "PART_BYTES", 1_000)
    results.write_table(table, frame, entries)
    assert not table.exists() and len(results.stored_files(table)) >= 2
    _one_line_exit_2(in_process("report", run, "--out", tmp_path / "nowhere" / "r.html"),
                     "no such directory", "--out")
    # and a resume with another budget names the setting that differs
    _one_line_exit_2(in_process("train", "standard", "--generations", "1", *TINY[:-6],
                                "--steps", "3", *TINY[-4:], "--out", run, "--resume"),
                     "steps given here differs from them", "leave it out")
    _one_line_exit_2(in_process("train", "standard", "--generations", "2", *TINY, "--out", run,
                                "--resume"),
                     "conditions.standard.generations_per_phase is 1 in the run there, 2 now")
    again = in_process("train", "standard", "--generations", "1", *TINY, "--out", run)
    _one_line_exit_2(again, "--resume", "--out")


def test_python_errors_name_python_arguments(tmp_path):
    from dart_reach.evolution.conditions import load_condition, scaled
    from dart_reach.evolution.rundir import RunError
    from dart_reach.evolution.settings import Settings
    from dart_reach.evolution.trainer import train

    cond = [scaled(load_condition("standard"), 1)]
    settings = Settings(replications=1, trials=1, steps=2)
    train(cond, settings, tmp_path / "r", workers=1, progress=False)
    with pytest.raises(RunError) as again:
        train(cond, settings, tmp_path / "r", workers=1, progress=False)
    assert "resume=True" in str(again.value) and "--" not in str(again.value)
    assert "--resume" in again.value.cli


def test_a_long_run_says_its_size_and_cost_before_starting(tmp_path, in_process):
    # the default budget: 15,000 replication-generations at the measured core-seconds each;
    # the run then stops at once on a directory that holds something else
    from dart_reach.evolution.cost import GENERATION_CORE_S

    low, high = (15_000 * s / 3600 for s in GENERATION_CORE_S)
    out = tmp_path / "busy"
    out.mkdir()
    (out / "something").write_text("x")
    result = _cli("train", "standard", "--workers", "1", "--out", out)
    assert result.returncode == 2
    assert "15,000 replication-generations" in result.stderr
    assert f"{low:,.0f}-{high:,.0f} core-hours" in result.stderr
    assert "--generations" in result.stderr
    assert "[y/N]" not in result.stderr  # a script is not asked
    small = in_process("train", "standard", "--generations", "1", "--replications", "1",
                       "--trials", "1", "--steps", "2", "--workers", "1", "--out", out)
    assert "replication-generations" not in small.stderr


def test_a_run_over_an_hour_asks_a_person_at_the_terminal_first(tmp_path):
    # the default budget, days on one worker: asked; "n" starts nothing
    out = tmp_path / "run"
    code, shown = _in_terminal("train", "standard", "--workers", "1", "--out", out, answer="n")
    assert code == 1 and "start it? [y/N]" in shown and "not started" in shown, shown
    assert not out.exists()
    # "y" starts it (here it stops at once on a directory that holds something else), as
    # --yes does without asking
    busy = tmp_path / "busy"
    busy.mkdir()
    (busy / "something").write_text("x")
    code, shown = _in_terminal("train", "standard", "--workers", "1", "--out", busy, answer="y")
    assert code == 2 and "not empty" in shown, shown
    code, shown = _in_terminal("train", "standard", "--workers", "1", "--out", busy, "--yes")
    assert code == 2 and "not empty" in shown and "[y/N]" not in shown, shown
    # a small run is not asked
    code, shown = _in_terminal("train", "standard", "--generations", "1", *TINY, "--out", busy)
    assert code == 2 and "[y/N]" not in shown, shown


def test_a_json_file_that_is_not_a_runs_manifest_says_so(tmp_path):
    (tmp_path / "manifest.json").write_text('{"name": "my notes", "version": 3}')
    result = _cli("status", tmp_path)
    _one_line_exit_2(result, "manifest.json: not a run's manifest")
    assert "incompatible" not in result.stderr


def test_status_says_where_training_stands(tmp_path, in_process):
    out = tmp_path / "run"
    tiny = ["train", "standard", "--generations", "2", "--replications", "2", "--trials", "1",
            "--steps", "3", "--workers", "1", "--record-every", "0", "--out", str(out)]
    assert in_process(*tiny).returncode == 0
    status = _cli("status", str(out))
    assert status.returncode == 0, status.stderr
    lines = status.stdout.splitlines()
    assert lines[0].split()[:3] == ["condition", "phase", "replication"]
    assert sum("2 / 2" in line for line in lines) == 6  # 3 phases x 2 replications, done
    (total,) = [line for line in lines if "replication-generations" in line]
    assert "12 of 12 replication-generations (100%)" in total
    assert "1 session(s)" in total and "unfinished: none" in total
    assert lines[-1] == "results: no post-evaluation (dart-reach evaluate RUN)"
    markdown = in_process("status", str(out), "--markdown").stdout.splitlines()
    assert markdown[0].startswith("| condition |") and markdown[1].startswith("|---|")
    missing = in_process("status", str(tmp_path / "none"))
    assert missing.returncode == 2 and "no such run directory" in missing.stderr
    # nothing post-evaluated: nothing to run again, said in one line
    unevaluated = in_process("status", str(out), "--reproduce")
    assert unevaluated.returncode == 2 and unevaluated.stderr.count("\n") == 1
    assert "no post-evaluated robot to run again" in unevaluated.stderr
