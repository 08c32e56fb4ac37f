//! Auxiliary images (AOVs): analytic values on simple scenes, and the same
//! exactness as the colour (any thread count, resumed renders, partial
//! renders merged); filter importance sampling puts each sample in one
//! pixel.

use lucent::film::{Accumulator, Aov, AovImages, AovSet, Filter, PartialFilm, ToneMap};
use lucent::prelude::*;
use lucent::render::{render_into, render_partial};

const ALL: [Aov; 4] = Aov::ALL;

fn scene(body: &str) -> LoadedScene {
    parse_scene(body, SceneFormat::Toml).unwrap()
}

/// A diffuse plane facing the camera, filling the view.
fn plane() -> LoadedScene {
    scene(
        r#"
        [camera]
        eye = [0, 0, -5]
        look_at = [0, 0, 0]
        fov = 40
        [render]
        width = 16
        height = 12
        spp = 4
        integrator = "path"
        [materials.wall.diffuse]
        color = [0.5, 0.25, 0.125]
        [[plane]]
        point = [0, 0, 0]
        normal = [0, 0, -1]
        material = "wall"
        [[point_light]]
        position = [0, 0, -4]
        intensity = 3
        "#,
    )
}

fn with_aovs(loaded: &LoadedScene, aovs: &[Aov]) -> RenderSettings {
    RenderSettings { aovs: AovSet::of(aovs), ..loaded.settings.clone() }
}

fn render_with(loaded: &LoadedScene, settings: &RenderSettings, threads: usize) -> RenderOutput {
    render(&loaded.scene, settings, RenderOptions { threads: Some(threads), ..Default::default() }).unwrap()
}

fn pixel(images: &AovImages, aov: Aov, i: usize) -> Vec3 {
    let layer = images.layer(aov).unwrap();
    match aov {
        Aov::Depth => Vec3::splat(layer[i]),
        _ => Vec3::new(layer[3 * i], layer[3 * i + 1], layer[3 * i + 2]),
    }
}

#[test]
fn a_diffuse_plane_gives_its_reflectance_normal_position_and_depth() {
    let loaded = plane();
    let out = render_with(&loaded, &with_aovs(&loaded, &ALL), 2);
    let eye = Vec3::new(0.0, 0.0, -5.0);
    // One fixed-point unit (2⁻²⁰) per sample at most.
    let unit = 4.0 / (1u64 << 20) as f32;
    for i in 0..16 * 12 {
        let albedo = pixel(&out.aovs, Aov::Albedo, i);
        assert!((albedo - Vec3::new(0.5, 0.25, 0.125)).abs().max_element() <= unit, "pixel {i}: albedo {albedo}");
        let n = pixel(&out.aovs, Aov::Normal, i);
        assert!((n - Vec3::new(0.0, 0.0, -1.0)).abs().max_element() <= unit, "pixel {i}: normal {n}");
        let p = pixel(&out.aovs, Aov::Position, i);
        assert!(p.z.abs() <= 1e-4, "pixel {i}: position {p}");
        // The mean distance of the samples is the distance of their mean
        // point to second order in the pixel's size.
        let depth = pixel(&out.aovs, Aov::Depth, i).x;
        assert!((depth - (p - eye).length()).abs() <= 1e-3 * depth, "pixel {i}: depth {depth}, point {p}");
        assert!(depth >= 5.0 - 1e-4 && depth <= 5.0 / (20f32.to_radians().cos() * 0.93), "pixel {i}: depth {depth}");
    }
    // The colour does not depend on which AOVs are made.
    assert_eq!(out.film, render_with(&loaded, &loaded.settings, 2).film);
    // Only what was asked for.
    let some = render_with(&loaded, &with_aovs(&loaded, &[Aov::Depth]), 1);
    assert_eq!(some.aovs.aovs.channel_names(), ["Z"]);
    assert_eq!(some.aovs.layer(Aov::Depth), out.aovs.layer(Aov::Depth));
}

#[test]
fn perfect_mirrors_are_followed_to_the_surface_they_show() {
    // A perfect mirror (Schlick reflectance 1 at every angle) at 45° sends
    // the camera's rays up to a diffuse ceiling.
    let loaded = scene(
        r#"
        [camera]
        eye = [0, 0, -5]
        look_at = [0, 0, 0]
        fov = 8
        [render]
        width = 8
        height = 8
        spp = 2
        integrator = "path"
        [materials.mirror.conductor]
        color = [1, 1, 1]
        [materials.ceiling.diffuse]
        color = [0.2, 0.4, 0.6]
        [[plane]]
        point = [0, 0, 0]
        normal = [0, 1, -1]
        material = "mirror"
        [[plane]]
        point = [0, 3, 0]
        normal = [0, -1, 0]
        material = "ceiling"
        "#,
    );
    let out = render_with(&loaded, &with_aovs(&loaded, &ALL), 2);
    let unit = 2.0 / (1u64 << 20) as f32;
    for i in 0..64 {
        let albedo = pixel(&out.aovs, Aov::Albedo, i);
        assert!((albedo - Vec3::new(0.2, 0.4, 0.6)).abs().max_element() <= 4.0 * unit, "pixel {i}: {albedo}");
        let n = pixel(&out.aovs, Aov::Normal, i);
        assert!((n - Vec3::new(0.0, -1.0, 0.0)).abs().max_element() <= unit, "pixel {i}: {n}");
        // Position and depth are the mirror's: the first hit.
        let p = pixel(&out.aovs, Aov::Position, i);
        assert!((p.y - p.z).abs() <= 1e-4 && p.length() < 0.8, "pixel {i}: {p}");
        let depth = pixel(&out.aovs, Aov::Depth, i).x;
        assert!((depth - 5.0).abs() < 0.5, "pixel {i}: {depth}");
    }
}

#[test]
fn escaping_rays_see_the_background_clamped_and_no_surface() {
    let loaded = scene(
        r#"
        [camera]
        eye = [0, 0, -5]
        look_at = [0, 0, 0]
        [render]
        width = 4
        height = 3
        spp = 1
        integrator = "path"
        background = [0.5, 2, 0.25]
        "#,
    );
    let out = render_with(&loaded, &with_aovs(&loaded, &ALL), 1);
    for i in 0..12 {
        assert_eq!(pixel(&out.aovs, Aov::Albedo, i), Vec3::new(0.5, 1.0, 0.25));
        for aov in [Aov::Normal, Aov::Position, Aov::Depth] {
            assert_eq!(pixel(&out.aovs, aov, i), Vec3::ZERO, "{aov}");
        }
    }
}

/// A scene with texture, glass and a wide filter, so that AOVs vary within
/// pixels and splat into neighbours.
fn busy() -> LoadedScene {
    scene(
        r#"
        [camera]
        eye = [0, 1, -4]
        look_at = [0, 0.5, 0]
        fov = 50
        [render]
        width = 24
        height = 16
        spp = 6
        integrator = "path"
        filter = { kind = "gaussian", radius = 1.5 }
        [materials.floor.matte]
        checker = { even = [0.8, 0.8, 0.8], odd = [0.1, 0.2, 0.3], scale = 0.5 }
        [materials.glass.dielectric]
        eta = 1.5
        [[plane]]
        point = [0, 0, 0]
        normal = [0, 1, 0]
        material = "floor"
        [[sphere]]
        center = [0, 0.6, 0]
        radius = 0.6
        material = "glass"
        [[point_light]]
        position = [2, 4, -3]
        intensity = 20
        "#,
    )
}

#[test]
fn aovs_are_exact_for_any_thread_count_resume_and_parts() {
    let loaded = busy();
    let settings = with_aovs(&loaded, &ALL);
    let one = render_with(&loaded, &settings, 1);
    let two = render_with(&loaded, &settings, 2);
    assert_eq!(one.aovs, two.aovs);
    assert_eq!(one.film, two.film);

    // Resumed: 2 samples, then 4 more.
    let (w, h) = (24, 16);
    let mut acc = Accumulator::with_aovs(w, h, settings.aovs).unwrap();
    let opts = |spp| RenderOptions { threads: Some(2), spp: Some(spp), ..Default::default() };
    render_into(&loaded.scene, &settings, &mut acc, opts(2)).unwrap();
    render_into(&loaded.scene, &settings, &mut acc, opts(6)).unwrap();
    assert_eq!(acc.to_aov_images(), one.aovs);

    // Parts of 0..1, 1..4, 4..6 merged.
    let parts: Vec<PartialFilm> = [0..1, 1..4, 4..6]
        .into_iter()
        .map(|r| render_partial(&loaded.scene, &settings, r, 7, RenderOptions::default()).unwrap().0)
        .collect();
    let merged = PartialFilm::merge_all(parts.iter().rev()).unwrap();
    assert_eq!(merged.aovs(), settings.aovs);
    assert_eq!(merged.to_aov_images(), one.aovs);
    assert_eq!(merged.to_accumulator().raw(), acc.raw());

    // An accumulator of other AOVs is refused.
    let mut other = Accumulator::with_aovs(w, h, AovSet::of(&[Aov::Depth])).unwrap();
    let e = render_into(&loaded.scene, &settings, &mut other, opts(1)).unwrap_err();
    assert!(
        e.to_string()
            .contains("holds the auxiliary images depth, but the render asks for albedo,normal,position,depth"),
        "{e}"
    );
    // ... and so is merging parts with different AOVs.
    let plain = render_partial(&loaded.scene, &loaded.settings, 6..7, 7, RenderOptions::default()).unwrap().0;
    assert!(merged.merge(&plain).unwrap_err().to_string().contains("auxiliary images"));
    assert_eq!(plain.to_aov_images().aovs, AovSet::NONE);
    let _ = ToneMap::Classic;
}

#[test]
fn filter_importance_sampling_puts_each_sample_in_its_own_pixel() {
    let loaded = busy();
    let spp = loaded.settings.spp;
    let splat = RenderSettings { aovs: AovSet::NONE, ..loaded.settings.clone() };
    let fis = RenderSettings { filter_importance: true, ..splat.clone() };
    let weight_sums = |settings: &RenderSettings| {
        let mut acc = Accumulator::new(24, 16).unwrap();
        render_into(&loaded.scene, settings, &mut acc, RenderOptions::default()).unwrap();
        acc.raw().chunks_exact(4).map(|s| s[3]).collect::<Vec<i64>>()
    };
    // A Gaussian is never negative: every sample adds weight 1 to one
    // pixel, so each pixel's weight is exactly its sample count; splatted,
    // the weights vary (and are smaller at the image's edges).
    let unit = 1i64 << 20;
    assert!(weight_sums(&fis).iter().all(|&w| w == spp as i64 * unit));
    let splatted = weight_sums(&splat);
    assert!(splatted.iter().any(|&w| w != splatted[0]));

    // Mitchell's negative lobes: weights ±1, and a uniform image stays
    // exactly uniform (an odd sample count keeps every weight sum nonzero).
    let flat = scene(
        r#"
        [camera]
        eye = [0, 0, -5]
        look_at = [0, 0, 0]
        [render]
        width = 9
        height = 7
        spp = 5
        integrator = "path"
        background = [0.375, 0.25, 0.125]
        filter = { kind = "mitchell" }
        "#,
    );
    let settings = RenderSettings { filter_importance: true, ..flat.settings.clone() };
    assert_eq!(settings.filter, Filter::Mitchell { radius: 2.0, b: 1.0 / 3.0, c: 1.0 / 3.0 });
    let out = render_with(&flat, &settings, 2);
    assert!(out.film.pixels().iter().all(|&p| p == Color::new(0.375, 0.25, 0.125)));
}
