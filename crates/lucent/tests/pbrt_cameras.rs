//! pbrt-v4's cameras through the public API: where a small sphere placed in
//! camera space appears on the image (pbrt's raster: `+x` to the right,
//! `+y` up, row 0 at the top, `fov` over the shorter axis), for the
//! perspective and orthographic projections, and a camera placed by pbrt's
//! usual `Scale -1 1 1` + `LookAt`.

use lucent::camera::{Projection, ThinLens};
use lucent::film::Filter;
use lucent::prelude::*;

const W: u32 = 200;
const H: u32 = 100;

/// Render (Whitted, ambient light only, 64 samples per pixel) a sphere of
/// radius `r` at `centre` on black, and return the centre of the image's
/// brightness: each pixel's centre weighted by its value, which is the
/// fraction of the pixel the sphere covers.
fn centroid(camera: Camera, centre: Vec3, r: f32) -> (f32, f32) {
    let mut b = SceneBuilder::new(camera);
    let white = b.add_material(Material::matte(Color::ONE, 1.0).unwrap()).unwrap();
    b.add_shape(Sphere::new(centre, r).unwrap(), Transform::IDENTITY, white).unwrap();
    b.set_ambient(Color::ONE).unwrap();
    let s = RenderSettings { spp: 64, filter: Filter::Box { radius: 0.5 }, ..Default::default() };
    let film = render(&b.build().unwrap(), &s, RenderOptions::default()).unwrap().film;
    let (mut sum, mut sx, mut sy) = (0.0f64, 0.0f64, 0.0f64);
    for y in 0..H {
        for x in 0..W {
            let v = film.pixel(x, y).x as f64;
            sum += v;
            sx += v * (x as f64 + 0.5);
            sy += v * (y as f64 + 0.5);
        }
    }
    assert!(sum > 0.0, "nothing visible");
    ((sx / sum) as f32, (sy / sum) as f32)
}

#[test]
fn perspective_raster_follows_pbrt() {
    // fov 90 over the shorter (vertical) axis: screen [-2, 2] × [-1, 1] at
    // z = 1. A point at camera (1, 0.5, 1)·8 is at screen (1, 0.5): raster
    // x = (1 + 2)/4 · 200 = 150, y = (1 − 0.5)/2 · 100 = 25.
    let p = Projection::Perspective { fov_degrees: 90.0, screen_window: None, frame_aspect_ratio: None, lens: None };
    let cam = Camera::pbrt(&Transform::IDENTITY, p, W, H).unwrap();
    let (x, y) = centroid(cam, Vec3::new(8.0, 4.0, 8.0), 0.4);
    assert!((x - 150.0).abs() < 0.2 && (y - 25.0).abs() < 0.2, "({x}, {y})");
    // A thin lens focused on the sphere's plane does not move it.
    let lens = ThinLens { radius: 0.2, focal_distance: 8.0 };
    let p =
        Projection::Perspective { fov_degrees: 90.0, screen_window: None, frame_aspect_ratio: None, lens: Some(lens) };
    let cam = Camera::pbrt(&Transform::IDENTITY, p, W, H).unwrap();
    let (x, y) = centroid(cam, Vec3::new(8.0, 4.0, 8.0), 0.4);
    assert!((x - 150.0).abs() < 0.2 && (y - 25.0).abs() < 0.2, "({x}, {y})");
}

#[test]
fn orthographic_raster_follows_pbrt() {
    // Window [-2, 2] × [-1, 1] in camera units: (1, 0.5) is raster (150, 25)
    // at any depth.
    let p = Projection::Orthographic { screen_window: None, frame_aspect_ratio: None, lens: None };
    for z in [3.0, 30.0] {
        let cam = Camera::pbrt(&Transform::IDENTITY, p, W, H).unwrap();
        let (x, y) = centroid(cam, Vec3::new(1.0, 0.5, z), 0.05);
        assert!((x - 150.0).abs() < 0.2 && (y - 25.0).abs() < 0.2, "depth {z}: ({x}, {y})");
    }
}

#[test]
fn pbrt_look_at_with_a_mirror_matches_lucents_look_at() {
    // pbrt's `Scale -1 1 1  LookAt eye target up` makes world-to-camera
    // M = S · L, L pbrt's left-handed look-at; camera-to-world is
    // M⁻¹ = L⁻¹ · S. Columns of L⁻¹: right = normalize(up × dir) (pbrt's
    // Cross(Normalize(up), dir)), new up = dir × right, dir, eye. With the
    // mirror the image is lucent's right-handed look-at camera's.
    let (eye, target, up) = (Vec3::new(1.0, 3.0, -6.0), Vec3::new(0.5, 0.0, 1.0), Vec3::Y);
    let dir = (target - eye).normalize();
    let right = up.normalize().cross(dir).normalize();
    let new_up = dir.cross(right);
    let look_inverse = glam::Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0));
    let camera_to_world =
        Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap().then(&Transform::from_matrix(look_inverse).unwrap());
    // A square image: lucent's fov is horizontal, pbrt's over the shorter
    // axis: the same here.
    let p = Projection::Perspective { fov_degrees: 50.0, screen_window: None, frame_aspect_ratio: None, lens: None };
    let pbrt = Camera::pbrt(&camera_to_world, p, 64, 64).unwrap();
    let ours = Camera::new(eye, target, up, 50.0, 64, 64).unwrap();
    for (x, y) in [(0.0, 0.0), (64.0, 0.0), (10.5, 50.25), (32.0, 32.0)] {
        let a = pbrt.generate_ray(Vec2::new(x, y), Vec2::splat(0.5));
        let b = ours.generate_ray(Vec2::new(x, y), Vec2::splat(0.5));
        assert!((a.origin - b.origin).length() < 1e-5 && (a.dir - b.dir).length() < 1e-5, "({x}, {y}): {a:?} vs {b:?}");
    }
}
