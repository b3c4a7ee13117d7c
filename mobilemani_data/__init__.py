"""MobileManiDataset: teacher rollouts -> raw HDF5 episodes -> rendered LeRobot v3 dataset."""

from mobilemani_data.video import quiet_video_libraries

quiet_video_libraries()
