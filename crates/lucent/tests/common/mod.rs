//! Helpers shared by the integration tests: an independent double-precision
//! model of the camera and of ray–sphere / ray–plane intersection, a small
//! deterministic random source, and tolerant colour comparison.
//!
//! The reference computations here deliberately do not call into lucent: the
//! tests compare what the renderer produces with what the geometry says it
//! must produce.

#![allow(dead_code)]

use glam::{DMat3, DVec3};
use lucent::geometry::Vec3;
use lucent::prelude::*;
use lucent::sampling::Pcg32;

/// A pinhole camera in double precision, built from the same parameters as
/// [`Camera::new`] and following its documented model: `w` the view
/// direction, `u = w × up`, `v = u × w`, an image plane at distance 1 that
/// spans `tan(fov/2)` either side horizontally, square pixels, pixel `(0, 0)`
/// at the top left.
#[derive(Clone, Debug)]
pub struct RefCamera {
    pub eye: DVec3,
    pub u: DVec3,
    pub v: DVec3,
    pub w: DVec3,
    pub half_width: f64,
    pub half_height: f64,
    pub width: u32,
    pub height: u32,
    params: ([f32; 3], [f32; 3], [f32; 3], f32),
}

impl RefCamera {
    pub fn new(eye: [f32; 3], look_at: [f32; 3], up: [f32; 3], fov: f32, width: u32, height: u32) -> Self {
        let e = d3(eye);
        let w = (d3(look_at) - e).normalize();
        let u = w.cross(d3(up)).normalize();
        let v = u.cross(w);
        let half_width = ((fov as f64).to_radians() * 0.5).tan();
        let half_height = half_width * height as f64 / width as f64;
        Self { eye: e, u, v, w, half_width, half_height, width, height, params: (eye, look_at, up, fov) }
    }

    /// The same camera, as lucent builds it.
    pub fn camera(&self) -> Camera {
        let (eye, look_at, up, fov) = self.params;
        Camera::new(Vec3::from(eye), Vec3::from(look_at), Vec3::from(up), fov, self.width, self.height).unwrap()
    }

    /// Unit direction through film position `(fx, fy)` (pixels).
    pub fn dir_at(&self, fx: f64, fy: f64) -> DVec3 {
        let x = (2.0 * fx / self.width as f64 - 1.0) * self.half_width;
        let y = (1.0 - 2.0 * fy / self.height as f64) * self.half_height;
        (self.w + x * self.u + y * self.v).normalize()
    }

    /// The ray through the centre of pixel `(x, y)`: what a render with one
    /// sample per pixel traces.
    pub fn pixel_ray(&self, x: u32, y: u32) -> (DVec3, DVec3) {
        (self.eye, self.dir_at(x as f64 + 0.5, y as f64 + 0.5))
    }

    /// Film position (pixels) at which the pinhole sees world point `p`.
    pub fn project(&self, p: DVec3) -> (f64, f64) {
        let q = p - self.eye;
        let (x, y, z) = (q.dot(self.u), q.dot(self.v), q.dot(self.w));
        let fx = (x / z / self.half_width + 1.0) * 0.5 * self.width as f64;
        let fy = (1.0 - y / z / self.half_height) * 0.5 * self.height as f64;
        (fx, fy)
    }

    /// Every pixel, row by row.
    pub fn pixels(&self) -> impl Iterator<Item = (u32, u32)> {
        let (w, h) = (self.width, self.height);
        (0..h).flat_map(move |y| (0..w).map(move |x| (x, y)))
    }
}

pub fn d3(v: [f32; 3]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

pub fn v3(v: [f32; 3]) -> Vec3 {
    Vec3::from(v)
}

/// Outcome of a reference intersection: clearly a hit, clearly a miss, or
/// too close to a tangency for single precision to be expected to agree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hit {
    /// Nearest hit at `t > 0`.
    At(f64),
    Miss,
    Uncertain,
}

/// Ray `o + t d` against the sphere `|x - c| = r`: nearest `t > t_min`.
/// Rays passing within `margin · r` of the silhouette are `Uncertain`.
pub fn ray_sphere(o: DVec3, d: DVec3, c: DVec3, r: f64, margin: f64) -> Hit {
    let a = d.length_squared();
    let oc = o - c;
    let tc = -oc.dot(d) / a; // closest approach
    let perp = (oc + tc * d).length();
    if (perp - r).abs() <= margin * r {
        return Hit::Uncertain;
    }
    if perp > r {
        return Hit::Miss;
    }
    let half = ((r - perp) * (r + perp) / a).sqrt();
    let (t0, t1) = (tc - half, tc + half);
    if t0 > 0.0 {
        Hit::At(t0)
    } else if t1 > 0.0 {
        Hit::At(t1)
    } else {
        Hit::Miss
    }
}

/// Ray against the plane through `p0` with normal `n`, `t > 0`.
pub fn ray_plane(o: DVec3, d: DVec3, p0: DVec3, n: DVec3) -> Option<f64> {
    let denom = d.dot(n);
    if denom == 0.0 {
        return None;
    }
    let t = (p0 - o).dot(n) / denom;
    (t > 0.0).then_some(t)
}

/// Does the segment from `a` to `b` pass through the sphere? `Some(true)`
/// when it clearly does, `Some(false)` when it clearly does not, `None` when
/// it grazes it (within `margin · r`).
pub fn segment_hits_sphere(a: DVec3, b: DVec3, c: DVec3, r: f64, margin: f64) -> Option<bool> {
    let d = b - a;
    let s = ((c - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    let dist = (a + s * d - c).length();
    if (dist - r).abs() <= margin * r {
        None
    } else {
        Some(dist < r)
    }
}

/// Mirror `d` (pointing at the surface) about unit normal `n`.
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

/// Hermite smoothstep, as documented for spot lights.
pub fn smooth_step(x: f64, a: f64, b: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The film's resolution: a pixel holds the weighted mean of its samples
/// as fixed-point sums in units of 1/`FIXED_POINT_SCALE` (2⁻²⁰), each sample
/// rounded to the nearest unit, so a rendered pixel is within half a unit of
/// the radiance it was given (plus one rounding to f32). This is the only
/// slack the "exact" checks of rendered pixels allow.
pub fn film_tolerance(want: Vec3) -> f32 {
    0.5 / lucent::film::FIXED_POINT_SCALE as f32 + want.abs().max_element() * f32::EPSILON
}

/// `got` (a rendered pixel) equals `want` up to the film's resolution
/// ([`film_tolerance`]).
#[track_caller]
pub fn assert_pixel(got: Vec3, want: Vec3, what: &str) {
    let d = (got - want).abs().max_element();
    assert!(d <= film_tolerance(want), "{what}: rendered {got}, expected {want} (difference {d:e})");
}

/// Largest channel difference.
pub fn diff(got: Vec3, want: DVec3) -> f64 {
    (got.as_dvec3() - want).abs().max_element()
}

/// Deterministic random source for the randomised tests (the library's own
/// PCG32, fixed seeds).
pub struct Rng(Pcg32);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(Pcg32::new(seed, 0x5eed))
    }

    /// Uniform in `[0, 1)`, double precision (two draws).
    pub fn f64(&mut self) -> f64 {
        let hi = (self.0.next_u32() >> 5) as f64; // 27 bits
        let lo = (self.0.next_u32() >> 6) as f64; // 26 bits
        (hi * 67_108_864.0 + lo) / 9_007_199_254_740_992.0
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }

    /// Log-uniform in `[lo, hi]`, both > 0.
    pub fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.f64()).exp()
    }

    /// Uniform on the unit sphere.
    pub fn unit(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }

    /// Uniform in the unit ball.
    pub fn in_ball(&mut self) -> DVec3 {
        self.unit() * self.f64().cbrt()
    }

    /// A unit direction in the hemisphere around unit `n`, with
    /// `n · dir ≥ min_cos`. Half the draws are close to grazing (cosine
    /// log-uniform down to `min_cos`), half uniform.
    pub fn hemisphere(&mut self, n: DVec3, min_cos: f64) -> DVec3 {
        let cos = if self.f64() < 0.5 { self.log_range(min_cos, 1.0) } else { self.range(min_cos, 1.0) };
        let (s, t) = n.any_orthonormal_pair();
        let phi = self.range(0.0, std::f64::consts::TAU);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        (cos * n + sin * (phi.cos() * s + phi.sin() * t)).normalize()
    }
}

/// A scene under construction with its render settings, for tests that set
/// things up field by field: a [`SceneBuilder`] (every object goes through
/// it, validated as usual) with the ambient light, background and
/// [`RenderSettings`] kept as plain fields until [`TestScene::build`].
#[derive(Clone)]
pub struct TestScene {
    pub builder: SceneBuilder,
    pub settings: RenderSettings,
    pub ambient: Color,
    pub background: Color,
    pub environment: Option<lucent::light::Environment>,
}

impl TestScene {
    pub fn new(camera: Camera) -> Self {
        Self {
            builder: SceneBuilder::new(camera),
            settings: RenderSettings::default(),
            ambient: Color::ZERO,
            background: Color::ZERO,
            environment: None,
        }
    }

    pub fn add_material(&mut self, material: Material) -> MaterialId {
        self.builder.add_material(material).unwrap()
    }

    pub fn add(&mut self, primitive: Primitive) {
        self.builder.add(primitive, None).unwrap();
    }

    pub fn add_light(&mut self, light: Light) {
        self.builder.add_light(light);
    }

    pub fn add_emissive(&mut self, primitive: Primitive, radiance: Color, two_sided: bool) -> Result<(), SceneError> {
        self.builder.add(primitive, Some(Emission { radiance, two_sided, reverse: false, image: None })).map(|_| ())
    }

    pub fn set_environment(&mut self, environment: Option<lucent::light::Environment>) {
        self.environment = environment;
    }

    /// The scene, built.
    pub fn build(&self) -> Scene {
        let mut b = self.builder.clone();
        b.set_ambient(self.ambient).unwrap();
        b.set_background(self.background).unwrap();
        if let Some(env) = &self.environment {
            b.set_environment(env.clone()).unwrap();
        }
        b.build().unwrap()
    }
}

/// A scene around `camera` with one sample per pixel, so that pixel `(x, y)`
/// is exactly the radiance along the ray through its centre.
pub fn scene_one_spp(camera: Camera) -> TestScene {
    let mut scene = TestScene::new(camera);
    scene.settings.spp = 1;
    scene
}

/// Build and render with default options.
pub fn render_film(scene: &TestScene) -> Film {
    render(&scene.build(), &scene.settings, RenderOptions::default()).unwrap().film
}

/// Render a loaded scene file with its own settings and default options.
pub fn render_loaded(loaded: &LoadedScene) -> Film {
    render(&loaded.scene, &loaded.settings, RenderOptions::default()).unwrap().film
}

/// A camera for tests that never render (only `scene.intersect` is used).
pub fn dummy_camera() -> Camera {
    Camera::new(Vec3::new(0.0, 0.0, -1.0), Vec3::ZERO, Vec3::Y, 60.0, 1, 1).unwrap()
}

/// Rotation by `deg` degrees about the unit `axis`, right-handed (Rodrigues).
pub fn rotation(axis: DVec3, deg: f64) -> DMat3 {
    let k = axis.normalize();
    let (s, c) = deg.to_radians().sin_cos();
    let col = |e: DVec3| e * c + k.cross(e) * s + k * k.dot(e) * (1.0 - c);
    DMat3::from_cols(col(DVec3::X), col(DVec3::Y), col(DVec3::Z))
}

/// An ellipsoid in world space.
pub struct Ellipsoid {
    pub centre: DVec3,
    /// `R diag(1/aᵢ²) Rᵀ`.
    pub m: DMat3,
}

impl Ellipsoid {
    /// The image of the sphere `|x - c| = ρ` under scale `s`, then rotation
    /// `rot`, then translation `tr`: centre `rot·(s∘c) + tr`, semi-axes `ρ·sᵢ`
    /// along the rotated coordinate axes.
    pub fn from_sphere(c: DVec3, rho: f64, s: DVec3, rot: DMat3, tr: DVec3) -> Self {
        let inv_sq = (rho * s).powf(-2.0);
        Self { centre: rot * (s * c) + tr, m: rot * DMat3::from_diagonal(inv_sq) * rot.transpose() }
    }

    /// Nearest `t > 0` where `o + t d` meets the surface, if any.
    pub fn hit(&self, o: DVec3, d: DVec3) -> Option<f64> {
        let oc = o - self.centre;
        let a = d.dot(self.m * d);
        let b = 2.0 * oc.dot(self.m * d);
        let c = oc.dot(self.m * oc) - 1.0;
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        let (t0, t1) = (q / a, c / q);
        let (t0, t1) = (t0.min(t1), t0.max(t1));
        if t0 > 0.0 {
            Some(t0)
        } else if t1 > 0.0 {
            Some(t1)
        } else {
            None
        }
    }

    /// `(x - C)ᵀ M (x - C) - 1`: zero on the surface.
    pub fn level(&self, x: DVec3) -> f64 {
        let q = x - self.centre;
        q.dot(self.m * q) - 1.0
    }

    /// Outward unit normal at a surface point: the gradient of the level
    /// function.
    pub fn normal(&self, x: DVec3) -> DVec3 {
        (self.m * (x - self.centre)).normalize()
    }

    /// A point inside, at "radius" `f ∈ [0, 1)` of the way to the surface.
    pub fn inside(&self, rng: &mut Rng, f: f64) -> DVec3 {
        // x = C + L u with L Lᵀ = M⁻¹ maps the unit ball onto the ellipsoid.
        let u = rng.in_ball() * f;
        let minv = self.m.inverse();
        // M⁻¹ is symmetric positive definite: a Cholesky factor will do.
        let l11 = minv.x_axis.x.sqrt();
        let l21 = minv.x_axis.y / l11;
        let l31 = minv.x_axis.z / l11;
        let l22 = (minv.y_axis.y - l21 * l21).sqrt();
        let l32 = (minv.y_axis.z - l31 * l21) / l22;
        let l33 = (minv.z_axis.z - l31 * l31 - l32 * l32).sqrt();
        self.centre + DVec3::new(l11 * u.x, l21 * u.x + l22 * u.y, l31 * u.x + l32 * u.y + l33 * u.z)
    }
}

/// A scene from TOML text, panicking with the loader's message.
pub fn scene(body: &str) -> LoadedScene {
    parse_scene(body, SceneFormat::Toml).unwrap_or_else(|e| panic!("{e}"))
}

/// Mean of every channel of every pixel, and the largest deviation of a
/// pixel's channel from `expected`.
pub fn film_stats(film: &Film, expected: f32) -> (f64, f32) {
    let mut sum = 0.0f64;
    let mut worst = 0.0f32;
    for c in film.pixels() {
        for v in c.to_array() {
            sum += v as f64;
            worst = worst.max((v - expected).abs());
        }
    }
    (sum / (film.pixels().len() * 3) as f64, worst)
}
