//! The contact contract, in one place: how a query's options and size turn
//! into the distance at which contact is declared and the level that
//! conservative advancement aims at.
//!
//! Every CCD query in nearmiss (the linear-vertex VF/EE queries, rigid mesh
//! pairs) and every stage that must agree with it (the broad phase's box
//! margin, the `Bounce` response's re-detection distance) calls this file.
//!
//! - The **tolerance** is `distance_tolerance × S` for a query of size `S`
//!   ([`ContactRule::ScaleRelative`]), or an absolute distance
//!   ([`ContactRule::Absolute`]); either is floored by the rounding of the
//!   coordinates in play (the caller states that floor).
//! - The **contact distance** is `minimum_separation + tolerance`: a query
//!   reports contact once the primitives come this close.
//! - The **target** is `minimum_separation + TARGET_FRACTION × tolerance`:
//!   each advancement step is proven to keep the distance above it, so the
//!   margin `(1 − TARGET_FRACTION) × tolerance` absorbs rounding.

use super::options::CcdOptions;
use crate::math::Real;

/// The fraction of the tolerance above `minimum_separation` that
/// conservative advancement aims at. `0.5`: the other half is the margin
/// that keeps each floating-point step on the safe side.
pub const TARGET_FRACTION: Real = 0.5;

/// Each body's swept box grows by `minimum_separation +
/// BOX_MARGIN_TOLERANCE_FACTOR × distance_tolerance × r` (`r` its radius), so
/// that two boxes together cover any pair's contact distance
/// `minimum_separation + distance_tolerance × min(r_a, r_b)` (and its
/// rounding floor) with room to spare. `2.0`.
pub(crate) const BOX_MARGIN_TOLERANCE_FACTOR: Real = 2.0;

/// How a query's contact distance is chosen.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub enum ContactRule {
    /// `minimum_separation + distance_tolerance × S`, `S` the query's size
    /// (the options' own rule). The default.
    #[default]
    ScaleRelative,
    /// Contact within this absolute distance (the options'
    /// `minimum_separation` and `distance_tolerance` are not used).
    Absolute(Real),
    /// The options' rule with this minimum separation in place of theirs:
    /// `separation + distance_tolerance × S` (the guard's contact skin,
    /// `crate::guard`).
    Separation(Real),
}

/// The distances of one query's contract.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ContactContract {
    /// The tolerance above `minimum_separation` (after the rounding floor).
    pub tolerance: Real,
    /// Contact is declared at this distance or closer.
    pub contact_distance: Real,
    /// Every advancement step keeps the distance above this.
    pub target: Real,
}

impl ContactContract {
    /// The contract of a gap `minimum_separation` plus `tolerance`.
    #[inline]
    pub fn new(minimum_separation: Real, tolerance: Real) -> ContactContract {
        ContactContract {
            tolerance,
            contact_distance: minimum_separation + tolerance,
            target: minimum_separation + TARGET_FRACTION * tolerance,
        }
    }

    /// The contract of a query of size `size` under `options` and `rule`,
    /// with the tolerance never below `rounding_floor` (an absolute
    /// distance: the rounding of the coordinates the query computes with).
    #[inline]
    pub fn of(options: &CcdOptions, rule: ContactRule, size: Real, rounding_floor: Real) -> ContactContract {
        match rule {
            ContactRule::ScaleRelative => ContactContract::new(
                options.minimum_separation,
                (options.distance_tolerance * size).max(rounding_floor),
            ),
            ContactRule::Absolute(distance) => ContactContract::new(0.0, distance.max(rounding_floor)),
            ContactRule::Separation(separation) => {
                ContactContract::new(separation, (options.distance_tolerance * size).max(rounding_floor))
            }
        }
    }
}

/// How far a body's swept box must grow (before rounding) so that the
/// broad phase never drops a pair the CCD would report under `options`'
/// scale-relative rule: see `BOX_MARGIN_TOLERANCE_FACTOR`.
#[inline]
pub fn box_margin(options: &CcdOptions, radius: Real) -> Real {
    options.minimum_separation + BOX_MARGIN_TOLERANCE_FACTOR * options.distance_tolerance * radius
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_box_margins_cover_the_contact_distance() {
        let options =
            CcdOptions { distance_tolerance: 1e-3, minimum_separation: 0.01, ..CcdOptions::default() };
        for (ra, rb) in [(1.0, 1.0), (0.001, 1e4), (3.0, 0.5)] {
            let contract = ContactContract::of(&options, ContactRule::ScaleRelative, ra + rb, 0.0);
            assert!(box_margin(&options, ra) + box_margin(&options, rb) >= contract.contact_distance);
        }
    }

    #[test]
    fn target_lies_between_separation_and_contact() {
        let options =
            CcdOptions { distance_tolerance: 1e-6, minimum_separation: 0.5, ..CcdOptions::default() };
        let c = ContactContract::of(&options, ContactRule::ScaleRelative, 2.0, 0.0);
        assert_eq!(c.tolerance, 2e-6);
        assert!(0.5 < c.target && c.target < c.contact_distance);
        // The rounding floor wins when it is larger.
        let floored = ContactContract::of(&options, ContactRule::ScaleRelative, 2.0, 1e-3);
        assert_eq!(floored.tolerance, 1e-3);
        // An absolute rule ignores the options' separation and tolerance.
        let absolute = ContactContract::of(&options, ContactRule::Absolute(1e-4), 2.0, 0.0);
        assert_eq!((absolute.contact_distance, absolute.target), (1e-4, 0.5e-4));
    }
}
