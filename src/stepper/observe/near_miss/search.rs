//! The order in which a pair's held steps are bracketed: the nearest end
//! by a golden-section search, then outwards.

use super::MAX_HELD_STEPS;
use crate::math::Real;

/// The index in `0..n` (`n` at most [`MAX_HELD_STEPS`]) where `f` is
/// least, by a golden-section search over the indices (for `f` falling and
/// then rising; otherwise some local minimum): `f` is called about
/// `1.44 log2(n) + 3` times, once per index.
pub(super) fn nearest_index(n: usize, f: &mut impl FnMut(usize) -> Real) -> usize {
    let mut known = [Real::NAN; MAX_HELD_STEPS];
    let mut at = |k: usize| {
        if known[k].is_nan() {
            known[k] = f(k);
        }
        known[k]
    };
    let (mut lo, mut hi) = (0usize, n.saturating_sub(1));
    let inner = |lo: usize, hi: usize| {
        let long = (((hi - lo) as Real * 0.381_966_011_250_105_1).round() as usize).max(1);
        let left = lo + long;
        (left, (hi - long).max(left + 1))
    };
    while hi - lo > 3 {
        let (left, right) = inner(lo, hi);
        if at(left) <= at(right) {
            hi = right;
        } else {
            lo = left;
        }
    }
    (lo..=hi).min_by(|&x, &y| at(x).total_cmp(&at(y))).unwrap_or(lo)
}

/// `0..n` from `start` outwards: `start`, `start + 1`, `start − 1`,
/// `start + 2`, ... (the step after the nearest end first: the minimum may
/// be just past it).
pub(super) fn outwards(start: usize, n: usize) -> impl Iterator<Item = usize> {
    (0..2 * n).filter_map(move |i| {
        let offset = i.div_ceil(2);
        let k = if i % 2 == 1 { start.checked_add(offset) } else { start.checked_sub(offset) };
        k.filter(|&k| k < n)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_of_a_falling_then_rising_sequence_is_found_with_few_calls() {
        for n in 1..=MAX_HELD_STEPS {
            for least in 0..n {
                let mut calls = 0;
                let mut f = |k: usize| {
                    calls += 1;
                    (k as Real - least as Real).abs()
                };
                assert_eq!(nearest_index(n, &mut f), least, "n {n}");
                assert!(calls <= n.min(14), "n {n}: {calls} calls");
            }
        }
    }

    #[test]
    fn outwards_visits_every_index_once_from_the_start() {
        for n in 1..10 {
            for start in 0..n {
                let order: Vec<usize> = outwards(start, n).collect();
                assert_eq!(order[0], start);
                let mut sorted = order.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>());
                if start + 1 < n {
                    assert_eq!(order[1], start + 1);
                }
            }
        }
    }
}
