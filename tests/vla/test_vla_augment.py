"""Train-time image augmentation: shifts keep each camera's RGB and depth aligned,
colour jitter leaves depth alone."""

import torch

from mobilemani_vla.data.augment import (
    AugmentCfg,
    augment_images,
    jitter_colour,
    random_convolution,
    shift_images,
)

CAMERAS = ["head_rgb", "head_depth", "wrist_rgb", "wrist_depth"]


def test_shift_moves_content_by_whole_pixels_and_replicates_edges():
    image = torch.arange(36.0).view(1, 1, 6, 6)
    moved = shift_images(image, torch.tensor([[2, -1]]))  # 2 right, 1 up
    assert torch.equal(moved[0, 0, 0:4, 2:], image[0, 0, 1:5, :4])
    assert torch.equal(moved[0, 0, :, 0], moved[0, 0, :, 1])  # left edge replicated
    assert torch.equal(moved[0, 0, 5], image[0, 0, 5, [0, 0, 0, 1, 2, 3]])  # bottom row replicated
    assert torch.equal(shift_images(image, torch.zeros(1, 2, dtype=torch.long)), image)


def test_rgb_and_depth_of_a_camera_shift_together_and_depth_keeps_its_values():
    torch.manual_seed(0)
    base = torch.rand(16, 1, 3, 32, 32).expand(16, 4, 3, 32, 32).contiguous()  # every camera the same image
    out = augment_images(base, CAMERAS, AugmentCfg(shift=4, brightness=0, contrast=0, saturation=0))
    assert torch.equal(out[:, 0], out[:, 1]) and torch.equal(out[:, 2], out[:, 3])  # aligned per camera
    assert not torch.equal(out[:, 0], out[:, 2])  # cameras shift independently
    jittered = augment_images(
        base, CAMERAS, AugmentCfg(shift=0, brightness=0.3, contrast=0.3, saturation=0.3)
    )
    assert torch.equal(jittered[:, 1], base[:, 1]) and torch.equal(jittered[:, 3], base[:, 3])
    assert (jittered[:, 0] - base[:, 0]).abs().mean() > 0.01
    assert jittered.min() >= 0 and jittered.max() <= 1


def test_colour_jitter_factors_stay_in_range_and_zero_config_is_the_identity():
    torch.manual_seed(0)
    grey = torch.full((64, 3, 8, 8), 0.5)
    brighter = jitter_colour(grey, AugmentCfg(shift=0, brightness=0.2, contrast=0, saturation=0))
    ratio = brighter[:, 0, 0, 0] / 0.5
    assert ratio.min() >= 0.8 - 1e-6 and ratio.max() <= 1.2 + 1e-6 and ratio.std() > 0.05
    off = AugmentCfg(shift=0, brightness=0, contrast=0, saturation=0)
    images = torch.rand(2, 4, 3, 8, 8)
    assert not off.enabled and augment_images(images, CAMERAS, off) is images


def test_random_convolution_recolours_its_share_of_rgb_images_only():
    torch.manual_seed(0)
    images = torch.rand(64, 4, 3, 16, 16)
    cfg = AugmentCfg(shift=0, brightness=0, contrast=0, saturation=0, random_conv=0.5)
    out = augment_images(images, CAMERAS, cfg)
    for k in (1, 3):  # depth keeps its values
        assert torch.equal(out[:, k], images[:, k])
    changed = (out[:, [0, 2]] != images[:, [0, 2]]).flatten(2).any(-1)
    assert 0.25 < changed.float().mean() < 0.75  # about half of the RGB images
    recoloured = out[:, [0, 2]][changed]
    assert recoloured.amin() == 0.0 and recoloured.amax() == 1.0  # each rescaled to [0, 1]
    flat = torch.ones(1, 3, 8, 8) * 0.5  # a uniform image stays uniform per channel (edges replicated)
    assert torch.allclose(random_convolution(flat, 1.0).flatten(2).std(-1), torch.zeros(1, 3), atol=1e-6)
