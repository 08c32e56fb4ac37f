//! Adaptive sampling: samples go where the noise is, and the image is
//! exactly the same for any thread count, pass size or resumption.

use lucent::film::adaptive::ADAPTIVE_MIN_SPP;
use lucent::film::{Accumulator, AovSet};
use lucent::prelude::*;
use lucent::render::{render_into, render_partial, RenderError};
use std::time::Duration;

/// A lit diffuse sphere in front of a uniform background: the background
/// has no noise at all, the sphere's soft shadow and penumbra a lot.
fn scene() -> LoadedScene {
    parse_scene(
        r#"
        [camera]
        eye = [0, 1, -4]
        look_at = [0, 0.5, 0]
        fov = 50
        [render]
        width = 32
        height = 24
        spp = 64
        integrator = "path"
        background = [0.25, 0.25, 0.25]
        adaptive = 0.05
        [materials.white.diffuse]
        color = [0.8, 0.8, 0.8]
        [[sphere]]
        center = [0, 0.6, 0]
        radius = 0.6
        material = "white"
        [[sphere]]
        center = [0, 3, -1]
        radius = 0.3
        material = "white"
        emission = [20, 20, 20]
        "#,
        SceneFormat::Toml,
    )
    .unwrap()
}

fn acc_of() -> Accumulator {
    Accumulator::with_layout(32, 24, AovSet::NONE, true).unwrap()
}

fn run(loaded: &LoadedScene, acc: &mut Accumulator, spp: u32, threads: usize, interval: Option<Duration>) {
    let options =
        RenderOptions { threads: Some(threads), spp: Some(spp), pass_interval: interval, ..Default::default() };
    render_into(&loaded.scene, &loaded.settings, acc, options).unwrap();
}

#[test]
fn flat_pixels_stop_at_the_first_decision_and_noisy_ones_go_on() {
    let loaded = scene();
    assert_eq!(loaded.settings.adaptive, Some(0.05));
    let mut acc = acc_of();
    run(&loaded, &mut acc, 64, 2, None);
    let counts = acc.sample_counts().unwrap();
    // The top corners see only the background (constant radiance, zero
    // error), far from the sphere: they stop after the first 16 samples.
    assert_eq!(counts[0], ADAPTIVE_MIN_SPP);
    assert_eq!(counts[31], ADAPTIVE_MIN_SPP);
    // Some pixels needed all 64.
    assert!(counts.contains(&64));
    let mean = counts.iter().map(|&c| c as f64).sum::<f64>() / counts.len() as f64;
    assert!(mean < 60.0, "{mean}");
    // Every count is a decision point or the target.
    assert!(counts.iter().all(|&c| c == 64 || (c >= 16 && c % 8 == 0)), "{counts:?}");
    // The stopped background is exact.
    assert_eq!(acc.to_film().pixel(0, 0), Color::splat(0.25));
}

#[test]
fn adaptive_renders_are_exact_for_any_threads_passes_and_resumption() {
    let loaded = scene();
    let mut one = acc_of();
    run(&loaded, &mut one, 64, 1, None);
    // Two threads, passes of any size (a tiny interval: one sample each).
    let mut many = acc_of();
    run(&loaded, &mut many, 64, 2, Some(Duration::from_nanos(1)));
    assert_eq!(one, many);
    // Resumed from 20, a point between two decisions, then from 40.
    let mut resumed = acc_of();
    run(&loaded, &mut resumed, 20, 2, None);
    run(&loaded, &mut resumed, 40, 2, None);
    run(&loaded, &mut resumed, 64, 2, None);
    assert_eq!(one, resumed);
    // The render function gives the same image.
    let out = render(&loaded.scene, &loaded.settings, RenderOptions::default()).unwrap();
    assert_eq!(out.film, one.to_film());
}

#[test]
fn what_adaptive_sampling_cannot_do_is_refused() {
    let loaded = scene();
    let e = render_partial(&loaded.scene, &loaded.settings, 0..8, 1, RenderOptions::default()).unwrap_err();
    assert!(matches!(e, RenderError::AdaptivePartial), "{e}");
    let stratified = RenderSettings { sampler: lucent::sampling::SamplerKind::Stratified, ..loaded.settings.clone() };
    let e = render(&loaded.scene, &stratified, RenderOptions::default()).unwrap_err();
    assert!(e.to_string().contains("needs the sobol or independent sampler"), "{e}");
    // An accumulator without adaptive state.
    let mut plain = Accumulator::new(32, 24).unwrap();
    let e = render_into(&loaded.scene, &loaded.settings, &mut plain, RenderOptions::default()).unwrap_err();
    assert!(e.to_string().contains("made without adaptive sampling"), "{e}");
}
