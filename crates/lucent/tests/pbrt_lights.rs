//! pbrt-v4's lights rendered end to end through the public API: the power
//! of a point light, the illuminance of distant and uniform infinite
//! lights, and an equal-area environment map seen pixel for pixel by
//! pbrt-v4's equal-area spherical camera.
//!
//! Expectations are analytic: a Lambertian surface of albedo `ρ` receiving
//! irradiance `E` has radiance `ρ E / π`.

use glam::{Mat4, Vec4};
use lucent::camera::{Projection, SphericalMapping};
use lucent::color::luminance;
use lucent::film::Filter;
use lucent::light::{DistantLightParams, Environment, EnvironmentMap, MapOptions, PointLightParams};
use lucent::prelude::*;
use std::f32::consts::PI;
use std::sync::Arc;

/// Direct lighting only, a box filter over each pixel.
fn settings(spp: u32) -> RenderSettings {
    let mut s = RenderSettings::for_integrator(IntegratorKind::Path);
    s.spp = spp;
    s.max_depth = 1;
    s.filter = Filter::Box { radius: 0.5 };
    s
}

/// A pbrt perspective camera at `(0, height, 0)` looking straight down with
/// a 1° field of view: the centre pixel sees the origin's neighbourhood.
fn looking_down(height: f32) -> Camera {
    // Camera +z turned 90° about x is −y.
    let t = Transform::rotate_x(90.0).then(&Transform::translate(Vec3::new(0.0, height, 0.0)));
    let p = Projection::Perspective { fov_degrees: 1.0, screen_window: None, frame_aspect_ratio: None, lens: None };
    Camera::pbrt(&t, p, 5, 5).unwrap()
}

/// The floor `y = 0`, Lambertian with albedo `rho`.
fn floor(b: &mut SceneBuilder, rho: f32) {
    let m = b.add_material(Material::Diffuse { reflectance: Texture::Constant(Color::splat(rho)) }).unwrap();
    b.add_shape(Plane::new(Vec3::ZERO, Vec3::Y).unwrap(), Transform::IDENTITY, m).unwrap();
}

#[test]
fn a_point_light_of_power_phi_gives_phi_over_4_pi_d_squared() {
    let (phi, d, rho) = (300.0f32, 2.5f32, 0.6f32);
    let mut b = SceneBuilder::new(looking_down(1.0));
    floor(&mut b, rho);
    let params = PointLightParams { i: Color::new(1.0, 0.7, 0.3), power: Some(phi), ..Default::default() };
    // `from` is carried by the transform: the light is at (0, d, 0).
    let light = Light::pbrt_point(
        &Transform::translate(Vec3::new(0.0, d - 1.0, 0.0)),
        &PointLightParams { from: Vec3::new(0.0, 1.0, 0.0), ..params },
    )
    .unwrap();
    b.add_light(light);
    let out = render(&b.build().unwrap(), &settings(4), RenderOptions::default()).unwrap();
    let got = luminance(out.film.pixel(2, 2));
    let want = rho / PI * phi / (4.0 * PI * d * d);
    assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
}

#[test]
fn a_distant_light_delivers_its_illuminance() {
    let (e, rho) = (7.0f32, 0.5f32);
    let mut b = SceneBuilder::new(looking_down(1.0));
    floor(&mut b, rho);
    // 60° from the zenith: the floor receives E cos 60°.
    let a = 60f32.to_radians();
    let params = DistantLightParams {
        l: Color::new(0.9, 1.0, 0.4),
        illuminance: Some(e),
        from: Vec3::new(a.sin(), a.cos(), 0.0),
        to: Vec3::ZERO,
        ..Default::default()
    };
    b.add_light(Light::pbrt_distant(&Transform::IDENTITY, &params).unwrap());
    let out = render(&b.build().unwrap(), &settings(4), RenderOptions::default()).unwrap();
    let got = luminance(out.film.pixel(2, 2));
    let want = rho / PI * e * 0.5;
    assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
}

#[test]
fn a_uniform_infinite_light_delivers_its_illuminance() {
    let (e, rho) = (4.0f32, 0.8f32);
    let mut b = SceneBuilder::new(looking_down(1.0));
    floor(&mut b, rho);
    b.set_environment(Environment::uniform(Color::new(0.3, 0.6, 1.0), 1.0, Some(e)).unwrap()).unwrap();
    let out = render(&b.build().unwrap(), &settings(1024), RenderOptions::default()).unwrap();
    // The floor hides the lower hemisphere: E on the floor is E_v.
    let want = rho / PI * e;
    let mean: f32 =
        (0..5).flat_map(|y| (0..5).map(move |x| (x, y))).map(|(x, y)| luminance(out.film.pixel(x, y))).sum::<f32>()
            / 25.0;
    assert!((mean - want).abs() < 0.01 * want, "{mean} vs {want}");
}

/// The matrix swapping `y` and `z` (a mirror).
fn swap_yz() -> Transform {
    Transform::from_matrix(Mat4::from_cols(Vec4::X, Vec4::Z, Vec4::Y, Vec4::W)).unwrap()
}

#[test]
fn the_equal_area_camera_sees_an_equal_area_map_pixel_for_pixel() {
    // pbrt's spherical camera swaps y and z of the equal-area direction
    // (its zenith is camera +y); undoing the swap with the camera transform
    // makes camera pixel (i, j) look along the direction of map pixel
    // (i, j), whatever rotation places both.
    let n = 32u32;
    let px: Vec<Color> = (0..n * n).map(|k| Color::new((k % n) as f32, (k / n) as f32, (k % 7) as f32 + 0.5)).collect();
    for r in [Transform::IDENTITY, Transform::rotate(Vec3::new(1.0, -2.0, 0.5), 77.0).unwrap()] {
        let camera =
            Camera::pbrt(&swap_yz().then(&r), Projection::Spherical { mapping: SphericalMapping::EqualArea }, n, n)
                .unwrap();
        let map =
            EnvironmentMap::with_options(n, n, px.clone(), &MapOptions { light_to_world: r, ..MapOptions::default() })
                .unwrap();
        let mut b = SceneBuilder::new(camera);
        b.set_environment(Environment::Image(Arc::new(map))).unwrap();
        let out = render(&b.build().unwrap(), &settings(1), RenderOptions::default()).unwrap();
        let mut wrong = 0;
        for y in 0..n {
            for x in 0..n {
                let (got, want) = (out.film.pixel(x, y), px[(y * n + x) as usize]);
                if (got - want).abs().max_element() > 1e-4 * want.max_element() {
                    wrong += 1;
                }
            }
        }
        // Samples within a rounding error of a pixel border may land in
        // the neighbour.
        assert!(wrong <= 5, "{wrong} of {} pixels differ", n * n);
    }
}

/// The centre pixel of a 5 × 5 render of a floor (albedo 0.5) lit by a
/// two-sided 2 × 2 square light one unit above it, whose `AreaLightSource`
/// is `light`, imported from pbrt-v4 text in `dir`.
fn floor_under_square_light(dir: &std::path::Path, light: &str) -> (Color, LoadedScene) {
    let text = format!(
        r#"LookAt 0 0 0.5  0 0 0  0 1 0
Camera "perspective" "float fov" 1
Film "rgb" "integer xresolution" 5 "integer yresolution" 5
Sampler "independent" "integer pixelsamples" 4096
Integrator "path" "integer maxdepth" 1
WorldBegin
AttributeBegin
  {light}
  Material "diffuse" "rgb reflectance" [0 0 0]
  Shape "trianglemesh" "point3 P" [-1 -1 1  1 -1 1  1 1 1  -1 1 1] "integer indices" [0 1 2 0 2 3]
    "point2 uv" [0 0 1 0 1 1 0 1]
AttributeEnd
Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "disk" "float radius" 10
"#
    );
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, text).unwrap();
    let loaded = lucent::loader::pbrt::import_pbrt(&path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let film = render(&loaded.scene, &loaded.settings, RenderOptions::default()).unwrap().film;
    (film.pixel(2, 2), loaded)
}

#[test]
fn an_area_light_image_scales_radiance_by_the_surface_texture_coordinates() {
    // A 2 × 1 image, white on the left (u < 1/2), black on the right.
    // Interpolated bilinearly with wrapping, its value v(u) satisfies
    // v(u) + v(1 − u) = 1, so a point under the centre of the light gets
    // exactly half the irradiance of the light with a uniform L = 1.
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("half.png");
    image::RgbImage::from_fn(2, 1, |x, _| image::Rgb(if x == 0 { [255; 3] } else { [0; 3] })).save(&png).unwrap();
    let (uniform, _) =
        floor_under_square_light(dir.path(), r#"AreaLightSource "diffuse" "rgb L" [2 2 2] "bool twosided" true"#);
    let (imaged, scene) = floor_under_square_light(
        dir.path(),
        r#"AreaLightSource "diffuse" "string filename" "half.png" "float scale" 2 "bool twosided" true"#,
    );
    let ratio = imaged.y / uniform.y;
    assert!((ratio - 0.5).abs() < 0.02, "{imaged} vs {uniform}: ratio {ratio}");

    // Seen directly, the light's radiance is scale × the image at (u, v).
    let light = &scene.scene.area_lights()[0];
    let at = |u: f32| light.emitted(Vec3::new(0.0, 0.0, 1.0), Vec2::new(u, 0.5), -Vec3::Z);
    assert!((at(0.25) - Color::splat(2.0)).abs().max_element() < 1e-5, "{}", at(0.25));
    assert!(at(0.75).max_element() < 1e-5, "{}", at(0.75));
    assert!((at(0.5) - Color::splat(1.0)).abs().max_element() < 1e-5, "{}", at(0.5));
}

#[test]
fn an_area_light_with_both_l_and_an_image_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.pbrt");
    std::fs::write(
        &path,
        "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"string filename\" \"x.png\"\nShape \"sphere\"\n",
    )
    .unwrap();
    let e = lucent::loader::pbrt::import_pbrt(&path, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("give either \"L\" or \"filename\""), "{e}");
}
