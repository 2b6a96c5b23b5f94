//! Which pairs rapier solves (its solid colliders' rules and the
//! application's contact hooks), read by the guard's sweep.

use super::ContactHooks;
use std::sync::RwLock;

/// Which pairs of guarded bodies (indices in the guard's list) rapier
/// solves: their colliders' collision and solver groups, sensors, disabled
/// colliders and the bodies' types, as rapier's narrow phase decides; and
/// where a body's colliders have contact hooks, the application's filter
/// as last asked (a body whose hooks modify contacts is never guarded).
pub(crate) struct PairRules {
    rules: Box<dyn Fn(usize, usize) -> bool + Send + Sync>,
    hooks: Vec<ContactHooks>,
    /// Pairs joined with contacts disabled, sorted.
    jointed: RwLock<Vec<(usize, usize)>>,
    /// The hooked pairs the application's filter refused at the step's
    /// start, sorted.
    refused: RwLock<Vec<(usize, usize)>>,
}

impl PairRules {
    /// The rules `rules` of pairs, and each body's hooks.
    pub fn new(
        rules: Box<dyn Fn(usize, usize) -> bool + Send + Sync>,
        hooks: Vec<ContactHooks>,
    ) -> PairRules {
        PairRules { rules, hooks, jointed: RwLock::new(Vec::new()), refused: RwLock::new(Vec::new()) }
    }

    /// Every pair (a scene's bodies under `Simulate`: no groups, sensors or
    /// hooks; a pair with no dynamic body is swept for its contacts and
    /// never acted on).
    pub fn all(bodies: usize) -> PairRules {
        PairRules::new(Box::new(|_, _| true), vec![ContactHooks::None; bodies])
    }

    /// Whether rapier solves the pair `(a, b)` (`a < b`).
    pub fn solves(&self, a: usize, b: usize) -> bool {
        if !(self.rules)(a, b) || read(&self.jointed).binary_search(&(a, b)).is_ok() {
            return false;
        }
        match self.hooks[a].max(self.hooks[b]) {
            ContactHooks::None => true,
            ContactHooks::Modify => false,
            ContactHooks::Filter => read(&self.refused).binary_search(&(a, b)).is_err(),
        }
    }

    /// Takes `jointed` (pairs `(a, b)`, `a < b`) as the pairs joined with
    /// contacts disabled.
    pub fn set_jointed(&self, mut jointed: Vec<(usize, usize)>) {
        jointed.sort_unstable();
        jointed.dedup();
        *self.jointed.write().unwrap_or_else(|poisoned| poisoned.into_inner()) = jointed;
    }

    /// Whether some body's colliders filter their contact pairs.
    pub fn has_filters(&self) -> bool {
        self.hooks.contains(&ContactHooks::Filter)
    }

    /// The pairs with a filtering body that rapier's rules solve but
    /// `keeps` refuses, sorted.
    pub fn filtered_pairs(&self, mut keeps: impl FnMut(usize, usize) -> bool) -> Vec<(usize, usize)> {
        let mut refused = Vec::new();
        for (h, _) in self.hooks.iter().enumerate().filter(|(_, hooks)| **hooks == ContactHooks::Filter) {
            for other in (0..self.hooks.len()).filter(|&o| o != h) {
                let (a, b) = (h.min(other), h.max(other));
                if (self.rules)(a, b) && !keeps(a, b) {
                    refused.push((a, b));
                }
            }
        }
        refused.sort_unstable();
        refused.dedup();
        refused
    }

    /// Takes `refused` as the filter's answer until the next.
    pub fn refuse(&self, refused: Vec<(usize, usize)>) {
        *self.refused.write().unwrap_or_else(|poisoned| poisoned.into_inner()) = refused;
    }
}

/// A list behind a lock, read (a poisoned lock still holds the list: its
/// writers replace it whole).
pub(crate) fn read(
    list: &RwLock<Vec<(usize, usize)>>,
) -> std::sync::RwLockReadGuard<'_, Vec<(usize, usize)>> {
    list.read().unwrap_or_else(|poisoned| poisoned.into_inner())
}
