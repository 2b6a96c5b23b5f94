//! A pair's CCD query as the stepper asks it, and what its result means:
//! shared by the narrow phase and the responses' re-checks.

use super::world::PairState;
use crate::ccd::{CcdStatus, ContactRule, MeshCcdQuery, MeshCcdResult, MovingMesh};
use crate::math::Real;
use crate::motion::StepMotion;
use crate::scene::Model;

/// What a pair's CCD result means to the stepper (the narrow phase's and
/// a response's re-checks alike).
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum CcdVerdict {
    /// The query ran out of iterations: undecided is not a contact; the
    /// run ends after this step ([`World::note_undecided`](super::world::World::note_undecided)).
    Undecided,
    /// A contact at this time (in the query's interval).
    Contact(Real),
    /// No contact within the interval.
    Apart,
}

impl CcdVerdict {
    /// The verdict of `result`.
    pub(crate) fn of(result: &MeshCcdResult) -> CcdVerdict {
        match (result.status, result.time_of_impact) {
            (CcdStatus::OutOfIterations, _) => CcdVerdict::Undecided,
            (_, Some(time)) => CcdVerdict::Contact(time),
            (_, None) => CcdVerdict::Apart,
        }
    }
}

/// A contact the narrow phase found: the pair (index into `world.pairs`)
/// and its CCD result (with a time of impact).
#[derive(Clone, Debug)]
pub(crate) struct Found {
    pub pair: usize,
    pub result: MeshCcdResult,
}

/// The mesh CCD query of `pair` over `duration`, its bodies moving by
/// `motions`, under the scene's options and kernel and the rule `contact`.
pub(crate) fn pair_query<'a>(
    model: &'a Model,
    pair: &PairState,
    motions: [&'a StepMotion; 2],
    duration: Real,
    contact: ContactRule,
) -> MeshCcdQuery<'a> {
    MeshCcdQuery {
        a: MovingMesh { mesh: &model.bodies[pair.a].mesh, motion: motions[0] },
        b: MovingMesh { mesh: &model.bodies[pair.b].mesh, motion: motions[1] },
        duration,
        options: model.ccd,
        contact,
        kernel: model.kernel,
    }
}
