"""The real Rerun viewer, headless (software Vulkan), on a real trial recording with the
default layout: every view of the layout is there, shows data of the recording, and reports
no error; the screenshot is a real picture."""

from __future__ import annotations

import numpy as np
import pytest

from dart_reach.recording import rrd as rec
from dart_reach.recording.layout import PANELS
from dart_reach.robots import evolved_pre
from dart_reach.evolution.settings import standard_trial
from dart_reach.evolution.genome import ParamGroup, decode
from dart_reach.viewing.headless import HeadlessViewer, renderer_missing
from dart_reach.model.task import Trial, network_for
from dart_reach.model.world import World

pytestmark = pytest.mark.skipif(renderer_missing() is not None,
                                reason=f"no headless renderer here: {renderer_missing()}")


def test_every_view_of_the_layout_has_data_and_no_error(tmp_path):
    world = World()
    cfg = standard_trial("pre")
    network = network_for(decode(evolved_pre()[0][0], {ParamGroup.DIRECT}), cfg)
    data = Trial(world, cfg).run(network, 4, world.sector_point(4, 0.5, 0.5))
    info = rec.TrialInfo("standard", "pre", 0, 0, 4, 20, "systematic", "normal")
    path = rec.write_rrd(tmp_path / "t.rrd",
                         rec.trial_rrd(data, info, rec.RobotModel(world), blueprint=False))
    layout = rec.write_blueprint(tmp_path / "trial.rbl")
    with HeadlessViewer() as viewer:
        state = viewer.show(path, layout, sim_time_s=9.0)
        shot = viewer.screenshot(tmp_path / "shot.png")
        schema = viewer.client.get_recording_schema()
    views = {v.name: v for v in state.views}
    expected = {name for name, _ in PANELS} | {"robot and ball", "hand and ball paths"}
    assert set(views) == expected
    assert all(not v.reports for v in views.values()), {n: v.reports for n, v in views.items()}
    logged = str(schema)
    for name, entities in PANELS:
        assert all(f"/{e}" in logged for e in entities), name  # each panel's data is there
    from matplotlib.image import imread

    pixels = imread(shot)
    assert pixels.shape[0] >= 800 and pixels.shape[1] >= 1200
    assert np.unique(pixels.reshape(-1, pixels.shape[-1])[::97], axis=0).shape[0] > 50
