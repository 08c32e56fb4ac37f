//! Build a scene in Rust instead of a scene file, render it and save it.
//!
//! ```sh
//! cargo run --release -p lucent --example in_code -- out.png
//! ```

use lucent::prelude::*;
use std::error::Error;

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "in_code.png".into());

    let camera = Camera::new(Vec3::new(0.0, 2.0, -8.0), Vec3::new(0.0, 1.0, 0.0), Vec3::Y, 50.0, 480, 270)?;
    let mut scene = SceneBuilder::new(camera);
    scene.set_background(Color::new(0.05, 0.06, 0.1))?;
    scene.set_ambient(Color::splat(0.08))?;

    let floor = scene.add_material(Material::matte(
        Texture::Checker { even: Color::splat(0.8), odd: Color::splat(0.2), scale: 1.0 },
        0.9,
    )?)?;
    let mirror = scene.add_material(Material::phong(Color::splat(0.9), 0.1, 0.8, 200.0, 0.8)?)?;
    let red = scene.add_material(Material::matte(Color::new(0.9, 0.15, 0.1), 0.9)?)?;

    scene.add_shape(Plane::new(Vec3::ZERO, Vec3::Y)?, Transform::IDENTITY, floor)?;
    scene.add_shape(Sphere::new(Vec3::new(0.0, 1.0, 0.0), 1.0)?, Transform::IDENTITY, mirror)?;
    // An ellipsoid: a unit sphere scaled, then moved.
    let ellipsoid = Transform::scale(Vec3::new(0.5, 1.0, 0.5))?.then(&Transform::translate(Vec3::new(2.2, 1.0, 0.5)));
    scene.add_shape(Sphere::new(Vec3::ZERO, 1.0)?, ellipsoid, red)?;

    scene.add_light(Light::point(Vec3::new(-4.0, 6.0, -5.0), Color::ONE, 1.2, Falloff::None)?);
    scene.add_light(Light::directional(Vec3::new(1.0, -1.0, 0.5), Color::new(0.4, 0.45, 0.6), 0.5)?);
    let scene = scene.build()?;

    let settings = RenderSettings { spp: 16, ..RenderSettings::default() };
    let output = render(&scene, &settings, RenderOptions::default())?;
    PendingImage::create(&out)?.write(&output.film, settings.tone_map, settings.srgb)?;
    println!("{out}: {:.2} Mrays/s", output.mrays_per_second());
    Ok(())
}
