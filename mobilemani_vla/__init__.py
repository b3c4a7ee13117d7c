"""MobileManiVLA: PaliGemma/SigLIP backbone + cognition token + DiT action head."""

from mobilemani_data.video import quiet_video_libraries

quiet_video_libraries()
