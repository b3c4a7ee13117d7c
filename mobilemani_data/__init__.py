"""MobileManiDataset: teacher rollouts -> raw HDF5 episodes -> rendered LeRobot v3 dataset."""

from mobilemani_rl.utils.video_logs import quiet_video_libraries

quiet_video_libraries()
