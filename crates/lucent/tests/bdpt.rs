//! Bidirectional path tracing against analytic answers and against the
//! path tracer: a closed emissive enclosure (every strategy, splats
//! included, must add up to the sum of the bounces), every strategy alone,
//! the Cornell box, a caustic, and determinism across threads, resumed and
//! partial renders.

use lucent::film::{Accumulator, AovSet, PartialFilm};
use lucent::integrator::BdptIntegrator;
use lucent::loader::{ImageDimension, SampleCount};
use lucent::prelude::*;
use lucent::render::{render_into, render_into_with, render_partial, IntegratorKind};

mod common;
use common::{film_stats, scene};

/// The camera inside a closed sphere of albedo ρ = ½ whose inside emits
/// Lₑ = ½: with at most `d` scattering vertices every pixel sees
/// `Lₑ·(1 + ρ + … + ρᵈ)`. Light reaches the camera by all strategies
/// (the lens is joined to light subpaths too), so this checks that the
/// weights of each path's strategies sum to one and that the splats of
/// light tracing are normalised.
fn enclosure(max_depth: u32, spp: u32) -> LoadedScene {
    scene(&format!(
        r#"
        [camera]
        eye = [0.3, -0.2, 0.1]
        look_at = [0, 0, 1]
        fov = 70
        [render]
        integrator = "bdpt"
        width = 16
        height = 12
        spp = {spp}
        max_depth = {max_depth}
        [materials.wall.diffuse]
        color = [0.5, 0.5, 0.5]
        [[sphere]]
        radius = 2
        material = "wall"
        emission = [0.5, 0.5, 0.5]
        two_sided = true
    "#
    ))
}

#[test]
fn closed_emissive_sphere_sums_every_bounce() {
    let s = enclosure(3, 64);
    assert_eq!(s.settings.integrator, IntegratorKind::Bdpt);
    let film = render(&s.scene, &s.settings, RenderOptions::default()).unwrap().film;
    let expected = 0.5 * (1.0 + 0.5 + 0.25 + 0.125);
    let (mean, worst) = film_stats(&film, expected);
    assert!((mean - expected as f64).abs() < 5e-3 * expected as f64, "image mean {mean}, expected {expected}");
    assert!(worst < 0.1 * expected, "a pixel is {worst} away from {expected}");
}

/// `s` rendered with the strategy `(sv, t)` alone, unweighted, at depth
/// `depth` ([`BdptIntegrator::with_only_strategy`]).
fn strategy_alone(s: &LoadedScene, depth: u32, sv: usize, t: usize) -> Film {
    let integrator = BdptIntegrator::new(&s.scene, depth).with_only_strategy(sv, t);
    let (w, h) = (s.scene.camera().width(), s.scene.camera().height());
    let mut acc = Accumulator::with_aovs(w, h, AovSet::NONE.with_light_image()).unwrap();
    render_into_with(&s.scene, &s.settings, &integrator, &mut acc, RenderOptions::default()).unwrap();
    acc.to_film()
}

/// The mean of channel `k` over the image.
fn channel_mean(f: &Film, k: usize) -> f64 {
    f.pixels().iter().map(|p| p[k] as f64).sum::<f64>() / f.pixels().len() as f64
}

/// Each strategy alone, unweighted, estimates all the light of paths with
/// its number of bounces: in the enclosure, `Lₑ·ρ²` for two.
#[test]
fn every_strategy_alone_converges_to_the_same_image() {
    let s = enclosure(2, 64);
    let expected = 0.5f32 * 0.25;
    for (sv, t) in [(0, 4), (1, 3), (2, 2), (3, 1)] {
        let (mean, _) = film_stats(&strategy_alone(&s, 2, sv, t), expected);
        assert!(
            (mean - expected as f64).abs() < 0.02 * expected as f64,
            "strategy s = {sv}, t = {t}: image mean {mean}, expected {expected}"
        );
    }
}

/// A caustic with an exact answer: a point light of intensity `I` above a
/// thin glass pane (straight transmission, no bending) over a diffuse floor
/// of albedo ρ, seen from a camera between the pane and the floor. Light
/// reaches the floor only through the pane, so a floor point at distance
/// `d` from the light, lit at angle θ, has radiance
/// `ρ/π · T(θ) · I cos θ / d²`, where `T = 1 − R'` with
/// `R' = R + (1 − R)² R / (1 − R²)`, `R` the Fresnel reflectance at θ (the
/// inter-reflections of a thin pane, pbrt-v4's `ThinDielectricBxDF`). A
/// path tracer cannot find this light at all (a point light behind a
/// specular surface); bidirectional path tracing finds it by light
/// tracing. With `max_depth = 2` the pane and the floor are the only
/// scattering events.
#[test]
fn a_point_light_through_a_pane_is_found_by_light_tracing() {
    use lucent::bsdf::fresnel::fr_dielectric;
    use lucent::geometry::{Vec2, Vec3};
    let (intensity, rho, eta) = (4.0f32, 0.6f32, 1.5f32);
    let light = Vec3::new(0.3, 1.6, 0.2);
    let body = |integrator: &str| {
        format!(
            r#"
        [camera]
        eye = [0, 1, 0.001]
        look_at = [0, 0, 0]
        fov = 90
        [render]
        integrator = "{integrator}"
        width = 16
        height = 16
        spp = 512
        max_depth = 2
        [materials.floor.diffuse]
        color = [{rho}, {rho}, {rho}]
        [materials.pane.thin_dielectric]
        eta = {eta}
        [[quad]]
        vertices = [[-50, 0, -50], [-50, 0, 50], [50, 0, 50], [50, 0, -50]]
        material = "floor"
        [[quad]]
        vertices = [[-50, 1.3, -50], [-50, 1.3, 50], [50, 1.3, 50], [50, 1.3, -50]]
        material = "pane"
        [[point_light]]
        position = [{}, {}, {}]
        intensity = {intensity}
        falloff = "inverse_square"
    "#,
            light.x, light.y, light.z
        )
    };
    let b = scene(&body("bdpt"));
    let film = render(&b.scene, &b.settings, RenderOptions::default()).unwrap().film;
    // The exact radiance of the floor point each pixel's centre sees.
    let camera = b.scene.camera();
    let expected = |x: u32, y: u32| {
        let ray = camera.generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), Vec2::splat(0.5));
        let p = ray.origin + ray.dir * (-ray.origin.y / ray.dir.y);
        let to = light - p;
        let cos = to.y / to.length();
        let r = fr_dielectric(cos, eta);
        let t = 1.0 - (r + (1.0 - r) * (1.0 - r) * r / (1.0 - r * r));
        rho / std::f32::consts::PI * t * intensity * cos / to.length_squared()
    };
    // Means over 4 × 4 blocks of pixels, against the expected ones.
    let (mut got_all, mut want_all) = (0.0f64, 0.0f64);
    for by in (0..16).step_by(4) {
        for bx in (0..16).step_by(4) {
            let (mut got, mut want) = (0.0f64, 0.0f64);
            for y in by..by + 4 {
                for x in bx..bx + 4 {
                    got += film.pixel(x, y).x as f64;
                    want += expected(x, y) as f64;
                }
            }
            assert!((got - want).abs() < 0.08 * want, "block ({bx}, {by}): {got} against {want}");
            got_all += got;
            want_all += want;
        }
    }
    assert!((got_all - want_all).abs() < 0.02 * want_all, "image: {got_all} against {want_all}");
    let p = scene(&body("path"));
    let film = render(&p.scene, &p.settings, RenderOptions::default()).unwrap().film;
    assert_eq!(film_stats(&film, 0.0).0, 0.0, "the path tracer cannot see a point light through glass");
}

fn small_cornell(integrator: IntegratorKind, spp: u32) -> LoadedScene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let mut file = SceneFile::load(path).unwrap();
    file.description.render.width = ImageDimension(24);
    file.description.render.height = ImageDimension(24);
    file.description.render.spp = SampleCount(spp);
    let mut s = file.build().unwrap();
    s.settings.integrator = integrator;
    s.settings.max_depth = 5;
    s
}

/// Means over blocks of `b × b` pixels.
fn block_means(film: &Film, b: u32) -> Vec<f64> {
    let mut out = Vec::new();
    for by in (0..film.height()).step_by(b as usize) {
        for bx in (0..film.width()).step_by(b as usize) {
            let mut sum = 0.0;
            for y in by..(by + b).min(film.height()) {
                for x in bx..(bx + b).min(film.width()) {
                    sum += film.pixel(x, y).to_array().iter().map(|&v| v as f64).sum::<f64>();
                }
            }
            out.push(sum / (3 * b * b) as f64);
        }
    }
    out
}

/// Without caustics that only light tracing finds, bidirectional path
/// tracing converges to the path tracer's image.
#[test]
fn cornell_box_matches_the_path_tracer() {
    let path = small_cornell(IntegratorKind::Path, 1024);
    let bdpt = small_cornell(IntegratorKind::Bdpt, 256);
    let a = render(&path.scene, &path.settings, RenderOptions::default()).unwrap().film;
    let b = render(&bdpt.scene, &bdpt.settings, RenderOptions::default()).unwrap().film;
    let (ma, mb) = (block_means(&a, 24)[0], block_means(&b, 24)[0]);
    assert!((ma - mb).abs() < 0.01 * ma, "image means: path {ma}, bdpt {mb}");
    for (i, (x, y)) in block_means(&a, 6).into_iter().zip(block_means(&b, 6)).enumerate() {
        assert!((x - y).abs() < 0.04 * x.max(0.05), "block {i}: path {x}, bdpt {y}");
    }
}

/// In a chromatic, scattering medium (the camera, the light and the room
/// in it) the two integrators agree too: light subpaths scatter in the
/// medium and connections carry its transmittance. (The point light has
/// no distance falloff, the scene format's default: its light subpaths
/// carry the d² that makes its irradiance constant.)
#[test]
fn a_chromatic_medium_matches_the_path_tracer() {
    let body = r#"
        [media.haze.homogeneous]
        sigma_a = [0.01, 0.02, 0.04]
        sigma_s = [0.05, 0.1, 0.2]
        g = 0.6
        [materials.boundary.interface]
        [materials.floor.diffuse]
        color = [0.7, 0.7, 0.7]
        [materials.red.diffuse]
        color = [0.5, 0.3, 0.3]
        [camera]
        eye = [0, 3, 6]
        look_at = [0, 0.5, 0]
        fov = 50
        medium = "haze"
        [render]
        width = 24
        height = 16
        max_depth = 3
        [[sphere]]
        radius = 30
        material = "boundary"
        medium_inside = "haze"
        [[quad]]
        vertices = [[-6, 0, -4], [6, 0, -4], [6, 0, 8], [-6, 0, 8]]
        material = "floor"
        medium_inside = "haze"
        [[sphere]]
        center = [0, 0.7, 0]
        radius = 0.7
        material = "red"
        medium_outside = "haze"
        [[point_light]]
        position = [1, 4, 2]
        intensity = 10
    "#;
    agree(body, 1024, 256, 0.015, 0.05, 8);
}

/// Renders `body` (a scene without `[render]`'s integrator and spp) with
/// the path tracer at `spp_path` and bdpt at `spp_bdpt`, and checks that
/// the channel means agree within `tol` and the means of `block`-pixel
/// blocks within `block_tol` (of max(mean, 0.05)). Returns both films.
fn agree(body: &str, spp_path: u32, spp_bdpt: u32, tol: f64, block_tol: f64, block: u32) -> (Film, Film) {
    let with = |integrator: &str, spp: u32| {
        let text = body.replace("[render]", &format!("[render]\nintegrator = \"{integrator}\"\nspp = {spp}"));
        let s = scene(&text);
        render(&s.scene, &s.settings, RenderOptions::default()).unwrap().film
    };
    let (a, c) = (with("path", spp_path), with("bdpt", spp_bdpt));
    for k in 0..3 {
        let (x, y) = (channel_mean(&a, k), channel_mean(&c, k));
        assert!((x - y).abs() < tol * x, "channel {k}: path {x}, bdpt {y}");
    }
    for (i, (x, y)) in block_means(&a, block).into_iter().zip(block_means(&c, block)).enumerate() {
        assert!((x - y).abs() < block_tol * x.max(0.05), "block {i}: path {x}, bdpt {y}");
    }
    (a, c)
}

/// Smooth shading (vertex normals far from the geometric normal): light
/// subpaths carry Veach's correction for shading normals, in their walks
/// and at their connections. Light tracing alone (`s = 2, t = 1`) then
/// gives the same direct light as next-event estimation alone
/// (`s = 1, t = 2`), and the weighted whole agrees with the path tracer.
#[test]
fn shading_normals_match_the_path_tracer() {
    let body = r#"
        [camera]
        eye = [0, 2.5, 3]
        look_at = [0, 0, 0]
        fov = 60
        [render]
        width = 24
        height = 16
        max_depth = 3
        [materials.white.diffuse]
        color = [0.8, 0.8, 0.8]
        [materials.black.diffuse]
        color = [0, 0, 0]
        [[triangle]]
        vertices = [[-2, 0, -2], [-2, 0, 2], [2, 0, 2]]
        normals = [[0.9, 1, 0], [0, 1, 1], [-0.8, 1, -0.6]]
        material = "white"
        [[triangle]]
        vertices = [[-2, 0, -2], [2, 0, 2], [2, 0, -2]]
        normals = [[0.9, 1, 0], [-0.8, 1, -0.6], [0.6, 1, 0.9]]
        material = "white"
        [[quad]]
        vertices = [[-0.5, 1.5, -0.5], [0.5, 1.5, -0.5], [0.5, 1.5, 0.5], [-0.5, 1.5, 0.5]]
        material = "black"
        emission = [4, 4, 4]
        two_sided = true
    "#;
    agree(body, 1024, 256, 0.015, 0.06, 8);
    let s = scene(&body.replace("[render]", "[render]\nintegrator = \"bdpt\"\nspp = 256"));
    let (nee, traced) = (strategy_alone(&s, 1, 1, 2), strategy_alone(&s, 1, 2, 1));
    let (x, y) = (channel_mean(&nee, 0), channel_mean(&traced, 0));
    assert!((x - y).abs() < 0.02 * x, "direct light: next-event estimation {x}, light tracing {y}");
}

/// Light from infinity over an infinite plane: light subpaths from the
/// environment and the sun start on a disk across the scene's finite
/// bounds and never reach the far plane; the weights give those parts to
/// the camera's strategies alone (no dark ring beyond the disk).
#[test]
fn lights_at_infinity_over_an_infinite_plane_match_the_path_tracer() {
    agree(
        r#"
        [camera]
        eye = [0, 1.2, 5]
        look_at = [0, 0.5, 0]
        fov = 70
        [render]
        width = 24
        height = 16
        max_depth = 3
        [environment]
        color = [0.4, 0.5, 0.7]
        [materials.white.diffuse]
        color = [0.7, 0.7, 0.7]
        [[plane]]
        material = "white"
        [[sphere]]
        center = [0, 0.5, 0]
        radius = 0.5
        material = "white"
        [[directional_light]]
        direction = [-0.4, -1, -0.3]
        intensity = 2
    "#,
        512,
        128,
        0.015,
        0.06,
        8,
    );
}

/// Wide filters splat light-traced contributions into the pixels they
/// cover, normalised over the part of the filter inside the image, as the
/// camera samples' weights are; with filter importance sampling some
/// camera rays leave from outside the image. Either way the edges agree
/// with the path tracer.
#[test]
fn image_edges_agree_under_wide_filters() {
    for fis in [false, true] {
        let body = format!(
            r#"
        [camera]
        eye = [0, 1, 3.4]
        look_at = [0, 1, 0]
        fov = 40
        [render]
        width = 16
        height = 16
        max_depth = 3
        filter = {{ kind = "gaussian", radius = 2, sigma = 0.8 }}
        filter_importance = {fis}
        [materials.white.diffuse]
        color = [0.7, 0.7, 0.7]
        [materials.black.diffuse]
        color = [0, 0, 0]
        [[quad]]
        vertices = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "white"
        [[quad]]
        vertices = [[-3, 0, -1], [3, 0, -1], [3, 3, -1], [-3, 3, -1]]
        material = "white"
        [[quad]]
        vertices = [[-0.4, 2, -0.4], [0.4, 2, -0.4], [0.4, 2, 0.4], [-0.4, 2, 0.4]]
        material = "black"
        emission = [6, 6, 6]
        two_sided = true
    "#
        );
        let (a, c) = agree(&body, 1024, 256, 0.015, 0.06, 4);
        // The outermost ring of pixels on its own.
        let ring = |f: &Film| {
            let (w, h) = (f.width(), f.height());
            let mut sum = 0.0f64;
            let mut n = 0;
            for y in 0..h {
                for x in 0..w {
                    if x == 0 || y == 0 || x == w - 1 || y == h - 1 {
                        sum += f.pixel(x, y).x as f64;
                        n += 1;
                    }
                }
            }
            sum / n as f64
        };
        let (x, y) = (ring(&a), ring(&c));
        assert!((x - y).abs() < 0.03 * x, "filter importance {fis}: the edge pixels: path {x}, bdpt {y}");
    }
}

/// The same seed gives the same image for any number of threads, and a
/// render resumed twice equals one done in one go (the splats of light
/// tracing go through the exact fixed-point film too).
#[test]
fn bdpt_is_deterministic_across_threads_and_resumes() {
    let s = small_cornell(IntegratorKind::Bdpt, 6);
    let one = render(&s.scene, &s.settings, RenderOptions { threads: Some(1), ..Default::default() }).unwrap().film;
    let three = render(&s.scene, &s.settings, RenderOptions { threads: Some(3), ..Default::default() }).unwrap().film;
    assert_eq!(one, three);
    let layout = s.settings.film_aovs();
    let mut parts = Accumulator::with_aovs(24, 24, layout).unwrap();
    for target in [2, 3, 6] {
        let options = RenderOptions { spp: Some(target), threads: Some(2), ..Default::default() };
        render_into(&s.scene, &s.settings, &mut parts, options).unwrap();
    }
    assert_eq!(parts.to_film(), one);
}

/// Partial renders of disjoint sample ranges merge into exactly the
/// render of all of them, light image included.
#[test]
fn bdpt_partial_renders_merge_exactly() {
    let s = small_cornell(IntegratorKind::Bdpt, 5);
    let whole = render(&s.scene, &s.settings, RenderOptions::default()).unwrap().film;
    let (a, _) = render_partial(&s.scene, &s.settings, 0..2, 7, RenderOptions::default()).unwrap();
    let (b, _) = render_partial(&s.scene, &s.settings, 2..5, 7, RenderOptions::default()).unwrap();
    let merged: PartialFilm = a.merge(&b).unwrap();
    assert_eq!(merged.to_film(), whole);
}

/// Adaptive sampling cannot tell a pixel's error with splats arriving from
/// everywhere: refused with a clear error.
#[test]
fn bdpt_refuses_adaptive_sampling() {
    let mut s = small_cornell(IntegratorKind::Bdpt, 4);
    s.settings.adaptive = Some(0.01);
    let e = render(&s.scene, &s.settings, RenderOptions::default()).unwrap_err();
    assert!(e.to_string().contains("adaptive sampling does not work with bdpt"), "{e}");
}
