//! The start of a ray segment in a medium, shared by the path tracer's
//! surface stage and the bidirectional random walks: the segment's two
//! samples are drawn before its ray query, so that the medium's free
//! flight can bound the query.

use crate::color::Color;
use crate::medium::MediumId;
use crate::sampling::Sampler;
use crate::scene::Scene;

/// A segment's samples in a medium and the free flight they give
/// ([`crate::medium::Medium::free_flight`]): the distance within which the
/// path collides in the medium, if it reaches no surface first.
#[derive(Clone, Copy, Debug)]
pub(super) struct MediumSegment {
    /// The medium the segment crosses.
    pub medium: MediumId,
    /// The channel and distance samples, for `Medium::sample`.
    pub u: (f32, f32),
    /// Where the path collides in the medium (infinite in one that needs
    /// no distances).
    pub free_flight: f32,
}

impl MediumSegment {
    /// The segment's samples for a path of throughput `beta` in `medium`
    /// (the next two dimensions of `sampler`); `None` outside media, where
    /// nothing is drawn.
    #[inline]
    pub fn draw(scene: &Scene, medium: Option<MediumId>, beta: Color, sampler: &mut Sampler) -> Option<Self> {
        medium.map(|medium| {
            let u = (sampler.get_1d(), sampler.get_1d());
            Self { medium, u, free_flight: scene.medium(medium).free_flight(beta, u.0, u.1) }
        })
    }

    /// The bound of the segment's ray query: just above the free flight
    /// (the queries' intervals are open at `t_max`, and a surface exactly
    /// there is still reached, as without the bound), infinite outside
    /// media. A path that collides before any surface then finds none and
    /// builds no hit record; `Medium::sample`, given the hit found or
    /// none, decides as it would with the unbounded query.
    #[inline]
    pub fn query_bound(segment: Option<Self>) -> f32 {
        segment.map_or(f32::INFINITY, |s| s.free_flight.next_up())
    }
}
