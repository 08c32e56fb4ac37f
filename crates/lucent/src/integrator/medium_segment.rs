//! The start of a ray segment in a medium, shared by the path tracer's
//! surface stage and the bidirectional random walks: the segment's free
//! flight is drawn before its ray query, so that it can bound the query.

use crate::color::Color;
use crate::medium::{FreeFlight, MediumId};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// A segment's free flight in a medium
/// ([`crate::medium::Medium::free_flight`]): where the path collides in the
/// medium, if it reaches no surface first.
#[derive(Clone, Copy, Debug)]
pub(super) struct MediumSegment {
    /// The medium the segment crosses.
    pub medium: MediumId,
    /// The free flight, for the query's bound and for
    /// `Medium::sample_flight`.
    pub flight: FreeFlight,
}

impl MediumSegment {
    /// The segment's free flight for a path of throughput `beta` in
    /// `medium` (drawn with the next two dimensions of `sampler`: channel,
    /// distance); `None` outside media, where nothing is drawn.
    #[inline]
    pub fn draw(scene: &Scene, medium: Option<MediumId>, beta: Color, sampler: &mut Sampler) -> Option<Self> {
        medium.map(|medium| {
            let (u_channel, u_distance) = (sampler.get_1d(), sampler.get_1d());
            Self { medium, flight: scene.medium(medium).free_flight(beta, u_channel, u_distance) }
        })
    }

    /// The bound of the segment's ray query: just above the free flight's
    /// distance (the queries' intervals are open at `t_max`, and a surface
    /// exactly there is still reached, as without the bound), infinite
    /// outside media. A path that collides before any surface then finds
    /// none and builds no hit record; `Medium::sample_flight`, given the
    /// hit found or none, decides as it would with the unbounded query.
    #[inline]
    pub fn query_bound(segment: Option<Self>) -> f32 {
        segment.map_or(f32::INFINITY, |s| s.flight.distance().next_up())
    }
}
