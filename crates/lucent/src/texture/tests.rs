//! Tests of the texture classes (the image, MIP map and mapping files have
//! their own).

use super::*;

fn uv(u: f32, v: f32) -> TextureContext {
    TextureContext::from_uv(Vec2::new(u, v))
}

fn f(v: f32) -> FloatTexture {
    FloatTexture::Constant(v)
}

fn c(c: Color) -> Texture {
    Texture::Constant(c)
}

#[test]
fn checker_alternates() {
    let t = Texture::Checker { even: Color::ONE, odd: Color::ZERO, scale: 2.0 };
    assert_eq!(t.evaluate(&uv(0.5, 0.5)), Color::ONE);
    assert_eq!(t.evaluate(&uv(2.5, 0.5)), Color::ZERO);
    assert_eq!(t.evaluate(&uv(-0.5, 0.5)), Color::ZERO);
    assert_eq!(t.evaluate(&uv(-0.5, -0.5)), Color::ONE);
}

#[test]
fn checkerboard_2d_squares_and_mapping() {
    let red = Color::new(1.0, 0.0, 0.0);
    let t = Texture::checkerboard(TextureMapping::default(), c(red), c(Color::ZERO));
    assert_eq!(t.evaluate(&uv(0.5, 0.5)), red);
    assert_eq!(t.evaluate(&uv(1.5, 0.5)), Color::ZERO);
    assert_eq!(t.evaluate(&uv(1.5, 1.5)), red);
    assert_eq!(t.evaluate(&uv(-0.5, 0.5)), Color::ZERO);
    // uscale 2: u = 0.6 → s = 1.2, an odd square.
    let t = FloatTexture::checkerboard(TextureMapping::uv(2.0, 1.0, 0.0, 0.0), f(1.0), f(0.0));
    assert_eq!(t.evaluate(&uv(0.6, 0.1)), 0.0);
    assert_eq!(t.evaluate(&uv(0.4, 0.1)), 1.0);
}

#[test]
fn checkerboard_filters_across_edges() {
    let t = FloatTexture::checkerboard(TextureMapping::default(), f(0.0), f(1.0));
    // ∂u/∂x = 1/3: triangle half-width ½ centred on the edge s = 1 → ½.
    let ctx = uv(1.0, 0.5).with_differentials(Vec3::ZERO, Vec3::ZERO, 1.0 / 3.0, 0.0, 0.0, 0.0);
    assert!((t.evaluate(&ctx) - 0.5).abs() < 1e-6);
    // Half-width 0.3 at s = 0.9: the triangle's tail beyond s = 1 holds
    // (0.2²/2)/0.3² = 2/9 of its area, which reads tex2.
    let ctx = uv(0.9, 0.5).with_differentials(Vec3::ZERO, Vec3::ZERO, 0.2, 0.0, 0.0, 0.0);
    assert!((t.evaluate(&ctx) - 2.0 / 9.0).abs() < 1e-5, "{}", t.evaluate(&ctx));
    // Well inside a square the filter changes nothing.
    let ctx = uv(0.5, 0.5).with_differentials(Vec3::ZERO, Vec3::ZERO, 0.1, 0.0, 0.0, 0.1);
    assert_eq!(t.evaluate(&ctx), 0.0);
}

#[test]
fn checkerboard_3d_cubes_in_texture_space() {
    let t = Texture::checkerboard_3d(&Transform::IDENTITY, c(Color::ONE), c(Color::ZERO));
    let at = |p: Vec3| TextureContext::new(p, Vec3::Z, Vec2::ZERO);
    assert_eq!(t.evaluate(&at(Vec3::splat(0.5))), Color::ONE);
    assert_eq!(t.evaluate(&at(Vec3::new(1.5, 0.5, 0.5))), Color::ZERO);
    assert_eq!(t.evaluate(&at(Vec3::new(1.5, 1.5, -0.5))), Color::ZERO);
    // Cubes twice as large under a CTM scaling by 2.
    let t = FloatTexture::checkerboard_3d(&Transform::scale(Vec3::splat(2.0)).unwrap(), f(1.0), f(0.0));
    assert_eq!(t.evaluate(&at(Vec3::new(1.5, 0.5, 0.5))), 1.0);
    assert_eq!(t.evaluate(&at(Vec3::new(2.5, 0.5, 0.5))), 0.0);
}

#[test]
fn bilerp_corners_and_interior() {
    let t = FloatTexture::bilerp(TextureMapping::default(), 1.0, 2.0, 3.0, 4.0);
    assert_eq!(t.evaluate(&uv(0.0, 0.0)), 1.0);
    assert_eq!(t.evaluate(&uv(0.0, 1.0)), 2.0);
    assert_eq!(t.evaluate(&uv(1.0, 0.0)), 3.0);
    assert_eq!(t.evaluate(&uv(1.0, 1.0)), 4.0);
    // ⅜·1 + ⅛·3 + ⅜·2 + ⅛·4 = 2.
    assert_eq!(t.evaluate(&uv(0.25, 0.5)), 2.0);
    let b = Texture::bilerp(TextureMapping::default(), Color::X, Color::Y, Color::Z, Color::ONE);
    assert_eq!(b.evaluate(&uv(0.5, 0.5)), Color::new(0.5, 0.5, 0.5));
}

#[test]
fn mix_blends_by_a_float_texture() {
    let t = Texture::mix(
        c(Color::ONE),
        c(Color::ZERO),
        FloatTexture::bilerp(TextureMapping::default(), 0.0, 0.0, 1.0, 1.0),
    );
    // amount = s.
    assert_eq!(t.evaluate(&uv(0.25, 0.7)), Color::splat(0.75));
    assert_eq!(t.evaluate(&uv(1.0, 0.7)), Color::ZERO);
    let t = FloatTexture::mix(f(2.0), f(4.0), f(0.25));
    assert_eq!(t.evaluate(&uv(0.0, 0.0)), 2.5);
}

#[test]
fn direction_mix_at_a_known_normal() {
    let t = FloatTexture::direction_mix(f(1.0), f(0.0), Vec3::Y, &Transform::IDENTITY).unwrap();
    let at = |n: Vec3| TextureContext::new(Vec3::ZERO, n, Vec2::ZERO);
    // |n·dir| = 0.6 → 0.6·tex1 + 0.4·tex2.
    assert!((t.evaluate(&at(Vec3::new(0.0, 0.6, 0.8))) - 0.6).abs() < 1e-7);
    assert_eq!(t.evaluate(&at(Vec3::new(0.0, -1.0, 0.0))), 1.0);
    assert_eq!(t.evaluate(&at(Vec3::X)), 0.0);
    // The direction is in texture space: rotated by the CTM (+y → −x),
    // and normalised.
    let t = Texture::direction_mix(c(Color::ONE), c(Color::ZERO), Vec3::new(0.0, 3.0, 0.0), &Transform::rotate_z(90.0))
        .unwrap();
    let v = t.evaluate(&at(Vec3::new(0.8, 0.6, 0.0)));
    assert!((v - Color::splat(0.8)).abs().max_element() < 1e-6, "{v}");
    assert!(Texture::direction_mix(c(Color::ONE), c(Color::ZERO), Vec3::ZERO, &Transform::IDENTITY).is_err());
}

#[test]
fn scale_multiplies_and_simplifies_like_pbrt() {
    let k = Color::new(0.2, 0.4, 0.6);
    assert_eq!(Texture::scale(c(k), f(1.0)), Texture::Constant(k));
    assert_eq!(Texture::scale(c(k), f(0.5)), Texture::Constant(k * 0.5));
    let var = FloatTexture::bilerp(TextureMapping::default(), 0.0, 0.0, 2.0, 2.0);
    let t = Texture::scale(c(k), var.clone());
    assert!(matches!(t, Texture::Scale { .. }));
    assert_eq!(t.evaluate(&uv(0.5, 0.0)), k);
    assert_eq!(t.evaluate(&uv(0.0, 0.0)), Color::ZERO);
    // Either side of a float scale may be the constant.
    assert_eq!(FloatTexture::scale(f(1.0), var.clone()), var);
    assert_eq!(FloatTexture::scale(f(3.0), f(0.5)), f(1.5));
    assert_eq!(FloatTexture::scale(var.clone(), f(3.0)).evaluate(&uv(0.5, 0.0)), 3.0);
}

fn tiny_image_texture(params: ImageTextureParams) -> Arc<ImageTexture> {
    let im = TextureImage::new(1, 2, 1, vec![0.25, 0.75]).unwrap(); // top 0.25, bottom 0.75
    Arc::new(ImageTexture::new(TextureMapping::default(), Arc::new(MipMap::new(im).unwrap()), params))
}

#[test]
fn a_constant_scale_folds_into_an_image() {
    let im = tiny_image_texture(ImageTextureParams::default());
    let t = Texture::scale(Texture::image(im.clone()), f(2.0));
    let Texture::Image(scaled) = &t else { panic!("expected an image texture, got {t:?}") };
    assert_eq!(scaled.params().scale, 2.0);
    assert!(Arc::ptr_eq(scaled.mipmap(), im.mipmap()));
    // v = 0.25 is the bottom texel (0.75).
    assert_eq!(t.evaluate(&uv(0.5, 0.25)), Color::splat(1.5));
    let t = FloatTexture::scale(f(4.0), FloatTexture::image(im));
    assert_eq!(t.evaluate(&uv(0.5, 0.75)), 1.0);
}

#[test]
fn nested_textures_are_shared() {
    let shared = Arc::new(Texture::Constant(Color::splat(0.5)));
    let amount = Arc::new(f(0.5));
    let a = Texture::mix(shared.clone(), shared.clone(), amount.clone());
    let b = Texture::scale(shared.clone(), Arc::new(FloatTexture::mix(f(0.0), f(1.0), amount.clone())));
    assert_eq!(Arc::strong_count(&shared), 4);
    assert_eq!(Arc::strong_count(&amount), 3);
    assert_eq!(a.evaluate(&uv(0.0, 0.0)), Color::splat(0.5));
    assert_eq!(b.evaluate(&uv(0.0, 0.0)), Color::splat(0.25));
}

#[test]
fn image_texture_from_a_file_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("quad.png");
    let png = ::image::RgbImage::from_fn(2, 2, |x, y| match (x, y) {
        (0, 0) => ::image::Rgb([255, 0, 0]),
        (1, 0) => ::image::Rgb([0, 255, 0]),
        (0, 1) => ::image::Rgb([0, 0, 255]),
        _ => ::image::Rgb([128, 128, 128]),
    });
    png.save(&path).unwrap();
    let cache = ImageCache::new();
    let map = cache.mipmap(&path, ColorEncoding::pbrt_default_for(&path)).unwrap();
    let tex = Texture::image(ImageTexture::new(TextureMapping::default(), map, ImageTextureParams::default()));
    // Image row 0 (red, green) is at the top: v near 1.
    assert_eq!(tex.evaluate(&uv(0.25, 0.75)), Color::X);
    assert_eq!(tex.evaluate(&uv(0.75, 0.75)), Color::Y);
    assert_eq!(tex.evaluate(&uv(0.25, 0.25)), Color::Z);
    let grey = tex.evaluate(&uv(0.75, 0.25));
    assert!((grey - Color::splat(0.2158605)).abs().max_element() < 1e-6, "{grey}");
}

#[test]
fn footprint_context() {
    let ctx = TextureContext::new(Vec3::X, Vec3::Z, Vec2::new(0.5, 0.5)).with_footprint(0.1, Vec3::Y, Vec3::Z * 2.0);
    assert_eq!((ctx.dudx, ctx.dudy, ctx.dvdx, ctx.dvdy), (0.1, 0.0, 0.0, 0.1));
    assert_eq!(ctx.dpdx, Vec3::Y * 0.1);
    assert_eq!(ctx.dpdy, Vec3::Z * 0.2);
    let plain = TextureContext::from_uv(Vec2::new(0.5, 0.5));
    assert_eq!((plain.p, plain.n, plain.dpdx, plain.dudx), (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, 0.0));
}
