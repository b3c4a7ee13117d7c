"""MobileManiDataset: teacher rollouts -> raw HDF5 episodes -> rendered LeRobot v3 dataset."""
