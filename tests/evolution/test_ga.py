"""The genetic algorithm as ask/tell over immutable state (section III-C, ref. [47])."""

from __future__ import annotations

import numpy as np
import pytest

from dart_reach.evolution import ga as E
from dart_reach.evolution import genome as G
from dart_reach.evolution.ga import GAConfig, Pending, Scheme
from dart_reach.evolution.genome import ParamGroup

L = G.N_GENES
PRE_MASK = G.free_mask({ParamGroup.DIRECT})


def ones_fitness(candidates: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Toy fitness in [0, 1]: the fraction of 1-bits in the free genes."""
    bits = np.unpackbits(candidates[:, mask], axis=1)
    return bits.mean(axis=1)


def run(seed: int, config: GAConfig, generations: int, mask=PRE_MASK, fitness=ones_fitness):
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    state = E.init_state(G.random_genome(rng, config.population))
    states, stats = [state], []
    for _ in range(generations):
        cand, state = E.ask(state, config, mask, rng)
        states.append(state)
        f = fitness(cand, mask)
        stats.append(E.generation_stats(f))
        state = E.tell(state, f)
        states.append(state)
    return states, stats


def test_config_defaults_and_validation():
    c = GAConfig()
    assert (c.population, c.mutation_rate, c.scheme) == (20, 0.02, Scheme.STEADY_STATE)
    with pytest.raises(ValueError, match="multiple of n_parents"):
        GAConfig(scheme=Scheme.GENERATIONAL, n_parents=3)
    with pytest.raises(ValueError, match="mutation_rate"):
        GAConfig(mutation_rate=1.5)
    with pytest.raises(TypeError, match="Scheme"):
        GAConfig(scheme="steady_state")
    with pytest.raises(ValueError, match="population"):
        GAConfig(population=0)


def test_steady_state_ask_parents_then_offspring_mutating_free_bits_only():
    rng = np.random.default_rng(0)
    state = E.init_state(G.random_genome(rng, 20))
    cand, asked = E.ask(state, GAConfig(), PRE_MASK, rng)
    assert cand.shape == (40, L) and cand.dtype == np.uint8
    assert np.array_equal(cand[:20], state.genomes)
    assert np.array_equal(cand[20:, ~PRE_MASK], state.genomes[:, ~PRE_MASK])
    flipped = np.unpackbits(cand[20:, PRE_MASK] ^ state.genomes[:, PRE_MASK]).mean()
    n_bits = 20 * PRE_MASK.sum() * 8
    assert abs(flipped - 0.02) < 5 * np.sqrt(0.02 * 0.98 / n_bits)
    assert asked.pending_kind is Pending.STEADY_STATE and asked.generation == 0
    assert state.pending_kind is Pending.NONE  # the input state is untouched
    with pytest.raises(ValueError, match="read-only"):
        asked.genomes[0, 0] = 1
    with pytest.raises(ValueError, match="ask\\(\\) called twice"):
        E.ask(asked, GAConfig(), PRE_MASK, rng)
    with pytest.raises(ValueError, match="expected 40 fitness"):
        E.tell(asked, np.zeros(20))
    with pytest.raises(ValueError, match="without a pending ask"):
        E.tell(state, np.zeros(40))


def test_lifetime_average_bookkeeping_by_hand():
    """Population 2, two generations, fitness chosen by hand (exact binary fractions).

    gen 1: parents A, B get 0.25, 0.5; offspring a, b get 0.75, 0.125
           -> averages A .25, B .5, a .75, b .125 -> survivors [a (0.75/1), B (0.5/1)]
    gen 2: candidates [a, B, a', B'] get 0.25, 0.75, 0.5, 0.25
           -> a (0.75+0.25)/2 = .5, B (0.5+0.75)/2 = .625, a' .5, B' .25
           -> survivors [B (1.25/2), a (1.0/2)]: a beats a' on the tie (parents first).
    """
    cfg = GAConfig(population=2, mutation_rate=0.5)
    rng = np.random.default_rng(1)
    A, B = G.random_genome(rng, 2)
    state = E.init_state(np.stack([A, B]))
    cand, state = E.ask(state, cfg, np.ones(L, bool), rng)
    a = cand[2].copy()
    state = E.tell(state, [0.25, 0.5, 0.75, 0.125])
    assert state.generation == 1
    assert np.array_equal(state.genomes, np.stack([a, B]))
    assert state.fitness_sum.tolist() == [0.75, 0.5] and state.fitness_count.tolist() == [1, 1]
    cand, state = E.ask(state, cfg, np.ones(L, bool), rng)
    assert np.array_equal(cand[:2], np.stack([a, B]))
    assert not np.array_equal(cand[2], a)
    state = E.tell(state, [0.25, 0.75, 0.5, 0.25])
    assert state.generation == 2
    assert np.array_equal(state.genomes, np.stack([B, a]))
    assert state.fitness_sum.tolist() == [1.25, 1.0] and state.fitness_count.tolist() == [2, 2]
    g, f = E.best(state)
    assert np.array_equal(g, B) and f == 0.625
    np.testing.assert_array_equal(E.lifetime_fitness(state), [0.625, 0.5])


def test_nan_and_inf_fitness_count_as_zero():
    cfg = GAConfig(population=2)
    rng = np.random.default_rng(2)
    state = E.init_state(G.random_genome(rng, 2))
    _, state = E.ask(state, cfg, PRE_MASK, rng)
    state = E.tell(state, [np.nan, 0.5, np.inf, -np.inf])
    assert state.fitness_sum.tolist() == [0.5, 0.0]  # B, then A (NaN -> 0, parents first on ties)
    assert E.generation_stats([np.nan, 0.5, 0.25, np.inf]) == {
        "best": 0.5, "mean": 0.1875, "min": 0.0}


@pytest.mark.parametrize("scheme", list(Scheme))
def test_selection_raises_the_mean_fitness_on_a_toy_problem(scheme):
    cfg = GAConfig(scheme=scheme)
    states, stats = run(4, cfg, 50)
    final = states[-1]
    start_mean = stats[0]["mean"]
    assert start_mean == pytest.approx(0.5, abs=0.02)
    assert stats[-1]["mean"] > start_mean + 0.04  # ~ +0.06 steady-state, +0.08 generational
    assert np.nanmean(E.lifetime_fitness(final)) > start_mean + 0.04
    if scheme is Scheme.STEADY_STATE:  # deterministic fitness: the best never gets worse
        told = [s for s in states[1:] if s.pending_kind is Pending.NONE]
        best = [E.best(s)[1] for s in told]
        assert all(b1 >= b0 for b0, b1 in zip(best, best[1:]))
    # frozen genes never changed over the whole run
    first = states[0].genomes[:, ~PRE_MASK]
    assert all(any(np.array_equal(row, r0) for r0 in first) for row in final.genomes[:, ~PRE_MASK])


def test_generational_scheme_parents_and_elitism():
    cfg = GAConfig(scheme=Scheme.GENERATIONAL, n_parents=4, elitism=True)
    rng = np.random.default_rng(6)
    state = E.init_state(G.random_genome(rng, 20))
    cand, state = E.ask(state, cfg, PRE_MASK, rng)  # never evaluated: evaluate as is
    assert np.array_equal(cand, state.genomes) and state.pending_kind is Pending.REPLACE
    f = ones_fitness(cand, PRE_MASK)
    state = E.tell(state, f)
    order = np.argsort(-f, kind="stable")
    assert np.array_equal(state.genomes, cand[order])
    cand2, state = E.ask(state, cfg, PRE_MASK, rng)
    assert cand2.shape == (20, L)
    assert np.array_equal(cand2[0], cand[order[0]])  # elite copied unmutated
    for k in range(4):  # 5 offspring of each of the 4 best, in rank order
        kids = cand2[5 * k: 5 * (k + 1)]
        assert np.array_equal(kids[:, ~PRE_MASK],
                              np.repeat(cand[order[k]][None, ~PRE_MASK], 5, axis=0))
    no_elite = GAConfig(scheme=Scheme.GENERATIONAL, n_parents=4, elitism=False)
    state = E.tell(state, ones_fitness(cand2, PRE_MASK))
    cand3, _ = E.ask(state, no_elite, PRE_MASK, np.random.default_rng(0))
    assert not np.array_equal(cand3[0], state.genomes[0])


@pytest.mark.parametrize("scheme", list(Scheme))
def test_same_seed_same_states_to_the_last_bit(scheme):
    cfg = GAConfig(scheme=scheme)
    a, _ = run(9, cfg, 6)
    b, _ = run(9, cfg, 6)
    c, _ = run(10, cfg, 6)
    assert len(a) == len(b)
    assert all(E.states_equal(x, y) for x, y in zip(a, b))
    assert not E.states_equal(a[-1], c[-1])


def test_state_round_trips_through_arrays_and_npz(tmp_path):
    states, _ = run(3, GAConfig(), 3)
    for i, s in enumerate(states[-2:]):  # one with pending candidates, one without
        d = E.state_to_arrays(s)
        assert all(isinstance(v, np.ndarray) for v in d.values())
        assert E.states_equal(E.state_from_arrays(d), s)
        path = tmp_path / f"s{i}.npz"
        np.savez(path, **d)
        with np.load(path) as z:  # allow_pickle=False
            back = E.state_from_arrays(z)
        assert E.states_equal(back, s)
        assert back.pending_kind is s.pending_kind and back.generation == s.generation
    with pytest.raises(ValueError, match="missing arrays"):
        E.state_from_arrays({"genomes": states[0].genomes})


def test_resuming_from_a_checkpoint_continues_identically():
    cfg = GAConfig()
    rng = np.random.default_rng(12)
    state = E.init_state(G.random_genome(rng, 20))
    for _ in range(3):
        cand, state = E.ask(state, cfg, PRE_MASK, rng)
        state = E.tell(state, ones_fitness(cand, PRE_MASK))
    saved_state = E.state_from_arrays(E.state_to_arrays(state))
    saved_rng = np.random.default_rng()
    saved_rng.bit_generator.state = rng.bit_generator.state
    outs = []
    for s, r in ((state, rng), (saved_state, saved_rng)):
        for _ in range(3):
            cand, s = E.ask(s, cfg, PRE_MASK, r)
            s = E.tell(s, ones_fitness(cand, PRE_MASK))
        outs.append(s)
    assert E.states_equal(*outs)


def test_best_k_and_transition_population():
    rng = np.random.default_rng(8)
    finals = []
    for r in range(10):
        state = E.init_state(G.random_genome(rng, 20))
        cand, state = E.ask(state, GAConfig(), PRE_MASK, rng)
        finals.append(E.tell(state, ones_fitness(cand, PRE_MASK)))
    with pytest.raises(ValueError, match="not been evaluated"):
        E.best(E.init_state(G.random_genome(rng, 20)))
    tops = [E.best_k(s, 2)[0] for s in finals]
    pop = E.transition_population(tops, n=2)
    assert pop.shape == (20, L)
    for r, s in enumerate(finals):
        assert np.array_equal(pop[2 * r], E.best(s)[0])
        assert np.array_equal(pop[2 * r: 2 * r + 2], s.genomes[:2])
    # more rows than n: the first n are taken
    assert np.array_equal(E.transition_population([s.genomes for s in finals], n=2), pop)
    with pytest.raises(ValueError, match="population size is 20"):
        E.transition_population(tops[:9], n=2)
    with pytest.raises(ValueError, match="fewer than n=3"):
        E.transition_population(tops, n=3)
    new = E.init_state(G.release(pop, {ParamGroup.HIDDEN}))
    assert new.population == 20 and new.generation == 0
