"""MobileManiVLA: PaliGemma/SigLIP backbone + cognition token + DiT action head."""

from mobilemani_rl.utils.video_logs import quiet_video_libraries

quiet_video_libraries()
