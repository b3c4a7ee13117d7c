"""MobileManiVLA: PaliGemma/SigLIP backbone + cognition token + DiT action head."""
