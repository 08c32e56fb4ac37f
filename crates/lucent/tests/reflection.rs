//! Mirror reflection: the recursion depth limit and what a mirror shows.
//!
//! Mirrors here have no diffuse or specular lobe (`kd = ks = 0`), so what
//! they show is only their ambient term plus `kr` times what the reflected
//! ray sees. Between mirrors, a pixel is then a geometric series in `kr`,
//! truncated by `max_depth`: `a₀ + kr₀·(a₁ + kr₁·(a₂ + …))`. The expected
//! sums are computed in double precision from the single-precision inputs
//! and must match to a few units in the last place (the renderer's order of
//! summation is its own business); where only one term survives, exactly.

mod common;

use common::*;
use glam::DVec3;
use lucent::prelude::*;
use std::f64::consts::PI;

/// A mirror: no lobes, reflectivity `kr`, ambient coefficient `ka`.
fn mirror(color: Color, ka: f32, kr: f32) -> Material {
    Material::phong(color, 0.0, 0.0, 1.0, kr).unwrap().with_ka(ka).unwrap()
}

/// `terms[0] + kr[0]·(terms[1] + kr[1]·(… + kr[n-2]·terms[n-1]))`, in
/// double precision.
fn nested(terms: &[Color], kr: &[f32]) -> DVec3 {
    let mut l = terms.last().unwrap().as_dvec3();
    for i in (0..terms.len() - 1).rev() {
        l = terms[i].as_dvec3() + kr[i] as f64 * l;
    }
    l
}

/// Equal to single precision: within 8 units of roundoff of the largest
/// channel (each of the at most 13 terms is rounded a few times, relative to
/// a sum of positive terms), plus the film's resolution.
fn assert_series(got: Color, want: DVec3, what: &str) {
    let tol = 8.0 * f32::EPSILON as f64 * want.max_element() + film_tolerance(want.as_vec3a()) as f64;
    assert!(diff(got, want) <= tol, "{what}: rendered {got}, series {want} (difference {:e})", diff(got, want));
}

#[test]
fn recursion_between_parallel_mirrors_stops_at_max_depth() {
    // The camera sits between a floor mirror (y = -1) and a ceiling mirror
    // (y = 1) and looks down at the floor: every ray bounces between them
    // forever, so only max_depth ends it. Each bounce adds that mirror's
    // ambient term; a reflection stopped by the depth limit adds nothing.
    let cam = RefCamera::new([0.0, 0.0, 0.0], [0.0, -1.0, 2.0], [0.0, 1.0, 0.0], 30.0, 9, 7);
    for (x, y) in cam.pixels() {
        assert!(cam.pixel_ray(x, y).1.y < -0.2, "every pixel must look down at the floor");
    }
    let ambient = Color::new(0.5, 0.8, 1.0);
    let (col_a, ka_a, kr_a) = (Color::new(1.0, 0.5, 0.25), 0.4, 0.5);
    let (col_b, ka_b, kr_b) = (Color::new(0.2, 0.4, 0.8), 0.3, 0.75);
    let a = ka_a * col_a * ambient;
    let b = ka_b * col_b * ambient;
    for max_depth in [0u32, 1, 2, 5, 12] {
        let mut scene = scene_one_spp(cam.camera());
        scene.settings.max_depth = max_depth;
        scene.background = Color::splat(7.0); // never seen
        scene.ambient = ambient;
        let floor = scene.add_material(mirror(col_a, ka_a, kr_a));
        let ceiling = scene.add_material(mirror(col_b, ka_b, kr_b));
        scene.add(Primitive::new(Plane::new(-Vec3::Y, Vec3::Y).unwrap(), Transform::IDENTITY, floor));
        scene.add(Primitive::new(Plane::new(Vec3::Y, -Vec3::Y).unwrap(), Transform::IDENTITY, ceiling));
        let film = render_film(&scene);

        // Floor, ceiling, floor, …: max_depth + 1 surfaces in all.
        let n = max_depth as usize + 1;
        let terms: Vec<Color> = (0..n).map(|i| if i % 2 == 0 { a } else { b }).collect();
        let krs: Vec<f32> = (0..n).map(|i| if i % 2 == 0 { kr_a } else { kr_b }).collect();
        let want = nested(&terms, &krs);
        for (x, y) in cam.pixels() {
            assert_series(film.pixel(x, y), want, &format!("max_depth {max_depth}, pixel ({x}, {y})"));
            if max_depth == 0 {
                assert_pixel(film.pixel(x, y), a, "no reflection: the floor's ambient term exactly");
            }
        }
        // Each extra bounce changes the value by more than the tolerance:
        // the check above pins the depth down.
        if max_depth > 0 {
            let shorter = nested(&terms[..n - 1], &krs[..n - 1]);
            assert!(diff(film.pixel(0, 0), shorter) > 1e3 * f32::EPSILON as f64 * want.max_element());
        }
        // The closed form, for the record: pairs of bounces multiply by
        // kr_a·kr_b, so the series is geometric in it.
        let q = (kr_a * kr_b) as f64;
        let pair = a.as_dvec3() + kr_a as f64 * b.as_dvec3();
        let closed = match max_depth % 2 {
            1 => pair * (1.0 - q.powi((n / 2) as i32)) / (1.0 - q),
            _ => pair * (1.0 - q.powi((n / 2) as i32)) / (1.0 - q) + q.powi((n / 2) as i32) * a.as_dvec3(),
        };
        assert!((want - closed).abs().max_element() < 1e-12, "max_depth {max_depth}: {want} vs closed form {closed}");
    }
}

#[test]
fn a_corner_reflector_returns_the_background_after_three_bounces() {
    // Three mutually perpendicular mirror planes through the origin. A ray
    // heading into the corner (all direction components negative) meets each
    // plane once, its direction flipping one component each time, then
    // leaves: three bounces and the background.
    let cam = RefCamera::new([3.0, 3.5, 4.0], [0.2, 0.1, 0.3], [0.0, 1.0, 0.0], 40.0, 10, 8);
    for (x, y) in cam.pixels() {
        let d = cam.pixel_ray(x, y).1;
        assert!(d.max_element() < -0.05, "pixel ({x}, {y}) must look into the corner: {d}");
    }
    let background = Color::new(0.9, 0.6, 0.3);
    let ambient = Color::splat(0.5);
    for (ka, kr) in [(0.0f32, 1.0f32), (0.0, 0.6), (0.2, 0.6)] {
        let color = Color::new(0.7, 0.8, 0.9);
        let a = ka * color * ambient;
        for max_depth in [0u32, 1, 2, 3, 5] {
            let mut scene = scene_one_spp(cam.camera());
            scene.settings.max_depth = max_depth;
            scene.background = background;
            scene.ambient = ambient;
            let m = scene.add_material(mirror(color, ka, kr));
            for n in [Vec3::X, Vec3::Y, Vec3::Z] {
                scene.add(Primitive::new(Plane::new(Vec3::ZERO, n).unwrap(), Transform::IDENTITY, m));
            }
            let film = render_film(&scene);
            let bounces = max_depth.min(3) as usize;
            let mut terms = vec![a; bounces + 1];
            if max_depth >= 3 {
                terms[3] = background; // the fourth ray leaves the corner
            }
            let want = nested(&terms, &vec![kr; bounces + 1]);
            for (x, y) in cam.pixels() {
                let got = film.pixel(x, y);
                assert_series(got, want, &format!("ka {ka}, kr {kr}, max_depth {max_depth}, pixel ({x}, {y})"));
                if ka == 0.0 {
                    // Black mirrors: darkness until the background is
                    // reached, then kr³ of it: exactly the background for
                    // perfect mirrors.
                    let expect = if max_depth >= 3 { (kr as f64).powi(3) * background.as_dvec3() } else { DVec3::ZERO };
                    assert!((want - expect).abs().max_element() < 1e-12);
                    if kr == 1.0 || max_depth < 3 {
                        assert_pixel(
                            got,
                            expect.as_vec3a(),
                            &format!("ka 0, kr {kr}, max_depth {max_depth}, pixel ({x}, {y})"),
                        );
                    }
                }
            }
        }
    }
}

/// A lit matte sphere above a mirror floor.
struct MirrorScene {
    cam: RefCamera,
    centre: DVec3,
    radius: f64,
    albedo: DVec3,
    kd: f64,
    ka: f64,
    ambient: DVec3,
    light: DVec3,
    intensity: f64,
    kr: f32,
    background: Color,
}

impl MirrorScene {
    fn new() -> Self {
        Self {
            cam: RefCamera::new([0.0, 2.0, -7.0], [0.0, 0.6, 0.0], [0.0, 1.0, 0.0], 50.0, 41, 31),
            centre: DVec3::new(0.0, 1.5, 0.0),
            radius: 1.0,
            albedo: DVec3::new(0.9, 0.3, 0.2),
            kd: 0.8,
            ka: 0.2,
            ambient: DVec3::splat(0.1),
            light: DVec3::new(2.0, 5.0, -3.0),
            intensity: 1.5,
            kr: 0.8,
            background: Color::new(0.1, 0.2, 0.3),
        }
    }

    fn scene(&self, max_depth: u32) -> TestScene {
        let mut scene = scene_one_spp(self.cam.camera());
        scene.settings.max_depth = max_depth;
        scene.background = self.background;
        scene.ambient = self.ambient.as_vec3a();
        let ball = scene.add_material(
            Material::matte(self.albedo.as_vec3a(), self.kd as f32).unwrap().with_ka(self.ka as f32).unwrap(),
        );
        let glass = scene.add_material(mirror(Color::ONE, 0.0, self.kr));
        scene.add(Primitive::new(
            Sphere::new(self.centre.as_vec3a(), self.radius as f32).unwrap(),
            Transform::IDENTITY,
            ball,
        ));
        scene.add(Primitive::new(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, glass));
        scene.add_light(Light::point(self.light.as_vec3a(), Color::ONE, self.intensity as f32, Falloff::None).unwrap());
        scene
    }

    /// Radiance leaving the sphere at `q` (matte: the same in every
    /// direction). Nothing can shadow it: the floor lies below both the
    /// sphere and the light.
    fn sphere_radiance(&self, q: DVec3) -> Option<DVec3> {
        let n = (q - self.centre).normalize();
        let cos = n.dot((self.light - q).normalize());
        if cos.abs() < 1e-5 {
            return None; // terminator
        }
        let direct = if cos > 0.0 { self.kd * self.albedo / PI * self.intensity * cos } else { DVec3::ZERO };
        Some(self.ka * self.albedo * self.ambient + direct)
    }
}

#[test]
fn a_mirror_shows_kr_times_the_radiance_of_what_it_reflects() {
    let s = MirrorScene::new();
    let film = render_film(&s.scene(5));
    let (mut direct, mut reflected, mut sky) = (0, 0, 0);
    for (x, y) in s.cam.pixels() {
        let (o, d) = s.cam.pixel_ray(x, y);
        let got = film.pixel(x, y);
        let t_floor = ray_plane(o, d, DVec3::ZERO, DVec3::Y);
        match ray_sphere(o, d, s.centre, s.radius, 1e-4) {
            Hit::Uncertain => continue,
            Hit::At(t) if !matches!(t_floor, Some(tf) if tf <= t) => {
                // The sphere seen directly.
                let Some(want) = s.sphere_radiance(o + t * d) else { continue };
                assert!(
                    diff(got, want) < 2e-5 * want.max_element() + film_tolerance(want.as_vec3a()) as f64,
                    "pixel ({x}, {y}): {got} vs {want}"
                );
                direct += 1;
                continue;
            }
            _ => {}
        }
        let Some(tf) = t_floor else {
            assert_pixel(got, s.background, &format!("pixel ({x}, {y}) sees the sky"));
            continue;
        };
        // The floor mirror: reflect about +y and follow.
        let p = o + tf * d;
        let r = reflect(d, DVec3::Y);
        match ray_sphere(p, r, s.centre, s.radius, 1e-4) {
            Hit::Uncertain => {}
            Hit::Miss => {
                // 0 (ambient) + 0 (no lobes) + kr·background, exactly.
                assert_pixel(got, s.kr * s.background, &format!("pixel ({x}, {y}): the mirror reflects the sky"));
                sky += 1;
            }
            Hit::At(t) => {
                let Some(radiance) = s.sphere_radiance(p + t * r) else { continue };
                let want = s.kr as f64 * radiance;
                assert!(
                    diff(got, want) < 2e-5 * want.max_element() + film_tolerance(want.as_vec3a()) as f64,
                    "pixel ({x}, {y}): mirror shows {got}, kr × sphere radiance is {want}"
                );
                reflected += 1;
            }
        }
    }
    eprintln!("{direct} direct, {reflected} reflected, {sky} sky in the mirror");
    assert!(direct > 100 && reflected > 60 && sky > 100, "{direct} direct, {reflected} reflected, {sky} sky");
}

#[test]
fn with_max_depth_zero_a_black_mirror_is_black() {
    let s = MirrorScene::new();
    let film = render_film(&s.scene(0));
    let mut black = 0;
    for (x, y) in s.cam.pixels() {
        let (o, d) = s.cam.pixel_ray(x, y);
        let Some(tf) = ray_plane(o, d, DVec3::ZERO, DVec3::Y) else { continue };
        if matches!(ray_sphere(o, d, s.centre, s.radius, 1e-4), Hit::At(t) if t < tf) {
            continue;
        }
        if matches!(ray_sphere(o, d, s.centre, s.radius, 1e-4), Hit::Uncertain) {
            continue;
        }
        assert_pixel(film.pixel(x, y), Color::ZERO, &format!("pixel ({x}, {y})"));
        black += 1;
    }
    assert!(black > 300, "{black}");
}
