//! Determinism: the image depends on the scene and its seed only, never on
//! the number of worker threads or on how rows are scheduled.

use lucent::prelude::*;

/// Every lucent feature that involves sampling or recursion: stratified
/// anti-aliasing (a non-square count, so Latin hypercube samples), mirrors,
/// a checker texture, an ellipsoid, triangles, every kind of light.
fn scene_text(seed: u64, spp: u32, lens: &str) -> String {
    format!(
        r#"
        [camera]
        eye = [0, 2.5, -8]
        look_at = [0, 1, 0]
        fov = 55
        {lens}

        [render]
        width = 37
        height = 23
        spp = {spp}
        max_depth = 4
        background = [0.1, 0.15, 0.2]
        seed = {seed}

        [ambient]
        intensity = 0.1

        [materials.floor.matte]
        checker = {{ even = [0.9, 0.9, 0.9], odd = [0.1, 0.1, 0.1], scale = 0.7 }}
        [materials.mirror.phong]
        color = [0.9, 0.9, 0.9]
        kd = 0.1
        ks = 0.7
        exponent = 60
        kr = 0.8
        [materials.red.matte]
        color = [0.9, 0.2, 0.1]
        [materials.blue.phong]
        color = [0.2, 0.3, 0.9]
        kr = 0.3

        [[point_light]]
        position = [-4, 6, -5]
        intensity = 0.8
        [[spot_light]]
        position = [3, 5, -2]
        direction = [-0.5, -1, 0.3]
        intensity = 30
        [[directional_light]]
        direction = [1, -2, 1]
        intensity = 0.4

        [[plane]]
        material = "floor"
        [[sphere]]
        center = [0, 1.2, 1]
        radius = 1.2
        material = "mirror"
        [[sphere]]
        center = [-2.2, 0.6, -0.5]
        radius = 0.6
        material = "red"
        [[sphere]]
        material = "blue"
        transform = [{{ scale = [0.4, 1, 0.6] }}, {{ rotate_z = 30 }}, {{ translate = [2.3, 1, -0.8] }}]
        [[triangle]]
        vertices = [[1, 0, 2], [4, 0, 3], [2.5, 2.5, 2.5]]
        normals = [[-0.5, 0.5, -1], [0.5, 0.5, -1], [0, 1, -0.3]]
        material = "red"
        "#
    )
}

fn scene(seed: u64, spp: u32, lens: &str) -> LoadedScene {
    parse_scene(&scene_text(seed, spp, lens), SceneFormat::Toml).unwrap()
}

fn render_threads(scene: &LoadedScene, threads: Option<usize>) -> RenderOutput {
    render(&scene.scene, &scene.settings, RenderOptions { threads, ..RenderOptions::default() }).unwrap()
}

/// Bit patterns of every channel of every pixel.
fn bits(film: &Film) -> Vec<[u32; 3]> {
    film.pixels().iter().map(|c| c.to_array().map(f32::to_bits)).collect()
}

fn assert_identical(a: &Film, b: &Film, what: &str) {
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    // `==` on the colours first (the brief's comparison), then on the bits,
    // which also tells 0.0 from -0.0 and catches NaN.
    for (i, (x, y)) in a.pixels().iter().zip(b.pixels()).enumerate() {
        assert!(x == y, "{what}: pixel {i} differs: {x} vs {y}");
    }
    assert!(bits(a) == bits(b), "{what}: images differ in their bits");
}

fn check_thread_counts(scene: &LoadedScene, what: &str) -> Film {
    let reference = render_threads(scene, Some(1));
    assert!(reference.film.pixels().iter().all(|c| c.is_finite()), "{what}: non-finite pixels");
    for threads in [Some(2), Some(3), None, Some(1)] {
        let out = render_threads(scene, threads);
        assert_identical(&reference.film, &out.film, &format!("{what}, threads {threads:?} vs 1"));
        assert_eq!(out.stats, reference.stats, "{what}, threads {threads:?}: ray counts");
    }
    reference.film
}

#[test]
fn the_image_does_not_depend_on_the_thread_count() {
    let film = check_thread_counts(&scene(7, 5, ""), "pinhole, 5 spp");
    // Not a blank image: the comparison above compared something.
    let distinct: std::collections::HashSet<_> = bits(&film).into_iter().collect();
    assert!(distinct.len() > 300, "{} distinct pixels", distinct.len());
}

#[test]
fn the_image_does_not_depend_on_the_thread_count_with_a_thin_lens() {
    let lens = "lens_radius = 0.4\nfocal_distance = 7";
    check_thread_counts(&scene(3, 4, lens), "thin lens, 4 spp");
    // One sample per pixel: the lens position still comes from the
    // generator, per pixel.
    check_thread_counts(&scene(3, 1, lens), "thin lens, 1 spp");
}

#[test]
fn same_seed_same_image_different_seed_different_image() {
    for (spp, lens) in [(4, ""), (7, ""), (4, "lens_radius = 0.4")] {
        let a = render_threads(&scene(11, spp, lens), None).film;
        let again = render_threads(&scene(11, spp, lens), Some(2)).film;
        assert_identical(&a, &again, "same seed");
        let b = render_threads(&scene(12, spp, lens), None).film;
        let differ = a.pixels().iter().zip(b.pixels()).filter(|(x, y)| x != y).count();
        // Jittered samples move every edge, texture border and highlight.
        assert!(differ > 50, "spp {spp} {lens:?}: only {differ} pixels differ between seeds 11 and 12");
    }
}

#[test]
fn one_sample_through_a_pinhole_ignores_the_seed() {
    // With one sample per pixel the ray goes through the pixel centre, and a
    // pinhole has no lens to sample: nothing random is left.
    let a = render_threads(&scene(1, 1, ""), None).film;
    let b = render_threads(&scene(99, 1, ""), Some(3)).film;
    assert_identical(&a, &b, "spp 1, seeds 1 and 99");
    // A lens brings randomness back.
    let lens = "lens_radius = 0.4\nfocal_distance = 4";
    let a = render_threads(&scene(1, 1, lens), None).film;
    let b = render_threads(&scene(99, 1, lens), None).film;
    assert!(a.pixels() != b.pixels(), "thin lens, spp 1: seeds 1 and 99 gave the same image");
}

#[test]
fn a_scene_built_in_code_renders_identically_across_threads() {
    let camera = Camera::new(Vec3::new(0.5, 1.0, -4.0), Vec3::ZERO, Vec3::Y, 50.0, 19, 13)
        .unwrap()
        .with_lens(ThinLens { radius: 0.2, focal_distance: 3.0 })
        .unwrap();
    let mut b = SceneBuilder::new(camera);
    let settings = RenderSettings { spp: 9, seed: 0xdead_beef, ..RenderSettings::default() };
    let chrome = b.add_material(Material::phong(Color::ONE, 0.2, 0.5, 40.0, 0.6).unwrap()).unwrap();
    let red = b.add_material(Material::matte(Color::new(0.9, 0.1, 0.1), 0.9).unwrap()).unwrap();
    b.add_shape(Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::IDENTITY, chrome).unwrap();
    b.add_shape(Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).unwrap(), Transform::IDENTITY, red).unwrap();
    b.add_light(Light::point(Vec3::new(3.0, 4.0, -3.0), Color::ONE, 20.0, Falloff::InverseSquare).unwrap());
    let scene = LoadedScene { scene: b.build().unwrap(), settings, files: Vec::new() };
    check_thread_counts(&scene, "scene built in code");
}
