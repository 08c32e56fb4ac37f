"""Images: writing (atomically) and reading through the library, showing
in notebooks, comparing."""

import os
import struct
import zlib

import numpy as np
import pytest

import lucent
from conftest import run_cli, SCENES


def gradient(w=8, h=4):
    y, x = np.mgrid[0:h, 0:w].astype(np.float32)
    return np.stack([x / w, y / h, np.full_like(x, 2.0)], axis=-1)


def png_pixels(data: bytes) -> "tuple[int, int, bytes]":
    """Width, height and RGB bytes of an 8-bit RGB PNG without
    interlacing, decoded with the standard library (filter types undone)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    w, h, depth, color = header[:4]
    assert (depth, color) == (8, 2)
    raw, stride, out, prev = zlib.decompress(idat), w * 3, bytearray(), bytearray(w * 3)
    for row in range(h):
        kind = raw[row * (stride + 1)]
        line = bytearray(raw[row * (stride + 1) + 1:(row + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 3] if i >= 3 else 0
            b, c = prev[i], prev[i - 3] if i >= 3 else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return w, h, bytes(out)


def test_exr_round_trips_bit_for_bit(tmp_path):
    image = gradient()
    image[0, 0] = [1e-30, 123456.0, -0.5]
    lucent.write(tmp_path / "g.exr", image)
    back = lucent.read(tmp_path / "g.exr")
    assert back.dtype == np.float32 and back.shape == (4, 8, 3)
    assert back.tobytes() == image.tobytes()


def test_png_is_tone_mapped_and_srgb_encoded(tmp_path):
    image = gradient()
    lucent.write(tmp_path / "g.png", image, tone_map="clamp", srgb=False)
    w, h, rgb = png_pixels((tmp_path / "g.png").read_bytes())
    assert (w, h) == (8, 4)
    # Linear, clamped: blue 2.0 → 255; red x/8 → round(255 x/8).
    assert rgb[2] == 255 and rgb[3 * 4] == round(255 * 4 / 8)
    lucent.write(tmp_path / "s.png", image, tone_map="classic", srgb=True)
    _, _, srgb = png_pixels((tmp_path / "s.png").read_bytes())
    # Classic divides by the largest channel (2.0): red 0.5/2 = 0.25 → sRGB 137.
    assert srgb[3 * 4] == 137 and srgb[3 * 4 + 2] == 255
    # PNG reads back decoded from sRGB.
    assert abs(lucent.read(tmp_path / "s.png")[0, 4, 0] - 0.25) < 0.005


def test_png_equals_the_cli_png(tmp_path):
    run_cli("render", str(SCENES / "showcase.toml"), "-o", str(tmp_path / "cli.png"), "--quiet",
            "--width=24", "--height=16", "--spp=2")
    scene = lucent.load(SCENES / "showcase.toml")
    lucent.write(tmp_path / "py.png", scene.render(width=24, height=16, spp=2, progress=False), scene.tone_map, scene.srgb)
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_bmp(tmp_path):
    lucent.write(tmp_path / "g.bmp", gradient())
    assert (tmp_path / "g.bmp").read_bytes()[:2] == b"BM"


def test_write_errors_leave_no_file(tmp_path):
    with pytest.raises(ValueError, match="unknown image extension '.jpg' \\(accepted: .png, .bmp, .exr, .hdr\\)"):
        lucent.write(tmp_path / "g.jpg", gradient())
    with pytest.raises(OSError, match="does not exist"):
        lucent.write(tmp_path / "no" / "g.png", gradient())
    with pytest.raises(ValueError, match="unknown tone map 'filmic'"):
        lucent.write(tmp_path / "g.png", gradient(), tone_map="filmic")
    with pytest.raises(ValueError, match="must have shape \\(height, width, 3\\), got \\(4, 8\\)"):
        lucent.write(tmp_path / "g.png", np.zeros((4, 8)))
    assert os.listdir(tmp_path) == []


def test_write_replaces_a_file_only_when_complete(tmp_path):
    path = tmp_path / "g.exr"
    path.write_bytes(b"old")
    with pytest.raises(ValueError):
        lucent.write(path, np.zeros((4, 8, 2)))
    assert path.read_bytes() == b"old"
    lucent.write(path, gradient())
    assert lucent.read(path).tobytes() == gradient().tobytes()
    assert os.listdir(tmp_path) == ["g.exr"]


def test_read_errors(tmp_path):
    with pytest.raises(OSError, match="cannot read"):
        lucent.read(tmp_path / "none.exr")
    (tmp_path / "x.exr").write_bytes(b"garbage")
    with pytest.raises(ValueError, match="cannot decode '.*x.exr': Format error decoding OpenExr"):
        lucent.read(tmp_path / "x.exr")


def test_accepts_other_dtypes_and_layouts(tmp_path):
    image = gradient().astype(np.float64)[:, ::-1]  # not contiguous
    lucent.write(tmp_path / "g.exr", image)
    assert lucent.read(tmp_path / "g.exr").tobytes() == np.ascontiguousarray(image, dtype=np.float32).tobytes()


def test_show_displays_as_png_in_notebooks(tmp_path):
    shown = lucent.show(gradient(), tone_map="clamp", srgb=False)
    assert repr(shown) == "<lucent.Image 8×4, tone_map='clamp', srgb=False>"
    lucent.write(tmp_path / "g.png", gradient(), tone_map="clamp", srgb=False)
    assert shown._repr_png_() == (tmp_path / "g.png").read_bytes()
    assert np.asarray(shown).tobytes() == gradient().tobytes()
    with pytest.raises(ValueError, match="unknown tone map"):
        lucent.show(gradient(), tone_map="x")


def test_diff_figures():
    a, b = gradient(), gradient()
    b[1, 2, 1] += 0.5
    d = lucent.diff(a, b)
    assert d["max_at"] == [2, 1] and d["max_channel"] == "g"
    assert d["max_abs_error"] == pytest.approx(0.5)
    assert d["mse"] == pytest.approx(0.25 / (8 * 4 * 3))
    assert (d["width"], d["height"], d["nonfinite"]) == (8, 4, 0)
    with pytest.raises(ValueError, match="cannot compare a 8×4 image with a 4×4 one"):
        lucent.diff(a, a[:, :4])
