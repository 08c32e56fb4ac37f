//! Robust ray spawning: no self-intersection ("shadow acne") and no light
//! leaking through surfaces.
//!
//! Random rays hit one primitive at a time (spheres near and far, huge and
//! tiny, ellipsoids under arbitrary transforms, tilted planes far from the
//! origin, triangles). From each hit:
//!
//! * a ray spawned on the side of the surface the ray came from must not hit
//!   the primitive again: it is convex (or flat), so nothing lies that way;
//! * a shadow ray to a point above the surface must report it unoccluded;
//! * a ray spawned to the other side must, for a closed shape, meet the far
//!   side at the chord length, and for a flat one, meet nothing.

mod common;

use common::*;
use glam::DVec3;
use lucent::interaction::SurfaceInteraction;
use lucent::prelude::*;

enum Kind {
    Ellipsoid(Ellipsoid),
    Plane { point: DVec3, normal: DVec3 },
    Triangle([DVec3; 3]),
}

struct Case {
    name: String,
    scene: Scene,
    kind: Kind,
    /// Size of the shape (for spheres the largest semi-axis), or of the
    /// region of a plane that rays are aimed at.
    size: f64,
}

fn scene_of(shape: impl Into<lucent::shapes::Shape>, transform: Transform) -> Scene {
    let mut scene = TestScene::new(dummy_camera());
    let m = scene.add_material(Material::matte(Color::ONE, 1.0).unwrap());
    scene.add(Primitive::new(shape, transform, m));
    scene.build()
}

fn sphere(centre: [f32; 3], radius: f32) -> Case {
    Case {
        name: format!("sphere at {centre:?}, radius {radius}"),
        scene: scene_of(Sphere::new(v3(centre), radius).unwrap(), Transform::IDENTITY),
        kind: Kind::Ellipsoid(Ellipsoid::from_sphere(
            d3(centre),
            radius as f64,
            DVec3::ONE,
            glam::DMat3::IDENTITY,
            DVec3::ZERO,
        )),
        size: radius as f64,
    }
}

fn ellipsoid(centre: [f32; 3], radius: f32, scale: [f32; 3], axis: [f32; 3], angle: f32, tr: [f32; 3]) -> Case {
    let t = Transform::scale(v3(scale))
        .unwrap()
        .then(&Transform::rotate(v3(axis), angle).unwrap())
        .then(&Transform::translate(v3(tr)));
    let e = Ellipsoid::from_sphere(d3(centre), radius as f64, d3(scale), rotation(d3(axis), angle as f64), d3(tr));
    Case {
        name: format!("ellipsoid: sphere {centre:?} r {radius}, scale {scale:?}, rotate {angle}° about {axis:?}, translate {tr:?}"),
        scene: scene_of(Sphere::new(v3(centre), radius).unwrap(), t),
        kind: Kind::Ellipsoid(e),
        size: radius as f64 * d3(scale).max_element(),
    }
}

fn plane(point: [f32; 3], normal: [f32; 3], size: f64) -> Case {
    let p = Plane::new(v3(point), v3(normal)).unwrap();
    Case {
        name: format!("plane through {point:?}, normal {normal:?}"),
        kind: Kind::Plane { point: d3(point), normal: p.normal().as_dvec3() },
        scene: scene_of(p, Transform::IDENTITY),
        size,
    }
}

fn triangle(v: [[f32; 3]; 3]) -> Case {
    let size = (d3(v[1]) - d3(v[0])).length().max((d3(v[2]) - d3(v[0])).length());
    Case {
        name: format!("triangle {v:?}"),
        scene: scene_of(Triangle::new(v.map(v3), None).unwrap(), Transform::IDENTITY),
        kind: Kind::Triangle(v.map(d3)),
        size,
    }
}

impl Case {
    /// A random ray that hits the shape's front or back.
    fn ray(&self, rng: &mut Rng) -> Ray {
        let (origin, target) = match &self.kind {
            Kind::Ellipsoid(e) => {
                let target = e.inside(rng, 0.99);
                (e.centre + rng.unit() * self.size * rng.range(1.5, 20.0), target)
            }
            Kind::Plane { point, normal } => {
                let (s, t) = normal.any_orthonormal_pair();
                let u = rng.in_ball() * self.size;
                let target = *point + u.x * s + u.y * t;
                let side = if rng.f64() < 0.5 { *normal } else { -*normal };
                (target + rng.hemisphere(side, 0.02) * self.size * rng.log_range(0.01, 10.0), target)
            }
            Kind::Triangle(v) => {
                let (b1, b2) = (rng.range(0.01, 0.98), rng.range(0.01, 0.98));
                let (b1, b2) = if b1 + b2 < 0.99 { (b1, b2) } else { (0.99 - b1, 0.99 - b2) };
                let target = v[0] + b1 * (v[1] - v[0]) + b2 * (v[2] - v[0]);
                let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
                let side = if rng.f64() < 0.5 { n } else { -n };
                (target + rng.hemisphere(side, 0.02) * self.size * rng.log_range(0.01, 10.0), target)
            }
        };
        // Aim from the origin as rounded to single precision, so the ray
        // really passes through the target.
        let origin = origin.as_vec3a();
        let d = (target - origin.as_dvec3()) * rng.log_range(0.1, 10.0);
        Ray::new(origin, d.as_vec3a())
    }
}

#[derive(Debug, Default)]
struct Tally {
    rays: usize,
    /// Inward rays checked against the chord length, and the worst error
    /// seen relative to the tolerance.
    chords: usize,
    worst_chord: f64,
}

fn check(case: &Case, seed: u64, rays: usize) -> Tally {
    let mut rng = Rng::new(seed);
    let mut tally = Tally::default();
    let scene = &case.scene;
    for i in 0..rays {
        let ray = case.ray(&mut rng);
        let si: SurfaceInteraction =
            scene.intersect(&ray, f32::INFINITY).unwrap_or_else(|| panic!("{}: ray {i} {ray:?} missed", case.name));
        let n = si.n.as_dvec3();
        // The side the ray came from.
        let front = if n.dot(ray.dir.as_dvec3()) < 0.0 { n } else { -n };
        let ctx =
            |what: &str, r: &Ray| format!("{}: ray {i} {ray:?} hit at {} (n {}); {what} {r:?}", case.name, si.p, si.n);

        // Leaving on the near side, down to grazing angles.
        for _ in 0..4 {
            let dir = rng.hemisphere(front, 1e-4).as_vec3a();
            let out = si.spawn_ray(dir);
            assert!(scene.intersect(&out, f32::INFINITY).is_none(), "{}", ctx("self-intersection of", &out));
            assert!(!scene.intersect_p(&out, f32::INFINITY), "{}", ctx("self-occlusion of", &out));
        }

        // Shadow rays to points above the surface: from just above it to far.
        // The target must be above the tangent plane by more than the hit
        // point's error bound and its own rounding, or "above" means nothing.
        let p = si.p.as_dvec3();
        let fuzz = n.abs().dot(si.p_error.as_dvec3());
        for _ in 0..2 {
            let target = loop {
                let t = (p + rng.hemisphere(front, 0.01) * case.size * rng.log_range(1e-2, 1e3)).as_vec3a();
                let ulp = f32::EPSILON as f64 * t.abs().max_element() as f64;
                if (t.as_dvec3() - p).dot(front) > 4.0 * (fuzz + ulp) {
                    break t;
                }
            };
            let (shadow, t_max) = si.spawn_ray_to(target);
            assert!(!scene.intersect_p(&shadow, t_max), "{}", ctx("light leak / acne: occluded", &shadow));
            assert!(scene.intersect(&shadow, t_max).is_none(), "{}", ctx("occluded (closest hit)", &shadow));
        }

        // Into the surface.
        let dir = rng.hemisphere(-front, 0.05);
        let inward = si.spawn_ray(dir.as_vec3a());
        match &case.kind {
            Kind::Ellipsoid(e) => {
                // The ray arrives from outside the closed surface, so the
                // other side is its inside, and it crosses to the far side.
                let (o, d) = (inward.origin.as_dvec3(), inward.dir.as_dvec3());
                let chord = e.hit(o, d).unwrap_or_else(|| panic!("{}", ctx("no analytic far side for", &inward)));
                let far = scene
                    .intersect(&inward, f32::INFINITY)
                    .unwrap_or_else(|| panic!("{}", ctx("no far-side hit of", &inward)));
                // Relative accuracy, but no better than the rounding of the
                // coordinates (times the ellipsoid's aspect ratio, through
                // its object space).
                let m_inv = e.m.inverse();
                let a_max = (m_inv.x_axis.x + m_inv.y_axis.y + m_inv.z_axis.z).sqrt();
                let a_min = 1.0 / (e.m.x_axis.x + e.m.y_axis.y + e.m.z_axis.z).sqrt();
                let floor = 8.0 * f32::EPSILON as f64 * o.abs().max_element() * a_max / a_min / d.length();
                let err = ((far.t as f64) - chord).abs() / (1e-4 * chord + floor);
                assert!(err <= 1.0, "{}: t {} vs chord {chord}", ctx("inward", &inward), far.t);
                assert!(
                    (far.p - si.p).as_dvec3().length() > 0.5 * chord * d.length(),
                    "{}",
                    ctx("re-hit the start of", &inward)
                );
                tally.chords += 1;
                tally.worst_chord = tally.worst_chord.max(err);
            }
            Kind::Plane { .. } | Kind::Triangle(_) => {
                assert!(
                    scene.intersect(&inward, f32::INFINITY).is_none(),
                    "{}",
                    ctx("flat shape hit twice by", &inward)
                );
            }
        }
        tally.rays += 1;
    }
    tally
}

#[test]
fn spheres_near_far_large_and_tiny() {
    let cases = [
        sphere([0.0, 0.0, 0.0], 1.0),
        sphere([3.0, -1.0, 2.0], 0.5),
        sphere([1e4, -2e4, 3e4], 1.0),
        sphere([5.0, 5.0, 5.0], 1e4),
        sphere([1.0, 2.0, 3.0], 1e-3),
        sphere([1e3, 0.0, 0.0], 1e-2),
        sphere([-2e5, 1e5, 0.0], 100.0),
    ];
    for (k, case) in cases.iter().enumerate() {
        let t = check(case, k as u64, 400);
        eprintln!("{}: {t:?}", case.name);
    }
}

#[test]
fn transformed_ellipsoids() {
    let cases = [
        ellipsoid([0.0; 3], 1.0, [1.0, 2.0, 1.0], [0.0, 0.0, 1.0], 0.0, [10.0, 20.0, 0.0]),
        ellipsoid([0.5, 0.0, -1.0], 2.0, [3.0, 0.2, 0.7], [1.0, 2.0, 3.0], 37.0, [-4.0, 1.0, 9.0]),
        ellipsoid([0.0; 3], 1.0, [10.0, 10.0, 0.1], [1.0, 0.0, 0.0], 60.0, [0.0, 0.0, 0.0]),
        ellipsoid([0.0; 3], 0.01, [1.0, 5.0, 1.0], [0.0, 1.0, 1.0], -20.0, [500.0, -300.0, 100.0]),
        ellipsoid([1.0, 1.0, 1.0], 50.0, [2.0, 1.0, 0.5], [1.0, 1.0, 1.0], 120.0, [1e4, 0.0, 0.0]),
    ];
    for (k, case) in cases.iter().enumerate() {
        let t = check(case, 100 + k as u64, 400);
        eprintln!("{}: {t:?}", case.name);
    }
}

#[test]
fn planes_tilted_and_far_from_the_origin() {
    let cases = [
        plane([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 10.0),
        plane([0.0, -1.0, 0.0], [0.3, 1.0, -0.2], 100.0),
        plane([1e4, -3e3, 2e4], [1.0, 2.0, 3.0], 50.0),
        plane([-1e5, 0.0, 5e4], [0.0, 0.0, -1.0], 1e3),
        plane([0.25, 0.5, 0.75], [1.0, 1e-3, 0.0], 1.0),
    ];
    for (k, case) in cases.iter().enumerate() {
        let t = check(case, 200 + k as u64, 500);
        eprintln!("{}: {t:?}", case.name);
    }
}

#[test]
fn triangles_small_large_and_far() {
    let cases = [
        triangle([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        triangle([[-3.0, 1.0, 2.0], [4.0, 0.5, -1.0], [0.5, 5.0, 3.0]]),
        triangle([[1e4, 2e4, -1e4], [1e4 + 5.0, 2e4, -1e4 + 1.0], [1e4, 2e4 + 3.0, -1e4 - 2.0]]),
        triangle([[0.1, 0.1, 0.1], [0.1001, 0.1, 0.1], [0.1, 0.1002, 0.1001]]),
        triangle([[-500.0, 0.0, -500.0], [500.0, 10.0, -500.0], [0.0, -5.0, 800.0]]),
    ];
    for (k, case) in cases.iter().enumerate() {
        let t = check(case, 300 + k as u64, 500);
        eprintln!("{}: {t:?}", case.name);
    }
}

#[test]
fn hits_do_not_depend_on_the_length_of_the_ray_direction() {
    // t is measured in units of the direction, so scaling the direction by k
    // must scale t by 1/k and change nothing else. (Regression: the
    // triangle's conservative t bound once grew with 1/|d| and rejected real
    // hits for short directions and for small triangles far along an axis.)
    let cases = [
        triangle([[0.1, 0.1, 0.1], [0.1001, 0.1, 0.1], [0.1, 0.1002, 0.1001]]),
        triangle([[-3.0, 1.0, 2.0], [4.0, 0.5, -1.0], [0.5, 5.0, 3.0]]),
        sphere([3.0, -1.0, 2.0], 0.5),
        sphere([1e3, 0.0, 0.0], 1e-2),
        ellipsoid([0.0; 3], 1.0, [3.0, 0.2, 0.7], [1.0, 2.0, 3.0], 37.0, [-4.0, 1.0, 9.0]),
        plane([1e4, -3e3, 2e4], [1.0, 2.0, 3.0], 50.0),
    ];
    for (n, case) in cases.iter().enumerate() {
        let mut rng = Rng::new(400 + n as u64);
        for i in 0..300 {
            let ray = case.ray(&mut rng);
            let base =
                case.scene.intersect(&ray, f32::INFINITY).unwrap_or_else(|| panic!("{}: ray {i} missed", case.name));
            for k in [1e-4f32, 1e-2, 0.5, 3.0, 1e2, 1e4] {
                let scaled = Ray::new(ray.origin, ray.dir * k);
                let si = case.scene.intersect(&scaled, f32::INFINITY).unwrap_or_else(|| {
                    panic!("{}: ray {i} {ray:?} hits, but not with its direction scaled by {k}", case.name)
                });
                // Equal to single precision: relative to the distance, and no
                // finer than the rounding of the coordinates involved.
                let len = ray.dir.length() as f64;
                let moved = ((si.t * k) as f64 - base.t as f64).abs() * len;
                let coords = ray.origin.abs().max_element().max(base.p.abs().max_element()) as f64;
                let tol = 1e-5 * base.t as f64 * len + 8.0 * f32::EPSILON as f64 * coords;
                assert!(moved < tol, "{}: ray {i}, scale {k}: t·k = {} vs t = {}", case.name, si.t * k, base.t);
                assert!(case.scene.intersect_p(&scaled, f32::INFINITY));
            }
        }
    }
    // The far case in the regression, spelled out: a 1 mm triangle 1 km down
    // the z axis, seen along a unit direction.
    let tri =
        Triangle::new([Vec3::new(0.0, 0.0, 1e3), Vec3::new(1e-3, 0.0, 1e3), Vec3::new(0.0, 1e-3, 1e3)], None).unwrap();
    let ray = Ray::new(Vec3::ZERO, Vec3::new(3e-4, 3e-4, 1e3).normalize());
    let (t, ..) = tri.intersect_t(&ray, f32::INFINITY).expect("the triangle straight ahead must be hit");
    assert!((t - 1e3).abs() < 1e-2, "t = {t}");
}
