//! Light samples of an environment image across lanes.
//!
//! Sampling an environment image (PBRT 4th ed., §12.5.2) is two searches
//! of tabulated distributions: the row in the marginal table, then the
//! column in that row's table, whose pixel is then read. A large map's row
//! tables and pixels do not fit in the caches, and a sample's reads are
//! at random, so one lane at a time each sample waited on two or three
//! cache misses in turn, and on the loops of its searches. The light stage
//! of [`super::lanes`] gathers the non-specular vertices whose light pick
//! is the environment (in a scene without media) and takes their samples
//! together ([`Environment::sample_li_many`]): each step of the searches
//! for all the lanes before the next, so that their misses overlap, and a
//! lat-long map's directions across vector lanes.
//!
//! Each lane's sample is [`Environment::sample_li`]'s bit for bit (tested
//! equal to it), and it is then weighed as [`PathIntegrator::sample_light`]
//! weighs it.

use super::lanes::LightStage;
#[cfg(doc)]
use super::PathIntegrator;
use crate::bsdf::Bsdf;
use crate::geometry::{Vec2, LANES};
use crate::light::{Environment, LiSample};
use crate::sampling::VertexSamples;
use crate::scene::Scene;

/// The lanes of one light stage whose light pick is the environment
/// image, with their samples.
pub(super) struct EnvironmentLanes<'a> {
    env: &'a Environment,
    /// The environment's index among the scene's lights.
    index: usize,
    /// The lanes taken, with the probability of their light pick, the
    /// sample's point in the square and the light sample.
    lanes: [(u8, f32); LANES],
    points: [Vec2; LANES],
    samples: [Option<LiSample>; LANES],
    len: usize,
    /// Bit `i` is set when lane `i` was taken.
    taken: u64,
}

impl<'a> EnvironmentLanes<'a> {
    /// For a scene whose environment is an image; `None` in scenes without
    /// one, or with media (whose light samples carry transmittance).
    pub(super) fn new(scene: &'a Scene) -> Option<Self> {
        let (index, env) = scene.environment_light()?;
        (env.is_image() && !scene.has_media()).then_some(Self {
            env,
            index,
            lanes: [(0, 0.0); LANES],
            points: [Vec2::ZERO; LANES],
            samples: [None; LANES],
            len: 0,
            taken: 0,
        })
    }

    /// Takes the lanes of `shade` whose vertex is not specular and whose
    /// light pick is the environment, and samples the environment for all
    /// of them. (Each step runs out of line, so that profiles show its
    /// cost.)
    #[inline(never)]
    pub(super) fn start(&mut self, scene: &Scene, bsdfs: &[Option<Bsdf>], u: &[VertexSamples], shade: &[u8]) {
        let lights = scene.light_set();
        self.len = 0;
        self.taken = 0;
        for &lane in shade {
            let i = lane as usize;
            let Some(bsdf) = &bsdfs[i] else { continue };
            if bsdf.is_specular() {
                continue;
            }
            let Some((light, pmf)) = lights.sample(u[i].light) else { continue };
            if light != self.index {
                continue;
            }
            self.lanes[self.len] = (lane, pmf);
            self.points[self.len] = u[i].point;
            self.len += 1;
            self.taken |= 1 << i;
        }
        self.env.sample_li_many(&self.points[..self.len], &mut self.samples[..self.len]);
    }

    /// Whether [`EnvironmentLanes::start`] took `lane`: its light sample is
    /// this kernel's.
    #[inline]
    pub(super) fn took(&self, lane: u8) -> bool {
        self.taken & (1 << lane) != 0
    }

    /// Each lane's light sample, weighed and, where it carries light,
    /// tested with a shadow ray; what it finds is added to the lane's path.
    #[inline(never)]
    pub(super) fn estimate(&self, stage: &mut LightStage) {
        for (&(lane, pmf), ls) in self.lanes[..self.len].iter().zip(&self.samples) {
            let Some(ls) = *ls else { continue };
            stage.add_light_sample(lane as usize, pmf, ls);
        }
    }
}
