//! The camera: where primary rays go, at ordinary and extreme fields of
//! view, through a pinhole and through a thin lens.
//!
//! Expected directions come from the documented camera model, rebuilt in
//! double precision (`common::RefCamera`); thin-lens expectations from the
//! geometry of a lens in the camera's `u`–`v` plane focusing on the plane at
//! distance `f` along `w`.

mod common;

use common::*;
use glam::{DVec2, DVec3};
use lucent::prelude::*;

/// Distance from point `p` to the line of `ray`.
fn distance_to_ray(p: DVec3, ray: &Ray) -> f64 {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3().normalize());
    let q = p - o;
    (q - q.dot(d) * d).length()
}

#[test]
fn the_centre_ray_hits_the_look_at_point() {
    let mut rng = Rng::new(1);
    for _ in 0..200 {
        let eye = (rng.unit() * rng.range(0.5, 100.0)).as_vec3a();
        let look = (rng.unit() * rng.range(0.0, 100.0)).as_vec3a();
        let up = rng.unit().as_vec3a();
        let fov = rng.range(5.0, 170.0) as f32;
        let (w, h) = (1 + 2 * (rng.f64() * 300.0) as u32, 1 + 2 * (rng.f64() * 300.0) as u32);
        let Ok(cam) = Camera::new(eye, look, up, fov, w, h) else { continue };
        let ray = cam.generate_ray(Vec2::new(w as f32 / 2.0, h as f32 / 2.0), Vec2::new(rng.f64() as f32, 0.3));
        let dist = (look - eye).length() as f64;
        assert!(
            distance_to_ray(look.as_dvec3(), &ray) < 1e-5 * dist,
            "eye {eye}, look_at {look}, fov {fov}, {w}×{h}: centre ray {ray:?}"
        );
        assert!(ray.dir.dot(look - eye) > 0.0, "the centre ray points towards the look-at point");
        assert!((ray.dir.length() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn the_centre_pixel_of_a_render_sees_a_small_sphere_at_the_look_at_point() {
    // An odd image size puts a pixel centre on the look-at point; a sphere
    // there smaller than one pixel is seen by that pixel only.
    let (w, h) = (21, 15);
    let look = Vec3::new(3.0, -2.0, 7.0);
    let eye = Vec3::new(-1.0, 4.0, -6.0);
    let cam = Camera::new(eye, look, Vec3::Y, 40.0, w, h).unwrap();
    let pixel_angle = 2.0 * 20f32.to_radians().tan() / w as f32;
    let radius = 0.3 * pixel_angle * (look - eye).length();
    let mut scene = scene_one_spp(cam);
    let white = scene.add_material(Material::matte(Color::ONE, 1.0).unwrap());
    scene.add(Primitive::new(Sphere::new(look, radius).unwrap(), Transform::IDENTITY, white));
    scene.add_light(Light::directional(look - eye, Color::ONE, 1.0).unwrap());
    let film = render_film(&scene);
    for y in 0..h {
        for x in 0..w {
            let lit = film.pixel(x, y).x > 0.0;
            assert_eq!(lit, (x, y) == (w / 2, h / 2), "pixel ({x}, {y})");
        }
    }
    // Seen head on, lit head on: kd·albedo/π.
    assert!((film.pixel(w / 2, h / 2).x - std::f32::consts::FRAC_1_PI).abs() < 1e-4);
}

#[test]
fn rays_follow_the_documented_projection() {
    let reference = RefCamera::new([1.0, 2.0, -3.0], [0.5, 0.0, 4.0], [0.1, 1.0, 0.0], 70.0, 40, 30);
    let cam = reference.camera();
    let mut rng = Rng::new(2);
    for _ in 0..500 {
        let (fx, fy) = (rng.range(0.0, 40.0), rng.range(0.0, 30.0));
        let ray = cam.generate_ray(Vec2::new(fx as f32, fy as f32), Vec2::splat(0.5));
        let want = reference.dir_at(fx as f32 as f64, fy as f32 as f64);
        assert!((ray.dir.as_dvec3() - want).length() < 1e-6, "film ({fx}, {fy}): {} vs {want}", ray.dir);
        assert!((ray.origin.as_dvec3() - reference.eye).length() < 1e-6);
        // And the projection inverts it.
        let (px, py) = reference.project(reference.eye + 5.0 * want);
        assert!((px - fx as f32 as f64).abs() < 1e-6 && (py - fy as f32 as f64).abs() < 1e-6);
    }
    // Pixel (0, 0) is at the top left: its ray points up and to the
    // camera's left.
    let corner = cam.generate_ray(Vec2::new(0.5, 0.5), Vec2::splat(0.5)).dir.as_dvec3();
    assert!(corner.dot(reference.u) < 0.0 && corner.dot(reference.v) > 0.0);
}

#[test]
fn wide_angles_give_finite_unit_directions_at_every_corner() {
    for fov in [166.0f32, 175.0, 179.0, 179.9] {
        for (w, h) in [(64u32, 48u32), (48, 64), (1, 1), (1000, 3)] {
            let reference = RefCamera::new([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], fov, w, h);
            let cam = reference.camera();
            let (wf, hf) = (w as f32, h as f32);
            let corners = [(0.0, 0.0), (wf, 0.0), (0.0, hf), (wf, hf)];
            let centres = [(0.5, 0.5), (wf - 0.5, 0.5), (0.5, hf - 0.5), (wf - 0.5, hf - 0.5)];
            for (fx, fy) in corners.into_iter().chain(centres).chain([(wf / 2.0, hf / 2.0), (wf, hf / 2.0)]) {
                let ray = cam.generate_ray(Vec2::new(fx, fy), Vec2::splat(0.5));
                let what = format!("fov {fov}, {w}×{h}, film ({fx}, {fy})");
                assert!(ray.dir.is_finite() && ray.origin.is_finite(), "{what}: {ray:?}");
                assert!((ray.dir.length() - 1.0).abs() < 1e-6, "{what}: |dir| = {}", ray.dir.length());
                assert!(ray.dir.z > 0.0, "{what}: the ray must still point forwards: {}", ray.dir);
                let want = reference.dir_at(fx as f64, fy as f64);
                // Single precision resolves the angle to about 1e-7 radians.
                assert!((ray.dir.as_dvec3() - want).length() < 1e-6, "{what}: {} vs {want}", ray.dir);
            }
            // The middle of the right edge is at exactly half the field of
            // view from the axis.
            let edge = cam.generate_ray(Vec2::new(wf, hf / 2.0), Vec2::splat(0.5)).dir.as_dvec3();
            let angle = edge.z.clamp(-1.0, 1.0).acos().to_degrees();
            assert!((angle - fov as f64 / 2.0).abs() < 1e-4, "fov {fov}: edge at {angle}°");
        }
    }
}

#[test]
fn a_very_wide_render_has_no_invalid_pixels() {
    for fov in [166.0, 175.0, 179.9] {
        let src = format!(
            r#"
            [camera]
            eye = [0, 1, -3]
            look_at = [0, 1, 0]
            fov = {fov}
            [render]
            width = 48
            height = 32
            spp = 4
            background = [0.2, 0.3, 0.4]
            [materials.white.matte]
            color = [1, 1, 1]
            [[plane]]
            material = "white"
            [[sphere]]
            center = [0, 1, 0]
            material = "white"
            [[point_light]]
            position = [2, 4, -2]
            "#
        );
        let scene = parse_scene(&src, SceneFormat::Toml).unwrap();
        let film = render_loaded(&scene);
        assert!(film.pixels().iter().all(|c| c.is_finite() && c.min_element() >= 0.0), "fov {fov}");
        // The sphere straight ahead is in the middle of the image.
        assert_ne!(film.pixel(24, 16), Color::new(0.2, 0.3, 0.4));
    }
}

/// A thin-lens camera and its double-precision model.
fn lens_camera(radius: f32, focal: f32) -> (RefCamera, Camera) {
    let reference = RefCamera::new([2.0, 1.0, -10.0], [0.0, 0.5, 0.0], [0.0, 1.0, 0.0], 45.0, 160, 120);
    let cam = reference.camera().with_lens(ThinLens { radius, focal_distance: focal }).unwrap();
    (reference, cam)
}

/// Lens samples covering the unit square, its corners included.
fn lens_samples() -> impl Iterator<Item = Vec2> {
    (0..=16).flat_map(|i| (0..=16).map(move |j| Vec2::new(i as f32, j as f32) / 16.0 * 0.999_999))
}

#[test]
fn every_lens_sample_of_a_point_on_the_focal_plane_lands_on_the_same_pixel() {
    let (radius, focal) = (0.8f32, 9.0f32);
    let (reference, cam) = lens_camera(radius, focal);
    let mut rng = Rng::new(3);
    for _ in 0..50 {
        // A random point of the focal plane inside the view.
        let (x, y) = (rng.range(-0.9, 0.9) * reference.half_width, rng.range(-0.9, 0.9) * reference.half_height);
        let p = reference.eye + focal as f64 * (reference.w + x * reference.u + y * reference.v);
        // Where the pinhole sees it: that film position is where every lens
        // sample must image it.
        let (fx, fy) = reference.project(p);
        let film = Vec2::new(fx as f32, fy as f32);
        let mut spread = 0.0f64;
        for lens in lens_samples() {
            let ray = cam.generate_ray(film, lens);
            // The ray starts on the lens disk, in the u–v plane of the eye…
            let o = ray.origin.as_dvec3() - reference.eye;
            assert!(o.dot(reference.w).abs() < 1e-5 && o.length() <= radius as f64 * (1.0 + 1e-5));
            // …and passes through the point.
            spread = spread.max(distance_to_ray(p, &ray));
        }
        // Film positions are single precision: fx carries an error of about
        // 1e-5 pixels, i.e. 1e-5 × pixel size × focal distance here.
        assert!(spread < 2e-5 * focal as f64, "point {p} spreads over {spread}");
    }
}

#[test]
fn a_point_off_the_focal_plane_spreads_over_the_circle_of_confusion() {
    let (radius, focal) = (0.8f32, 9.0f32);
    let (reference, cam) = lens_camera(radius, focal);
    let pixels_per_unit = reference.width as f64 / (2.0 * reference.half_width);
    for depth in [4.0f64, 7.0, 9.0, 12.0, 30.0] {
        let q = reference.eye + depth * (reference.w + 0.1 * reference.u - 0.05 * reference.v);
        let pinhole = DVec2::from(reference.project(q));
        // Thin lens: seen through lens point o (in the u–v plane), q images
        // where the line from o through q meets the plane of focus, i.e. at
        // q's pinhole position shifted by o·(1/f − 1/z) on the image plane at
        // distance 1. The largest shift, at the rim, is the circle of
        // confusion: R·|1/f − 1/z|.
        let k = 1.0 / focal as f64 - 1.0 / depth;
        let coc = radius as f64 * k.abs() * pixels_per_unit;
        let mut largest = 0.0f64;
        for lens in lens_samples() {
            let o = cam.generate_ray(Vec2::ZERO, lens).origin.as_dvec3() - reference.eye;
            let (ou, ov) = (o.dot(reference.u), o.dot(reference.v));
            let x = reference.eye + o + (q - reference.eye - o) * (focal as f64 / depth);
            let film = DVec2::from(reference.project(x));
            // The shift predicted by the thin-lens formula (film y runs down).
            let want = DVec2::new(ou * k, -ov * k) * pixels_per_unit;
            assert!(
                (film - pinhole - want).length() < 1e-6 * (1.0 + want.length()),
                "depth {depth}: shift {} vs {want}",
                film - pinhole
            );
            // The camera really images q there with that lens sample.
            let ray = cam.generate_ray(film.as_vec2(), lens);
            assert!(distance_to_ray(q, &ray) < 1e-4 * depth, "depth {depth}: lens {lens} misses the point");
            largest = largest.max((film - pinhole).length());
        }
        assert!((largest - coc).abs() <= 1e-3 * coc + 1e-9, "depth {depth}: spread {largest} px, expected {coc} px");
        if depth == focal as f64 {
            assert!(largest < 1e-9);
        } else {
            assert!(largest > 1.0, "depth {depth}: a visible blur ({largest} px)");
        }
    }
}

/// A matte checkerboard wall facing the camera at distance `wall`, lit
/// head-on, seen through a lens focused at `focal` (or a pinhole).
fn wall_scene(wall: f32, lens: Option<f32>) -> TestScene {
    let cam = Camera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, 40.0, 48, 32).unwrap();
    let cam = match lens {
        Some(focal) => cam.with_lens(ThinLens { radius: 0.5, focal_distance: focal }).unwrap(),
        None => cam,
    };
    let mut scene = TestScene::new(cam);
    scene.settings.spp = 16;
    scene.settings.seed = 5;
    let checker = lucent::texture::Texture::Checker { even: Color::ONE, odd: Color::splat(0.1), scale: 0.37 };
    let m = scene.add_material(Material::matte(checker, 1.0).unwrap());
    scene.add(Primitive::new(Plane::new(Vec3::new(0.0, 0.0, wall), -Vec3::Z).unwrap(), Transform::IDENTITY, m));
    scene.add_light(Light::directional(Vec3::Z, Color::ONE, 1.0).unwrap());
    scene
}

#[test]
fn a_thin_lens_render_is_sharp_at_the_focal_plane_only() {
    let pinhole = render_film(&wall_scene(6.0, None));
    // Same seed, so the same film samples: focused on the wall, every lens
    // sample's ray meets the wall where the pinhole ray does.
    let focused = render_film(&wall_scene(6.0, Some(6.0)));
    let off = pinhole.pixels().iter().zip(focused.pixels()).filter(|(a, b)| (**a - **b).abs().max_element() > 1e-4);
    assert!(off.count() <= 2, "focused on the wall, the image must match the pinhole's");
    // Focused elsewhere, checker edges blur.
    let blurred = render_film(&wall_scene(6.0, Some(2.0)));
    let off = pinhole.pixels().iter().zip(blurred.pixels()).filter(|(a, b)| (**a - **b).abs().max_element() > 0.05);
    assert!(off.count() > 100, "out of focus, the image must differ from the pinhole's");
}
