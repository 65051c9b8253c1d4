"""The update-speed tool switches its levers on SB3's real TQC model and restores it."""

from __future__ import annotations

import sb3_contrib.tqc.tqc as tqc_module

from benchmarks import update_speed

TASK = "UnifiedManip/Arm4Reach-v0"


def test_levers_switch_on_for_the_block_and_off_after():
    model = update_speed.build_model(TASK, n_envs=2, warmup=200, seed=0)
    compiled = {name: object() for name in ("actor", "critic", "critic_target", "action_log_prob", "quantile")}
    loss = tqc_module.quantile_huber_loss
    with update_speed.switched(model, ("fused", "compile", "quantile"), compiled):
        assert {g["fused"] for opt in update_speed._optimizers(model) for g in opt.param_groups} == {True}
        assert model.critic.forward is compiled["critic"] and model.actor.action_log_prob is compiled["action_log_prob"]
        assert tqc_module.quantile_huber_loss is compiled["quantile"]
    assert {g["fused"] for opt in update_speed._optimizers(model) for g in opt.param_groups} == {None}
    assert "forward" not in vars(model.critic) and "action_log_prob" not in vars(model.actor)
    assert tqc_module.quantile_huber_loss is loss


def test_measure_times_every_variant_against_the_baseline_in_one_run():
    rows = update_speed.measure(TASK, ("fused",), rounds=1, updates=2, warmup=200, n_envs=2, log=lambda _: None)
    assert [r.variant for r in rows] == ["baseline", "fused"]
    assert all(r.ms_per_update > 0 and len(r.rounds) == 1 for r in rows)
