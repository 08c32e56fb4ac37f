//! A scene built entirely in code and path traced: a prototype (a glass
//! ball on a plinth) placed five times along an arc, a gold and a copper
//! variant by material override, a warm area light, and a procedural sky.
//!
//! ```sh
//! cargo run --release -p lucent --example path_traced -- out.png [SPP]
//! ```

use lucent::light::{Environment, EnvironmentMap};
use lucent::prelude::*;
use lucent::tools::sky::{sky, SkyParams};
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "path_traced.png".to_owned());
    let spp: u32 = args.next().map_or(Ok(64), |s| s.parse())?;

    let camera = Camera::new(Vec3::new(0.0, 2.2, -7.5), Vec3::new(0.0, 0.7, 0.0), Vec3::Y, 45.0, 480, 270)?;
    let mut b = SceneBuilder::new(camera);

    // Materials: the path tracer's physically based ones.
    let floor = b.add_material(Material::Diffuse {
        reflectance: Texture::Checker { even: Color::splat(0.7), odd: Color::splat(0.2), scale: 1.0 },
    })?;
    let stone = b.add_material(Material::Diffuse { reflectance: Texture::Constant(Color::new(0.6, 0.55, 0.5)) })?;
    let glass = b.add_material(Material::Dielectric { eta: 1.5, roughness: 0.0.into(), tint: Color::ONE })?;
    let gold = b.add_material(Material::Plastic {
        reflectance: Texture::Constant(Color::new(0.9, 0.6, 0.1)),
        eta: 1.5,
        roughness: 0.05,
    })?;
    let copper = b.add_material(Material::Plastic {
        reflectance: Texture::Constant(Color::new(0.8, 0.35, 0.25)),
        eta: 1.5,
        roughness: 0.3,
    })?;
    let lamp = b.add_material(Material::Diffuse { reflectance: Texture::Constant(Color::ZERO) })?;

    b.add_shape(Plane::new(Vec3::ZERO, Vec3::Y)?, Transform::IDENTITY, floor)?;

    // The prototype: a ball resting on a plinth (a squashed sphere).
    b.begin_prototype("ball on plinth")?;
    b.add_shape(Sphere::new(Vec3::new(0.0, 0.9, 0.0), 0.5)?, Transform::IDENTITY, glass)?;
    b.add_shape(Sphere::new(Vec3::ZERO, 1.0)?, Transform::scale(Vec3::new(0.45, 0.4, 0.45))?, stone)?;
    b.end_prototype()?;
    for i in 0..5 {
        let angle = -60.0 + 30.0 * i as f32;
        let place = Transform::translate(Vec3::new(0.0, 0.0, 3.0)).then(&Transform::rotate_y(angle));
        // The outer two are gold and copper all over; the rest keep the
        // prototype's own materials.
        let material = match i {
            0 => Some(gold),
            4 => Some(copper),
            _ => None,
        };
        b.add_instance("ball on plinth", place.then(&Transform::translate(Vec3::new(0.0, 0.0, -2.0))), material)?;
    }

    // A warm spherical lamp above, and a sky with a sun.
    b.add_emissive(
        Sphere::new(Vec3::new(-2.0, 3.5, -1.0), 0.3)?,
        Transform::IDENTITY,
        lamp,
        Emission { radiance: Color::new(30.0, 20.0, 10.0), two_sided: false, reverse: false, image: None },
    )?;
    let sky = sky(256, &SkyParams::default())?;
    let map = EnvironmentMap::new(sky.width(), sky.height(), sky.pixels().to_vec(), 1.0, 0.0)?;
    b.set_environment(Environment::Image(Arc::new(map)))?;

    let scene = b.build()?;
    let settings = RenderSettings { spp, ..RenderSettings::for_integrator(IntegratorKind::Path) };
    let output = render(&scene, &settings, RenderOptions::default())?;
    PendingImage::create(&out)?.write(&output.film, ToneMap::Aces, true)?;
    println!(
        "{out}: {}×{}, {spp} spp, {:.2} s, {:.2} Mrays/s",
        output.film.width(),
        output.film.height(),
        output.elapsed.as_secs_f64(),
        output.mrays_per_second()
    );
    Ok(())
}
