use super::path::{material_context, occluded, MAX_INTERFACE_SKIPS};
use super::{Integrator, RayStats};
use crate::color::Color;
use crate::geometry::{face_forward, reflect, Ray};
use crate::light::LightSource;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// Whitted-style ray tracing (Whitted, "An Improved Illumination Model for
/// Shaded Display", CACM 23(6), 1980): at each hit, direct light from every
/// light not blocked by a shadow ray, ambient light, and a recursively traced
/// mirror reflection.
///
/// The outgoing radiance at a point with shading normal `n` is
///
/// `L = ka·c·L_ambient + Σ_lights f(wo, wi) · E_i · max(0, n·wi) + kr · L(reflected ray)`
///
/// where `E_i` is what the light delivers (see [`crate::light::Light`]) and
/// `f` is the [`crate::material::PhongBsdf`]. Reflection stops after
/// `max_depth` bounces; a ray that leaves the scene sees the background
/// colour.
///
/// The physically based materials are approximated by the classic model
/// (see [`crate::material::Material::bsdf`]); `Mix` materials are resolved
/// and bump and normal maps applied as under the path tracer, and
/// interfaces are passed through, by camera, mirror and shadow rays alike.
///
/// With a single reflected ray per hit the recursion is a chain, so it is
/// evaluated as a loop carrying the product of the `kr` factors so far (the
/// path throughput): no stack growth, whatever the depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WhittedIntegrator {
    /// Most mirror bounces followed (0: no reflections).
    pub max_depth: u32,
}

impl Integrator for WhittedIntegrator {
    /// Deterministic: no sample dimensions are used beyond the film and lens.
    fn li(&self, scene: &Scene, camera_ray: &Ray, _sampler: &mut Sampler, stats: &mut RayStats) -> Color {
        stats.camera += 1;
        let mut radiance = Color::ZERO;
        let mut throughput = Color::ONE;
        let mut ray = *camera_ray;
        let mut depth = 0;
        let mut skips = 0;
        let mut interfaces: Option<bool> = None;
        loop {
            let Some(si) = scene.intersect(&ray, f32::INFINITY) else {
                return radiance + throughput * scene.background();
            };
            let wo = -ray.dir.normalize();
            // An emissive surface shows its own radiance.
            if let Some(light) = si.light {
                radiance += throughput * scene.area_lights()[light as usize].emitted_at(si.p, si.uv, si.attributes, wo);
            }
            // Resolve the material; an interface is no surface.
            let ctx = material_context(&si, wo);
            let Some(resolved) = scene.material(si.material).resolve(&ctx, scene.materials()) else {
                skips += 1;
                if skips > MAX_INTERFACE_SKIPS {
                    return radiance;
                }
                ray = si.spawn_ray(ray.dir);
                continue;
            };
            skips = 0;
            // Shade the side the ray arrived on: surfaces are two-sided.
            let ng = face_forward(si.n, wo);
            let ns = face_forward(resolved.shading.ns, ng);
            let bsdf = resolved.material.bsdf_in(&ctx.texture_context());

            let mut l = bsdf.ambient * scene.ambient();
            for light in scene.lights() {
                let Some(sample) = light.sample_li(si.p) else { continue };
                let cos = ns.dot(sample.wi);
                // Light must be above both the shading and the geometric
                // surface: interpolated normals must not let light through
                // the back.
                if cos <= 0.0 || ng.dot(sample.wi) <= 0.0 {
                    continue;
                }
                stats.shadow += 1;
                let target = match sample.source {
                    LightSource::At(p) => Some(p),
                    LightSource::Infinite => None,
                };
                if !occluded(scene, &si, target, sample.wi, &mut interfaces) {
                    l += bsdf.f(wo, sample.wi, ns) * sample.li * cos;
                }
            }
            radiance += throughput * l;

            if bsdf.kr.max_element() <= 0.0 || depth >= self.max_depth {
                return radiance;
            }
            throughput *= bsdf.kr;
            depth += 1;
            stats.secondary += 1;
            ray = si.spawn_ray(reflect(wo, ns));
        }
    }
}
