//! Rendered pixels against closed-form shading.
//!
//! One sphere, one sample per pixel (the ray through the pixel centre), and
//! every pixel of the image compared with the value computed here from the
//! geometry in double precision: where the ray meets the sphere, the normal
//! there, the direction and distance to the light, and the documented
//! shading model
//!
//! `L = ka·albedo·ambient + Σ (kd·albedo/π + ks·max(0, r·wo)^e) · E · max(0, n·wi)`.
//!
//! Pixels that miss must show the background colour exactly, and pixels no
//! light reaches must show the ambient term exactly.

mod common;

use common::*;
use glam::DVec3;
use lucent::prelude::*;
use std::f64::consts::PI;

const W: u32 = 33;
const H: u32 = 25;
const CENTRE: [f32; 3] = [0.0, 0.0, 0.0];
const RADIUS: f32 = 1.2;
const ALBEDO: [f32; 3] = [0.8, 0.6, 0.4];
const KD: f32 = 0.7;
const KA: f32 = 0.25;
const AMBIENT: [f32; 3] = [0.05, 0.1, 0.15];
const BACKGROUND: [f32; 3] = [0.02, 0.03, 0.04];
/// Relative tolerance of lit pixels: single-precision hit points, normals and
/// light directions agree with the double-precision ones to a few 1e-7; the
/// shading formula amplifies that at most tenfold (Phong exponent 30).
const REL: f64 = 5e-5;

fn ref_camera() -> RefCamera {
    // Odd width and height: pixel (16, 12) is centred on the look-at point.
    RefCamera::new([1.0, 2.0, -6.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 36.0, W, H)
}

fn sphere_scene(material: Material, lights: &[Light]) -> (RefCamera, TestScene) {
    let cam = ref_camera();
    let mut scene = scene_one_spp(cam.camera());
    scene.background = v3(BACKGROUND);
    scene.ambient = v3(AMBIENT);
    let m = scene.add_material(material);
    scene.add(Primitive::new(Sphere::new(v3(CENTRE), RADIUS).unwrap(), Transform::IDENTITY, m));
    for l in lights {
        scene.add_light(l.clone());
    }
    (cam, scene)
}

/// A light, in double precision.
enum RefLight {
    Point { pos: DVec3, i: DVec3, inverse_square: bool },
    Directional { dir: DVec3, i: DVec3 },
    Spot { pos: DVec3, axis: DVec3, i: DVec3, cos_total: f64, cos_start: f64, inverse_square: bool },
}

/// What a light does at a point, as far as double precision can tell what
/// single precision will decide.
enum Reach {
    /// Light arrives from `wi` with irradiance `li` (perpendicular to `wi`),
    /// known to within the third value: single precision resolves the cosine
    /// to a spot's axis only to about 1e-7, and the smooth cone edge
    /// multiplies that by the slope of its smoothstep.
    Light(DVec3, DVec3, f64),
    /// Clearly none (outside a spot cone).
    None,
    /// On the edge of a cone: either answer is acceptable.
    Edge,
}

impl RefLight {
    fn sample(&self, p: DVec3) -> Reach {
        match *self {
            RefLight::Point { pos, i, inverse_square } => {
                let to = pos - p;
                let falloff = if inverse_square { 1.0 / to.length_squared() } else { 1.0 };
                Reach::Light(to.normalize(), i * falloff, 0.0)
            }
            RefLight::Directional { dir, i } => Reach::Light(-dir.normalize(), i, 0.0),
            RefLight::Spot { pos, axis, i, cos_total, cos_start, inverse_square } => {
                let to = pos - p;
                let wi = to.normalize();
                let cos_theta = (-wi).dot(axis.normalize());
                if (cos_theta - cos_total).abs() < 1e-6 {
                    return Reach::Edge;
                }
                if cos_theta < cos_total {
                    return Reach::None;
                }
                let falloff = if inverse_square { 1.0 / to.length_squared() } else { 1.0 };
                let cone = smooth_step(cos_theta, cos_total, cos_start);
                let s = ((cos_theta - cos_total) / (cos_start - cos_total)).clamp(0.0, 1.0);
                let slope = 6.0 * s * (1.0 - s) / (cos_start - cos_total);
                Reach::Light(wi, i * cone * falloff, i.max_element() * falloff * slope * 5e-7)
            }
        }
    }
}

struct RefMaterial {
    albedo: DVec3,
    kd: f64,
    ka: f64,
    ks: f64,
    exponent: f64,
}

impl RefMaterial {
    fn matte() -> Self {
        Self { albedo: d3(ALBEDO), kd: KD as f64, ka: KA as f64, ks: 0.0, exponent: 1.0 }
    }

    /// BRDF: Lambert plus the Phong lobe about the mirror direction of `wi`.
    fn f(&self, wo: DVec3, wi: DVec3, n: DVec3) -> DVec3 {
        let mut f = self.kd * self.albedo / PI;
        let r = 2.0 * n.dot(wi) * n - wi;
        let cos_r = r.dot(wo);
        if self.ks > 0.0 && cos_r > 0.0 {
            f += DVec3::splat(self.ks * cos_r.powf(self.exponent));
        }
        f
    }
}

#[derive(Debug, Default)]
struct Tally {
    /// Pixels lit by at least one light, checked against the formula.
    lit: usize,
    /// Pixels on the sphere no light reaches, checked for the exact ambient term.
    ambient_only: usize,
    /// Pixels that miss, checked for the exact background colour.
    background: usize,
    /// Largest relative error among lit pixels.
    max_rel_err: f64,
}

/// Compare every pixel of `film` with the reference.
fn compare(cam: &RefCamera, film: &Film, mat: &RefMaterial, lights: &[RefLight]) -> Tally {
    let mut tally = Tally::default();
    let ambient_f32 = KA * v3(ALBEDO) * v3(AMBIENT);
    assert_eq!(mat.ka, KA as f64);
    let ambient = mat.ka * mat.albedo * d3(AMBIENT);
    for (x, y) in cam.pixels() {
        let got = film.pixel(x, y);
        let (o, d) = cam.pixel_ray(x, y);
        let t = match ray_sphere(o, d, d3(CENTRE), RADIUS as f64, 1e-4) {
            Hit::Miss => {
                assert_pixel(got, v3(BACKGROUND), &format!("pixel ({x}, {y}) misses the sphere: background expected"));
                tally.background += 1;
                continue;
            }
            Hit::Uncertain => continue,
            Hit::At(t) => t,
        };
        let p = o + t * d;
        let n = (p - d3(CENTRE)) / RADIUS as f64;
        let wo = -d;
        let mut want = ambient;
        let mut any_light = false;
        let mut edge = false;
        let mut slack = 0.0;
        for light in lights {
            match light.sample(p) {
                Reach::Light(wi, li, uncertainty) => {
                    let cos = n.dot(wi);
                    if cos > 1e-5 {
                        let f = mat.f(wo, wi, n);
                        want += f * li * cos;
                        slack += f.max_element() * uncertainty * cos;
                        any_light = true;
                    } else if cos > -1e-5 {
                        edge = true; // at the terminator
                    }
                }
                Reach::None => {}
                Reach::Edge => edge = true,
            }
        }
        if edge {
            continue;
        }
        if any_light {
            let scale = want.max_element();
            let err = (diff(got, want) - slack).max(0.0) / scale;
            assert!(
                err <= REL,
                "pixel ({x}, {y}): rendered {got}, analytic {want} (relative error {err:e}); hit {p}, normal {n}"
            );
            tally.max_rel_err = tally.max_rel_err.max(err);
            tally.lit += 1;
        } else {
            assert_pixel(
                got,
                ambient_f32,
                &format!("pixel ({x}, {y}) receives no light: the ambient term exactly expected"),
            );
            tally.ambient_only += 1;
        }
    }
    eprintln!("{tally:?}");
    tally
}

fn light_color() -> Color {
    Color::new(1.0, 0.9, 0.7)
}

#[test]
fn point_light_without_falloff_is_lambertian() {
    let pos = [3.0, 4.0, -2.0];
    let light = Light::point(v3(pos), light_color(), 2.0, Falloff::None).unwrap();
    let (cam, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(KA).unwrap(), &[light]);
    let film = render_film(&scene);
    let i = light_color().as_dvec3() * 2.0;
    let t = compare(&cam, &film, &RefMaterial::matte(), &[RefLight::Point { pos: d3(pos), i, inverse_square: false }]);
    assert!(t.lit > 200 && t.ambient_only > 20 && t.background > 100, "{t:?}");

    // One pixel spelled out: the centre pixel looks along the view axis and
    // meets the sphere where the axis enters it.
    let (o, d) = cam.pixel_ray(16, 12);
    assert!((d - cam.w).length() < 1e-15);
    let p = o + ((d3(CENTRE) - o).length() - RADIUS as f64) * d;
    let n = (p - d3(CENTRE)).normalize();
    let cos = n.dot((d3(pos) - p).normalize());
    let want = (KD as f64 / PI) * d3(ALBEDO) * i * cos + (KA as f64) * d3(ALBEDO) * d3(AMBIENT);
    assert!(diff(film.pixel(16, 12), want) < 1e-5 * want.max_element(), "{} vs {want}", film.pixel(16, 12));
}

#[test]
fn point_light_with_inverse_square_falloff() {
    let pos = [-2.5, 3.0, -3.0];
    let light = Light::point(v3(pos), light_color(), 20.0, Falloff::InverseSquare).unwrap();
    let (cam, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(KA).unwrap(), &[light]);
    let film = render_film(&scene);
    let i = light_color().as_dvec3() * 20.0;
    let t = compare(&cam, &film, &RefMaterial::matte(), &[RefLight::Point { pos: d3(pos), i, inverse_square: true }]);
    assert!(t.lit > 200 && t.ambient_only > 20 && t.background > 100, "{t:?}");

    // The same light without falloff is brighter by exactly d² at each point.
    let light = Light::point(v3(pos), light_color(), 20.0, Falloff::None).unwrap();
    let (_, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(0.0).unwrap(), &[light]);
    let flat = render_film(&scene);
    let light = Light::point(v3(pos), light_color(), 20.0, Falloff::InverseSquare).unwrap();
    let (_, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(0.0).unwrap(), &[light]);
    let falling = render_film(&scene);
    let (o, d) = cam.pixel_ray(16, 12);
    let Hit::At(t) = ray_sphere(o, d, d3(CENTRE), RADIUS as f64, 1e-4) else { panic!("centre pixel misses") };
    let d2 = (d3(pos) - (o + t * d)).length_squared();
    let ratio = flat.pixel(16, 12).as_dvec3() / falling.pixel(16, 12).as_dvec3();
    assert!((ratio - DVec3::splat(d2)).abs().max_element() < 1e-5 * d2, "ratio {ratio}, d² {d2}");
}

#[test]
fn directional_light_is_lambertian() {
    // Travelling towards the camera: much of the visible side is in the dark.
    let dir = [-2.0, -1.0, 0.5];
    let light = Light::directional(v3(dir), light_color(), 1.5).unwrap();
    let (cam, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(KA).unwrap(), &[light]);
    let film = render_film(&scene);
    let i = light_color().as_dvec3() * 1.5;
    let t = compare(&cam, &film, &RefMaterial::matte(), &[RefLight::Directional { dir: d3(dir), i }]);
    assert!(t.lit > 200 && t.ambient_only > 20 && t.background > 100, "{t:?}");
}

#[test]
fn spot_light_is_full_on_its_axis_and_dark_outside_its_cone() {
    let cam = ref_camera();
    // The centre pixel's hit point, and a spot aimed straight at it.
    let (o, d) = cam.pixel_ray(16, 12);
    let Hit::At(t) = ray_sphere(o, d, d3(CENTRE), RADIUS as f64, 1e-4) else { panic!("centre pixel misses") };
    let target = o + t * d;
    let pos = [1.5f32, 2.5, -3.5];
    let axis = (target - d3(pos)).as_vec3a();
    let (angle, delta) = (12.0f32, 3.0f32);
    for falloff in [Falloff::None, Falloff::InverseSquare] {
        let light = Light::spot(v3(pos), axis, light_color(), 6.0, angle, delta, falloff).unwrap();
        let (cam, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(KA).unwrap(), &[light]);
        let film = render_film(&scene);
        let inverse_square = falloff == Falloff::InverseSquare;
        let reference = RefLight::Spot {
            pos: d3(pos),
            axis: axis.as_dvec3(),
            i: light_color().as_dvec3() * 6.0,
            cos_total: (angle as f64).to_radians().cos(),
            cos_start: ((angle - delta) as f64).to_radians().cos(),
            inverse_square,
        };
        let t = compare(&cam, &film, &RefMaterial::matte(), std::slice::from_ref(&reference));
        // The cone covers part of the sphere: lit pixels inside, many on
        // the sphere outside it get the ambient term only.
        assert!(t.lit > 20 && t.ambient_only > 100 && t.background > 100, "{t:?}");

        // On the axis: the full intensity, no cone attenuation.
        let n = (target - d3(CENTRE)).normalize();
        let to = d3(pos) - target;
        let cos = n.dot(to.normalize());
        let e = if inverse_square { 6.0 / to.length_squared() } else { 6.0 };
        let want =
            (KD as f64 / PI) * d3(ALBEDO) * light_color().as_dvec3() * e * cos + KA as f64 * d3(ALBEDO) * d3(AMBIENT);
        let got = film.pixel(16, 12);
        assert!(diff(got, want) < 1e-5 * want.max_element(), "on the axis: {got} vs {want}");
    }
}

#[test]
fn phong_highlight_peaks_at_the_mirror_configuration() {
    let cam = ref_camera();
    let (ks, exponent) = (0.6f32, 30.0f32);
    // Put the light where pixel (20, 9) sees its mirror image: along the view
    // ray reflected about the normal.
    let (px, py) = (20, 9);
    let (o, d) = cam.pixel_ray(px, py);
    let Hit::At(t) = ray_sphere(o, d, d3(CENTRE), RADIUS as f64, 1e-3) else { panic!("pixel misses") };
    let p = o + t * d;
    let n = (p - d3(CENTRE)).normalize();
    let mirror = reflect(d, n);
    let pos = (p + 4.0 * mirror).as_vec3a();
    let light = Light::point(pos, light_color(), 1.5, Falloff::None).unwrap();
    let material = Material::phong(v3(ALBEDO), KD, ks, exponent, 0.0).unwrap().with_ka(KA).unwrap();
    let (cam, scene) = sphere_scene(material, &[light]);
    let film = render_film(&scene);
    let mat = RefMaterial { ks: ks as f64, exponent: exponent as f64, ..RefMaterial::matte() };
    let i = light_color().as_dvec3() * 1.5;
    let tally = compare(&cam, &film, &mat, &[RefLight::Point { pos: pos.as_dvec3(), i, inverse_square: false }]);
    assert!(tally.lit > 200 && tally.background > 100, "{tally:?}");

    // At the mirror pixel the lobe is at its peak: the BRDF gains exactly ks.
    let wi = (pos.as_dvec3() - p).normalize();
    let cos = n.dot(wi);
    let ambient = KA as f64 * d3(ALBEDO) * d3(AMBIENT);
    let diffuse = (KD as f64 / PI) * d3(ALBEDO) * i * cos;
    let highlight = film.pixel(px, py).as_dvec3() - ambient - diffuse;
    let want = ks as f64 * i * cos;
    assert!(
        (highlight - want).abs().max_element() < 1e-4 * want.max_element(),
        "highlight {highlight}, expected ks·I·cosθ = {want}"
    );
    // And it is the brightest pixel of the image.
    let brightest = film.pixels().iter().map(|c| c.x).fold(0.0f32, f32::max);
    assert_eq!(brightest, film.pixel(px, py).x);
}

#[test]
fn ambient_only_and_background_are_exact() {
    let albedo = Color::new(0.3, 0.7, 0.9);
    let ka = 0.35;
    let material = Material::phong(albedo, 0.8, 0.5, 10.0, 0.0).unwrap().with_ka(ka).unwrap();
    let (cam, scene) = sphere_scene(material, &[]);
    let film = render_film(&scene);
    let want = ka * albedo * v3(AMBIENT);
    let (mut on, mut off) = (0, 0);
    for (x, y) in cam.pixels() {
        let (o, d) = cam.pixel_ray(x, y);
        match ray_sphere(o, d, d3(CENTRE), RADIUS as f64, 1e-4) {
            Hit::At(_) => {
                assert_pixel(film.pixel(x, y), want, &format!("pixel ({x}, {y})"));
                on += 1;
            }
            Hit::Miss => {
                assert_pixel(film.pixel(x, y), v3(BACKGROUND), &format!("pixel ({x}, {y})"));
                off += 1;
            }
            Hit::Uncertain => {}
        }
    }
    assert!(on > 200 && off > 100, "{on} on the sphere, {off} off");
}

#[test]
fn lights_add_up() {
    let point = [3.0, 4.0, -2.0];
    let dir = [-1.0, -2.0, 1.5];
    let lights = [
        Light::point(v3(point), light_color(), 2.0, Falloff::None).unwrap(),
        Light::directional(v3(dir), Color::new(0.2, 0.4, 1.0), 0.8).unwrap(),
    ];
    let (cam, scene) = sphere_scene(Material::matte(v3(ALBEDO), KD).unwrap().with_ka(KA).unwrap(), &lights);
    let film = render_film(&scene);
    let refs = [
        RefLight::Point { pos: d3(point), i: light_color().as_dvec3() * 2.0, inverse_square: false },
        RefLight::Directional { dir: d3(dir), i: DVec3::new(0.2, 0.4, 1.0) * 0.8 },
    ];
    let t = compare(&cam, &film, &RefMaterial::matte(), &refs);
    assert!(t.lit > 250 && t.background > 100, "{t:?}");
}
