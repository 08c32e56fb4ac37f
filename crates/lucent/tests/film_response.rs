//! The film's response (pbrt-v4's `Film "rgb"`): `RenderSettings::film_scale`
//! multiplies every sample, `max_component` caps it, per sample, in the
//! render loop, deterministically.

use lucent::prelude::*;

/// A white sphere under a bright point light, in front of a background of
/// dyadic radiance (exact in the film's fixed point, even doubled).
fn scene(light: f32) -> LoadedScene {
    let text = format!(
        r#"
        [camera]
        eye = [0, 0, -5]
        look_at = [0, 0, 0]
        fov = 40
        [render]
        width = 24
        height = 16
        spp = 4
        background = [0.375, 0.25, 0.125]
        [materials.white.matte]
        color = [0.9, 0.8, 0.7]
        [[sphere]]
        material = "white"
        [[point_light]]
        position = [-3, 4, -5]
        intensity = {light}
        "#
    );
    parse_scene(&text, SceneFormat::Toml).unwrap()
}

fn render_with(loaded: &LoadedScene, settings: &RenderSettings, threads: usize) -> Film {
    render(&loaded.scene, settings, RenderOptions { threads: Some(threads), ..Default::default() }).unwrap().film
}

#[test]
fn a_scale_of_two_doubles_every_pixel() {
    let loaded = scene(40.0);
    let base = render_with(&loaded, &loaded.settings, 2);
    let settings = RenderSettings { film_scale: Color::splat(2.0), ..loaded.settings.clone() };
    let doubled = render_with(&loaded, &settings, 2);
    // One fixed-point unit per sample at most: the film rounds each
    // sample's contribution to 2⁻²⁰.
    let unit = 1.0 / (1u64 << 20) as f32;
    let mut exact = 0;
    for (b, d) in base.pixels().iter().zip(doubled.pixels()) {
        assert!((*d - 2.0 * *b).abs().max_element() <= unit + 2.0 * f32::EPSILON * b.max_element(), "{b} → {d}");
        exact += (*d == 2.0 * *b) as usize;
    }
    // The background is dyadic: doubled exactly.
    assert_eq!(base.pixel(0, 0), Color::new(0.375, 0.25, 0.125));
    assert_eq!(doubled.pixel(0, 0), Color::new(0.75, 0.5, 0.25));
    assert!(exact > base.pixels().len() / 4, "{exact}");
    // Per channel.
    let settings = RenderSettings { film_scale: Color::new(1.0, 0.0, 4.0), ..loaded.settings.clone() };
    let tinted = render_with(&loaded, &settings, 2);
    assert_eq!(tinted.pixel(0, 0), Color::new(0.375, 0.0, 0.5));
}

#[test]
fn a_clamp_caps_bright_samples_and_leaves_dim_ones() {
    let loaded = scene(400.0);
    let one_spp = RenderSettings { spp: 1, ..loaded.settings.clone() };
    let base = render_with(&loaded, &one_spp, 2);
    let clamped = render_with(&loaded, &RenderSettings { max_component: Some(1.0), ..one_spp.clone() }, 2);
    let unit = 1.0 / (1u64 << 20) as f32;
    let mut capped = 0;
    for (b, c) in base.pixels().iter().zip(clamped.pixels()) {
        if b.max_element() <= 1.0 {
            assert_eq!(b, c, "a dim sample is unchanged");
        } else {
            // One sample per pixel (box filter): the pixel is the sample,
            // scaled down to a largest component of 1, hue kept.
            capped += 1;
            assert!((c.max_element() - 1.0).abs() <= unit, "{b} → {c}");
            let expected = *b / b.max_element();
            assert!((*c - expected).abs().max_element() <= 2.0 * unit, "{b} → {c}, expected {expected}");
        }
    }
    assert!(capped > 10, "the light is bright enough to clamp: {capped} pixels");
}

#[test]
fn the_response_is_deterministic_across_thread_counts() {
    let loaded = scene(400.0);
    let settings = RenderSettings {
        film_scale: Color::new(0.5, 1.5, 2.0),
        max_component: Some(2.0),
        filter: lucent::film::Filter::Lanczos { radius: 2.0, tau: 2.0 },
        ..loaded.settings.clone()
    };
    let a = render_with(&loaded, &settings, 1);
    let b = render_with(&loaded, &settings, 3);
    assert_eq!(a.pixels(), b.pixels());
}

#[test]
fn invalid_responses_are_rejected() {
    let loaded = scene(1.0);
    for settings in [
        RenderSettings { film_scale: Color::new(1.0, f32::NAN, 1.0), ..loaded.settings.clone() },
        RenderSettings { film_scale: Color::splat(-1.0), ..loaded.settings.clone() },
        RenderSettings { max_component: Some(0.0), ..loaded.settings.clone() },
    ] {
        let e = render(&loaded.scene, &settings, RenderOptions::default()).unwrap_err();
        assert!(matches!(e, lucent::render::RenderError::FilmResponse(_)), "{e}");
    }
}
