"""A local, untrained SmolVLM backbone directory for LeRobot's SmolVLA, written without any download.

SmolVLA reads its VLM's config (`AutoConfig`) and processor (`AutoProcessor`: the tokenizer's image token ids)
from `--policy.vlm_model_name`, and its pre-processor loads the tokenizer from it (`AutoTokenizer`), even with
`--policy.load_vlm_weights=false`; the default is a hub id. This writes those files, built from transformers'
SmolVLM classes and a byte-level tokenizer made with `tokenizers`, so that

    python -m mobilemani_vla.smolvla_backbone outputs/lerobot/smolvlm_tiny
    lerobot-train --policy.type=smolvla --policy.vlm_model_name=outputs/lerobot/smolvlm_tiny \
        --policy.load_vlm_weights=false --policy.resize_imgs_with_padding=[128,128] ...

trains SmolVLA (its VLM and action expert) from scratch. The checkpoint keeps the directory's path
(config.json, policy_preprocessor.json), so evaluation needs it at the same place.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from mobilemani_rl.utils.cli import count, entry_point
from mobilemani_rl.utils.errors import InputError

# SmolVLM's special tokens, as its processor and SmolVLA look them up on the tokenizer.
IMAGE_TOKENS = {
    "fake_image_token": "<fake_token_around_image>",
    "global_image_token": "<global-img>",
    "image_token": "<image>",
    "end_of_utterance_token": "<end_of_utterance>",
}


def write_smolvlm_backbone(
    out: str | Path,
    hidden_size: int = 256,
    num_layers: int = 4,
    vision_hidden_size: int = 128,
    vision_layers: int = 2,
    image_size: int = 128,
    patch_size: int = 16,
) -> Path:
    """Writes config.json, the tokenizer and the processor of a SmolVLM of this size into `out`.

    Images reach the vision encoder at SmolVLA's `resize_imgs_with_padding`, which must be
    (image_size, image_size): the connector folds the square patch grid by `scale_factor` 2.
    """
    from tokenizers import Tokenizer, decoders, models, pre_tokenizers
    from transformers import LlamaConfig, PreTrainedTokenizerFast, SmolVLMConfig, SmolVLMVisionConfig
    from transformers.models.smolvlm import SmolVLMImageProcessor, SmolVLMProcessor, SmolVLMVideoProcessor

    if image_size % (2 * patch_size):
        raise InputError(f"--image-size {image_size} must be a multiple of 2 x patch_size {patch_size}")
    out = Path(out)
    # Byte-level BPE without merges: every string encodes (one token per UTF-8 byte), no vocabulary to learn.
    alphabet = sorted(pre_tokenizers.ByteLevel.alphabet())
    backend = Tokenizer(models.BPE(vocab={c: i for i, c in enumerate(alphabet)}, merges=[]))
    backend.pre_tokenizer = pre_tokenizers.ByteLevel(add_prefix_space=False)
    backend.decoder = decoders.ByteLevel()
    tokenizer = PreTrainedTokenizerFast(
        tokenizer_object=backend,
        bos_token="<|im_start|>",
        eos_token="<|im_end|>",
        pad_token="<|im_end|>",
        extra_special_tokens=IMAGE_TOKENS,
    )
    heads = max(1, hidden_size // 64)
    text = LlamaConfig(
        vocab_size=len(tokenizer),
        hidden_size=hidden_size,
        intermediate_size=4 * hidden_size,
        num_hidden_layers=num_layers,
        num_attention_heads=heads,
        num_key_value_heads=heads,
        head_dim=hidden_size // heads,
        max_position_embeddings=2048,
        pad_token_id=tokenizer.pad_token_id,
        tie_word_embeddings=False,  # SmolVLA freezes `lm_head` by name when the VLM trains
    )
    vision = SmolVLMVisionConfig(
        hidden_size=vision_hidden_size,
        intermediate_size=4 * vision_hidden_size,
        num_hidden_layers=vision_layers,
        num_attention_heads=max(1, vision_hidden_size // 64),
        image_size=image_size,
        patch_size=patch_size,
    )
    config = SmolVLMConfig(
        text_config=text.to_dict(),
        vision_config=vision.to_dict(),
        scale_factor=2,
        image_token_id=tokenizer.convert_tokens_to_ids(IMAGE_TOKENS["image_token"]),
        pad_token_id=tokenizer.pad_token_id,
        tie_word_embeddings=False,
    )
    size = {"longest_edge": image_size}
    processor = SmolVLMProcessor(
        image_processor=SmolVLMImageProcessor(size=size, max_image_size=size),
        tokenizer=tokenizer,
        video_processor=SmolVLMVideoProcessor(size=size, max_image_size=size),
        image_seq_len=(image_size // patch_size) ** 2 // 4,
    )
    config.save_pretrained(out)
    processor.save_pretrained(out)
    return out


@entry_point
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("out", type=Path, help="directory to write (pass it as --policy.vlm_model_name)")
    parser.add_argument("--hidden-size", type=count, default=256)
    parser.add_argument("--num-layers", type=count, default=4)
    parser.add_argument("--vision-hidden-size", type=count, default=128)
    parser.add_argument("--vision-layers", type=count, default=2)
    parser.add_argument("--image-size", type=count, default=128)
    args = parser.parse_args()
    out = write_smolvlm_backbone(
        args.out,
        hidden_size=args.hidden_size,
        num_layers=args.num_layers,
        vision_hidden_size=args.vision_hidden_size,
        vision_layers=args.vision_layers,
        image_size=args.image_size,
    )
    print(f"SmolVLM backbone (untrained) written to {out}")


if __name__ == "__main__":
    main()
