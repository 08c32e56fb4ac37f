//! pbrt-v4 materials through the renderer: interfaces are invisible, mixes
//! blend, both integrators cope with every material.

use lucent::camera::Camera;
use lucent::color::Color;
use lucent::geometry::{Transform, Vec3};
use lucent::light::{Falloff, Light};
use lucent::material::{CoatedConductorMaterial, CoatedDiffuseMaterial, Material, Roughness};
use lucent::render::{render, IntegratorKind, RenderOptions, RenderSettings};
use lucent::scene::{Scene, SceneBuilder};
use lucent::shapes::Sphere;
use lucent::texture::{FloatTexture, Texture};

/// A grey ground sphere lit by a point light and an environment-free sky,
/// seen from above; `extra` adds a unit sphere of that material between
/// the camera, the light and the ground.
fn scene(extra: Option<Material>, ground: Material) -> Scene {
    let cam = Camera::new(Vec3::new(0.0, 3.0, 6.0), Vec3::ZERO, Vec3::Y, 40.0, 24, 16).unwrap();
    let mut b = SceneBuilder::new(cam);
    let g = b.add_material(ground).unwrap();
    b.add_shape(Sphere::new(Vec3::new(0.0, -101.0, 0.0), 100.0).unwrap(), Transform::IDENTITY, g).unwrap();
    if let Some(m) = extra {
        let m = b.add_material(m).unwrap();
        b.add_shape(Sphere::new(Vec3::new(0.0, 0.5, 1.0), 1.0).unwrap(), Transform::IDENTITY, m).unwrap();
    }
    b.add_light(Light::point(Vec3::new(0.5, 4.0, 1.5), Color::ONE, 20.0, Falloff::InverseSquare).unwrap());
    b.build().unwrap()
}

fn grey() -> Material {
    Material::Diffuse { reflectance: Texture::Constant(Color::splat(0.5)) }
}

fn render_path(scene: &Scene, spp: u32) -> Vec<Color> {
    let settings = RenderSettings { spp, max_depth: 5, ..RenderSettings::for_integrator(IntegratorKind::Path) };
    render(scene, &settings, RenderOptions::default()).unwrap().film.pixels().to_vec()
}

#[test]
fn an_interface_sphere_is_invisible() {
    // Skipping an interface draws no sample dimension, so the image is
    // not only the same in expectation but sample for sample, up to the
    // rounding of rays restarted at the interface: the sphere sits between
    // the camera and the ground and between the ground and the light
    // (shadow rays pass through it as in pbrt-v4's volpath).
    let without = render_path(&scene(None, grey()), 4);
    let with = render_path(&scene(Some(Material::Interface), grey()), 4);
    assert!(without.iter().any(|c| c.max_element() > 0.01));
    for (a, b) in without.iter().zip(&with) {
        assert!((*a - *b).abs().max_element() <= 1e-4 * a.max_element().max(1e-3), "{a} vs {b}");
    }
    // The Whitted integrator passes through it as well.
    let settings = RenderSettings { spp: 1, ..RenderSettings::default() };
    let a = render(&scene(None, grey()), &settings, RenderOptions::default()).unwrap().film;
    let b = render(&scene(Some(Material::Interface), grey()), &settings, RenderOptions::default()).unwrap().film;
    for (a, b) in a.pixels().iter().zip(b.pixels()) {
        assert!((*a - *b).abs().max_element() <= 1e-4 * a.max_element().max(1e-3), "{a} vs {b}");
    }
}

#[test]
fn a_mix_of_black_and_white_averages_to_its_amount() {
    // The ground is a mix of a black and a white diffuse with amount 0.25:
    // on average a quarter as bright as white, pixel by pixel, within
    // noise (the choice hashes position and direction, so it varies from
    // sample to sample).
    let white = Material::Diffuse { reflectance: Texture::Constant(Color::ONE) };
    let reference = render_path(&scene(None, white.clone()), 64);
    let cam = Camera::new(Vec3::new(0.0, 3.0, 6.0), Vec3::ZERO, Vec3::Y, 40.0, 24, 16).unwrap();
    let mut b = SceneBuilder::new(cam);
    let black = b.add_material(Material::Diffuse { reflectance: Texture::Constant(Color::ZERO) }).unwrap();
    let white = b.add_material(white).unwrap();
    let mix =
        b.add_material(Material::Mix { materials: [black, white], amount: FloatTexture::Constant(0.25) }).unwrap();
    b.add_shape(Sphere::new(Vec3::new(0.0, -101.0, 0.0), 100.0).unwrap(), Transform::IDENTITY, mix).unwrap();
    b.add_light(Light::point(Vec3::new(0.5, 4.0, 1.5), Color::ONE, 20.0, Falloff::InverseSquare).unwrap());
    let mixed = render_path(&b.build().unwrap(), 64);
    let (sum_ref, sum_mix): (f32, f32) =
        reference.iter().zip(&mixed).fold((0.0, 0.0), |(a, b), (r, m)| (a + r.x, b + m.x));
    let ratio = sum_mix / sum_ref;
    assert!((ratio - 0.25).abs() < 0.02, "mixed/white = {ratio}");
}

#[test]
fn every_pbrt_material_renders_finite_images_under_both_integrators() {
    let materials = [
        Material::Conductor {
            fresnel: lucent::bsdf::ConductorFresnel::Reflectance { r: Texture::Constant(Color::new(0.9, 0.6, 0.3)) },
            roughness: Roughness::anisotropic(0.05, 0.3, true),
        },
        Material::Dielectric { eta: 1.5, roughness: Roughness::isotropic(0.1, true), tint: Color::ONE },
        Material::ThinDielectric { eta: 1.5 },
        Material::DiffuseTransmission {
            reflectance: Texture::Constant(Color::splat(0.25)),
            transmittance: Texture::Constant(Color::splat(0.25)),
            scale: 1.0,
        },
        Material::CoatedDiffuse(CoatedDiffuseMaterial::default()),
        Material::CoatedDiffuse(CoatedDiffuseMaterial {
            roughness: Roughness::isotropic(0.2, true),
            albedo: Texture::Constant(Color::splat(0.5)),
            g: FloatTexture::Constant(0.3),
            ..Default::default()
        }),
        Material::CoatedConductor(CoatedConductorMaterial::default()),
        grey().with_bump(FloatTexture::Constant(0.1)),
        grey().with_normal_map(Texture::Constant(Color::new(0.6, 0.5, 0.9))),
    ];
    for m in materials {
        let s = scene(Some(m.clone()), grey());
        let img = render_path(&s, 2);
        assert!(img.iter().all(|c| c.is_finite() && c.min_element() >= 0.0), "{m:?}");
        let settings = RenderSettings { spp: 1, ..RenderSettings::default() };
        let w = render(&s, &settings, RenderOptions::default()).unwrap().film;
        assert!(w.pixels().iter().all(|c| c.is_finite()), "{m:?}");
    }
}
