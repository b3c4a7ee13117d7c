"""Offline tokenizers: a local pretrained directory
(PaliGemma's Gemma tokenizer) or the project's word-level one.

The word-level tokenizer covers the fixed instruction language "<skill> <object category>" plus the prompt
template; it is deterministic (vocabulary order is fixed here) and saved with every checkpoint.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from tokenizers import Tokenizer, normalizers, pre_tokenizers, processors
from tokenizers.models import WordLevel
from transformers import AutoTokenizer, PreTrainedTokenizerBase, PreTrainedTokenizerFast

from mobilemani_rl.utils.errors import MissingFileError

SPECIAL_TOKENS = ("<pad>", "<eos>", "<bos>", "<unk>")
PROMPT_WORDS = ("what", "action", "should", "the", "robot", "take", "to", "?", "in", ":", "out")
LOCATION_WORDS = (
    "at",
    "top",
    "bottom",
    "left",
    "right",
    "middle",
    "center",
    "upper",
    "lower",
    "front",
    "back",
)
SKILL_WORDS = ("open", "close", "pull", "push", "pick")
# The 20 object categories, split into words ("washing_machine" -> "washing machine").
OBJECT_WORDS = (
    "box",
    "toilet",
    "laptop",
    "trashcan",
    "dishwasher",
    "oven",
    "microwave",
    "refrigerator",
    "washing",
    "machine",
    "car",
    "safe",
    "fridge",
    "cabinet",
    "window",
    "lever",
    "door",
    "round",
    "faucet",
    "table",
    "cart",
    "holistic",
    "ycb",
    "object",
)
WORD_VOCAB = SPECIAL_TOKENS + PROMPT_WORDS + LOCATION_WORDS + SKILL_WORDS + OBJECT_WORDS


def build_word_tokenizer(texts: Iterable[str] = ()) -> PreTrainedTokenizerFast:
    """The fixed vocabulary, extended (in sorted order, so deterministically) by any other words in `texts`,
    e.g. the dataset's task strings such as "pick cracker box"."""
    base = _normalizer()
    words = {
        w for text in texts for w, _ in pre_tokenizers.Whitespace().pre_tokenize_str(base.normalize_str(text))
    }
    vocab = {word: i for i, word in enumerate(WORD_VOCAB + tuple(sorted(words - set(WORD_VOCAB))))}
    tok = Tokenizer(WordLevel(vocab, unk_token="<unk>"))
    tok.normalizer = base
    tok.pre_tokenizer = pre_tokenizers.Whitespace()
    # Like Gemma: every prompt starts with <bos>.
    tok.post_processor = processors.TemplateProcessing(
        single="<bos> $A", special_tokens=[("<bos>", vocab["<bos>"])]
    )
    return PreTrainedTokenizerFast(
        tokenizer_object=tok,
        bos_token="<bos>",
        eos_token="<eos>",
        pad_token="<pad>",
        unk_token="<unk>",
        padding_side="left",
    )


def _normalizer() -> normalizers.Normalizer:
    return normalizers.Sequence([normalizers.Lowercase(), normalizers.Replace("_", " ")])


def load_tokenizer(path: str | Path | None, texts: Iterable[str] = ()) -> PreTrainedTokenizerBase:
    """A saved/pretrained tokenizer directory, or the word-level tokenizer over `texts` when `path` is
    None."""
    if path is None:
        return build_word_tokenizer(texts)
    if not Path(path).is_dir():
        raise MissingFileError(f"tokenizer directory {path} does not exist (set model.tokenizer_path)")
    tokenizer = AutoTokenizer.from_pretrained(str(path), local_files_only=True)
    tokenizer.padding_side = "left"  # the cognition token then sits at position -1 of every row
    return tokenizer
