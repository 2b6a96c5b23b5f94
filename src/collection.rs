//! One mesh against many: a [`Collection`] of named meshes with poses, and
//! the broad phase inside it.
//!
//! A robot link against the obstacles of a cell, a part against a fixture:
//! the questions are those of trimesh's and FCL's collision managers
//! (which objects does this mesh touch, how far is the nearest, which two
//! objects are nearest each other), and two that no peer answers, for a
//! mesh *moving* against the whole collection over an interval: its
//! **first contact** (never late, as [`mesh_time_of_impact`]) and its
//! **certified clearance** (a bracket on the smallest distance to any
//! object, as [`closest_approach`]).
//!
//! ## Semantics
//! Surfaces, as in FCL's and trimesh's managers: a mesh touches an object
//! when their surfaces touch or cross (exactly: distance 0 by
//! [`mesh_distance`]); a mesh wholly inside another does not touch it.
//! Distances are the exact ones of [`mesh_distance`]; `point_a` is always
//! on the collection's object and `point_b` on the query mesh (or the
//! second object of a pair).
//!
//! ## The broad phase
//! Each object keeps its world box (the box of its mesh's own box turned
//! by its pose, widened by [`BOX_ROUNDING_ULPS`] of its reach), refreshed
//! when its pose is set. One mesh against the collection looks at each
//! box once (a few comparisons an object) and measures only the objects
//! that can matter: those whose box touches the query's (collisions), or
//! those in the order of their box's gap, until the gap passes the best
//! distance found (distances, first contacts and clearances: the query
//! narrows as it finds). Pairs within the collection come from a sort and
//! sweep along x ([`crate::broad_phase::sweep_pairs`]); the nearest pair
//! first measures the nearest boxes of that sweep's order and then only
//! the pairs whose boxes are closer than that.

use std::collections::HashMap;
use std::sync::Arc;

use crate::broad_phase::{box_gap, sweep_pairs, swept_box, SweptBox};
use crate::ccd::{
    box_margin, closest_approach, mesh_time_of_impact, ApproachStatus, CcdOptions, CcdStatus,
    ClosestApproach, ClosestApproachQuery, MeshCcdQuery, MeshCcdScratch, MovingMesh, WarmStart,
};
use crate::math::{MatrixPose, Placement, Pose, Real};
use crate::mesh::{mesh_distance, DistanceSearch, MeshDistance, MeshDistanceScratch, TriMesh};
use crate::motion::StepMotion;

/// An object's world box (and a query's) is widened by this many ulps of
/// its reach (the largest coordinate it spans): `1e3`, as the stepper's
/// swept boxes (`StepParameters::broad_phase_rounding_ulps`). The box is
/// computed from the pose's matrix, the distances from the relative pose
/// of the pair (their closest pair posed again by the poses as given, a
/// [`MatrixPose`]'s matrix as it is); the widening covers the difference of
/// their roundings and
/// the CCD's rounding floor (`ccd::ROUNDING_FLOOR_ULPS` of the largest
/// coordinate), so that no pair the CCD would count as touching is
/// dropped.
pub const BOX_ROUNDING_ULPS: Real = 1e3;

/// A named mesh at a pose.
#[derive(Clone, Debug)]
pub struct Object {
    name: String,
    mesh: Arc<TriMesh>,
    pose: Pose,
    /// The pose as given (a rotation matrix kept as it is): the distances
    /// pose their closest pair by it.
    placement: MatrixPose,
    world_box: SweptBox,
}

impl Object {
    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its mesh (vertices in its own frame).
    pub fn mesh(&self) -> &Arc<TriMesh> {
        &self.mesh
    }

    /// Its pose (its frame in the world).
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// Its pose as given (inserted with a [`MatrixPose`]: its matrix; with
    /// a [`Pose`]: its quaternion's matrix).
    pub fn placement(&self) -> &MatrixPose {
        &self.placement
    }

    /// Its world box (see the module).
    pub fn world_box(&self) -> &SweptBox {
        &self.world_box
    }
}

/// The box of `mesh` over `motion`'s interval `[0, duration]`, widened by
/// `margin` and by the rounding of the pose ([`BOX_ROUNDING_ULPS`]).
fn widened_box(mesh: &TriMesh, motion: &StepMotion, duration: Real, margin: Real) -> SweptBox {
    let reach =
        [0.0, duration].iter().map(|&s| motion.center_at(s).coords.amax()).fold(mesh.radius(), Real::max)
            + mesh.radius();
    swept_box(mesh, motion, duration, margin + BOX_ROUNDING_ULPS * Real::EPSILON * reach)
}

/// A name the collection does not hold.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the collection holds no object named {0:?}")]
pub struct UnknownObject(pub String);

/// An object a query mesh touches, or two objects that touch.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Touch<'c> {
    /// The object (the first of the two, for pairs within the collection).
    pub a: &'c str,
    /// The second object of a pair within the collection; `None` for a
    /// query mesh.
    pub b: Option<&'c str>,
    /// Where they touch: distance 0, `point_a` = `point_b` a common point
    /// (world frame), and the triangles that meet.
    pub found: MeshDistance,
}

/// The nearest object to a query mesh, or the nearest two objects.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Nearest<'c> {
    /// The object (the first of the two, for pairs within the collection).
    pub a: &'c str,
    /// The second object of a pair; `None` for a query mesh.
    pub b: Option<&'c str>,
    /// The exact distance and closest points (world frame): `point_a` on
    /// `a`, `point_b` on the query mesh or on `b`.
    pub found: MeshDistance,
}

/// How a first-contact query against a collection ended.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FirstContactStatus {
    /// No object comes within its contact distance over the interval
    /// (certified for every object).
    Clear,
    /// The mesh first touches `object` at `time` (never later than the
    /// true time; early by at most the pair's contact distance over the
    /// closing speed).
    Contact,
    /// The CCD of the pair with `object` ran out of iterations at `time`:
    /// no object is touched before `time`, nothing is known after it.
    Undecided,
}

/// The first contact of a moving mesh with a collection.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FirstContact<'c> {
    /// How the query ended.
    pub status: FirstContactStatus,
    /// The time of contact (or where the query could not decide); the
    /// interval's length when clear.
    pub time: Real,
    /// The object touched (or whose pair could not be decided).
    pub object: Option<&'c str>,
    /// The pair's CCD answer: its contact distance, triangles and points.
    pub contact: Option<crate::ccd::MeshCcdResult>,
    /// Objects whose boxes let them near the mesh's swept box (the pairs
    /// that ran a CCD).
    pub candidates: usize,
}

/// The certified clearance of a moving mesh from a collection: the
/// smallest distance `d*` to any object over the interval satisfies
/// `approach.lower ≤ d* ≤ approach.upper` (see [`ClosestApproach`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Clearance<'c> {
    /// The bracket, its time and closest points (`point_a` on the object),
    /// and how it ended: `Beyond` when nothing comes within the query's
    /// `within`, `Contact` when the mesh touches an object (its time the
    /// earliest first contact), `Undecided` or `OutOfIterations` when a
    /// pair that may hold the minimum could not be closed.
    pub approach: ClosestApproach,
    /// The object nearest at `approach.time`.
    pub object: Option<&'c str>,
    /// Objects whose boxes let them within `within` (or within the best
    /// distance found) of the mesh's swept box: the pairs bracketed.
    pub candidates: usize,
}

/// Named meshes with poses and a broad phase: see the module.
///
/// ```
/// use std::sync::Arc;
/// use nearmiss::collection::Collection;
/// use nearmiss::math::Pose;
/// use nearmiss::mesh::box_mesh;
/// use nearmiss::math::Vector;
///
/// let cube = Arc::new(box_mesh(&Vector::new(0.5, 0.5, 0.5)).unwrap());
/// let mut cell = Collection::new();
/// cell.insert("left", cube.clone(), Pose::translation(-3.0, 0.0, 0.0));
/// cell.insert("right", cube.clone(), Pose::translation(3.0, 0.0, 0.0));
/// // A cube at the origin: 2 from the faces of both; the first is named.
/// let nearest = cell.min_distance(&cube, &Pose::identity()).unwrap();
/// assert_eq!((nearest.a, nearest.found.distance), ("left", 2.0));
/// ```
#[derive(Clone, Debug, Default)]
pub struct Collection {
    objects: Vec<Object>,
    index: HashMap<String, usize>,
}

impl Collection {
    /// An empty collection.
    pub fn new() -> Collection {
        Collection::default()
    }

    /// Adds the object `name`, or replaces the one of that name (returned),
    /// at `pose`: a [`Pose`], or a [`MatrixPose`] whose matrix its
    /// distances apply as given.
    pub fn insert(
        &mut self,
        name: impl Into<String>,
        mesh: Arc<TriMesh>,
        pose: impl Placement,
    ) -> Option<Object> {
        let name = name.into();
        let (placement, pose) = (pose.matrix_pose(), pose.pose());
        let world_box = widened_box(&mesh, &StepMotion::fixed(pose), 0.0, 0.0);
        let object = Object { name: name.clone(), mesh, pose, placement, world_box };
        match self.index.get(&name) {
            Some(&i) => Some(std::mem::replace(&mut self.objects[i], object)),
            None => {
                self.index.insert(name, self.objects.len());
                self.objects.push(object);
                None
            }
        }
    }

    /// Removes the object `name` (the others keep their order).
    pub fn remove(&mut self, name: &str) -> Result<Object, UnknownObject> {
        let i = self.index.remove(name).ok_or_else(|| UnknownObject(name.to_owned()))?;
        let object = self.objects.remove(i);
        for later in &self.objects[i..] {
            *self.index.get_mut(&later.name).expect("every object is indexed") -= 1;
        }
        Ok(object)
    }

    /// Moves the object `name` to `pose`.
    pub fn set_pose(&mut self, name: &str, pose: impl Placement) -> Result<(), UnknownObject> {
        let i = *self.index.get(name).ok_or_else(|| UnknownObject(name.to_owned()))?;
        let object = &mut self.objects[i];
        let (placement, pose) = (pose.matrix_pose(), pose.pose());
        (object.pose, object.placement) = (pose, placement);
        object.world_box = widened_box(&object.mesh, &StepMotion::fixed(pose), 0.0, 0.0);
        Ok(())
    }

    /// The object `name`.
    pub fn get(&self, name: &str) -> Option<&Object> {
        self.index.get(name).map(|&i| &self.objects[i])
    }

    /// The objects, in the order they were first added.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// How many objects.
    pub fn len(&self) -> usize {
        self.objects.len()
    }

    /// Whether it holds no object.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }

    /// Every object `mesh` at `pose` touches (surfaces touching or
    /// crossing), in the collection's order.
    pub fn in_collision(&self, mesh: &TriMesh, pose: &impl Placement) -> Vec<Touch<'_>> {
        let placement = pose.matrix_pose();
        let query_box = widened_box(mesh, &StepMotion::fixed(pose.pose()), 0.0, 0.0);
        let mut scratch = MeshDistanceScratch::default();
        self.objects
            .iter()
            .filter(|object| box_gap(&object.world_box, &query_box) == 0.0)
            .filter_map(|object| {
                let found = touching(&object.mesh, &object.placement, mesh, &placement, &mut scratch)?;
                Some(Touch { a: &object.name, b: None, found })
            })
            .collect()
    }

    /// Every two objects that touch, each pair once (the earlier object
    /// first), in the collection's order.
    pub fn in_collision_internal(&self) -> Vec<Touch<'_>> {
        let boxes: Vec<SweptBox> = self.objects.iter().map(|o| o.world_box).collect();
        let mut scratch = MeshDistanceScratch::default();
        sweep_pairs(&boxes, 0.0)
            .into_iter()
            .filter_map(|(i, j)| {
                let (a, b) = (&self.objects[i], &self.objects[j]);
                let found = touching(&a.mesh, &a.placement, &b.mesh, &b.placement, &mut scratch)?;
                Some(Touch { a: &a.name, b: Some(&b.name), found })
            })
            .collect()
    }

    /// The nearest object to `mesh` at `pose` (the earliest in the
    /// collection's order among equally near ones; 0 where it touches one),
    /// or `None` for an empty collection.
    pub fn min_distance(&self, mesh: &TriMesh, pose: &impl Placement) -> Option<Nearest<'_>> {
        let placement = pose.matrix_pose();
        let query_box = widened_box(mesh, &StepMotion::fixed(pose.pose()), 0.0, 0.0);
        let search = DistanceSearch::default();
        let mut scratch = MeshDistanceScratch::default();
        let mut best: Option<(MeshDistance, usize)> = None;
        for (gap, i) in self.by_gap(&query_box, |_| Real::INFINITY) {
            if best.is_some_and(|(b, _)| gap > b.distance) {
                break;
            }
            let object = &self.objects[i];
            let found =
                mesh_distance(&object.mesh, &object.placement, mesh, &placement, &search, &mut scratch);
            if best.is_none_or(|(b, k)| (found.distance, i) < (b.distance, k)) {
                best = Some((found, i));
            }
        }
        best.map(|(found, i)| Nearest { a: &self.objects[i].name, b: None, found })
    }

    /// The nearest two objects (of `only` to the others, where given), or
    /// `None` with fewer than two.
    pub fn min_distance_internal(&self, only: Option<&str>) -> Result<Option<Nearest<'_>>, UnknownObject> {
        let only = match only {
            Some(name) => Some(*self.index.get(name).ok_or_else(|| UnknownObject(name.to_owned()))?),
            None => None,
        };
        let boxes: Vec<SweptBox> = self.objects.iter().map(|o| o.world_box).collect();
        let pair_gap = |&(i, j): &(usize, usize)| box_gap(&boxes[i], &boxes[j]);
        let search = DistanceSearch::default();
        let mut scratch = MeshDistanceScratch::default();
        let measure = |(i, j): (usize, usize), scratch: &mut MeshDistanceScratch| {
            let (a, b) = (&self.objects[i], &self.objects[j]);
            mesh_distance(&a.mesh, &a.placement, &b.mesh, &b.placement, &search, scratch)
        };
        // A first bound: the pair of the smallest box gap among neighbours
        // in x (or among `only`'s pairs).
        let first = match only {
            Some(k) => (0..self.objects.len())
                .filter(|&i| i != k)
                .map(|i| (i.min(k), i.max(k)))
                .min_by(|p, q| pair_gap(p).total_cmp(&pair_gap(q))),
            None => neighbours_in_x(&boxes).min_by(|p, q| pair_gap(p).total_cmp(&pair_gap(q))),
        };
        let Some(first) = first else { return Ok(None) };
        let bound = measure(first, &mut scratch).distance;
        // Every pair whose boxes are nearer than the bound, nearest first
        // (one object's: its pairs directly, not a sweep of all).
        let near = match only {
            Some(k) => (0..self.objects.len()).filter(|&i| i != k).map(|i| (i.min(k), i.max(k))).collect(),
            None => sweep_pairs(&boxes, bound),
        };
        let mut pairs: Vec<(Real, (usize, usize))> =
            near.into_iter().map(|p| (pair_gap(&p), p)).filter(|&(gap, _)| gap <= bound).collect();
        pairs.push((pair_gap(&first), first));
        pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        pairs.dedup_by_key(|p| p.1);
        let mut best: Option<(MeshDistance, (usize, usize))> = None;
        for (gap, pair) in pairs {
            if best.is_some_and(|(b, _)| gap > b.distance) {
                break;
            }
            let found = measure(pair, &mut scratch);
            if best.is_none_or(|(b, p)| (found.distance, pair) < (b.distance, p)) {
                best = Some((found, pair));
            }
        }
        Ok(best.map(|(found, (i, j))| Nearest {
            a: &self.objects[i].name,
            b: Some(&self.objects[j].name),
            found,
        }))
    }

    /// The first contact of `mesh` moving by `motion` over `[0, duration]`
    /// with any object (which stay at their poses): each pair's CCD under
    /// `options` (its contact distance relative to the pair's smaller
    /// radius), the objects taken in the order of their box's gap to the
    /// mesh's swept box, each over the interval up to the earliest contact
    /// found so far.
    pub fn first_contact(
        &self,
        mesh: &TriMesh,
        motion: &StepMotion,
        duration: Real,
        options: &CcdOptions,
    ) -> FirstContact<'_> {
        let swept = widened_box(mesh, motion, duration, box_margin(options, mesh.radius()));
        let order = self.by_gap(&swept, |o| box_margin(options, o.mesh.radius()));
        let mut answer = FirstContact {
            status: FirstContactStatus::Clear,
            time: duration,
            object: None,
            contact: None,
            candidates: order.len(),
        };
        let mut scratch = MeshCcdScratch::default();
        for (_, i) in order {
            let object = &self.objects[i];
            let fixed = StepMotion::fixed(object.pose);
            let query = MeshCcdQuery::new(
                MovingMesh { mesh: &object.mesh, motion: &fixed },
                MovingMesh { mesh, motion },
                answer.time,
                *options,
            );
            let found = mesh_time_of_impact(&query, WarmStart::default(), &mut scratch);
            let Some(time) = found.time_of_impact else { continue };
            // An earlier time wins; at the same time a contact beats an
            // undecided pair (known to be clear up to it).
            let status = match found.status {
                CcdStatus::OutOfIterations => FirstContactStatus::Undecided,
                _ => FirstContactStatus::Contact,
            };
            let decided_tie =
                time == answer.time && status == FirstContactStatus::Contact && answer.status != status;
            if time < answer.time || decided_tie || answer.status == FirstContactStatus::Clear {
                answer.status = status;
                answer.time = time;
                answer.object = Some(&object.name);
                answer.contact = Some(found);
            }
        }
        answer
    }

    /// The certified clearance of `mesh` moving by `motion` over `[0,
    /// duration]` from the collection: only approaches within `within`
    /// are bracketed (`Real::INFINITY`: the nearest object, however far;
    /// a negative or NaN `within` is 0),
    /// each pair to the bracket width `tolerance` (`None`: the closest
    /// approach's default, relative to the pair's smaller radius) with
    /// `options`' iteration budget. The objects are taken in the order of
    /// their box's gap to the mesh's swept box, each asked only for what
    /// would beat the best distance found so far.
    pub fn clearance(
        &self,
        mesh: &TriMesh,
        motion: &StepMotion,
        duration: Real,
        within: Real,
        tolerance: Option<Real>,
        options: &CcdOptions,
    ) -> Clearance<'_> {
        // A distance, at least 0 (a NaN asks for nothing but touching).
        let within = if within.is_nan() { 0.0 } else { within.max(0.0) };
        let swept = widened_box(mesh, motion, duration, 0.0);
        let mut answer = Clearance {
            approach: ClosestApproach {
                status: ApproachStatus::Beyond,
                lower: within,
                upper: Real::INFINITY,
                time: 0.0,
                closest: None,
                runs: 0,
            },
            object: None,
            candidates: 0,
        };
        // The least lower bound of the pairs bracketed, and of those that
        // could not close their bracket (each may hold the minimum below
        // the best upper bound). A pair found beyond the best upper bound,
        // or whose box is farther, never holds it.
        let (mut least_closed, mut least_open): (Real, Option<ClosestApproach>) = (Real::INFINITY, None);
        let mut scratch = MeshCcdScratch::default();
        for (gap, i) in self.by_gap(&swept, |_| within) {
            let reach = answer.approach.upper.min(within);
            if gap > reach {
                break;
            }
            answer.candidates += 1;
            let object = &self.objects[i];
            let fixed = StepMotion::fixed(object.pose);
            let mut query = ClosestApproachQuery::new(
                MovingMesh { mesh: &object.mesh, motion: &fixed },
                MovingMesh { mesh, motion },
                duration,
            );
            (query.within, query.tolerance, query.options) = (reach, tolerance, *options);
            let found = closest_approach(&query, &mut scratch);
            answer.approach.runs += found.runs;
            match found.status {
                ApproachStatus::Beyond => continue,
                ApproachStatus::Undecided | ApproachStatus::OutOfIterations => {
                    if least_open.is_none_or(|o| found.lower < o.lower) {
                        least_open = Some(found);
                    }
                }
                _ => least_closed = least_closed.min(found.lower),
            }
            let best = &answer.approach;
            let earlier_contact = found.status == ApproachStatus::Contact
                && (best.status != ApproachStatus::Contact || found.time < best.time);
            let closer = best.status != ApproachStatus::Contact && found.upper < best.upper;
            if earlier_contact || closer {
                answer.approach = ClosestApproach { runs: best.runs, ..found };
                answer.object = Some(&object.name);
            }
        }
        let approach = &mut answer.approach;
        if approach.status == ApproachStatus::Contact {
            approach.lower = 0.0;
        } else if approach.closest.is_some() {
            (approach.status, approach.lower) = (ApproachStatus::Bracketed, least_closed.min(approach.upper));
            if let Some(open) = least_open.filter(|o| o.lower < approach.lower) {
                (approach.status, approach.lower) = (open.status, open.lower);
            }
        }
        answer
    }

    /// The objects whose box's gap to `swept` is at most `limit` of
    /// theirs, nearest first (ties in the collection's order).
    fn by_gap(&self, swept: &SweptBox, limit: impl Fn(&Object) -> Real) -> Vec<(Real, usize)> {
        let mut order: Vec<(Real, usize)> = self
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| (box_gap(&o.world_box, swept), i))
            .filter(|&(gap, i)| gap <= limit(&self.objects[i]))
            .collect();
        order.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        order
    }
}

/// Where `b` at `pose_b` touches `a` at `pose_a`, if it does: the search
/// stops at the first pair at distance 0.
fn touching(
    a: &TriMesh,
    pose_a: &MatrixPose,
    b: &TriMesh,
    pose_b: &MatrixPose,
    scratch: &mut MeshDistanceScratch,
) -> Option<MeshDistance> {
    let search = DistanceSearch { enough: 0.0, ..DistanceSearch::default() };
    Some(mesh_distance(a, pose_a, b, pose_b, &search, scratch)).filter(|found| found.distance == 0.0)
}

/// The pairs of boxes next to each other in the order of their low x.
fn neighbours_in_x(boxes: &[SweptBox]) -> impl Iterator<Item = (usize, usize)> {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&i, &j| boxes[i].0.x.total_cmp(&boxes[j].0.x).then(i.cmp(&j)));
    (1..order.len()).map(move |k| (order[k - 1].min(order[k]), order[k - 1].max(order[k])))
}
