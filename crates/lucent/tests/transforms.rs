//! Object transforms: ellipsoids from scaled spheres, and the order in which
//! transform lists and nested groups compose.
//!
//! The expectations are built here in double precision from first
//! principles: an ellipsoid `(x - C)ᵀ M (x - C) = 1` with
//! `M = R diag(1/a², 1/b², 1/c²) Rᵀ`, its normal `M (x - C)`, rotation
//! matrices written out from their definitions, and matrix products in the
//! documented order (a list applies its first entry first; a group's
//! transform applies after its members' own).

mod common;

use common::*;
use glam::{DMat3, DMat4, DVec3, Mat4};
use lucent::geometry::Vec3;
use lucent::prelude::*;
use lucent::texture::Texture;

/// A scene holding only `shape` under `transform`.
fn single(shape: impl Into<lucent::shapes::Shape>, transform: Transform) -> Scene {
    let mut scene = TestScene::new(dummy_camera());
    let m = scene.add_material(Material::matte(Color::ONE, 1.0).unwrap());
    scene.add(Primitive::new(shape, transform, m));
    scene.build()
}

#[derive(Debug, Default)]
struct Worst {
    /// Relative error of `t`, over rays meeting the surface at a cosine of
    /// at least 0.3.
    t: f64,
    /// Distance of the hit point from the true surface, over its error bound.
    surface: f64,
    /// Position error along the ray, over the single-precision error model.
    along: f64,
    /// Normal error, over the single-precision error model.
    normal: f64,
}

/// Shoot random rays at the ellipsoid from all around and compare every hit
/// with the analytic one.
///
/// Single precision limits what can be asked, and the limits are those of an
/// object-space intersection: the ray origin is rounded in the sphere's own
/// space, where it lies `|o'| = √((o-C)ᵀM(o-C))` sphere radii away, which
/// moves the hit by about `ε·|o'|·a_max` in the world (a flat ellipsoid
/// seen edge-on from afar magnifies that); along the ray that grows as
/// `1/cos` of the incidence angle. The normal then turns by the curvature
/// (at most `a_max/a_min²`) times the position error. The checks:
///
/// * the hit point lies within its own error bound `p_error` of the true
///   surface (robust ray spawning relies on it);
/// * its position along the ray is within the error model above;
/// * the normal equals the analytic normal `M(x - C)` at the hit point to
///   within curvature × position error.
fn check_random_hits(scene: &Scene, e: &Ellipsoid, extent: f64, seed: u64) -> Worst {
    let eps = f32::EPSILON as f64;
    // Bounds on the largest and smallest semi-axis from the traces of M⁻¹
    // and M (the sums of 1/λ and λ over the axes).
    let m_inv = e.m.inverse();
    let a_max = (m_inv.x_axis.x + m_inv.y_axis.y + m_inv.z_axis.z).sqrt();
    let a_min = 1.0 / (e.m.x_axis.x + e.m.y_axis.y + e.m.z_axis.z).sqrt();
    let curvature = a_max / (a_min * a_min);
    let mut rng = Rng::new(seed);
    let mut worst = Worst::default();
    for i in 0..2000 {
        let target = e.inside(&mut rng, 0.999);
        let origin = e.centre + rng.unit() * extent * rng.range(1.5, 20.0);
        // Direction lengths vary: t is in units of the given direction.
        let d = (target - origin) * rng.log_range(0.01, 100.0);
        let ray = Ray::new(origin.as_vec3a(), d.as_vec3a());
        // The reference takes the ray exactly as lucent sees it.
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let want_t = e.hit(o, d).expect("the ray aims inside the ellipsoid");
        let si = scene.intersect(&ray, f32::INFINITY).unwrap_or_else(|| panic!("ray {i} ({ray:?}) missed"));
        let want_p = o + want_t * d;
        let want_n = e.normal(want_p);
        let cos = want_n.dot(d.normalize()).abs();
        let (p, n) = (si.p.as_dvec3(), si.n.as_dvec3());
        let p_error = si.p_error.as_dvec3();
        let ctx =
            || format!("ray {i} {ray:?}: t {} (analytic {want_t}), p {p} (analytic {want_p}), cos {cos:.3}", si.t);

        // Distance from the surface, to first order: level / |∇level|.
        let surface = e.level(p).abs() / (2.0 * (e.m * (p - e.centre)).length());
        let surface = surface / n.abs().dot(p_error);
        assert!(surface <= 1.0, "{}: off the surface by more than its error bound", ctx());

        let object_distance = (o - e.centre).dot(e.m * (o - e.centre)).sqrt();
        let position_scale = p_error.length() + eps * object_distance * a_max;
        let along = (p - want_p).length() * cos / position_scale;
        assert!(along <= 4.0, "{}: hit point too far along the ray", ctx());

        let normal = (n - e.normal(p)).length() / (curvature * p_error.length() + eps * a_max / a_min);
        assert!(normal <= 1.0, "{}: normal {n} vs analytic {}", ctx(), e.normal(p));
        assert!((si.ns - si.n).length() < 1e-6, "shading normal of an ellipsoid is its geometric normal");
        assert!(n.dot(want_n) > 0.99, "{}: the normal points outwards", ctx());

        let t_err = ((si.t as f64) - want_t).abs() / want_t;
        if cos >= 0.3 {
            assert!(t_err < 2e-5, "{}: t off by {t_err:e}", ctx());
            worst.t = worst.t.max(t_err);
        }
        worst.surface = worst.surface.max(surface);
        worst.along = worst.along.max(along);
        worst.normal = worst.normal.max(normal);
    }
    worst
}

#[test]
fn scaled_sphere_normals_and_distances_are_those_of_the_ellipsoid() {
    for (k, s) in [[1.0f32, 2.0, 1.0], [0.5, 1.0, 3.0], [3.0, 0.2, 0.7], [0.05, 1.0, 1.0], [10.0, 10.0, 0.1]]
        .into_iter()
        .enumerate()
    {
        let scene = single(Sphere::new(Vec3::ZERO, 1.0).unwrap(), Transform::scale(v3(s)).unwrap());
        let e = Ellipsoid::from_sphere(DVec3::ZERO, 1.0, d3(s), DMat3::IDENTITY, DVec3::ZERO);
        let worst = check_random_hits(&scene, &e, d3(s).max_element(), k as u64);
        eprintln!("scale {s:?}: {worst:?}");
    }
}

#[test]
fn transformed_sphere_hits_match_the_analytic_ellipsoid() {
    let mut rng = Rng::new(77);
    for k in 0..20 {
        let c = DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)).as_vec3a().as_dvec3();
        let rho = rng.log_range(0.1, 5.0) as f32 as f64;
        let s = DVec3::new(rng.log_range(0.2, 5.0), rng.log_range(0.2, 5.0), rng.log_range(0.2, 5.0)).as_vec3a();
        let axis = rng.unit().as_vec3a();
        let angle = rng.range(-180.0, 180.0) as f32;
        let tr = (rng.unit() * rng.range(0.0, 50.0)).as_vec3a();
        let transform =
            Transform::scale(s).unwrap().then(&Transform::rotate(axis, angle).unwrap()).then(&Transform::translate(tr));
        let scene = single(Sphere::new(c.as_vec3a(), rho as f32).unwrap(), transform);
        let e = Ellipsoid::from_sphere(c, rho, s.as_dvec3(), rotation(axis.as_dvec3(), angle as f64), tr.as_dvec3());
        let worst = check_random_hits(&scene, &e, rho * s.max_element() as f64, 100 + k);
        if k < 3 {
            eprintln!("random ellipsoid {k}: {worst:?}");
        }
    }
}

/// The `i`-th entry of a written transform list, as a matrix.
enum Op {
    Translate(DVec3),
    Scale(DVec3),
    RotateX(f64),
    RotateY(f64),
    RotateZ(f64),
    Rotate(DVec3, f64),
}

/// The matrix of a list applied in the written order: `… · M₂ · M₁`.
fn compose(ops: &[Op]) -> DMat4 {
    ops.iter().fold(DMat4::IDENTITY, |acc, op| {
        let m = match *op {
            Op::Translate(t) => DMat4::from_translation(t),
            Op::Scale(s) => DMat4::from_mat3(DMat3::from_diagonal(s)),
            Op::RotateX(a) => DMat4::from_mat3(rotation(DVec3::X, a)),
            Op::RotateY(a) => DMat4::from_mat3(rotation(DVec3::Y, a)),
            Op::RotateZ(a) => DMat4::from_mat3(rotation(DVec3::Z, a)),
            Op::Rotate(axis, a) => DMat4::from_mat3(rotation(axis, a)),
        };
        m * acc
    })
}

/// The primitive whose material has colour `c`.
fn by_color(scene: &Scene, c: Color) -> &Primitive {
    let mut found = scene
        .primitives()
        .iter()
        .filter(|p| scene.material(p.material()).classic().is_some_and(|m| m.color == Texture::Constant(c)));
    let p = found.next().unwrap_or_else(|| panic!("no primitive with colour {c}"));
    assert!(found.next().is_none(), "several primitives with colour {c}");
    p
}

fn assert_matrix(got: Mat4, want: DMat4, what: &str) {
    let err = (got.as_dmat4() - want).to_cols_array().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = want.to_cols_array().iter().fold(1.0f64, |m, v| m.max(v.abs()));
    assert!(err < 2e-6 * scale, "{what}: matrix\n{got}\nexpected\n{want}\n(error {err:e})");
}

const GROUPS: &str = r#"
[camera]
eye = [0, 0, -30]
look_at = [0, 0, 0]

[materials.top.matte]
color = [1, 0, 0]
[materials.outer.matte]
color = [0, 1, 0]
[materials.inner.matte]
color = [0, 0, 1]
[materials.innermost.matte]
color = [1, 1, 0]

[[sphere]]
material = "top"
center = [1, 2, 3]
radius = 0.5
transform = [{ scale = [1, 2, 3] }, { rotate_y = 20 }]

[[group]]
name = "outer"
transform = [{ rotate_z = 30 }, { translate = [1, 2, 3] }]

  [[group.sphere]]
  material = "outer"
  center = [0.5, 0, 0]
  radius = 0.5
  transform = [{ scale = [2, 1, 1] }]

  [[group.group]]
  name = "inner"
  transform = [{ scale = [2, 1, 0.5] }, { rotate_x = 45 }, { translate = [0, -1, 0] }]

    [[group.group.sphere]]
    material = "inner"
    radius = 0.75
    transform = [{ translate = [0.5, 0, 0] }, { rotate_y = -60 }]

    [[group.group.group]]
    name = "innermost"
    transform = [{ rotate = { axis = [1, 1, 0], angle = 60 } }, { scale = [1, 3, 1] }]

      [[group.group.group.triangle]]
      material = "innermost"
      vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
      transform = [{ translate = [0, 0, 2] }]
"#;

#[test]
fn nested_group_transforms_compose_outside_in() {
    let scene = parse_scene(GROUPS, SceneFormat::Toml).unwrap().scene;
    assert_eq!(scene.primitives().len(), 4);

    let top = compose(&[Op::Scale(DVec3::new(1.0, 2.0, 3.0)), Op::RotateY(20.0)]);
    let outer = compose(&[Op::RotateZ(30.0), Op::Translate(DVec3::new(1.0, 2.0, 3.0))]);
    let inner =
        compose(&[Op::Scale(DVec3::new(2.0, 1.0, 0.5)), Op::RotateX(45.0), Op::Translate(DVec3::new(0.0, -1.0, 0.0))]);
    let innermost = compose(&[Op::Rotate(DVec3::new(1.0, 1.0, 0.0), 60.0), Op::Scale(DVec3::new(1.0, 3.0, 1.0))]);
    // A member's own transform applies first, then its group's, then each
    // enclosing group's in turn.
    let cases = [
        (Color::new(1.0, 0.0, 0.0), top, "top-level sphere"),
        (Color::new(0.0, 1.0, 0.0), outer * compose(&[Op::Scale(DVec3::new(2.0, 1.0, 1.0))]), "outer > sphere"),
        (
            Color::new(0.0, 0.0, 1.0),
            outer * inner * compose(&[Op::Translate(DVec3::new(0.5, 0.0, 0.0)), Op::RotateY(-60.0)]),
            "outer > inner > sphere",
        ),
        (
            Color::new(1.0, 1.0, 0.0),
            outer * inner * innermost * compose(&[Op::Translate(DVec3::new(0.0, 0.0, 2.0))]),
            "outer > inner > innermost > triangle",
        ),
    ];
    let mut rng = Rng::new(5);
    for (color, want, what) in cases {
        let prim = by_color(&scene, color);
        let t = prim.transform();
        assert_matrix(t.matrix(), want, what);
        assert_matrix(t.inverse_matrix(), want.inverse(), what);
        for _ in 0..20 {
            let p = rng.unit() * rng.range(0.0, 3.0);
            let q = t.point(p.as_vec3a()).as_dvec3();
            let expect = want.transform_point3(p.as_vec3a().as_dvec3());
            assert!((q - expect).length() < 1e-5 * (1.0 + expect.length()), "{what}: {p} ↦ {q}, expected {expect}");
        }
    }

    // And the geometry lands where the composed transform says: rays aimed
    // at the deepest sphere hit the analytic ellipsoid, through the scene.
    let full = outer * inner * compose(&[Op::Translate(DVec3::new(0.5, 0.0, 0.0)), Op::RotateY(-60.0)]);
    let linear = DMat3::from_mat4(full);
    let centre = full.transform_point3(DVec3::ZERO);
    let m_inv = linear.inverse();
    let e = Ellipsoid { centre, m: m_inv.transpose() * m_inv / (0.75 * 0.75) };
    let prim = by_color(&scene, Color::new(0.0, 0.0, 1.0));
    let only = single(prim.shape().clone(), prim.transform());
    check_random_hits(&only, &e, 3.0, 9);
}

#[test]
fn rotate_then_scale_then_translate_maps_points_in_that_order() {
    for angle in [90.0f64, 30.0] {
        let src = format!(
            r#"
            [camera]
            eye = [10, 20, -30]
            look_at = [10, 20, 0]
            [materials.m.matte]
            color = [1, 1, 1]
            [[sphere]]
            material = "m"
            center = [1, 0, 0]
            radius = 0.5
            transform = [{{ rotate_z = {angle} }}, {{ scale = [1, 2, 1] }}, {{ translate = [10, 20, 0] }}]
            "#
        );
        let scene = parse_scene(&src, SceneFormat::Toml).unwrap().scene;
        let t = scene.primitives()[0].transform();
        let (s, c) = angle.to_radians().sin_cos();
        // (x, y, z) → rotate → (x c - y s, x s + y c, z) → scale y by 2 → translate.
        let map = |p: DVec3| {
            let r = DVec3::new(p.x * c - p.y * s, p.x * s + p.y * c, p.z);
            DVec3::new(r.x + 10.0, 2.0 * r.y + 20.0, r.z)
        };
        for p in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, -2.0, 0.5), DVec3::ZERO] {
            let got = t.point(p.as_vec3a()).as_dvec3();
            assert!((got - map(p)).length() < 1e-5, "rotate_z {angle}: {p} ↦ {got}, expected {}", map(p));
        }
        if angle == 90.0 {
            assert!((t.point(Vec3::X) - Vec3::new(10.0, 22.0, 0.0)).length() < 1e-5);
        }

        // The sphere's centre (1, 0, 0) lands at (10 + c, 20 + 2 s, 0); its
        // radius 0.5 becomes semi-axes (0.5, 1, 0.5): a rotation does not
        // change a sphere, so the scale acts on the world axes.
        let centre = map(DVec3::X);
        let down = Ray::new((centre + DVec3::Y * 10.0).as_vec3a(), -Vec3::Y);
        let si = scene.intersect(&down, f32::INFINITY).unwrap();
        assert!((si.t - 9.0).abs() < 1e-5, "rotate_z {angle}: top of the ellipsoid at t {}", si.t);
        assert!((si.n - Vec3::Y).length() < 1e-5);
        let across = Ray::new((centre - DVec3::X * 10.0).as_vec3a(), Vec3::X);
        let si = scene.intersect(&across, f32::INFINITY).unwrap();
        assert!((si.t - 9.5).abs() < 1e-5, "rotate_z {angle}: side of the ellipsoid at t {}", si.t);
        assert!((si.n + Vec3::X).length() < 1e-5);
        // Written in the other order, the same steps put it elsewhere.
        let reversed = compose(&[
            Op::Translate(DVec3::new(10.0, 20.0, 0.0)),
            Op::Scale(DVec3::new(1.0, 2.0, 1.0)),
            Op::RotateZ(angle),
        ]);
        assert!((reversed.transform_point3(DVec3::X) - centre).length() > 1.0);
    }
}
