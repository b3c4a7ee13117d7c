"""MP4 preview of a few exported episodes, decoded from the dataset as a reader sees them:

    python -m mobilemani_data.preview robot=g1 [preview.episodes=3]

Each video frame tiles the head (top) and wrist (bottom) cameras: RGB, depth, segmentation (labels spread to
0–255 so they are visible), captioned with the episode's instruction.
"""

from __future__ import annotations

from pathlib import Path

import av
import cv2
import hydra
import numpy as np
from lerobot.datasets.lerobot_dataset import LeRobotDataset
from omegaconf import DictConfig

from mobilemani_data import schema
from mobilemani_data.config import DataCfg
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.video_logs import quiet_video_libraries


def tile(frame: dict) -> np.ndarray:
    rows = []
    for camera in schema.CAMERAS:
        images = []
        for modality in schema.MODALITIES:
            key = schema.image_key(camera, modality)
            if key not in frame:  # a stream the export left out (export.cameras / export.modalities)
                continue
            image = (frame[key].permute(1, 2, 0).numpy() * 255).round()
            if modality == "seg":
                image = image * (255.0 / (2 * schema.SEGMENTATION_SCALE))
            images.append(np.clip(image, 0, 255).astype(np.uint8))
        if images:
            rows.append(np.concatenate(images, axis=1))
    out = np.ascontiguousarray(np.concatenate(rows, axis=0))
    cv2.putText(out, frame["task"], (4, 14), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (255, 255, 255), 1, cv2.LINE_AA)
    return out


def write_preview(cfg: DataCfg) -> Path:
    ds = LeRobotDataset(cfg.export.repo_id, root=cfg.dataset_dir, video_backend="pyav")
    episodes = range(min(cfg.preview.episodes, ds.num_episodes))
    path = Path(cfg.preview.path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".partial.mp4")
    with av.open(str(tmp), "w") as container:
        stream = None
        for e in episodes:
            start, stop = ds.meta.episodes["dataset_from_index"][e], ds.meta.episodes["dataset_to_index"][e]
            for index in range(start, stop):
                image = tile(ds[index])
                if stream is None:
                    stream = container.add_stream("libx264", rate=schema.FPS)
                    stream.height, stream.width = image.shape[:2]
                    stream.pix_fmt = "yuv420p"
                container.mux(stream.encode(av.VideoFrame.from_ndarray(image, format="rgb24")))
        container.mux(stream.encode())
    tmp.replace(path)
    return path


@hydra.main(config_path="../conf", config_name="data", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    quiet_video_libraries()
    print(write_preview(to_dataclass(with_env_task(cfg), DataCfg).check()))


if __name__ == "__main__":
    main()
