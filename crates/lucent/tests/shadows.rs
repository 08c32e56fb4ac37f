//! Hard shadows: a point is lit by a light exactly when nothing lies on the
//! segment (or, for a directional light, the half-line) between them.
//!
//! Each test renders a floor with occluders above it, one sample per pixel,
//! and classifies every floor pixel in double precision: for each light,
//! does the shadow segment from the floor point pass through an occluder?
//! Fully shadowed pixels must equal the ambient term exactly; lit ones the
//! Lambert term of the unblocked lights. Pixels whose shadow ray grazes an
//! occluder (either answer is right) or that see an occluder rather than the
//! floor are not judged.

mod common;

use common::*;
use glam::{DMat3, DVec3};
use lucent::prelude::*;
use std::f64::consts::PI;

const FLOOR_ALBEDO: [f32; 3] = [0.9, 0.85, 0.8];
const KD: f32 = 0.8;
const KA: f32 = 0.3;
const AMBIENT: [f32; 3] = [0.1, 0.12, 0.14];
const N: u32 = 41;

fn floor_material() -> Material {
    Material::matte(v3(FLOOR_ALBEDO), KD).unwrap().with_ka(KA).unwrap()
}

fn ambient_term() -> Color {
    KA * v3(FLOOR_ALBEDO) * v3(AMBIENT)
}

/// A floor `y = 0` seen from above at an angle, with ambient light.
fn floor_scene() -> (RefCamera, TestScene) {
    let cam = RefCamera::new([0.0, 10.0, -10.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 24.0, N, N);
    let mut scene = scene_one_spp(cam.camera());
    scene.ambient = v3(AMBIENT);
    let floor = scene.add_material(floor_material());
    scene.add(Primitive::new(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, floor));
    (cam, scene)
}

/// What lies between a floor point and a light, worked out in double
/// precision. `Some(true)`: blocked; `Some(false)`: clear; `None`: grazing.
type Occlusion<'a> = &'a dyn Fn(DVec3, &RefLight) -> Option<bool>;

#[derive(Clone, Copy)]
enum RefLight {
    Point(DVec3, f64),
    Directional(DVec3, f64),
}

impl RefLight {
    /// Unit direction to the light and irradiance on a surface facing it.
    fn at(&self, p: DVec3) -> (DVec3, f64) {
        match *self {
            RefLight::Point(pos, i) => ((pos - p).normalize(), i),
            RefLight::Directional(dir, i) => (-dir.normalize(), i),
        }
    }
}

#[derive(Debug, Default)]
struct Tally {
    /// Floor pixels in the shadow of every light: exact ambient checked.
    dark: usize,
    /// Floor pixels lit by at least one light, formula checked.
    lit: usize,
    /// Floor pixels where at least one light was blocked and another not.
    partly: usize,
}

/// Check every floor pixel. `hides_floor` says whether the camera ray sees an
/// occluder before the floor (`None`: too close to call).
fn check_floor(
    cam: &RefCamera,
    film: &Film,
    lights: &[RefLight],
    hides_floor: &dyn Fn(DVec3, DVec3, f64) -> Option<bool>,
    occluded: Occlusion,
) -> Tally {
    let mut tally = Tally::default();
    let albedo = d3(FLOOR_ALBEDO);
    let ambient = KA as f64 * albedo * d3(AMBIENT);
    'pixels: for (x, y) in cam.pixels() {
        let (o, d) = cam.pixel_ray(x, y);
        let Some(t) = ray_plane(o, d, DVec3::ZERO, DVec3::Y) else { continue };
        if hides_floor(o, d, t) != Some(false) {
            continue;
        }
        let p = o + t * d;
        let mut want = ambient;
        let (mut blocked, mut clear) = (0, 0);
        for light in lights {
            match occluded(p, light) {
                None => continue 'pixels,
                Some(true) => blocked += 1,
                Some(false) => {
                    let (wi, e) = light.at(p);
                    let cos = wi.y; // the floor's normal is +y
                    assert!(cos > 1e-3, "test lights must be above the floor");
                    want += KD as f64 * albedo / PI * e * cos;
                    clear += 1;
                }
            }
        }
        let got = film.pixel(x, y);
        if clear == 0 {
            assert_pixel(
                got,
                ambient_term(),
                &format!("pixel ({x}, {y}) at {p} is in shadow: only the ambient term expected"),
            );
            tally.dark += 1;
        } else {
            assert!(
                diff(got, want) <= 2e-5 * want.max_element() + film_tolerance(want.as_vec3a()) as f64,
                "pixel ({x}, {y}) at {p}: rendered {got}, expected {want} ({clear} lights visible, {blocked} blocked)"
            );
            tally.lit += 1;
            if blocked > 0 {
                tally.partly += 1;
            }
        }
    }
    eprintln!("{tally:?}");
    tally
}

/// Segment from `p` to the light (point) or half-line towards it
/// (directional) against a sphere.
fn sphere_blocks(p: DVec3, light: &RefLight, c: DVec3, r: f64, margin: f64) -> Option<bool> {
    match *light {
        RefLight::Point(pos, _) => segment_hits_sphere(p, pos, c, r, margin),
        RefLight::Directional(dir, _) => match ray_sphere(p, -dir, c, r, margin) {
            Hit::At(_) => Some(true),
            Hit::Miss => Some(false),
            Hit::Uncertain => None,
        },
    }
}

fn sphere_hides(c: DVec3, r: f64) -> impl Fn(DVec3, DVec3, f64) -> Option<bool> {
    move |o, d, t_floor| match ray_sphere(o, d, c, r, 1e-4) {
        Hit::At(t) => Some(t < t_floor),
        Hit::Miss => Some(false),
        Hit::Uncertain => None,
    }
}

fn gray(scene: &mut TestScene) -> MaterialId {
    scene.add_material(Material::matte(Color::splat(0.5), 0.9).unwrap())
}

#[test]
fn a_blocked_light_leaves_the_ambient_term_and_an_unblocked_one_lights() {
    let (c, r) = (DVec3::new(0.0, 1.0, 0.0), 0.5);
    let above = [0.0f32, 3.0, 0.0];
    let aside = [3.0f32, 3.0, 0.0];

    // One light straight above the occluder: the point under it is dark.
    let (cam, mut scene) = floor_scene();
    let m = gray(&mut scene);
    scene.add(Primitive::new(Sphere::new(c.as_vec3a(), r as f32).unwrap(), Transform::IDENTITY, m));
    scene.add_light(Light::point(v3(above), Color::ONE, 1.5, Falloff::None).unwrap());
    let film = render_film(&scene);
    let lights = [RefLight::Point(d3(above), 1.5)];
    let t = check_floor(&cam, &film, &lights, &sphere_hides(c, r), &|p, l| sphere_blocks(p, l, c, r, 1e-4));
    assert!(t.dark > 20 && t.lit > 500, "{t:?}");
    // The centre pixel looks at the origin, right under the occluder.
    assert_pixel(film.pixel(N / 2, N / 2), ambient_term(), "pixel");

    // Add a second light off to the side: it reaches the origin past the
    // occluder, so the centre pixel is lit by it alone.
    scene.add_light(Light::point(v3(aside), Color::ONE, 1.0, Falloff::None).unwrap());
    let film = render_film(&scene);
    let lights = [RefLight::Point(d3(above), 1.5), RefLight::Point(d3(aside), 1.0)];
    let t = check_floor(&cam, &film, &lights, &sphere_hides(c, r), &|p, l| sphere_blocks(p, l, c, r, 1e-4));
    assert!(t.partly > 40 && t.lit > 500, "{t:?}");
    let cos = d3(aside).normalize().y;
    let want = KA as f64 * d3(FLOOR_ALBEDO) * d3(AMBIENT) + KD as f64 * d3(FLOOR_ALBEDO) / PI * cos;
    assert!(diff(film.pixel(N / 2, N / 2), want) < 1e-5, "{} vs {want}", film.pixel(N / 2, N / 2));
}

#[test]
fn an_occluder_behind_the_light_casts_no_shadow() {
    let (c, r) = (DVec3::new(0.0, 4.0, 0.0), 1.0);
    let light = [0.0f32, 2.0, 0.0];
    let (cam, mut scene) = floor_scene();
    let m = gray(&mut scene);
    scene.add(Primitive::new(Sphere::new(c.as_vec3a(), r as f32).unwrap(), Transform::IDENTITY, m));
    scene.add_light(Light::point(v3(light), Color::ONE, 1.0, Falloff::None).unwrap());
    let film = render_film(&scene);
    let lights = [RefLight::Point(d3(light), 1.0)];
    let t = check_floor(&cam, &film, &lights, &sphere_hides(c, r), &|p, l| sphere_blocks(p, l, c, r, 1e-4));
    assert!(t.dark == 0 && t.lit > 600, "{t:?}");
    // The test has teeth: from the floor the occluder lies straight on past
    // the light, so a shadow ray not stopped at the light would be blocked.
    let mut behind = 0;
    for (x, y) in cam.pixels() {
        let (o, d) = cam.pixel_ray(x, y);
        if let Some(t) = ray_plane(o, d, DVec3::ZERO, DVec3::Y) {
            let p = o + t * d;
            if matches!(ray_sphere(p, d3(light) - p, c, r, 0.0), Hit::At(_)) {
                behind += 1;
            }
        }
    }
    assert!(behind > 100, "{behind}");
}

#[test]
fn a_plane_beyond_the_light_casts_no_shadow() {
    // A light between a floor and a ceiling: every shadow ray, continued,
    // meets the other plane, but only after passing the light.
    let cam = RefCamera::new([0.0, 1.5, -7.0], [0.0, 0.5, 0.0], [0.0, 1.0, 0.0], 90.0, N, N);
    let mut scene = scene_one_spp(cam.camera());
    scene.ambient = v3(AMBIENT);
    let floor = scene.add_material(floor_material());
    scene.add(Primitive::new(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, floor));
    scene.add(Primitive::new(Plane::new(Vec3::new(0.0, 4.0, 0.0), -Vec3::Y).unwrap(), Transform::IDENTITY, floor));
    let light = DVec3::new(0.5, 2.0, 1.0);
    scene.add_light(Light::point(light.as_vec3a(), Color::ONE, 2.0, Falloff::InverseSquare).unwrap());
    let film = render_film(&scene);
    let albedo = d3(FLOOR_ALBEDO);
    let (mut floor_px, mut ceiling_px) = (0, 0);
    for (x, y) in cam.pixels() {
        let (o, d) = cam.pixel_ray(x, y);
        let (t, n) = match (ray_plane(o, d, DVec3::ZERO, DVec3::Y), ray_plane(o, d, DVec3::Y * 4.0, DVec3::Y)) {
            (Some(t), _) => {
                floor_px += 1;
                (t, DVec3::Y)
            }
            (None, Some(t)) => {
                ceiling_px += 1;
                (t, -DVec3::Y)
            }
            _ => unreachable!("between two planes every ray meets one"),
        };
        let p = o + t * d;
        let to = light - p;
        let cos = n.dot(to.normalize());
        let want = KA as f64 * albedo * d3(AMBIENT) + KD as f64 * albedo / PI * (2.0 / to.length_squared()) * cos;
        let got = film.pixel(x, y);
        assert!(
            diff(got, want) <= 2e-5 * want.max_element() + film_tolerance(want.as_vec3a()) as f64,
            "pixel ({x}, {y}) at {p}: {got} vs {want}"
        );
    }
    assert!(floor_px > 200 && ceiling_px > 200, "{floor_px} floor, {ceiling_px} ceiling pixels");
}

#[test]
fn a_transformed_occluder_casts_its_transformed_shadow() {
    // A unit sphere flattened, turned and lifted: a tilted disc-like
    // ellipsoid. Its world-to-object map is built here independently.
    let (s, ry, rx, tr) = (DVec3::new(1.6, 0.15, 0.7), 35.0f64, 12.0f64, DVec3::new(0.3, 1.2, -0.2));
    let transform = Transform::scale(s.as_vec3a())
        .unwrap()
        .then(&Transform::rotate_y(ry as f32))
        .then(&Transform::rotate_x(rx as f32))
        .then(&Transform::translate(tr.as_vec3a()));
    let (cy, sy) = (ry.to_radians().cos(), ry.to_radians().sin());
    let (cx, sx) = (rx.to_radians().cos(), rx.to_radians().sin());
    // Columns: rotation about y takes z towards x; about x, y towards z.
    let rot_y = DMat3::from_cols(DVec3::new(cy, 0.0, -sy), DVec3::Y, DVec3::new(sy, 0.0, cy));
    let rot_x = DMat3::from_cols(DVec3::X, DVec3::new(0.0, cx, sx), DVec3::new(0.0, -sx, cx));
    let linear_inv = DMat3::from_diagonal(s.recip()) * (rot_x * rot_y).transpose();
    let to_object = move |p: DVec3| linear_inv * (p - tr);

    let (cam, mut scene) = floor_scene();
    let m = gray(&mut scene);
    scene.add(Primitive::new(Sphere::new(Vec3::ZERO, 1.0).unwrap(), transform, m));
    let light = [0.4f32, 4.0, -0.6];
    scene.add_light(Light::point(v3(light), Color::ONE, 1.2, Falloff::None).unwrap());
    let film = render_film(&scene);

    let hides = move |o: DVec3, d: DVec3, t_floor: f64| match ray_sphere(
        to_object(o),
        linear_inv * d,
        DVec3::ZERO,
        1.0,
        1e-4,
    ) {
        // Affine maps keep the ray parameter: t is the world-space one.
        Hit::At(t) => Some(t < t_floor),
        Hit::Miss => Some(false),
        Hit::Uncertain => None,
    };
    let blocks = move |p: DVec3, l: &RefLight| {
        let RefLight::Point(pos, _) = *l else { unreachable!() };
        segment_hits_sphere(to_object(p), to_object(pos), DVec3::ZERO, 1.0, 1e-4)
    };
    let t = check_floor(&cam, &film, &[RefLight::Point(d3(light), 1.2)], &hides, &blocks);
    assert!(t.dark > 60 && t.lit > 400, "{t:?}");

    // The untransformed unit sphere would shadow a different region: the
    // transform really is applied to shadow rays.
    let plain = |p: DVec3, l: &RefLight| sphere_blocks(p, l, tr, 1.0, 1e-4);
    let differs = cam.pixels().filter(|&(x, y)| {
        let (o, d) = cam.pixel_ray(x, y);
        let p = o + ray_plane(o, d, DVec3::ZERO, DVec3::Y).unwrap() * d;
        plain(p, &RefLight::Point(d3(light), 1.2)) != blocks(p, &RefLight::Point(d3(light), 1.2))
    });
    assert!(differs.count() > 50);
}

#[test]
fn directional_light_shadows_from_an_occluder_at_any_distance() {
    let dir = DVec3::new(1.0, -3.0, 0.5).normalize();
    let r = 0.6;
    let mut counts = Vec::new();
    for distance in [2.0, 50.0, 1e3, 1e5] {
        // Centred on the line through the origin along the light: the
        // shadow is the same disc-like patch whatever the distance.
        let c = -distance * dir;
        let (cam, mut scene) = floor_scene();
        let m = gray(&mut scene);
        scene.add(Primitive::new(Sphere::new(c.as_vec3a(), r as f32).unwrap(), Transform::IDENTITY, m));
        scene.add_light(Light::directional(dir.as_vec3a(), Color::ONE, 1.0).unwrap());
        let film = render_film(&scene);
        // Single precision places a far sphere to about 1e-7 of its distance,
        // so the shadow's edge is only that sharp.
        let margin = 1e-4 + 4.0 * f32::EPSILON as f64 * distance / r;
        let blocks = move |p: DVec3, l: &RefLight| sphere_blocks(p, l, c.as_vec3a().as_dvec3(), r, margin);
        let t = check_floor(&cam, &film, &[RefLight::Directional(dir, 1.0)], &sphere_hides(c, r), &blocks);
        assert!(t.dark > 20 && t.lit > 500, "distance {distance}: {t:?}");
        assert_pixel(
            film.pixel(N / 2, N / 2),
            ambient_term(),
            &format!("distance {distance}: origin must be in shadow"),
        );
        counts.push(t.dark);
    }
    eprintln!("shadowed pixels by distance: {counts:?}");
}

#[test]
fn a_plane_far_above_blocks_a_directional_light_everywhere() {
    for height in [20.0f32, 1e3, 1e6] {
        let (cam, mut scene) = floor_scene();
        let m = gray(&mut scene);
        let normal = Vec3::new(0.1, 1.0, -0.2); // slightly tilted
        scene.add(Primitive::new(Plane::new(Vec3::new(0.0, height, 0.0), normal).unwrap(), Transform::IDENTITY, m));
        scene.add_light(Light::directional(Vec3::new(0.3, -1.0, 0.2), Color::ONE, 1.0).unwrap());
        let film = render_film(&scene);
        for (x, y) in cam.pixels() {
            let (o, d) = cam.pixel_ray(x, y);
            // Only floor pixels: the camera is below the tilted plane.
            if ray_plane(o, d, DVec3::ZERO, DVec3::Y).is_some() {
                assert_pixel(film.pixel(x, y), ambient_term(), &format!("height {height}, pixel ({x}, {y})"));
            }
        }
    }
}
