//! A mesh CCD query's types: the moving meshes, the query, what it may
//! start from, its result and its buffers.

use super::contact::ContactRule;
use super::hull_gap::WarmSimplex;
use super::mesh_search::Front;
use super::options::{CcdOptions, CcdStatus};
use crate::math::{Real, Vector};
use crate::mesh::{DistanceKernel, MeshDistance, MeshDistanceScratch, TriMesh};
use crate::motion::StepMotion;

/// One body of a mesh CCD query: its mesh (vertices relative to the centre
/// of mass) and its motion over the step.
#[derive(Copy, Clone, Debug)]
pub struct MovingMesh<'a> {
    /// The mesh.
    pub mesh: &'a TriMesh,
    /// Its motion over the step.
    pub motion: &'a StepMotion,
}

/// The result of [`mesh_time_of_impact`](super::mesh_time_of_impact).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct MeshCcdResult {
    /// Time of first contact after the step's start, within `[0, duration]`,
    /// or `None`.
    pub time_of_impact: Option<Real>,
    /// How the iteration ended.
    pub status: CcdStatus,
    /// At contact: a triangle pair within the contact distance at the
    /// reported time (the one that stopped the search; not necessarily the
    /// closest), or, out of iterations, the closest pair there.
    pub closest: Option<MeshDistance>,
    /// The contact distance used (`minimum_separation + tolerance`): no
    /// contact is reported farther than this.
    pub contact_distance: Real,
    /// Every approach closer than this (`minimum_separation + tolerance /
    /// 2`, the advancement's target) is reported.
    pub guaranteed_distance: Real,
    /// Without contact: a lower bound on the distance at the step's end,
    /// to pass to the next step as `lower_bound`.
    pub end_lower_bound: Real,
    /// The last closest triangle pair, a good first guess for the next query.
    pub hint: Option<(usize, usize)>,
    /// The direction (world frame, from `a` towards `b`) along which the
    /// hulls' gap was measured at the step's start, a good first guess for
    /// the next query.
    pub axis: Option<Vector>,
    /// The hulls' GJK simplex at the last hulls' gap, a good start for the
    /// next query.
    pub simplex: WarmSimplex,
    /// Advancement steps searched (0 when a filter or the hulls' gap
    /// settled the step).
    pub iterations: usize,
    /// Advancement steps taken on the hulls' gap alone, before any search
    /// (at most `HULL_ADVANCE_MAX_STEPS`).
    pub hull_steps: usize,
    /// Triangle pairs evaluated over all searches.
    pub triangle_pairs: usize,
    /// BVH node pairs bounded over all searches.
    pub node_pairs: usize,
}

/// A mesh CCD query: two moving meshes over `[0, duration]`, and what
/// counts as contact.
#[derive(Copy, Clone, Debug)]
pub struct MeshCcdQuery<'a> {
    /// The first body.
    pub a: MovingMesh<'a>,
    /// The second body.
    pub b: MovingMesh<'a>,
    /// The length of the interval (the motions' time unit).
    pub duration: Real,
    /// Tolerances and the iteration limit.
    pub options: CcdOptions,
    /// How the contact distance is chosen: relative to the pair's size, the
    /// smaller radius `min(r_a, r_b)` (the default), or absolute.
    pub contact: ContactRule,
    /// The triangle distance kernel.
    pub kernel: DistanceKernel,
}

impl<'a> MeshCcdQuery<'a> {
    /// A query with the default contact rule and the exact kernel.
    pub fn new(
        a: MovingMesh<'a>,
        b: MovingMesh<'a>,
        duration: Real,
        options: CcdOptions,
    ) -> MeshCcdQuery<'a> {
        MeshCcdQuery {
            a,
            b,
            duration,
            options,
            contact: ContactRule::default(),
            kernel: DistanceKernel::Exact,
        }
    }
}

/// What a query may start from, carried over from the pair's previous
/// query (all optional; [`WarmStart::default`] is a cold start).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct WarmStart {
    /// A known lower bound on the distance at the interval's start (the
    /// previous query's [`MeshCcdResult::end_lower_bound`]).
    pub lower_bound: Option<Real>,
    /// A triangle pair to seed the search (the previous query's
    /// [`MeshCcdResult::hint`]).
    pub hint: Option<(usize, usize)>,
    /// A direction (world frame, from `a` towards `b`) to start the hulls'
    /// gap from (the previous query's [`MeshCcdResult::axis`]).
    pub axis: Option<Vector>,
    /// The hulls' GJK simplex to start from (the previous query's
    /// [`MeshCcdResult::simplex`]).
    pub simplex: WarmSimplex,
}

/// Reusable buffers of [`mesh_time_of_impact`](super::mesh_time_of_impact): queries do not allocate
/// once they have grown. Keep one per thread.
#[derive(Clone, Debug, Default)]
pub struct MeshCcdScratch {
    /// The front of the advancement search (kept between its steps).
    pub(super) front: Front,
    /// The buffers of the distance queries (also lent to the stepper's).
    pub(crate) distance: MeshDistanceScratch,
}

/// Which triangle pair [`mesh_time_of_impact`](super::mesh_time_of_impact) reports where the hulls
/// touch and neither the hint nor a pair around the hulls' closest
/// vertices is within the contact distance.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Touching {
    /// The BVH search's (a contact: the responses read its features).
    Searched,
    /// Also any pair GJK on the hulls names within the contact distance
    /// (the closest approach's runs, which need only the time, so that
    /// most screens need no search). Among tied pairs, say a box's face on
    /// a face, it may name another than the search would.
    Named,
}
