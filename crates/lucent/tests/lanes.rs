//! The path integrator traces many paths at once
//! ([`Integrator::li_lanes`]). Each path's radiance must be the one it gets
//! traced alone ([`Integrator::li`]), bit for bit, whatever the other lanes
//! of its batch, their order and the batch's size: that is what keeps
//! images independent of how the render loop groups its samples, and of the
//! thread count.

use lucent::camera::Camera;
use lucent::color::Color;
use lucent::geometry::{Ray, Vec2};
use lucent::integrator::{DirectLighting, Integrator, PathIntegrator, RayStats};
use lucent::loader::load_scene;
use lucent::sampling::{Sampler, SamplerKind};
use lucent::scene::Scene;
use std::path::Path;

/// A sampler of `kind` at sample `index` of pixel `(x, y)` with the film
/// and lens dimensions drawn, and the camera ray they give.
fn camera_sample(camera: &Camera, kind: SamplerKind, x: u32, y: u32, index: u32) -> (Ray, Sampler) {
    let mut sampler = Sampler::new(kind, 3, 16);
    sampler.start_pixel_sample(x, y, index);
    let u = sampler.pixel_2d();
    let lens = sampler.get_2d();
    let ray = camera.generate_ray(Vec2::new(x as f32, y as f32) + u, lens);
    (ray, sampler)
}

fn bits(c: Color) -> [u32; 3] {
    c.to_array().map(f32::to_bits)
}

/// 150 path samples of the top-left 10×5 pixels of `scene` (3 each), alone
/// and in batches of several sizes, in a shuffled order.
fn check(scene: &Scene, integrator: &PathIntegrator, kind: SamplerKind, what: &str) {
    let samples: Vec<(u32, u32, u32)> = (0..150u32).map(|i| (i % 10, (i / 10) % 5, i / 50)).collect();
    let mut alone = Vec::new();
    let mut alone_stats = RayStats::default();
    for &(x, y, index) in &samples {
        let (ray, mut sampler) = camera_sample(scene.camera(), kind, x, y, index);
        alone.push(integrator.li(scene, &ray, &mut sampler, &mut alone_stats));
    }
    // A fixed shuffle: every 7th sample, wrapping around.
    let order: Vec<usize> = (0..samples.len()).map(|i| i * 7 % samples.len()).collect();
    for batch in [1, 5, 64, 150] {
        let mut stats = RayStats::default();
        for chunk in order.chunks(batch) {
            let (rays, mut samplers): (Vec<Ray>, Vec<Sampler>) = chunk
                .iter()
                .map(|&i| {
                    let (x, y, index) = samples[i];
                    camera_sample(scene.camera(), kind, x, y, index)
                })
                .unzip();
            let mut radiance = vec![Color::ZERO; chunk.len()];
            integrator.li_lanes(scene, &rays, &mut samplers, &mut radiance, &mut stats);
            for (&i, &l) in chunk.iter().zip(&radiance) {
                assert_eq!(bits(l), bits(alone[i]), "{what}, batches of {batch}: sample {:?}", samples[i]);
            }
        }
        assert_eq!(stats, alone_stats, "{what}, batches of {batch}");
    }
}

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    load_scene(&path).unwrap_or_else(|e| panic!("{name}: {e}")).scene
}

#[test]
fn lanes_equal_paths_traced_alone() {
    // A rectangle light (spherical and area sampling), an environment with
    // glass and metals, and participating media with interfaces.
    for name in ["cornell-box.toml", "glass-and-metal.toml", "media.toml"] {
        let scene = scene(name);
        let integrator = PathIntegrator::new(16);
        check(&scene, &integrator, SamplerKind::Sobol, name);
    }
    let cornell = scene("cornell-box.toml");
    check(&cornell, &PathIntegrator::new(16), SamplerKind::Independent, "cornell, independent");
    check(&cornell, &PathIntegrator::new(16), SamplerKind::Stratified, "cornell, stratified");
    for direct in [DirectLighting::LightsOnly, DirectLighting::BsdfOnly] {
        let integrator = PathIntegrator { direct, ..PathIntegrator::new(8) };
        check(&cornell, &integrator, SamplerKind::Sobol, &format!("cornell, {direct:?}"));
    }
    let glass = scene("glass-and-metal.toml");
    let clamped = PathIntegrator::new(16).with_regularize(true).with_max_indirect(Some(2.0));
    check(&glass, &clamped, SamplerKind::Sobol, "glass-and-metal, regularized and clamped");
}

#[test]
fn lanes_of_different_lengths_are_an_error() {
    let scene = scene("cornell-box.toml");
    let (ray, sampler) = camera_sample(scene.camera(), SamplerKind::Sobol, 0, 0, 0);
    let result = std::panic::catch_unwind(|| {
        let mut samplers = vec![sampler.clone(); 2];
        let mut radiance = vec![Color::ZERO; 2];
        PathIntegrator::new(4).li_lanes(&scene, &[ray], &mut samplers, &mut radiance, &mut RayStats::default());
    });
    assert!(result.is_err());
}
