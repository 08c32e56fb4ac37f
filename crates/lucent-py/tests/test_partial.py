"""Partial renders add up to the full render bit for bit, pickle, save and
refuse to mix with others."""

import itertools
import pickle

import numpy as np
import pytest

import lucent
from conftest import SCENES, run_cli, tiny_dict

ARGS = dict(width=24, height=16, spp=4, progress=False)


@pytest.fixture(scope="module")
def cornell():
    return lucent.load(SCENES / "cornell-box.toml")


def test_parts_add_up_to_the_full_render_in_any_order(cornell):
    full = cornell.render(**ARGS)
    parts = [cornell.render_partial(0, 2, **ARGS), cornell.render_partial(2, 3, **ARGS), cornell.render_partial(3, 4, **ARGS)]
    for order in itertools.permutations(parts):
        whole = order[0] + order[1] + order[2]
        assert whole.image().tobytes() == full.tobytes()
        assert (whole.spp, whole.ranges, whole.missing) == (4, [range(0, 4)], [])
    assert sum(parts).image().tobytes() == full.tobytes()
    assert sum(reversed(parts)) == sum(parts)


def test_stratified_parts_add_up_too():
    scene = lucent.Scene.from_dict(tiny_dict())  # Whitted, stratified sampler
    full = scene.render(spp=4, progress=False)
    whole = scene.render_partial(0, 2, spp=4, progress=False) + scene.render_partial(2, 4, spp=4, progress=False)
    assert whole.image().tobytes() == full.tobytes()


def test_parts_equal_the_cli_exr(cornell, tmp_path):
    run_cli("render", str(SCENES / "cornell-box.toml"), "-o", str(tmp_path / "cli.exr"), "--quiet",
            "--width=24", "--height=16", "--spp=4")
    whole = cornell.render_partial(0, 1, **ARGS) + cornell.render_partial(1, 4, **ARGS)
    assert whole.image().tobytes() == lucent.read(tmp_path / "cli.exr").tobytes()


def test_properties(cornell):
    part = cornell.render_partial(2, 5, width=24, height=16, spp=8, progress=False)
    assert (part.width, part.height, part.spp) == (24, 16, 3)
    assert part.ranges == [range(2, 5)]
    assert part.missing == [range(0, 2)]
    assert part.fingerprint == cornell.fingerprint(width=24, height=16, spp=8)
    image = part.image()
    assert image.dtype == np.float32 and image.shape == (16, 24, 3)
    assert repr(part) == f"<lucent.Partial 24×16, samples 2..5, fingerprint {part.fingerprint:#018x}>"
    gap = part + cornell.render_partial(7, 8, width=24, height=16, spp=8, progress=False)
    assert gap.ranges == [range(2, 5), range(7, 8)] and gap.missing == [range(0, 2), range(5, 7)]


def test_pickle_bytes_and_files_round_trip(cornell, tmp_path):
    part = cornell.render_partial(0, 2, **ARGS)
    again = pickle.loads(pickle.dumps(part))
    assert isinstance(again, lucent.Partial) and again == part
    assert lucent.Partial.from_bytes(part.to_bytes()) == part
    part.save(tmp_path / "p.lpart")
    assert (tmp_path / "p.lpart").read_bytes() == part.to_bytes()
    assert lucent.load_partial(tmp_path / "p.lpart").image().tobytes() == part.image().tobytes()


def test_the_cli_merges_parts_saved_from_python(cornell, tmp_path):
    cornell.render_partial(0, 3, **ARGS).save(tmp_path / "a.lpart")
    cornell.render_partial(3, 4, **ARGS).save(tmp_path / "b.lpart")
    run_cli("merge", str(tmp_path / "a.lpart"), str(tmp_path / "b.lpart"), "-o", str(tmp_path / "m.exr"))
    assert lucent.read(tmp_path / "m.exr").tobytes() == cornell.render(**ARGS).tobytes()


def test_overlapping_ranges_are_refused(cornell):
    with pytest.raises(lucent.PartialError, match="the parts overlap: samples 2 are in both \\(each sample index may be merged once\\)"):
        cornell.render_partial(0, 3, **ARGS) + cornell.render_partial(2, 4, **ARGS)


def test_different_scenes_are_refused(cornell):
    a = cornell.render_partial(0, 2, **ARGS)
    others = [
        cornell.render_partial(2, 4, **ARGS, seed=9),
        lucent.Scene.from_dict(tiny_dict()).render_partial(2, 4, width=24, height=16, progress=False),
    ]
    for other in others:
        with pytest.raises(lucent.PartialError, match="^the parts come from different renders \\(fingerprints "):
            a + other
    with pytest.raises(lucent.PartialError, match="their image sizes differ \\(24×16 and 16×16\\)"):
        a + cornell.render_partial(2, 4, width=16, height=16, spp=4, progress=False)


def test_damaged_data_is_refused(cornell, tmp_path):
    data = bytearray(cornell.render_partial(0, 1, **ARGS).to_bytes())
    data[100] ^= 1
    with pytest.raises(lucent.PartialError, match="partial render: the checksum does not match: the file is damaged or truncated"):
        lucent.Partial.from_bytes(bytes(data))
    with pytest.raises(lucent.PartialError, match="too short to be a lucent partial render"):
        lucent.Partial.from_bytes(b"LUCENTPT")
    (tmp_path / "x.lpart").write_bytes(b"not a partial render at all, but long enough to have a header....")
    with pytest.raises(lucent.PartialError, match="x.lpart: not a lucent partial render \\(.lpart\\): wrong magic bytes"):
        lucent.load_partial(tmp_path / "x.lpart")
    with pytest.raises(lucent.PartialError, match="none.lpart: cannot read it"):
        lucent.load_partial(tmp_path / "none.lpart")


def test_empty_range_and_adding_other_things(cornell):
    with pytest.raises(lucent.PartialError, match="a partial render must hold at least one sample \\(got the empty range 3..3\\)"):
        cornell.render_partial(3, 3, **ARGS)
    part = cornell.render_partial(0, 1, **ARGS)
    with pytest.raises(TypeError):
        part + 1
    assert 0 + part is part


def test_python_parts_merge_with_the_clis(cornell, tmp_path):
    run_cli("render", str(SCENES / "cornell-box.toml"), "--samples", "0..2", "-o", str(tmp_path / "cli.lpart"), "--quiet",
            "--width=24", "--height=16", "--spp=4")
    from_cli = lucent.load_partial(tmp_path / "cli.lpart")
    assert from_cli.fingerprint == cornell.fingerprint(**ARGS)
    assert from_cli == cornell.render_partial(0, 2, **ARGS)
    whole = from_cli + cornell.render_partial(2, 4, **ARGS)
    assert whole.image().tobytes() == cornell.render(**ARGS).tobytes()
