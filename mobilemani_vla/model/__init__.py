"""MobileManiVLA's model: PaliGemma backbone with the cognition token, tokenizer, processor, DiT action head,
diffusion, the network that joins them, normalisation bounds and the adaptive action ensemble."""
