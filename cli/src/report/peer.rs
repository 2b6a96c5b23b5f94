//! The peer in the product: each first contact of a run computed again with
//! parry (`cast_shapes_nonlinear` for rotating bodies, `cast_shapes` for
//! translating ones), side by side with nearmiss's (`nearmiss run --compare
//! parry`).
//!
//! Compared pairs: every pair of a two-body scene, and otherwise every pair
//! nearmiss found in contact. Both bodies must move freely (constant
//! velocities) or be fixed: parry's casts follow constant velocities, so a
//! body under forces, integrated step by step, has no parry counterpart
//! (reported as such).

use std::time::Instant;

use nearmiss::math::{motion_to_parry, pose_to_parry, vector_to_parry, Real};
use nearmiss::run::RunResult;
use nearmiss::scene::{BodyMotion, Scene};

pub use nearmiss_summary::PeerComparison;

/// The comparison as a Markdown table.
pub fn peer_markdown(peer: &[PeerComparison]) -> String {
    let time = |t: Option<Real>| t.map_or("no contact".to_string(), crate::text::time);
    let mut out =
        String::from("| pair | nearmiss | parry | parry query | parry's time |\n|---|---|---|---|---|\n");
    for p in peer {
        out.push_str(&format!(
            "| {} / {} | {} | {} | {} | {} |\n",
            p.body_a,
            p.body_b,
            time(p.nearmiss),
            time(p.parry),
            p.parry_query,
            crate::text::wall(p.parry_wall_time_s)
        ));
    }
    out
}

/// Compares the run's contacts with parry's answers.
pub fn compare_with_parry(scene: &Scene, result: &RunResult) -> Vec<PeerComparison> {
    let mut pairs: Vec<(usize, usize)> = if scene.model().bodies.len() == 2 {
        scene.model().movable_pairs()
    } else {
        result.contacts.iter().map(|c| (c.body_a, c.body_b)).collect()
    };
    pairs.sort_unstable();
    pairs.dedup();
    let horizon = result.end_time.max(scene.run().duration);
    pairs
        .into_iter()
        .map(|(a, b)| {
            let nearmiss = result
                .contacts
                .iter()
                .filter(|c| (c.body_a, c.body_b) == (a, b))
                .map(|c| c.time)
                .reduce(Real::min);
            let (body_a, body_b) = (&scene.model().bodies[a], &scene.model().bodies[b]);
            let mut row = PeerComparison {
                body_a: body_a.name.clone(),
                body_b: body_b.name.clone(),
                nearmiss,
                parry: None,
                parry_query: String::new(),
                parry_wall_time_s: 0.0,
            };
            let integrated = |m: &BodyMotion| matches!(m, BodyMotion::Integrated { .. });
            if integrated(&body_a.motion) || integrated(&body_b.motion) {
                row.parry_query =
                    "none: a body is integrated under forces; parry's casts follow constant velocities"
                        .into();
                return row;
            }
            let (Some(shape_a), Some(shape_b)) = (body_a.mesh.to_parry(), body_b.mesh.to_parry()) else {
                row.parry_query = "none: parry refused a mesh".into();
                return row;
            };
            let velocity = |m: &nearmiss::scene::Body| {
                if m.motion == BodyMotion::Fixed {
                    Default::default()
                } else {
                    m.velocity
                }
            };
            let spin = |m: &nearmiss::scene::Body| {
                if m.motion == BodyMotion::Fixed {
                    Default::default()
                } else {
                    m.angular_velocity
                }
            };
            let start = Instant::now();
            let rotating = spin(body_a).norm() > 0.0 || spin(body_b).norm() > 0.0;
            let hit = if rotating {
                row.parry_query = "cast_shapes_nonlinear".into();
                let motion =
                    |body: &nearmiss::scene::Body| motion_to_parry(&body.pose, &velocity(body), &spin(body));
                parry3d_f64::query::cast_shapes_nonlinear(
                    &motion(body_a),
                    &shape_a,
                    &motion(body_b),
                    &shape_b,
                    0.0,
                    horizon,
                    true,
                )
            } else {
                row.parry_query = "cast_shapes".into();
                parry3d_f64::query::cast_shapes(
                    &pose_to_parry(&body_a.pose),
                    vector_to_parry(&velocity(body_a)),
                    &shape_a,
                    &pose_to_parry(&body_b.pose),
                    vector_to_parry(&velocity(body_b)),
                    &shape_b,
                    parry3d_f64::query::ShapeCastOptions::with_max_time_of_impact(horizon),
                )
            };
            row.parry_wall_time_s = start.elapsed().as_secs_f64();
            match hit {
                Ok(hit) => row.parry = hit.map(|h| h.time_of_impact),
                Err(_) => row.parry_query.push_str(": unsupported by parry"),
            }
            row
        })
        .collect()
}
