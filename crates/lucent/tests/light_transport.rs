//! Light transport against known answers: tests that fail when an
//! estimator of the path integrator is wrong, not only when it crashes.
//!
//! In the style of pbrt-v4's integrator tests
//! (`src/pbrt/cpu/integrators_test.cpp`): simple scenes whose exact answer
//! is known, each rendered with every sampler (Sobol, independent,
//! stratified) × several path depths × the three ways of finding light
//! ([`DirectLighting`]: MIS, light sampling only, BSDF sampling only; delta
//! lights are only ever found by light sampling, so their scenes skip
//! BSDF-only).
//!
//! | test | scene | expected value |
//! |---|---|---|
//! | `closed_scenes_converge_to_the_geometric_series` | camera inside an emitting, reflecting sphere and box | `Le Σₖ₌₀ᵐ aᵏ` |
//! | `diffuse_sphere_in_a_constant_environment` | convex sphere, uniform sky | `a·L` |
//! | `planes_under_a_non_uniform_environment_map` | tilted planes, image sky with a sun | `a/π ∫ L cos⁺ dω`, by quadrature here |
//! | `delta_lights_on_a_plane` | point, spot, directional light over a plane | `a/π · I cos θ / d²`, per pixel |
//! | `several_lights_of_different_power_add_up` | 3 area lights (radiance 1 to 100) + point + sun | the sum of one-light renders |
//! | `light_bsdf_and_mis_estimates_agree` | area lights + environment map, occluders | the three estimators agree |
//!
//! # Statistics
//!
//! Each pixel of a render is an independent estimate (the samplers scramble
//! every pixel independently, and the box filter of radius 1/2 keeps every
//! sample in its own pixel). Where every pixel has the same expectation the
//! spread of the pixels gives the standard error of the image mean,
//! `σ/√N`; where they differ, the same holds for residuals (pixel minus its
//! expected value) and for differences of two renders of the same pixel.
//! A check passes when `|got − want| ≤ 5·SE + 2·10⁻³·|want| + 10⁻⁴` (the
//! small slack is single-precision arithmetic), and *also* requires that
//! bound to be below 10 % of the expected value: a render too noisy to see
//! a 10 % bias fails, and so does an all-black image (its expected value is
//! never 0 here). Renders are deterministic (fixed seeds), so the tests are
//! too; the largest `|error| / bound` and `bound / value` of each test are
//! printed (`--nocapture`).

mod common;

use common::{ray_plane, smooth_step, RefCamera};
use glam::DVec3;
use lucent::film::{Accumulator, Filter};
use lucent::integrator::{DirectLighting, PathIntegrator};
use lucent::light::{Emitter, Environment, EnvironmentMap};
use lucent::prelude::*;
use lucent::render::render_into_with;
use lucent::sampling::SamplerKind;
use lucent::shapes::Shape;
use std::f64::consts::PI;
use std::sync::Arc;

const SAMPLERS: [SamplerKind; 3] = [SamplerKind::Sobol, SamplerKind::Independent, SamplerKind::Stratified];
const ALL_DIRECT: [DirectLighting; 3] = [DirectLighting::Mis, DirectLighting::LightsOnly, DirectLighting::BsdfOnly];
/// The estimators that can find delta lights (BSDF sampling never hits one).
const LIGHT_SAMPLING: [DirectLighting; 2] = [DirectLighting::Mis, DirectLighting::LightsOnly];

/// Standard errors allowed: some thousand checks per run, with slightly
/// heavier tails than a normal distribution (a small bright sun), must not
/// fail by chance when a change of sampler or integrator reshuffles the
/// random numbers.
const K_SIGMA: f64 = 5.0;
/// Relative slack for single-precision arithmetic.
const REL_SLACK: f64 = 2e-3;
/// Absolute slack.
const ABS_SLACK: f64 = 1e-4;
/// A bound wider than this fraction of the expected value makes the check
/// too weak to see a biased estimator: the check fails.
const MAX_BOUND: f64 = 0.1;

// ---------------------------------------------------------------------------
// Rendering and statistics.

/// A rendered image, linear radiance in double precision.
struct Image {
    width: u32,
    px: Vec<DVec3>,
}

impl Image {
    fn at(&self, x: u32, y: u32) -> DVec3 {
        self.px[(y * self.width + x) as usize]
    }

    fn channel(&self, c: usize) -> Vec<f64> {
        self.px.iter().map(|p| p[c]).collect()
    }

    fn mean(&self) -> DVec3 {
        self.px.iter().sum::<DVec3>() / self.px.len() as f64
    }
}

/// Render `scene` with the path tracer: box filter of radius 1/2 (each
/// sample in its own pixel), `spp` samples, default thread count.
fn render_path(
    scene: &Scene,
    sampler: SamplerKind,
    spp: u32,
    max_depth: u32,
    direct: DirectLighting,
    seed: u64,
) -> Image {
    let mut settings = RenderSettings::for_integrator(IntegratorKind::Path);
    settings.spp = spp;
    settings.max_depth = max_depth;
    settings.seed = seed;
    settings.sampler = sampler;
    settings.filter = Filter::Box { radius: 0.5 };
    let integrator = PathIntegrator { max_depth, direct, regularize: false, max_indirect: None };
    let camera = scene.camera();
    let mut acc = Accumulator::new(camera.width(), camera.height()).unwrap();
    let report = render_into_with(scene, &settings, &integrator, &mut acc, RenderOptions::default()).unwrap();
    // A discarded sample would bias the pixel it belonged to.
    assert_eq!(report.nonfinite, 0, "{sampler:?}/{max_depth}/{direct:?}: non-finite samples");
    assert_eq!(acc.spp(), spp);
    let film = acc.to_film();
    Image { width: film.width(), px: film.pixels().iter().map(|c| c.as_dvec3()).collect() }
}

/// Mean and standard error of the mean of independent values.
fn mean_se(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

fn label(sampler: SamplerKind, max_depth: u32, direct: DirectLighting) -> String {
    format!("{sampler:?}, max_depth {max_depth}, {direct:?}")
}

/// The checks of one test; failures are collected so that one run shows
/// every failing combination, and reported together at the end.
struct Checks {
    name: &'static str,
    count: usize,
    /// Largest `|error| / bound` seen (a pass is ≤ 1), and where.
    worst_ratio: f64,
    worst: String,
    /// Largest `bound / |expected|` seen (must stay ≤ MAX_BOUND).
    widest: f64,
    failures: Vec<String>,
}

impl Checks {
    fn new(name: &'static str) -> Self {
        Self { name, count: 0, worst_ratio: 0.0, worst: String::new(), widest: 0.0, failures: Vec::new() }
    }

    /// `got ± se` must estimate `want`, with a bound tight enough to see a
    /// bias of MAX_BOUND · want.
    fn expect(&mut self, what: &str, got: f64, se: f64, want: f64) {
        let bound = K_SIGMA * se + REL_SLACK * want.abs() + ABS_SLACK;
        self.record(what, got - want, bound, want.abs(), true, &format!("{got:.5} ± {se:.5}, expected {want:.5}"));
    }

    /// Two estimates of the same quantity (size `scale`), whose per-pixel
    /// differences are `diffs`, must agree; `sensitive`: the bound must be
    /// tight enough to see a bias of MAX_BOUND · scale.
    fn agree(&mut self, what: &str, diffs: &[f64], scale: f64, sensitive: bool) {
        let (d, se) = mean_se(diffs);
        let bound = K_SIGMA * se + REL_SLACK * scale + ABS_SLACK;
        self.record(what, d, bound, scale, sensitive, &format!("difference {d:.5} ± {se:.5}, scale {scale:.5}"));
    }

    /// A value that must be at least `floor` (against vacuous passes).
    fn at_least(&mut self, what: &str, got: f64, floor: f64) {
        self.count += 1;
        if got.is_nan() || got < floor {
            self.failures.push(format!("{what}: {got:.5} is below {floor:.5}"));
        }
    }

    fn record(&mut self, what: &str, error: f64, bound: f64, scale: f64, sensitive: bool, detail: &str) {
        self.count += 1;
        let ratio = error.abs() / bound;
        if ratio > self.worst_ratio {
            self.worst_ratio = ratio;
            self.worst = format!("{what}: {detail}");
        }
        if sensitive {
            self.widest = self.widest.max(bound / scale);
        }
        if error.is_nan() || ratio > 1.0 {
            self.failures.push(format!("{what}: {detail} (error {:.1}× the bound {bound:.5})", ratio));
        } else if sensitive && (bound > MAX_BOUND * scale || (bound / scale).is_nan()) {
            self.failures.push(format!(
                "{what}: {detail}: the bound {bound:.5} is over {:.0}% of {scale:.5}, too weak to see a biased estimator",
                MAX_BOUND * 100.0
            ));
        }
    }

    fn finish(self) {
        println!(
            "{}: {} checks, largest |error|/bound {:.2} ({}), largest bound/value {:.2}%",
            self.name,
            self.count,
            self.worst_ratio,
            self.worst,
            100.0 * self.widest
        );
        assert!(self.count > 0, "{}: nothing was checked", self.name);
        assert!(
            self.failures.is_empty(),
            "{}: {} of {} checks failed:\n{}",
            self.name,
            self.failures.len(),
            self.count,
            self.failures.join("\n")
        );
    }
}

// ---------------------------------------------------------------------------
// Scene pieces.

fn c3(v: DVec3) -> Color {
    v.as_vec3a()
}

fn diffuse(b: &mut SceneBuilder, albedo: DVec3) -> MaterialId {
    b.add_material(Material::Diffuse { reflectance: Texture::Constant(c3(albedo)) }).unwrap()
}

/// The two triangles of the planar quad `p` (corners in order around it),
/// wound so that their front (emitting) side faces `front`.
fn quad(p: [DVec3; 4], front: DVec3) -> [Triangle; 2] {
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let p = if n.dot(front) > 0.0 { p } else { [p[3], p[2], p[1], p[0]] };
    let v = p.map(|x| x.as_vec3a());
    [Triangle::new([v[0], v[1], v[2]], None).unwrap(), Triangle::new([v[0], v[2], v[3]], None).unwrap()]
}

/// A horizontal square quad of half-size `h` centred at `c`, its front
/// facing `front`.
fn square(c: DVec3, h: f64, front: DVec3) -> [Triangle; 2] {
    let (s, t) = front.normalize().any_orthonormal_pair();
    quad([c - h * s - h * t, c + h * s - h * t, c + h * s + h * t, c - h * s + h * t], front)
}

fn camera(eye: DVec3, look_at: DVec3, up: DVec3, fov: f32, w: u32, h: u32) -> RefCamera {
    let f = |v: DVec3| v.as_vec3a().to_array();
    RefCamera::new(f(eye), f(look_at), f(up), fov, w, h)
}

/// An equirectangular environment image: the texels (row by row from the
/// top) and the rotation about +y in degrees.
#[derive(Clone)]
struct EnvImage {
    width: u32,
    height: u32,
    texels: Vec<DVec3>,
    rotation: f64,
}

impl EnvImage {
    /// A blue sky varying with azimuth, a brown ground, and a small bright
    /// sun high in the sky: far from uniform, so importance sampling of the
    /// map matters, and not symmetric about any axis.
    fn sky(scale: f64) -> Self {
        let (w, h) = (32u32, 16u32);
        let mut texels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let u = (x as f64 + 0.5) / w as f64;
                let v = (y as f64 + 0.5) / h as f64;
                let l = if (20..22).contains(&x) && (3..5).contains(&y) {
                    DVec3::new(6.0, 5.0, 4.0) // the sun: 2 × 2 texels
                } else if y < h / 2 {
                    DVec3::new(0.3, 0.5, 1.0) * (0.6 + 0.4 * (2.0 * PI * u).sin()) * (1.2 - v)
                } else {
                    DVec3::new(0.3, 0.25, 0.2)
                };
                texels.push(l * scale);
            }
        }
        Self { width: w, height: h, texels, rotation: 30.0 }
    }

    fn environment(&self) -> Environment {
        let px = self.texels.iter().map(|&t| c3(t)).collect();
        let map = EnvironmentMap::new(self.width, self.height, px, 1.0, self.rotation as f32).unwrap();
        Environment::Image(Arc::new(map))
    }

    /// World direction of `(u, v)`, from the mapping documented in
    /// `light/environment.rs` (not from lucent's code): `θ = πv` from +y,
    /// `φ = 2π(u − 1/2)`, local `(sin θ sin φ, cos θ, −sin θ cos φ)`, then
    /// turned by the rotation R about +y, `(x, z) ↦ (x cos R + z sin R,
    /// −x sin R + z cos R)` (the image centre moves to `(−sin R, 0, −cos R)`).
    fn direction(&self, u: f64, v: f64) -> DVec3 {
        let (st, ct) = (PI * v).sin_cos();
        let (sp, cp) = (2.0 * PI * (u - 0.5)).sin_cos();
        let d = DVec3::new(st * sp, ct, -st * cp);
        let (s, c) = self.rotation.to_radians().sin_cos();
        DVec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    /// Irradiance on a surface with unit normal `n`, `∫ L(ω) max(0, n·ω) dω`.
    /// Lookup is nearest-texel, so `L` is constant over each texel's
    /// `(u, v)` rectangle, and `dω = 2π² sin(πv) du dv`; each texel's
    /// integral of `max(0, n·ω)` is a 16 × 16 midpoint rule.
    fn irradiance(&self, n: DVec3) -> DVec3 {
        const K: u32 = 16;
        let (w, h) = (self.width as f64, self.height as f64);
        let mut e = DVec3::ZERO;
        for y in 0..self.height {
            for x in 0..self.width {
                let mut g = 0.0;
                for j in 0..K {
                    for i in 0..K {
                        let u = (x as f64 + (i as f64 + 0.5) / K as f64) / w;
                        let v = (y as f64 + (j as f64 + 0.5) / K as f64) / h;
                        g += n.dot(self.direction(u, v)).max(0.0) * (PI * v).sin();
                    }
                }
                e += self.texels[(y * self.width + x) as usize] * g * 2.0 * PI * PI / (w * h * (K * K) as f64);
            }
        }
        e
    }
}

// ---------------------------------------------------------------------------
// 1. Closed scenes (pbrt-v4's "sphere with Le, Kd" scenes).

/// Inside a closed surface that everywhere emits `Le` and reflects
/// diffusely with albedo `a`, radiance is the same at every point and in
/// every direction, so the rendering equation `L = Le + ∫ (a/π) L cos dω`
/// becomes `L = Le + a·L`; with at most `m` scattering events the Neumann
/// series stops after `m + 1` terms:
///
/// `L_m = Le Σₖ₌₀ᵐ aᵏ = Le (1 − aᵐ⁺¹)/(1 − a)  →  Le / (1 − a)`
///
/// (pbrt-v4 `integrators_test.cpp`: Le = 0.5, Kd = 0.5 inside a sphere gives
/// 1). Depth 64 is far past Russian roulette's start, which must not bias
/// the answer. Two enclosures: a sphere, sampled by area from inside (one
/// light), and a box of 12 one-sided triangles of three sizes, emitting
/// inwards (12 lights picked by power, spherical-triangle sampling, lights
/// coplanar with the shading point).
#[test]
fn closed_scenes_converge_to_the_geometric_series() {
    let albedo = DVec3::new(0.3, 0.5, 0.7);
    let le = DVec3::splat(0.5);
    let emission = Emission { radiance: c3(le), two_sided: true, reverse: false, image: None };

    let cam = camera(DVec3::new(0.3, -0.2, 0.1), DVec3::new(1.0, 0.5, 2.0), DVec3::Y, 70.0, 12, 12);
    let mut b = SceneBuilder::new(cam.camera());
    let wall = diffuse(&mut b, albedo);
    b.add_emissive(Sphere::new(Vec3::ZERO, 2.0).unwrap(), Transform::IDENTITY, wall, emission).unwrap();
    let sphere = b.build().unwrap();

    let cam = camera(DVec3::new(0.5, 0.2, 0.0), DVec3::new(-1.0, -0.3, 2.0), DVec3::Y, 80.0, 12, 12);
    let mut b = SceneBuilder::new(cam.camera());
    let wall = diffuse(&mut b, albedo);
    let (lo, hi) = (DVec3::new(-2.0, -1.0, -1.5), DVec3::new(2.0, 1.5, 3.0));
    let centre = 0.5 * (lo + hi);
    let corner = |i: usize| DVec3::new([lo.x, hi.x][i & 1], [lo.y, hi.y][(i >> 1) & 1], [lo.z, hi.z][i >> 2]);
    // Each face as four corners in order around it.
    for face in [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]] {
        let p = face.map(corner);
        let inward = centre - 0.25 * (p[0] + p[1] + p[2] + p[3]);
        for t in quad(p, inward) {
            b.add_emissive(
                t,
                Transform::IDENTITY,
                wall,
                Emission { radiance: c3(le), two_sided: false, reverse: false, image: None },
            )
            .unwrap();
        }
    }
    let boxed = b.build().unwrap();
    // Each face's two triangles form a rectangle: one light per face,
    // sampled as a spherical rectangle.
    assert_eq!(boxed.light_set().emitters().len(), 6);
    assert!(boxed
        .light_set()
        .emitters()
        .iter()
        .all(|e| matches!(e, Emitter::Area(a) if matches!(a.shape, Shape::Rectangle(_)))));

    let mut checks = Checks::new("closed scenes");
    for (name, scene) in [("sphere", &sphere), ("box", &boxed)] {
        for sampler in SAMPLERS {
            for max_depth in [1, 2, 64] {
                for direct in ALL_DIRECT {
                    let img = render_path(scene, sampler, 32, max_depth, direct, 7);
                    for c in 0..3 {
                        let a = albedo[c];
                        let want = le[c] * (1.0 - a.powi(max_depth as i32 + 1)) / (1.0 - a);
                        let (got, se) = mean_se(&img.channel(c));
                        checks.expect(
                            &format!("{name}, {}, channel {c}", label(sampler, max_depth, direct)),
                            got,
                            se,
                            want,
                        );
                    }
                }
            }
        }
    }
    checks.finish();
}

// ---------------------------------------------------------------------------
// 2. Environment light.

/// A convex diffuse sphere (albedo a) under a constant sky L: every point
/// sees the sky over its whole hemisphere (a convex body never shadows
/// itself), so irradiance is πL and the reflected radiance (a/π)·πL = a·L,
/// at any depth (light leaving the sphere escapes). pbrt-v4's test: an
/// infinite light of radiance 1 and Kd = 0.5 gives 0.5. The camera sees
/// nothing but the sphere (half-angle of the sphere asin(1/3) = 19.5°, of
/// the image corners 14.0°).
#[test]
fn diffuse_sphere_in_a_constant_environment() {
    let albedo = DVec3::new(0.2, 0.5, 0.9);
    let sky = DVec3::new(1.0, 0.8, 0.6);
    let cam = camera(DVec3::new(0.0, 0.0, -3.0), DVec3::ZERO, DVec3::Y, 20.0, 12, 12);
    let mut b = SceneBuilder::new(cam.camera());
    let m = diffuse(&mut b, albedo);
    b.add_shape(Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::IDENTITY, m).unwrap();
    b.set_environment(Environment::Constant(c3(sky))).unwrap();
    let scene = b.build().unwrap();

    let mut checks = Checks::new("sphere in a constant environment");
    for sampler in SAMPLERS {
        for max_depth in [1, 5] {
            for direct in ALL_DIRECT {
                // Light sampling spends half its samples below the horizon.
                let spp = if direct == DirectLighting::BsdfOnly { 16 } else { 256 };
                let img = render_path(&scene, sampler, spp, max_depth, direct, 3);
                for c in 0..3 {
                    let (got, se) = mean_se(&img.channel(c));
                    let what = format!("{}, channel {c}", label(sampler, max_depth, direct));
                    checks.expect(&what, got, se, albedo[c] * sky[c]);
                }
            }
        }
    }
    checks.finish();
}

/// An infinite diffuse plane (albedo a) with unit normal n, under an
/// equirectangular sky with a sun: nothing occludes the sky above the
/// plane, so every visible point reflects
///
/// `L = (a/π) ∫_{n·ω > 0} L_env(ω) (n·ω) dω`
///
/// (the reflection equation for a Lambertian BRDF a/π), computed here by
/// quadrature over the texels ([`EnvImage::irradiance`]). The image is
/// uniform, so its mean is checked. Four normals, one facing the ground;
/// the map is rotated by 30°. Light sampling alone tests the map's
/// importance sampling and pdf, BSDF sampling alone its lookup, MIS both.
#[test]
fn planes_under_a_non_uniform_environment_map() {
    // The quadrature itself, on maps with a closed-form answer: a uniform
    // sky of radiance 1 gives π for any normal; a sky of 1 above the horizon
    // and 0 below gives π(1 + n_y)/2 (the sky view factor of a tilted
    // surface).
    let mut uniform = EnvImage::sky(1.0);
    uniform.texels.iter_mut().for_each(|t| *t = DVec3::ONE);
    let mut upper = uniform.clone();
    upper.texels.iter_mut().skip((upper.width * upper.height / 2) as usize).for_each(|t| *t = DVec3::ZERO);
    for n in [DVec3::Y, DVec3::new(1.0, 1.0, 0.3).normalize(), DVec3::new(0.3, -0.6, 0.7).normalize()] {
        let e = uniform.irradiance(n).x;
        assert!((e - PI).abs() < 1e-3 * PI, "uniform sky on {n}: {e}");
        let e = upper.irradiance(n).x;
        let want = PI * (1.0 + n.y) / 2.0;
        assert!((e - want).abs() < 2e-3 * PI, "upper sky on {n}: {e} vs {want}");
    }

    let sky = EnvImage::sky(1.0);
    let env = sky.environment();
    let albedo = DVec3::new(0.8, 0.6, 0.4);
    let mut checks = Checks::new("planes under an environment map");
    for n in [
        DVec3::Y,
        DVec3::new(1.0, 1.0, 0.3).normalize(),
        DVec3::new(-0.5, 0.2, -0.8).normalize(),
        DVec3::new(0.3, -0.6, 0.7).normalize(),
    ] {
        let up = if n.y.abs() < 0.9 { DVec3::Y } else { DVec3::X };
        let cam = camera(3.0 * n, DVec3::ZERO, up, 40.0, 16, 16);
        let mut b = SceneBuilder::new(cam.camera());
        let m = diffuse(&mut b, albedo);
        b.add_shape(Plane::new(Vec3::ZERO, n.as_vec3a()).unwrap(), Transform::IDENTITY, m).unwrap();
        b.set_environment(env.clone()).unwrap();
        let scene = b.build().unwrap();
        let want = albedo / PI * sky.irradiance(n);
        for sampler in SAMPLERS {
            for max_depth in [1, 4] {
                for direct in ALL_DIRECT {
                    // BSDF sampling finds the sun rarely: more samples.
                    let spp = if direct == DirectLighting::BsdfOnly { 512 } else { 128 };
                    let img = render_path(&scene, sampler, spp, max_depth, direct, 11);
                    for c in 0..3 {
                        let (got, se) = mean_se(&img.channel(c));
                        let what = format!("normal {n:.2}, {}, channel {c}", label(sampler, max_depth, direct));
                        checks.expect(&what, got, se, want[c]);
                    }
                }
            }
        }
    }
    checks.finish();
}

// ---------------------------------------------------------------------------
// 3. Delta lights under the path integrator.

/// Point, spot and directional lights over a diffuse plane y = 0 (albedo
/// a), seen by a camera from above. A delta light delivers irradiance
/// `E = I/d² · cos θ` (point; PBRT 4th ed. §12.1, inverse-square falloff),
/// `I·smoothstep(cos α, cos θ_total, cos θ_start)/d² · cos θ` (spot, α the
/// angle to its axis; PBRT 4th ed. §12.2.1 and `light/mod.rs`) or `E cos θ`
/// (directional), and the plane reflects `(a/π)·E`. Each pixel's expected
/// value is the average of that over the pixel (8 × 8 film positions, the
/// rays intersected with the plane in double precision).
///
/// Alone, a delta light makes the estimate at a point exact (one light,
/// chosen with probability 1, no occluder, reflected light escapes), so
/// every pixel must match to within the variation over the pixel:
/// `5·σ_pixel/√spp` (plus 0.1 % of the brightest pixel: the 8 × 8
/// reference positions can miss the faint tail of the spot's smoothstep). With a constant sky L added (two lights to choose
/// from), the plane also reflects a·L, and the image mean of the residuals
/// is checked.
#[test]
fn delta_lights_on_a_plane() {
    let albedo = DVec3::new(0.7, 0.5, 0.3);
    let (w, h) = (16, 12);
    let cam = camera(DVec3::new(0.4, 3.0, -2.5), DVec3::new(0.0, 0.0, 0.3), DVec3::Y, 50.0, w, h);
    let sky = DVec3::new(0.2, 0.3, 0.4);

    struct Case {
        name: &'static str,
        light: Light,
        /// Irradiance on the plane (normal +y) at a point.
        irradiance: Box<dyn Fn(DVec3) -> f64>,
    }
    let point_pos = DVec3::new(0.5, 2.0, 1.0);
    let spot_pos = DVec3::new(-0.5, 2.5, 0.5);
    let spot_axis = DVec3::new(0.2, -1.0, 0.1).normalize();
    let (spot_angle, spot_delta) = (35.0f64, 10.0f64);
    let sun_dir = DVec3::new(0.3, -1.0, 0.5).normalize();
    let cases = [
        Case {
            name: "point",
            light: Light::point(point_pos.as_vec3a(), Color::ONE, 6.0, Falloff::InverseSquare).unwrap(),
            irradiance: Box::new(move |p: DVec3| {
                let to = point_pos - p;
                6.0 * (to.y / to.length()) / to.length_squared()
            }),
        },
        Case {
            name: "spot",
            light: Light::spot(
                spot_pos.as_vec3a(),
                spot_axis.as_vec3a(),
                Color::ONE,
                10.0,
                spot_angle as f32,
                spot_delta as f32,
                Falloff::InverseSquare,
            )
            .unwrap(),
            irradiance: Box::new(move |p: DVec3| {
                let to = spot_pos - p;
                let cos_axis = (-to.normalize()).dot(spot_axis);
                let cone =
                    smooth_step(cos_axis, spot_angle.to_radians().cos(), (spot_angle - spot_delta).to_radians().cos());
                10.0 * cone * (to.y / to.length()) / to.length_squared()
            }),
        },
        Case {
            name: "directional",
            light: Light::directional(sun_dir.as_vec3a(), Color::ONE, 2.0).unwrap(),
            irradiance: Box::new(move |_| 2.0 * (-sun_dir.y)),
        },
    ];

    let mut checks = Checks::new("delta lights on a plane");
    for case in &cases {
        // Per pixel: mean and standard deviation of the radiance over the
        // pixel's film positions.
        const K: u32 = 8;
        let reference: Vec<(DVec3, DVec3)> = cam
            .pixels()
            .map(|(x, y)| {
                let (mut s, mut s2) = (DVec3::ZERO, DVec3::ZERO);
                for j in 0..K {
                    for i in 0..K {
                        let d =
                            cam.dir_at(x as f64 + (i as f64 + 0.5) / K as f64, y as f64 + (j as f64 + 0.5) / K as f64);
                        let t = ray_plane(cam.eye, d, DVec3::ZERO, DVec3::Y).expect("every ray hits the plane");
                        let l = albedo / PI * (case.irradiance)(cam.eye + t * d);
                        s += l;
                        s2 += l * l;
                    }
                }
                let n = (K * K) as f64;
                let mean = s / n;
                (mean, (s2 / n - mean * mean).max(DVec3::ZERO).sqrt())
            })
            .collect();
        let want_mean = reference.iter().map(|r| r.0).sum::<DVec3>() / reference.len() as f64;
        let peak = reference.iter().map(|r| r.0.max_element()).fold(0.0, f64::max);
        // Both lit and unlit pixels (the spot's cone edge is in view).
        checks.at_least(&format!("{}: lit pixels", case.name), want_mean.min_element(), 0.01);

        for with_sky in [false, true] {
            let mut b = SceneBuilder::new(cam.camera());
            let m = diffuse(&mut b, albedo);
            b.add_shape(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, m).unwrap();
            b.add_light(case.light.clone());
            if with_sky {
                b.set_environment(Environment::Constant(c3(sky))).unwrap();
            }
            let scene = b.build().unwrap();
            let extra = if with_sky { albedo * sky } else { DVec3::ZERO };
            for sampler in SAMPLERS {
                for max_depth in [1, 3] {
                    for direct in LIGHT_SAMPLING {
                        let spp = if with_sky { 512 } else { 16 };
                        let img = render_path(&scene, sampler, spp, max_depth, direct, 5);
                        let what = format!(
                            "{}{}, {}",
                            case.name,
                            if with_sky { " + sky" } else { "" },
                            label(sampler, max_depth, direct)
                        );
                        for c in 0..3 {
                            let residuals: Vec<f64> = cam
                                .pixels()
                                .zip(&reference)
                                .map(|((x, y), r)| img.at(x, y)[c] - r.0[c] - extra[c])
                                .collect();
                            let (r, se) = mean_se(&residuals);
                            let want = want_mean[c] + extra[c];
                            checks.expect(&format!("{what}, channel {c}"), want + r, se, want);
                        }
                        if !with_sky {
                            // Every pixel, to within its own sampling error.
                            let mut bad = Vec::new();
                            for ((x, y), (want, sd)) in cam.pixels().zip(&reference) {
                                let got = img.at(x, y);
                                let bound =
                                    5.0 * *sd / (spp as f64).sqrt() + REL_SLACK * *want + DVec3::splat(1e-3 * peak);
                                if (got - *want).abs().cmpgt(bound).any() {
                                    bad.push(format!("({x}, {y}): {got:.4} vs {want:.4}"));
                                }
                            }
                            checks.count += 1;
                            if !bad.is_empty() {
                                checks.failures.push(format!("{what}: {} pixels off: {}", bad.len(), bad.join(", ")));
                            }
                        }
                    }
                }
            }
        }
    }
    checks.finish();
}

// ---------------------------------------------------------------------------
// 4. Several lights of different power.

/// Three area lights of radiance 1, 10 and 100 (and different sizes), a
/// point light and a sun over a floor with a sphere on it: the light set
/// picks one by power (probabilities from about 2 % to 60 %) and divides
/// by that probability. Light transport is linear in the emitters, so the
/// expected image with all lights on is the sum of the expected images with
/// one light on at a time (the others' shapes stay, not emitting). The
/// one-light renders choose their light with probability 1, so a wrong
/// light-selection probability shows as a difference. Same seeds for all
/// renders (common random numbers: the per-pixel differences are less
/// noisy, and still estimate the difference of the expectations).
#[test]
fn several_lights_of_different_power_add_up() {
    let (w, h) = (20, 16);
    let cam = camera(DVec3::new(0.0, 2.2, -4.5), DVec3::new(0.0, 0.4, 0.3), DVec3::Y, 55.0, w, h);
    enum Emitter {
        Area(Vec<Triangle>, f64),
        Ball(DVec3, f64, f64),
        Delta(Light),
    }
    let down = -DVec3::Y;
    let emitters = [
        ("area, radiance 1", Emitter::Area(square(DVec3::new(-1.5, 2.5, 0.5), 0.75, down).to_vec(), 1.0)),
        ("area, radiance 10", Emitter::Area(square(DVec3::new(1.2, 2.0, -0.5), 0.3, down).to_vec(), 10.0)),
        ("sphere, radiance 100", Emitter::Ball(DVec3::new(0.3, 1.6, 1.2), 0.15, 100.0)),
        (
            "point",
            Emitter::Delta(Light::point(Vec3::new(-0.6, 1.2, -1.0), Color::ONE, 1.0, Falloff::InverseSquare).unwrap()),
        ),
        (
            "sun",
            Emitter::Delta(Light::directional(Vec3::new(0.4, -1.0, 0.2), Color::new(0.3, 0.25, 0.2), 1.0).unwrap()),
        ),
    ];
    // The scene with only emitter `on` emitting (None: all of them).
    let build = |on: Option<usize>| {
        let mut b = SceneBuilder::new(cam.camera());
        let floor = diffuse(&mut b, DVec3::new(0.6, 0.6, 0.5));
        let ball = diffuse(&mut b, DVec3::new(0.7, 0.4, 0.3));
        let black = diffuse(&mut b, DVec3::new(0.2, 0.2, 0.2));
        b.add_shape(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, floor).unwrap();
        b.add_shape(Sphere::new(Vec3::new(0.0, 0.5, 0.0), 0.5).unwrap(), Transform::IDENTITY, ball).unwrap();
        for (i, (_, e)) in emitters.iter().enumerate() {
            let lit = on.is_none_or(|k| k == i);
            match e {
                Emitter::Area(tris, radiance) => {
                    for t in tris {
                        if lit {
                            let emission = Emission {
                                radiance: Color::splat(*radiance as f32),
                                two_sided: false,
                                reverse: false,
                                image: None,
                            };
                            b.add_emissive(t.clone(), Transform::IDENTITY, black, emission).unwrap();
                        } else {
                            b.add_shape(t.clone(), Transform::IDENTITY, black).unwrap();
                        }
                    }
                }
                Emitter::Ball(c, r, radiance) => {
                    let s = Sphere::new(c.as_vec3a(), *r as f32).unwrap();
                    if lit {
                        let emission = Emission {
                            radiance: Color::splat(*radiance as f32),
                            two_sided: false,
                            reverse: false,
                            image: None,
                        };
                        b.add_emissive(s, Transform::IDENTITY, black, emission).unwrap();
                    } else {
                        b.add_shape(s, Transform::IDENTITY, black).unwrap();
                    }
                }
                Emitter::Delta(light) => {
                    if lit {
                        b.add_light(light.clone());
                    }
                }
            }
        }
        b.build().unwrap()
    };
    let all = build(None);
    // Light selection is far from uniform here.
    let set = all.light_set();
    let pmfs: Vec<f32> = (0..set.emitters().len()).map(|i| set.pmf(i)).collect();
    let (lo, hi) = pmfs.iter().fold((1.0f32, 0.0f32), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    assert!(hi > 10.0 * lo, "light selection probabilities {pmfs:?}");
    let singles: Vec<Scene> = (0..emitters.len()).map(|i| build(Some(i))).collect();

    let mut checks = Checks::new("several lights");
    for sampler in SAMPLERS {
        for max_depth in [1, 3] {
            for direct in LIGHT_SAMPLING {
                let what = label(sampler, max_depth, direct);
                let img = render_path(&all, sampler, 64, max_depth, direct, 13);
                let parts: Vec<Image> =
                    singles.iter().map(|s| render_path(s, sampler, 64, max_depth, direct, 13)).collect();
                let total = img.mean();
                for (k, part) in parts.iter().enumerate() {
                    // Every light contributes visibly (nothing vacuous).
                    checks.at_least(&format!("{what}: {} alone", emitters[k].0), part.mean().min_element(), 0.01);
                }
                for c in 0..3 {
                    let diffs: Vec<f64> = (0..img.px.len())
                        .map(|i| img.px[i][c] - parts.iter().map(|p| p.px[i][c]).sum::<f64>())
                        .collect();
                    checks.agree(&format!("{what}, channel {c}: all lights − Σ one light"), &diffs, total[c], true);
                }
                checks.at_least(&format!("{what}: image mean"), total.min_element(), 0.1);
            }
        }
    }
    checks.finish();
}

// ---------------------------------------------------------------------------
// 5. Light sampling, BSDF sampling and MIS agree.

/// The same scene, lit by a large quad light, a small bright sphere light
/// and the environment map (no delta lights, which BSDF sampling cannot find), with
/// a sphere shadowing the floor and a second bounce at depth 4: light
/// sampling alone, BSDF sampling alone and MIS are three unbiased
/// estimators of the same image (Veach & Guibas 1995), so their per-pixel
/// differences must average to zero, over the image (with a bound tight
/// enough to see a 10 % bias) and over each quarter of it. A wrong pdf on
/// either side, a wrong MIS weight, or light counted twice or not at all
/// breaks the agreement.
#[test]
fn light_bsdf_and_mis_estimates_agree() {
    let (w, h) = (24, 18);
    let cam = camera(DVec3::new(0.5, 1.8, -3.5), DVec3::new(0.0, 0.4, 0.0), DVec3::Y, 50.0, w, h);
    let mut b = SceneBuilder::new(cam.camera());
    let floor = diffuse(&mut b, DVec3::new(0.5, 0.45, 0.4));
    let ball = diffuse(&mut b, DVec3::new(0.7, 0.3, 0.2));
    let dark = diffuse(&mut b, DVec3::splat(0.1));
    b.add_shape(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, floor).unwrap();
    b.add_shape(Sphere::new(Vec3::new(0.0, 0.6, 0.0), 0.6).unwrap(), Transform::IDENTITY, ball).unwrap();
    // A large, dim ceiling light, where BSDF sampling carries most of the
    // MIS weight, and a small bright sphere, where light sampling does.
    let tilted = DVec3::new(0.2, -1.0, -0.15).normalize();
    for t in square(DVec3::new(-0.3, 2.6, 0.3), 1.75, tilted) {
        b.add_emissive(
            t,
            Transform::IDENTITY,
            dark,
            Emission { radiance: Color::new(0.6, 0.55, 0.5), two_sided: false, reverse: false, image: None },
        )
        .unwrap();
    }
    let emission = Emission { radiance: Color::new(12.0, 12.0, 15.0), two_sided: false, reverse: false, image: None };
    b.add_emissive(Sphere::new(Vec3::new(1.2, 1.3, -0.6), 0.25).unwrap(), Transform::IDENTITY, dark, emission).unwrap();
    b.set_environment(EnvImage::sky(0.5).environment()).unwrap();
    let scene = b.build().unwrap();

    let quarters = [
        ("top left", 0..w / 2, 0..h / 2),
        ("top right", w / 2..w, 0..h / 2),
        ("bottom left", 0..w / 2, h / 2..h),
        ("bottom right", w / 2..w, h / 2..h),
    ];
    let mut checks = Checks::new("light, BSDF and MIS estimates");
    for sampler in SAMPLERS {
        for max_depth in [1, 4] {
            let renders: Vec<(DirectLighting, Image)> = ALL_DIRECT
                .iter()
                .map(|&direct| {
                    let spp = if direct == DirectLighting::BsdfOnly { 256 } else { 64 };
                    (direct, render_path(&scene, sampler, spp, max_depth, direct, 17))
                })
                .collect();
            let mis = &renders[0].1;
            checks.at_least(&format!("{sampler:?}, max_depth {max_depth}: image mean"), mis.mean().min_element(), 0.1);
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                let ((da, a), (db, bb)) = (&renders[i], &renders[j]);
                let what = format!("{sampler:?}, max_depth {max_depth}: {da:?} vs {db:?}");
                for c in 0..3 {
                    let scale = a.mean()[c];
                    let diffs: Vec<f64> = a.px.iter().zip(&bb.px).map(|(p, q)| p[c] - q[c]).collect();
                    checks.agree(&format!("{what}, channel {c}"), &diffs, scale, true);
                    for (name, xs, ys) in &quarters {
                        let (mut d, mut s) = (Vec::new(), 0.0);
                        for y in ys.clone() {
                            for x in xs.clone() {
                                d.push(a.at(x, y)[c] - bb.at(x, y)[c]);
                                s += a.at(x, y)[c];
                            }
                        }
                        let scale = s / d.len() as f64;
                        checks.agree(&format!("{what}, {name}, channel {c}"), &d, scale, false);
                    }
                }
            }
        }
    }
    checks.finish();
}
