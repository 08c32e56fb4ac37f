//! Building a [`Scene`](crate::scene::Scene) from a parsed scene file: the
//! camera, settings, lights and environment, then the objects
//! ([`super::objects`]) and materials ([`super::materials`]).

use super::description::*;
use super::locate::*;
use super::objects::{BuildContext, Place};
use super::textures::TextureTable;
use super::values::*;
use super::{LoadedScene, SceneFile};
use crate::color::Color;
use crate::film::{check_image_size, Aov, AovSet, Filter, ToneMap};
use crate::geometry::Transform;
use crate::light::{Environment, EnvironmentMapping, Falloff, Light, MapOptions};
use crate::material::MaterialId;
use crate::render::{IntegratorKind, RenderSettings};
use crate::sampling::SamplerKind;
use crate::scene::{SceneBuilder, SceneError};
use std::collections::HashMap;
use std::path::PathBuf;

impl SceneFile {
    /// Validate the description and build the scene, through a
    /// [`SceneBuilder`], and the render settings.
    pub fn build(&self) -> Result<LoadedScene, SceneError> {
        let d = &self.description;
        let r = &d.render;
        let (w, h) = (r.width.0, r.height.0);
        check_image_size(w, h).map_err(|e| {
            let at = find_key(&self.source, "width", 0)
                .or_else(|| find_key(&self.source, "height", 0))
                .or_else(|| find_header(&self.source, "render"));
            self.error(at, e.to_string())
        })?;

        let camera = self.camera(w, h)?;

        let mut scene = SceneBuilder::new(camera);
        let settings = self.settings()?;
        scene.set_background(r.background.into()).map_err(|e| self.builder_error(e, "[render]", "background"))?;
        if let Some(env) = &d.environment {
            let env = self.environment(env)?;
            scene.set_environment(env).map_err(|e| self.builder_error(e, "[environment]", "color"))?;
        }
        if let Some(a) = &d.ambient {
            scene
                .set_ambient(Color::from(a.color) * a.intensity.get())
                .map_err(|e| self.builder_error(e, "[ambient]", "intensity"))?;
        }

        let mut textures = TextureTable::new(self)?;
        let ids = self.add_materials(&mut scene, &mut textures)?;
        let media = self.add_media(&mut scene)?;
        for (i, l) in d.point_light.iter().enumerate() {
            let falloff = falloff(l.falloff, Falloff::None);
            scene.add_light(Light::point(l.position.into(), l.color.into(), l.intensity.get(), falloff).map_err(
                |e| self.error(nth_table(&self.source, "point_light", i), format!("point_light #{}: {e}", i + 1)),
            )?);
        }
        for (i, l) in d.spot_light.iter().enumerate() {
            let falloff = falloff(l.falloff, Falloff::InverseSquare);
            let angle = l.angle.get();
            // The default blend width fits inside any cone; one given
            // explicitly must (the light error below says so).
            let delta = l.cone_delta.map_or(angle.min(5.0), NonNegative::get);
            let light = Light::spot(
                l.position.into(),
                l.direction.into(),
                l.color.into(),
                l.intensity.get(),
                angle,
                delta,
                falloff,
            )
            .map_err(|e| self.error(nth_table(&self.source, "spot_light", i), format!("spot_light #{}: {e}", i + 1)))?;
            scene.add_light(light);
        }
        for (i, l) in d.directional_light.iter().enumerate() {
            scene.add_light(Light::directional(l.direction.into(), l.color.into(), l.intensity.get()).map_err(
                |e| {
                    let at = nth_table(&self.source, "directional_light", i);
                    self.error(at, format!("directional_light #{}: {e}", i + 1))
                },
            )?);
        }

        self.check_prototypes()?;
        let root = GroupDesc {
            name: None,
            transform: Vec::new(),
            material: None,
            sphere: d.sphere.clone(),
            plane: d.plane.clone(),
            triangle: d.triangle.clone(),
            quad: d.quad.clone(),
            disk: d.disk.clone(),
            cylinder: d.cylinder.clone(),
            group: d.group.clone(),
            mesh: d.mesh.clone(),
            instance: d.instance.clone(),
        };
        let mut ctx = BuildContext { ids, meshes: HashMap::new(), active_prototypes: Vec::new(), textures, media };
        let place = Place { label: "", at: None, forced_material: None };
        self.add_group(&mut scene, &mut ctx, &root, Transform::IDENTITY, None, place)?;
        let scene = scene.build().map_err(|e| e.in_file(self.path.clone(), &self.source, None, ""))?;
        let mut files: Vec<PathBuf> = ctx.meshes.into_keys().map(|(path, _, _)| path).collect();
        if let Some(file) = d.environment.as_ref().and_then(|e| e.file.as_ref()) {
            files.push(self.relative(file));
        }
        files.extend(ctx.textures.files.iter().cloned());
        files.sort();
        files.dedup();
        Ok(LoadedScene { scene, settings, files })
    }

    /// Add the `[materials]`, each after the materials a `mix` of it names
    /// (a mix that contains itself is an error); the ids by name.
    fn add_materials(
        &self,
        scene: &mut SceneBuilder,
        textures: &mut TextureTable,
    ) -> Result<HashMap<String, MaterialId>, SceneError> {
        let materials = &self.description.materials;
        let mut ids = HashMap::new();
        let mut path: Vec<&str> = Vec::new();
        // Depth first through `mix` references, with an explicit stack of
        // (name, whether its dependencies are already pushed).
        for root in materials.keys() {
            let mut stack = vec![(root.as_str(), false)];
            while let Some((name, expanded)) = stack.pop() {
                if ids.contains_key(name) {
                    continue;
                }
                let m = &materials[name];
                if !expanded {
                    if let Some(start) = path.iter().position(|&p| p == name) {
                        let mut cycle: Vec<String> = path[start..].iter().map(|p| format!("\"{p}\"")).collect();
                        cycle.push(format!("\"{name}\""));
                        return Err(self.error(
                            find_table(&self.source, name),
                            format!("material \"{name}\" mixes itself ({})", cycle.join(" > ")),
                        ));
                    }
                    stack.push((name, true));
                    path.push(name);
                    if let MaterialKindDesc::Mix(mix) = &m.kind {
                        for other in mix.materials.iter().rev() {
                            if let Some((k, _)) = materials.get_key_value(other) {
                                if !ids.contains_key(k.as_str()) {
                                    stack.push((k.as_str(), false));
                                }
                            }
                        }
                    }
                    continue;
                }
                path.retain(|&p| p != name);
                let material = self.material(name, m, textures, &ids)?;
                let id = scene.add_material(material).map_err(|e| {
                    let at = find_table(&self.source, name);
                    let at = if e.message.starts_with("roughness") {
                        find_key_after(&self.source, "roughness", at).or(at)
                    } else {
                        at
                    };
                    e.in_file(self.path.clone(), &self.source, at, &format!("material \"{name}\""))
                })?;
                ids.insert(name.to_owned(), id);
            }
        }
        Ok(ids)
    }

    /// A path named in the file: relative to the file's directory.
    pub(super) fn relative(&self, file: &str) -> PathBuf {
        match self.path.as_ref().and_then(|p| p.parent()) {
            Some(dir) => dir.join(file),
            None => PathBuf::from(file),
        }
    }

    /// An error of the builder about `what`, located at `key` (or `what`'s
    /// table header).
    fn builder_error(&self, e: SceneError, what: &str, key: &str) -> SceneError {
        let header = what.trim_start_matches('[').trim_end_matches(']');
        let at = find_key(&self.source, key, 0).or_else(|| find_header(&self.source, header));
        e.in_file(self.path.clone(), &self.source, at, what)
    }

    /// The `[render]` table as render settings.
    fn settings(&self) -> Result<RenderSettings, SceneError> {
        let r = &self.description.render;
        let integrator = match r.integrator {
            IntegratorDesc::Whitted => IntegratorKind::Whitted,
            IntegratorDesc::Path => IntegratorKind::Path,
            IntegratorDesc::Bdpt => IntegratorKind::Bdpt,
        };
        Ok(RenderSettings {
            spp: r.spp.0,
            max_depth: r.max_depth.map_or(integrator.default_max_depth(), |d| d.0),
            tone_map: match r.tone_map {
                ToneMapDesc::Classic => ToneMap::Classic,
                ToneMapDesc::Clamp => ToneMap::Clamp,
                ToneMapDesc::Reinhard => ToneMap::Reinhard,
                ToneMapDesc::Aces => ToneMap::Aces,
            },
            srgb: r.srgb,
            seed: r.seed,
            integrator,
            sampler: match r.sampler {
                None => integrator.default_sampler(),
                Some(SamplerDesc::Stratified) => SamplerKind::Stratified,
                Some(SamplerDesc::Sobol) => SamplerKind::Sobol,
                Some(SamplerDesc::Independent) => SamplerKind::Independent,
            },
            filter: match r.filter {
                None => Filter::default(),
                Some(f) => self.filter(&f)?,
            },
            regularize: r.regularize,
            film_scale: r.film_scale.map_or(Color::ONE, Color::from),
            max_component: r.max_component.map(Positive::get),
            max_indirect: r.max_indirect.map(Positive::get),
            aovs: AovSet::of(&r.aov.iter().map(|&a| Aov::from(a)).collect::<Vec<_>>()),
            filter_importance: r.filter_importance,
            adaptive: r.adaptive.map(Positive::get),
        })
    }

    /// Refuse a prototype that places itself, directly or through others,
    /// whether or not an instance uses it (`docs/scene-format.md` promises
    /// this; the expansion below would only find the cycles it reaches).
    fn check_prototypes(&self) -> Result<(), SceneError> {
        let prototypes = &self.description.prototypes;
        // The prototypes a group places, with the instance's position among
        // its siblings, for the message.
        fn placed(group: &GroupDesc, out: &mut Vec<String>) {
            out.extend(group.instance.iter().map(|i| i.prototype.clone()));
            group.group.iter().for_each(|g| placed(g, out));
        }
        fn visit<'a>(
            file: &SceneFile,
            name: &'a str,
            path: &mut Vec<&'a str>,
            done: &mut Vec<&'a str>,
            prototypes: &'a std::collections::BTreeMap<String, GroupDesc>,
        ) -> Result<(), SceneError> {
            if let Some(start) = path.iter().position(|&p| p == name) {
                let mut cycle: Vec<String> = path[start..].iter().map(|p| format!("\"{p}\"")).collect();
                cycle.push(format!("\"{name}\""));
                let at = find_key(&file.source, &format!("prototypes.{}", path[start]), 0)
                    .or_else(|| nth_line_starting_with(&file.source, &format!("[prototypes.{}", path[start]), 0))
                    .or_else(|| find_key(&file.source, path[start], 0));
                return Err(
                    file.error(at, format!("prototype \"{}\" contains itself ({})", path[start], cycle.join(" > ")))
                );
            }
            if done.contains(&name) {
                return Ok(());
            }
            let Some((key, group)) = prototypes.get_key_value(name) else {
                return Ok(()); // reported where it is placed
            };
            path.push(key);
            let mut inner = Vec::new();
            placed(group, &mut inner);
            for p in &inner {
                if let Some((k, _)) = prototypes.get_key_value(p.as_str()) {
                    visit(file, k, path, done, prototypes)?;
                }
            }
            path.pop();
            done.push(key);
            Ok(())
        }
        let mut done = Vec::new();
        for name in prototypes.keys() {
            visit(self, name, &mut Vec::new(), &mut done, prototypes)?;
        }
        Ok(())
    }
    fn filter(&self, f: &FilterDesc) -> Result<Filter, SceneError> {
        let radius = |default: f32| f.radius.map_or(default, Positive::get);
        let filter = match f.kind {
            FilterKindDesc::Box => Filter::Box { radius: radius(0.5) },
            FilterKindDesc::Tent => Filter::Tent { radius: radius(1.0) },
            FilterKindDesc::Gaussian => {
                Filter::Gaussian { radius: radius(1.5), sigma: f.sigma.map_or(0.5, Positive::get) }
            }
            FilterKindDesc::Mitchell => Filter::Mitchell {
                radius: radius(2.0),
                b: f.b.map_or(1.0 / 3.0, Finite::get),
                c: f.c.map_or(1.0 / 3.0, Finite::get),
            },
            FilterKindDesc::Lanczos => Filter::Lanczos { radius: radius(4.0), tau: f.tau.map_or(3.0, Positive::get) },
        };
        let applies = |key: &str| {
            matches!(
                (f.kind, key),
                (FilterKindDesc::Gaussian, "sigma")
                    | (FilterKindDesc::Mitchell, "b" | "c")
                    | (FilterKindDesc::Lanczos, "tau")
            )
        };
        let given =
            [("sigma", f.sigma.is_some()), ("b", f.b.is_some()), ("c", f.c.is_some()), ("tau", f.tau.is_some())];
        for (key, given) in given {
            if given && !applies(key) {
                return Err(self.error(
                    find_key(&self.source, key, 0).or_else(|| find_key(&self.source, "filter", 0)),
                    format!("[render] filter: `{key}` does not apply to a {:?} filter", f.kind).to_lowercase(),
                ));
            }
        }
        filter
            .validate()
            .map_err(|e| self.error(find_key(&self.source, "filter", 0), format!("[render] filter: {e}")))?;
        Ok(filter)
    }

    fn environment(&self, env: &EnvironmentDesc) -> Result<Environment, SceneError> {
        let at = || find_header(&self.source, "environment");
        let scale = env.intensity.get();
        let illuminance = env.illuminance.map(Positive::get);
        match (&env.file, env.color) {
            (Some(_), Some(_)) => Err(self.error(at(), "[environment]: give `color` or `file`, not both")),
            (None, color) => {
                for (key, given) in [
                    ("rotation", env.rotation.is_some()),
                    ("mapping", env.mapping.is_some()),
                    ("transform", !env.transform.is_empty()),
                ] {
                    if given {
                        return Err(self.error(at(), format!("[environment]: `{key}` applies to an image (`file`)")));
                    }
                }
                Environment::uniform(color.map_or(Color::ONE, Color::from), scale, illuminance)
                    .map_err(|e| self.error(at(), format!("[environment]: {e}")))
            }
            (Some(file), None) => {
                let path = self.relative(file);
                let file_error =
                    |e| self.error(find_value(&self.source, "file", file).or_else(at), format!("[environment]: {e}"));
                let rotation = env.rotation.map_or(0.0, Finite::get);
                if env.mapping.is_none() && env.transform.is_empty() && illuminance.is_none() {
                    return Environment::from_file(&path, scale, rotation).map_err(file_error);
                }
                if env.rotation.is_some() && !env.transform.is_empty() {
                    return Err(self.error(at(), "[environment]: give `rotation` or `transform`, not both"));
                }
                let light_to_world = if env.transform.is_empty() {
                    Transform::rotate_y(rotation)
                } else {
                    self.transform(&env.transform, "[environment]", at())?
                };
                let options = MapOptions {
                    mapping: match env.mapping {
                        None | Some(SphericalMappingDesc::Equirectangular) => EnvironmentMapping::Equirectangular,
                        Some(SphericalMappingDesc::EqualArea) => EnvironmentMapping::EqualArea,
                    },
                    light_to_world,
                    scale,
                    illuminance,
                };
                Environment::from_file_with(&path, &options).map_err(file_error)
            }
        }
    }
}

fn falloff(f: Option<FalloffDesc>, default: Falloff) -> Falloff {
    match f {
        None => default,
        Some(FalloffDesc::None) => Falloff::None,
        Some(FalloffDesc::InverseSquare) => Falloff::InverseSquare,
    }
}
