"""Phases and experimental conditions as data (sections III-D, IV-C, Fig. 10)."""

from __future__ import annotations

import dataclasses
from importlib import resources
from pathlib import Path

import pytest

from dart_reach.evolution import genome as G
from dart_reach.evolution.conditions import (Condition, ConditionError, Phase, condition_from_dict,
                                   condition_names, list_conditions, load_condition, scaled)
from dart_reach.evolution.genome import ParamGroup as PG

SHIPPED = ("fine-hat", "fine-star", "gross-h", "gross-hat", "gross-hat-star", "pre-h",
           "pre-star", "standard")
ALL = (PG.DIRECT, PG.HIDDEN, PG.HIDDEN_GAIN, PG.OFFSET_GAIN)

# name -> (notation, [(phase notation, acuity, offset sensors, free groups, reflexes, generations)])
EXPECTED = {
    "standard": ("pre -> gross -> fine", [
        ("pre", 3.0, False, (PG.DIRECT,), True, 500),
        ("gross", 1.0, False, (PG.DIRECT, PG.HIDDEN), True, 500),
        ("fine", 1.0, True, ALL, True, 500)]),
    "pre-h": ("pre-h", [("pre-h", 1.0, False, (PG.DIRECT,), True, 500)]),
    "gross-h": ("pre-h -> gross-h", [
        ("pre-h", 1.0, False, (PG.DIRECT,), True, 500),
        ("gross-h", 1.0, False, (PG.DIRECT, PG.HIDDEN), True, 500)]),
    "pre-star": ("pre*", [("pre*", 3.0, False, (PG.DIRECT,), False, 500)]),
    "gross-hat": ("gross^", [("gross^", 1.0, False, (PG.DIRECT, PG.HIDDEN), True, 1000)]),
    "gross-hat-star": ("gross^*", [
        ("gross^*", 1.0, False, (PG.DIRECT, PG.HIDDEN), False, 1000)]),
    "fine-hat": ("fine^", [("fine^", 1.0, True, ALL, True, 1500)]),
    "fine-star": ("fine*", [("fine*", 1.0, True, ALL, False, 1500)]),
}


def test_shipped_conditions_are_package_data_and_all_load():
    assert condition_names() == SHIPPED
    assert tuple(c.name for c in list_conditions()) == SHIPPED
    folder = resources.files("dart_reach.evolution.conditions")
    for name in SHIPPED:
        assert (folder / f"{name}.toml").is_file()
        c = load_condition(name)
        assert isinstance(c, Condition) and c.name == name
        notation, phases = EXPECTED[name]
        assert c.notation == notation and c.description
        got = [(p.notation, p.acuity, p.offset_sensors, p.free_groups, p.reflexes, p.generations)
               for p in c.phases]
        assert got == phases, name


def test_standard_condition_follows_the_text_of_iii_d():
    c = load_condition("standard")
    assert [p.name for p in c.phases] == ["pre", "gross", "fine"]
    assert c.generations_per_phase == 500 and c.total_generations == 1500
    assert [p.acuity for p in c.phases] == [3.0, 1.0, 1.0]  # the text, not Table I
    assert [c.newly_free(i) for i in range(3)] == [
        frozenset(), {PG.HIDDEN}, {PG.HIDDEN_GAIN, PG.OFFSET_GAIN}]
    assert c.phases[0].free_mask().sum() == G.free_mask({PG.DIRECT}).sum()
    assert c.phases[2].free_group_names == ("direct", "hidden", "hidden_gain", "offset_gain")
    assert c.phase("gross") is c.phases[1]
    with pytest.raises(ConditionError, match="no phase 'x'"):
        c.phase("x")


def test_non_incremental_budgets_are_the_sums_of_the_phases_they_replace():
    std = load_condition("standard").total_generations
    assert load_condition("gross-hat").total_generations == 1000
    assert load_condition("fine-hat").total_generations == std
    assert load_condition("fine-hat").phases[0].budget_phases == 3


def test_prefix_keys_identify_shared_phases():
    pre_h = load_condition("pre-h").phases[0]
    gross_h = load_condition("gross-h")
    std = load_condition("standard")
    assert pre_h.key == gross_h.phases[0].key
    assert pre_h.key != std.phases[0].key  # acuity 1 vs 3
    # same content as standard's gross, different history: a different key
    assert gross_h.phases[1].key != std.phases[1].key
    assert gross_h.phases[1].previous_key == pre_h.key
    assert std.phases[0].previous_key == ""
    keys = [k for n in SHIPPED for k in load_condition(n).keys]
    assert len(set(keys)) == len(keys) - 1  # only pre-h is shared
    # stable: recomputed equal; names and notations do not enter it
    assert load_condition("standard").keys == std.keys
    renamed = dataclasses.replace(std, name="mine", phases=tuple(
        dataclasses.replace(p, name=p.name + "-x", notation="?") for p in std.phases))
    assert renamed.keys == std.keys
    assert all(len(k) == 16 for k in std.keys)


def test_scaled_budgets_keep_the_ratios():
    std = scaled(load_condition("standard"), 50)
    assert [p.generations for p in std.phases] == [50, 50, 50]
    assert std.generations_per_phase == 50
    assert scaled(load_condition("gross-hat"), 50).phases[0].generations == 100
    assert scaled(load_condition("fine-hat"), 50).phases[0].generations == 150
    assert std.keys != load_condition("standard").keys
    assert scaled(load_condition("pre-h"), 50).keys[0] == scaled(load_condition("gross-h"),
                                                                 50).keys[0]
    c = load_condition("gross-h")
    assert scaled(c) is c
    for bad in (0, -3, 2.5, True):
        with pytest.raises(ConditionError, match="generations must be an integer > 0"):
            scaled(c, bad)


USER = """
name = "slow-eyes"
notation = "pre(a=2) -> gross"
description = "Intermediate acuity, short budget."
generations_per_phase = 100

[[phases]]
name = "pre"
acuity = 2
offset_sensors = false
free_groups = ["direct"]
reflexes = true

[[phases]]
name = "gross"
acuity = 1.0
offset_sensors = false
free_groups = ["direct", "hidden"]
reflexes = true
budget_phases = 3
"""


def test_user_condition_file_without_touching_code(tmp_path):
    path = tmp_path / "slow-eyes.toml"
    path.write_text(USER, encoding="utf-8")
    for arg in (path, str(path)):
        c = load_condition(arg)
        assert c.name == "slow-eyes" and c.source == str(path)
        assert [p.generations for p in c.phases] == [100, 300]
        assert c.phases[0].acuity == 2.0 and c.phases[0].notation == "pre"


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "bad.toml"
    p.write_text(text, encoding="utf-8")
    return p


MALFORMED = {
    "unknown top-level key": (USER.replace("generations_per_phase", "generation_per_phase"),
                              "unknown key 'generation_per_phase'"),
    "unknown phase key": (USER.replace("reflexes = true\nbudget", "reflex = true\nbudget"),
                          r"phases\[1\] 'gross': unknown key 'reflex'"),
    "generations in a phase": (USER.replace("budget_phases = 3", "generations = 300"),
                               "unknown key 'generations'.*budget_phases"),
    "missing top-level key": (USER.replace('notation = "pre(a=2) -> gross"\n', ""),
                              "missing key.*'notation'"),
    "missing phase key": (USER.replace("acuity = 2\n", ""),
                          r"phases\[0\] 'pre': missing key.*'acuity'"),
    "no phases": ("\n".join(USER.splitlines()[:5]), "missing key.*'phases'"),
    "acuity wrong type": (USER.replace("acuity = 2", 'acuity = "low"'),
                          r"phases\[0\] 'pre': acuity must be a number > 0 .*got 'low' \(str\)"),
    "acuity not positive": (USER.replace("acuity = 2", "acuity = -1"), "acuity must be a number"),
    "bool wrong type": (USER.replace("offset_sensors = false\nfree_groups = [\"direct\"]",
                                     "offset_sensors = 0\nfree_groups = [\"direct\"]"),
                        "offset_sensors must be true or false, got 0"),
    "generations_per_phase zero": (USER.replace("= 100", "= 0"),
                                   "generations_per_phase must be an integer > 0, got 0"),
    "generations_per_phase float": (USER.replace("= 100", "= 100.0"),
                                    "generations_per_phase must be an integer > 0"),
    "budget_phases negative": (USER.replace("budget_phases = 3", "budget_phases = -1"),
                               r"phases\[1\] 'gross': budget_phases must be an integer > 0"),
    "unknown group": (USER.replace('["direct", "hidden"]', '["direct", "hiden"]'),
                      r"phases\[1\] 'gross': free_groups: unknown parameter group 'hiden'"),
    "groups not a list": (USER.replace('free_groups = ["direct"]', 'free_groups = "direct"'),
                          "free_groups must be a list"),
    "empty groups": (USER.replace('free_groups = ["direct"]', "free_groups = []"),
                     "free_groups is empty"),
    "duplicate group": (USER.replace('["direct", "hidden"]', '["direct", "direct"]'),
                        "lists a group twice"),
    "groups shrink": (USER.replace('["direct", "hidden"]', '["hidden"]'),
                      r"phases\[1\] 'gross': free_groups must include.*\['direct'\]"),
    "duplicate phase names": (USER.replace('name = "gross"', 'name = "pre"'),
                              r"phase names must be unique.*\['pre'\]"),
    "bad condition name": (USER.replace('name = "slow-eyes"', 'name = "slow eyes"'),
                           "command-line friendly"),
    "not TOML": (USER + "\n[[phases]\n", "not a valid TOML file"),
}


@pytest.mark.parametrize("case", list(MALFORMED))
def test_malformed_files_name_the_file_and_the_problem(tmp_path, case):
    text, pattern = MALFORMED[case]
    path = _write(tmp_path, text)
    with pytest.raises(ConditionError, match=pattern) as err:
        load_condition(path)
    assert str(err.value).startswith(f"{path}: ")
    assert isinstance(err.value, ValueError)


def test_unknown_names_and_missing_files():
    with pytest.raises(ConditionError, match="unknown condition 'gross-hats'.*gross-hat, "):
        load_condition("gross-hats")
    with pytest.raises(ConditionError, match="no such condition file"):
        load_condition("nowhere/standard.toml")


def test_phase_and_condition_constructors_validate():
    pre = Phase(name="pre", notation="pre", acuity=3, offset_sensors=False,
                free_groups=["direct"], reflexes=True, generations=500)
    assert pre.acuity == 3.0 and pre.free_groups == (PG.DIRECT,)
    with pytest.raises(ConditionError, match="generations must be an integer > 0"):
        dataclasses.replace(pre, generations=0)
    with pytest.raises(ConditionError, match="generations 500 != budget_phases 1 x"):
        Condition(name="c", notation="c", description="d", phases=(pre,),
                  generations_per_phase=100)
    c = condition_from_dict({"name": "c", "notation": "c", "description": "d", "phases": [
        {"name": "pre", "acuity": 3, "offset_sensors": False, "free_groups": ["direct"],
         "reflexes": True}]})
    assert c.phases[0].key == load_condition("standard").phases[0].key


def test_to_dict_is_json_friendly_and_round_trips():
    import json
    for c in list_conditions():
        d = c.to_dict()
        assert json.loads(json.dumps(d)) == d
        assert [p["key"] for p in d["phases"]] == list(c.keys)
        assert [p["generations"] for p in d["phases"]] == [p.generations for p in c.phases]
        back = condition_from_dict(c.to_dict(derived=False), "manifest")
        assert back == c and back.keys == c.keys
