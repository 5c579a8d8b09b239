"""`python -m pdsketch_mech.bench world`: the figures exist, are sane, and land in the JSON."""
import json

from pdsketch_mech.bench import world
from pdsketch_mech.bench.__main__ import main


def test_world_figures_are_measured():
    figures = world.measure_world(seed=1, ik_queries=10, motion_queries=3, checks=200, snapshots=50)
    assert set(world.TARGETS) <= set(figures)
    assert figures["collision_checks_per_s"] > 100 and 0 < figures["snapshot_restore_ms"] < 50
    assert 0.5 <= figures["ik_success_rate"] <= 1 and 0 <= figures["motion_plan_success_rate"] <= 1
    lines = world.report(figures)
    assert len(lines) == len(world.TARGETS) and all(line.endswith(("ok", "MISSED")) for line in lines)


def test_world_command_writes_json(tmp_path, monkeypatch, capsys):
    measure = world.measure_world
    monkeypatch.setattr(world, "measure_world",
                        lambda seed: measure(seed, ik_queries=6, motion_queries=2, checks=100, snapshots=20))
    out = tmp_path / "world.json"
    assert main(["world", "--seed", "3", "--json", str(out)]) == 0
    document = json.loads(out.read_text())
    assert document["seed"] == 3 and set(world.TARGETS) <= set(document)
    assert "collision_checks_per_s" in capsys.readouterr().out
