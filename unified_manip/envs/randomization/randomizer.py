"""One env's randomisation: its terms resolved on its model, drawn from its generator.

:func:`build_randomizer` turns ``randomization=`` (a preset or a list of terms) into a
:class:`Randomizer` on the backend's compiled model, or None for ``none`` (the nominal
task: nothing is drawn and ``info`` gains no key). The env then calls
:meth:`Randomizer.reset` before the backend's reset and :meth:`Randomizer.step` before
each step's physics, both with the env's ``np_random``, so a seed gives the same draws,
and the native vector env, calling them per sub-env with that env's generator, the same
draws as the single env.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping, NamedTuple, Sequence

import mujoco
import numpy as np

from unified_manip.envs.randomization.draws import DrawPlan
from unified_manip.envs.randomization.entities import Entity, Resolved, resolve
from unified_manip.envs.randomization.fields import CannotApply, FieldWriter, writer
from unified_manip.envs.randomization.geometry import Geometry
from unified_manip.envs.randomization.presets import preset_terms
from unified_manip.envs.randomization.terms import FIELD_WIDTH, RandomizationTerm, choices

#: The physics state kept across the constants' recomputation of an interval draw.
_STATE = int(mujoco.mjtState.mjSTATE_INTEGRATION)


def _keys(w: FieldWriter) -> list[str]:
    """The ``info["randomization"]`` keys of one writer's draw, row by row."""
    rows = [w.term.label] if w.term.shared or w.term.field == "shape" else [f"{w.term.label}[{e}]" for e in w.elements]
    width = FIELD_WIDTH[w.term.field]
    return [f"{r}[{k}]" if width > 1 else r for r in rows for k in range(width)]


class _Plan(NamedTuple):
    """The draws of one set of due terms: what to draw, the info keys of the values, the
    writes in the order they run (each writer with its block of the draw), and whether
    MuJoCo's constants must then be recomputed."""

    draws: DrawPlan
    keys: list[str]
    writes: list[tuple[FieldWriter, int]]
    needs_const: bool


class Randomizer:
    """The terms of one env, resolved on its backend's model.

    Args:
        terms: The terms, in the order they draw.
        entities: The task's entities (``TaskSpec.entities``).
        backend: The env's backend, freshly built (its model nominal).
        task_id: For error messages.
        strict: Every term must apply (a list given by the user); otherwise (a preset)
            the terms the task cannot take are left out.

    Raises:
        ValueError: An unknown entity, a field the entity lacks, a mesh's size or shape,
            or an ``add`` range that would make the model invalid (strict only).
    """

    def __init__(
        self,
        terms: Sequence[RandomizationTerm],
        entities: Mapping[str, Entity],
        backend,
        task_id: str,
        strict: bool = True,
    ) -> None:
        model = backend.model
        present = {n: r for n, r in ((n, resolve(n, e, model)) for n, e in entities.items()) if not r.empty}
        self.writers: list[FieldWriter] = []
        self.skipped: list[str] = []
        labels: set[str] = set()
        for term in terms:
            if term.entity not in present:
                if strict:
                    raise ValueError(
                        f"{task_id} has no entity {term.entity!r}; expected one of {choices(present) or 'none'}"
                    )
                self.skipped.append(f"{term.label}: {task_id} has no {term.entity!r}")
                continue
            if not strict and term.field == "shape":  # a preset keeps the shapes the task takes
                kept = tuple(x for x in term.shapes if x in present[term.entity].shapes)
                if len(kept) < 2:
                    self.skipped.append(f"{term.label}: {term.entity!r} keeps its shape on {task_id}")
                    continue
                term = replace(term, shapes=kept)
            if not strict and term.field == "size" and not present[term.entity].solid:
                self.skipped.append(f"{term.label}: a preset resizes solids only, and {term.entity!r} is not one")
                continue
            if term.label in labels:
                raise ValueError(f"two randomization terms write {term.label}; give each field of an entity once")
            try:
                self.writers.append(writer(term, present[term.entity], model, task_id))
            except CannotApply as err:
                if strict:
                    raise
                self.skipped.append(f"{term.label}: {err}")
                continue
            labels.add(term.label)
        geoms = [int(g) for w in self.writers if w.term.field in ("size", "shape") for g in w.ids]
        bodies = [int(b) for w in self.writers if w.term.field == "mass" for b in w.ids]
        solids: list[Resolved] = [r for r in present.values() if r.solid]
        self.geometry = Geometry(model, geoms, bodies, solids)
        self.geometry.capture_rest(backend)
        # The draws of a first or seeded reset (every term), of any other reset (no
        # startup term), and of each step that draws interval terms (built when first due).
        self._plans: dict[tuple[int, ...], _Plan] = {}
        self._every = sorted({w.term.every for w in self.writers if w.term.mode == "interval"})
        self._due_all = tuple(range(len(self.writers)))
        self._due_reset = tuple(i for i, w in enumerate(self.writers) if w.term.mode != "startup")
        self._state: dict[str, float] = {}
        self._started = False
        self._steps = 0

    @property
    def terms(self) -> tuple[RandomizationTerm, ...]:
        """The terms that apply, in draw order."""
        return tuple(w.term for w in self.writers)

    def reset(self, backend, np_random: np.random.Generator, seeded: bool) -> dict[str, float]:
        """Draw and write the terms due at a reset (before the backend's reset): every
        ``reset`` and ``interval`` term, and the ``startup`` ones at the first reset and
        at a reset given a seed. Returns the values in force (``info["randomization"]``)."""
        every = seeded or not self._started
        self._started = True
        self._steps = 0
        self._apply(backend, np_random, self._due_all if every else self._due_reset, False)
        return dict(self._state)

    def step(self, backend, np_random: np.random.Generator) -> dict[str, float] | None:
        """Draw the ``interval`` terms due before this step's physics; the values in force
        when any was drawn, else None."""
        steps = self._steps
        self._steps += 1
        if not steps or not any(steps % k == 0 for k in self._every):
            return None
        due = tuple(i for i, w in enumerate(self.writers) if w.term.mode == "interval" and steps % w.term.every == 0)
        self._apply(backend, np_random, due, True)
        return dict(self._state)

    def state(self) -> dict[str, float]:
        """The values in force, by ``info["randomization"]`` key."""
        return dict(self._state)

    def _plan(self, due: tuple[int, ...]) -> _Plan:
        plan = self._plans.get(due)
        if plan is None:
            writers = [self.writers[i] for i in due]
            order = sorted(range(len(writers)), key=lambda j: writers[j].term.field != "shape")
            plan = self._plans[due] = _Plan(
                DrawPlan([(w.term, w.count) for w in writers]),
                [k for w in writers for k in _keys(w)],
                [(writers[j], j) for j in order],
                any(w.needs_const for w in writers),
            )
        return plan

    def _apply(self, backend, np_random: np.random.Generator, due: tuple[int, ...], keep_state: bool) -> None:
        plan = self._plan(due)
        flat, blocks = plan.draws.draw(np_random)  # in term order
        model = backend.model
        for w, j in plan.writes:  # shape first, so that a size drawn with it scales it
            w.write(model, blocks[j], self.geometry)
        self._state.update(zip(plan.keys, flat.tolist()))
        self.geometry.commit(model, backend)
        if plan.needs_const:
            data = backend.data
            if keep_state:  # mj_setConst works at qpos0: keep the episode's state
                state = np.empty(mujoco.mj_stateSize(model, _STATE))
                mujoco.mj_getState(model, data, state, _STATE)
                mujoco.mj_setConst(model, data)
                mujoco.mj_setState(model, data, state, _STATE)
                mujoco.mj_forward(model, data)
            else:  # the backend's reset sets the state next
                mujoco.mj_setConst(model, data)


def build_randomizer(
    randomization: str | Sequence[RandomizationTerm], entities: Mapping[str, Entity], backend, task_id: str
) -> Randomizer | None:
    """The :class:`Randomizer` of ``randomization`` (a preset name or terms) on ``backend``,
    or None for ``none``.

    Raises:
        ValueError: A term that does not apply; a preset of which no term applies.
    """
    if isinstance(randomization, str):
        terms = preset_terms(randomization)
        if not terms:
            return None
        out = Randomizer(terms, entities, backend, task_id, strict=False)
        if not out.writers:
            raise ValueError(
                f"randomization {randomization!r} has no term that applies to {task_id}: " + "; ".join(out.skipped)
            )
        return out
    if not randomization:
        return None
    return Randomizer(tuple(randomization), entities, backend, task_id, strict=True)


def randomization_info(randomizer: Randomizer | None) -> dict[str, Any]:
    """``{"terms": [...], "skipped": [...]}`` of a randomizer, as plain values (metadata)."""
    if randomizer is None:
        return {"terms": [], "skipped": []}
    return {"terms": [t.as_dict() for t in randomizer.terms], "skipped": list(randomizer.skipped)}
