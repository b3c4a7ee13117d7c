"""MobileManiVLA building blocks: DiT head, cognition backbone, diffusion, normaliser, tokenizer, configs."""

import numpy as np
import pytest
import torch
from transformers.models.paligemma.modeling_paligemma import PaliGemmaModel, create_causal_mask_mapping

from mobilemani_vla.config import ModelCfg, VLACfg, compose_vla_cfg
from mobilemani_vla.model.backbone import CognitionBackbone, paligemma_config, prefix_lm_masks
from mobilemani_vla.model.diffusion import make_scheduler
from mobilemani_vla.model.dit import DiT
from mobilemani_vla.model.network import build_model
from mobilemani_vla.model.normalizer import Normalizer
from mobilemani_vla.model.tokenizer import build_word_tokenizer, load_tokenizer


def count(module: torch.nn.Module) -> int:
    return sum(p.numel() for p in module.parameters())


def test_default_yaml_equals_dataclass_defaults():
    assert compose_vla_cfg([]) == VLACfg()


def test_bad_choices_stop_with_the_valid_ones():
    with pytest.raises(ValueError, match="head_rgb.*wrist_seg"):
        compose_vla_cfg(["inputs.cameras=[head_ir]"])
    with pytest.raises(Exception, match="xhand"):
        compose_vla_cfg(["robot=h1"])
    assert compose_vla_cfg(["robot=xhand"]).action_dim == 18


def test_dit_b_size_with_a_paligemma2_condition():
    dit = DiT("B", action_dim=7, chunk=16, cond_dim=2304, guidance=True)
    assert 85e6 <= count(dit) <= 92e6, count(dit)
    assert dit.cond_embed.null.shape == (2304,)  # null embedding sized to the real condition


def test_dit_starts_at_zero_noise_and_drops_conditions():
    torch.manual_seed(0)  # batch sizes 3 and 1 round differently: a fixed draw keeps the tolerance meaningful
    dit = DiT("Ti", action_dim=7, chunk=16, cond_dim=64, guidance=True)
    x, t, c = torch.randn(3, 16, 7), torch.tensor([0, 50, 99]), torch.randn(3, 64)
    assert torch.equal(dit(x, t, c), torch.zeros(3, 16, 7))
    torch.nn.init.normal_(dit.out.weight)
    drop = torch.tensor([True, False, True])
    dropped = dit(x, t, c, drop=drop)
    assert torch.allclose(dropped[0], dit(x[:1], t[:1], torch.randn(1, 64), drop=drop[:1])[0], atol=1e-4)
    assert not torch.allclose(dropped[1], dit(x[1:2], t[1:2], torch.randn(1, 64))[0])


def test_state_dropout_withholds_the_state_of_that_share_of_training_samples_only(monkeypatch):
    torch.manual_seed(0)
    model = build_model(compose_vla_cfg(["inputs.state_dropout=0.5"]), build_word_tokenizer())
    seen = []
    monkeypatch.setattr(model.head, "loss", lambda actions, cognition, state: seen.append(state))
    monkeypatch.setattr(model, "condition", lambda batch: (None, torch.ones(400, 8)))
    model.train()
    model({"actions": None})
    model.eval()
    model({"actions": None})
    withheld = (seen[0] == 0).all(dim=1)
    assert torch.equal(seen[0][~withheld], torch.ones(int((~withheld).sum()), 8))
    assert 0.4 < withheld.float().mean() < 0.6
    assert torch.equal(seen[1], torch.ones(400, 8))  # evaluation always sees the state


def test_paligemma2_3b_on_the_meta_device():
    cfg = compose_vla_cfg(
        ["vla/model=paligemma2_3b", "model.pretrained_path=null", "model.tokenizer_path=null"]
    )
    with torch.device("meta"):
        model = build_model(cfg, build_word_tokenizer())
    backbone, head = count(model.backbone), count(model.head)
    # SigLIP-So400m (~0.41B) + Gemma-2-2B (~2.61B incl. the 257k x 2304 embedding) = ~3.03B.
    assert 2.95e9 <= backbone <= 3.1e9, backbone
    assert 85e6 <= head <= 92e6, head
    assert model.backbone.tokens_per_image == 256 and model.backbone.width == 2304
    assert next(model.parameters()).is_meta


@pytest.fixture(scope="module")
def backbone():
    torch.manual_seed(0)
    tokenizer = build_word_tokenizer()
    return CognitionBackbone(
        PaliGemmaModel(paligemma_config(ModelCfg())), tokenizer.eos_token_id
    ).eval(), tokenizer


def test_cognition_token_reads_the_prefix_and_leaves_it_unchanged(backbone):
    model, tokenizer = backbone
    enc = tokenizer(
        ["open box", "what action should the robot take to pull cart?"], padding=True, return_tensors="pt"
    )
    pixels = torch.rand(2, 3, 3, 32, 32)
    states = []
    hook = model.vlm.register_forward_hook(lambda m, i, o: states.append(o.last_hidden_state))
    with torch.no_grad():
        first = model(pixels, enc.input_ids, enc.attention_mask)
        model.cognition.add_(1.0)
        model(pixels, enc.input_ids, enc.attention_mask)
        model.cognition.sub_(1.0)
        alone = model(pixels[:1], *tokenizer(["open box"], return_tensors="pt").values())
        other = pixels.clone()
        other[0, 2] = torch.rand(3, 32, 32)
        moved = model(other, enc.input_ids, enc.attention_mask)
    hook.remove()
    # K cameras x 16 patches, prompt, cognition
    assert states[0].shape[1] == 3 * 16 + enc.input_ids.shape[1] + 1
    assert torch.equal(states[0][:, :-1], states[1][:, :-1])  # the prefix never sees the cognition token
    assert not torch.allclose(states[0][:, -1], states[1][:, -1])
    assert torch.allclose(first[0], alone[0], atol=1e-5)  # left padding does not change the feature
    assert not torch.allclose(first[0], moved[0])  # it sees every camera


def test_prefix_lm_masks_are_paligemmas_own_for_any_padding(backbone):
    config = backbone[0].vlm.config
    assert config.text_config._attn_implementation == "sdpa"  # the implementation that takes them
    generator = torch.Generator().manual_seed(0)
    for _ in range(20):
        prompt = torch.ones(4, 7, dtype=torch.long)
        for row in prompt:  # left padding of any length
            row[: int(torch.randint(0, 7, (1,), generator=generator))] = 0
        ones = prompt.new_ones(4, 1)
        mask = torch.cat([ones.expand(4, 6), prompt, ones], dim=1)
        positions = (mask.cumsum(-1) * mask).clamp(min=1)
        token_type = torch.cat([mask.new_zeros(4, 13), ones], dim=1)
        embeds = torch.zeros(4, mask.shape[1], 8)
        theirs = create_causal_mask_mapping(config, embeds, mask, None, positions, token_type, None, True)
        ours = prefix_lm_masks(mask, token_type, config.text_config.layer_types)
        assert ours.keys() == theirs.keys()
        for layer_type, expected in theirs.items():
            assert torch.equal(ours[layer_type], expected)


def test_features_equal_those_of_paligemmas_own_masking(backbone, monkeypatch):
    model, tokenizer = backbone
    prompts = tokenizer(
        ["open box", "what action should the robot take to pull cart?"], padding=True, return_tensors="pt"
    )
    pixels = torch.rand(2, 2, 3, 32, 32)
    with torch.no_grad():
        ours = model(pixels, prompts.input_ids, prompts.attention_mask)
        # PaliGemma's forward building the masks from the 2-D padding mask itself
        monkeypatch.setattr(model, "attention_masks", lambda embeds, mask, positions, token_type: mask)
        theirs = model(pixels, prompts.input_ids, prompts.attention_mask)
    assert torch.equal(ours, theirs)


def test_training_gradients_equal_those_of_paligemmas_own_masking(monkeypatch):
    cfg = compose_vla_cfg(["inputs.cameras=[head_rgb,wrist_rgb]"])
    torch.manual_seed(0)
    tokenizer = build_word_tokenizer()
    model = build_model(cfg, tokenizer).train()
    prompts = tokenizer(["open box", "pull the cart to the left"] * 2, padding=True, return_tensors="pt")
    batch = {
        "pixel_values": torch.rand(4, 2, 3, 32, 32),
        **prompts,
        "state": torch.rand(4, 9) * 2 - 1,
        "actions": torch.rand(4, cfg.diffusion.chunk, cfg.action_dim) * 2 - 1,
    }

    def gradients() -> dict[str, torch.Tensor]:
        model.zero_grad()
        torch.manual_seed(1)  # the same diffusion noise, timesteps and dropout draws
        model(batch).backward()
        return {name: p.grad.clone() for name, p in model.named_parameters() if p.grad is not None}

    ours = gradients()
    monkeypatch.setattr(
        model.backbone,
        "attention_masks",
        lambda embeds, mask, positions, token_type: create_causal_mask_mapping(
            model.backbone.vlm.config, embeds, mask, None, positions, token_type, None, is_training=True
        ),
    )
    theirs = gradients()
    assert ours.keys() == theirs.keys()
    assert all(torch.equal(ours[name], theirs[name]) for name in theirs)


def test_a_null_image_prediction_is_the_null_vectors_whatever_the_backbone_sees():
    torch.manual_seed(0)
    model = build_model(compose_vla_cfg(["inputs.states=[]"]), build_word_tokenizer()).eval()
    torch.nn.init.normal_(model.head.dit.out.weight, std=0.02)  # zero-initialised: every output 0
    features = iter([torch.randn(2, model.backbone.width), torch.randn(2, model.backbone.width)])
    model.condition = lambda batch: (next(features), None)

    def predict(null_image: bool) -> torch.Tensor:
        return model.predict({}, torch.Generator().manual_seed(3), null_image)

    assert torch.equal(predict(True), predict(True))  # two different image features, one prediction
    features = iter([torch.randn(2, model.backbone.width), torch.randn(2, model.backbone.width)])
    assert not torch.allclose(predict(False), predict(False))


def test_ddim_uses_cogacts_ten_leading_steps_and_an_oracle_recovers_x0():
    scheduler = make_scheduler(VLACfg().diffusion)
    scheduler.set_timesteps(10)
    assert scheduler.timesteps.tolist() == list(range(90, -1, -10))
    x0, noise = torch.rand(2, 16, 7) * 2 - 1, torch.randn(2, 16, 7)
    x = torch.randn(2, 16, 7)
    for t in scheduler.timesteps:  # the true epsilon of x relative to x0
        ab = scheduler.alphas_cumprod[t]
        eps = (x - ab.sqrt() * x0) / (1 - ab).sqrt()
        x = scheduler.step(eps, t, x, eta=0.0).prev_sample
    assert torch.allclose(x, x0, atol=1e-4)
    assert noise.shape == x.shape


def test_bounds_normaliser_round_trip(tmp_path):
    norm = Normalizer.fit({"a": np.array([[-2.0, 0.0], [2.0, 10.0], [0.0, 3.0]])})
    x = torch.tensor([[1.0, 5.0], [-3.0, 20.0]])
    y = norm.normalize("a", x)
    assert torch.allclose(y, torch.tensor([[0.5, 0.0], [-1.0, 1.0]]))
    norm.save(tmp_path / "n.json")
    back = Normalizer.load(tmp_path / "n.json").unnormalize("a", y)
    assert torch.allclose(back[0], x[0], atol=1e-5) and torch.allclose(back[1], torch.tensor([-2.0, 10.0]))


def test_word_tokenizer_is_deterministic_and_round_trips(tmp_path):
    a = build_word_tokenizer(["pick cracker box", "open table at top left"])
    b = build_word_tokenizer(["open table at top left", "pick cracker box"])
    assert a.get_vocab() == b.get_vocab()
    ids = a("Open WASHING_machine?").input_ids
    assert a.convert_ids_to_tokens(ids) == ["<bos>", "open", "washing", "machine", "?"]
    a.save_pretrained(tmp_path)
    again = load_tokenizer(tmp_path)
    assert again("pick cracker box").input_ids == a("pick cracker box").input_ids
    assert again.padding_side == "left" and np.all(np.array(ids) < 128)


def test_backbone_and_tokenizer_load_from_a_local_pretrained_directory(tmp_path):
    from transformers import PaliGemmaForConditionalGeneration

    torch.manual_seed(1)
    saved = PaliGemmaForConditionalGeneration(paligemma_config(ModelCfg()))
    saved.save_pretrained(tmp_path)
    build_word_tokenizer().save_pretrained(tmp_path)
    cfg = compose_vla_cfg([f"model.pretrained_path={tmp_path}", f"model.tokenizer_path={tmp_path}"])
    model = build_model(cfg, load_tokenizer(cfg.model.tokenizer_path))
    for name, value in saved.model.state_dict().items():
        assert torch.equal(model.backbone.vlm.state_dict()[name], value), name
    with pytest.raises(FileNotFoundError, match="pretrained_path"):
        build_model(
            compose_vla_cfg([f"model.pretrained_path={tmp_path / 'missing'}"]), build_word_tokenizer()
        )


def test_cpu_model_uses_exact_gelus_and_other_sizes_keep_the_tanh_approximation():
    cpu = compose_vla_cfg(["vla/model=cpu"]).model
    config = paligemma_config(cpu)
    assert config.vision_config.hidden_act == "gelu" and config.text_config.hidden_activation == "gelu"
    dit = DiT(cpu.dit, action_dim=7, chunk=16, cond_dim=128, guidance=True, gelu=cpu.dit_gelu)
    assert {m.approximate for m in dit.modules() if isinstance(m, torch.nn.GELU)} == {"none"}
    tiny = paligemma_config(ModelCfg())
    assert tiny.vision_config.hidden_act == "gelu_pytorch_tanh" and ModelCfg().dit_gelu == "tanh"
    with pytest.raises(ValueError, match="model.dit_gelu"):
        compose_vla_cfg(["model.dit_gelu=erf"])
