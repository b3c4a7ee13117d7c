"""Camera renderer: ray-distance depth against a plane, exact object/robot segmentation, image formats."""

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.scenes import add_scene
from mobilemani_rl.envs import scene as scene_module
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.render import LABEL_OBJECT, LABEL_ROBOT, CameraRenderCfg, CameraRenderer
from mobilemani_rl.render.depth import depth_to_uint8, ray_factor, z_depth_from_buffer
from mobilemani_rl.render.segmentation import geom_labels


def plane_model(distance: float) -> mujoco.MjModel:
    """A 90° camera at the origin looking along +y at a wall whose face is `distance` away."""
    spec = mujoco.MjSpec()
    # +90° about x: camera x = world x, camera y = world z, so its viewing axis -z = world +y.
    spec.worldbody.add_camera(name="head_camera", fovy=90.0, quat=[np.sqrt(0.5), np.sqrt(0.5), 0, 0])
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[50, 0.5, 50], pos=[0, distance + 0.5, 0])
    return spec.compile()


@pytest.mark.parametrize("distance", [0.05, 0.7, 2.0, 4.5])
def test_depth_is_ray_distance_to_a_plane_within_a_centimetre(distance):
    model = plane_model(distance)
    cfg = CameraRenderCfg(width=96, height=64, cameras=("head_camera",))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)  # places the camera (mj_camlight)
    with CameraRenderer(model, cfg) as renderer:
        frame = renderer.render(data)["head_camera"]
    expected = distance * ray_factor(96, 64, 90.0)
    assert np.abs(frame.depth - expected).max() < 0.01
    assert frame.depth.dtype == np.float32 and frame.depth_image.dtype == np.uint8
    np.testing.assert_array_equal(frame.depth_image, depth_to_uint8(frame.depth, 5.0))
    assert not frame.segmentation.any()  # no object, no robot


def test_depth_conversions():
    factor = ray_factor(4, 2, 90.0)  # f = 1 px: pixel centres at +-0.5 and +-1.5 px from the axis
    assert factor.shape == (2, 4)
    np.testing.assert_allclose(factor[0, 0], np.sqrt(1 + 1.5**2 + 0.5**2), rtol=1e-6)
    near, far, z = 0.01, 50.0, np.array([0.01, 0.5, 3.0, 50.0])
    buffer = near * (far - z) / (z * (far - near))  # reversed-Z depth buffer
    np.testing.assert_allclose(z_depth_from_buffer(buffer, near, far), z, rtol=1e-5)
    np.testing.assert_array_equal(
        depth_to_uint8(np.array([-1.0, 0.0, 2.5, 5.0, 9.0]), 5.0), [0, 0, 128, 255, 255]
    )


@pytest.fixture(scope="module")
def tabletop_env(request):
    """test/box on a table in a realistic room, plus a probe camera straight above the object."""

    def add_scene_and_probe(spec, placement, obj, pick_y_offset, table_jitter=0.0):
        add_scene(spec, placement, obj, pick_y_offset, table_jitter)
        top = placement.support_height + 1.2
        spec.worldbody.add_camera(name="probe", pos=[0, 0.1, top], fovy=25.0)  # looks down -z

    patch = pytest.MonkeyPatch()
    patch.setattr(scene_module, "add_scene", add_scene_and_probe)
    try:
        env = MobileManiEnv(
            EnvCfg(num_envs=1, seed=3, task=TaskCfg("g1", "test/box", "open", scene="tabletop/02"))
        )
    finally:
        patch.undo()
    env.reset()
    return env


def render_all(env, cameras=("head_camera", "wrist_camera", "probe")):
    cfg = CameraRenderCfg(width=160, height=120, cameras=cameras)
    with CameraRenderer(env.model, cfg) as renderer:
        return renderer.render(env.batch.get_data(0))


def test_segmentation_sees_object_and_robot_where_expected(tabletop_env):
    frames = render_all(tabletop_env)
    counts = {name: np.bincount(f.segmentation.ravel(), minlength=3) for name, f in frames.items()}
    assert counts["head_camera"][LABEL_OBJECT] > 0 and counts["head_camera"][LABEL_ROBOT] > 0
    assert counts["wrist_camera"][LABEL_ROBOT] > 0  # the gripper's fingers
    assert counts["probe"][LABEL_OBJECT] > 0 and counts["probe"][LABEL_ROBOT] == 0
    for frame in frames.values():
        assert frame.rgb.shape == (120, 160, 3) and frame.rgb.dtype == np.uint8
        assert frame.segmentation.shape == (120, 160) and frame.segmentation.max() <= LABEL_ROBOT


@pytest.mark.parametrize("label", [LABEL_OBJECT, LABEL_ROBOT])
def test_segmentation_matches_exactly_the_pixels_the_part_covers(tabletop_env, label):
    """Pixels labelled `label` are exactly those whose depth grows when that part's geoms are hidden."""
    model = tabletop_env.model
    frames = render_all(tabletop_env, ("head_camera",))["head_camera"]
    hidden = geom_labels(model) == label
    groups = model.geom_group.copy()
    model.geom_group[hidden] = 3
    try:
        without = render_all(tabletop_env, ("head_camera",))["head_camera"]
    finally:
        model.geom_group[:] = groups
    covered = without.depth > frames.depth + 1e-4
    assert covered.any()
    np.testing.assert_array_equal(frames.segmentation == label, covered)


def test_renderer_enlarges_the_offscreen_buffer(tabletop_env):
    model = tabletop_env.model
    model.vis.global_.offwidth = model.vis.global_.offheight = 64
    with CameraRenderer(model, CameraRenderCfg(width=300, height=200)) as renderer:
        frame = renderer.render_camera(tabletop_env.batch.get_data(0), "head_camera")
    assert frame.rgb.shape == (200, 300, 3) and model.vis.global_.offwidth >= 300
