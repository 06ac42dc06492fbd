"""bench.restir end to end at a tiny setting: every strategy validated against the reference and
timed, the targets read off the curves, the lit surfaces of the street told from its windows."""

from __future__ import annotations

import json

import numpy as np
import pytest

from bench import restir
from wgputrace import load_scene

pytestmark = pytest.mark.gpu


def test_the_street_s_lit_surfaces_leave_out_the_emitters_it_sees():
    scene = load_scene("night_street")
    lit = restir.lit_surfaces(scene, 32, 32)
    # a quarter of the view is windows, lamps and their edges; the rest is street and walls
    assert 0.5 < lit.mean() < 0.95


def test_a_small_run_files_every_strategy_and_target(tmp_path, capsys):
    assert restir.main(["--scenes", "cornell", "--no-sweep", "--max-spp", "16", "--out", str(tmp_path)]) == 0
    (path,) = tmp_path.glob("restir_*.json")
    result = json.loads(path.read_text())
    strategies = result["table"]["cornell"]["strategies"]
    assert set(strategies) == {strategy.label for strategy in restir.STRATEGIES}
    assert not result["validation_failed"] and not result["skipped"]
    efficiency = result["gains"]["cornell"]["restir/sobol_efficiency_over_mis/sobol"]
    assert efficiency == pytest.approx(result["measured"]["cornell_restir_efficiency_over_mis"])
    assert np.isfinite(efficiency) and efficiency > 0
    assert result["met"]["cornell_restir_efficiency_over_mis"] == (efficiency >= 1.0)
    assert "cornell_restir_efficiency_over_mis" in capsys.readouterr().out
