//! Work split over machines: `--shard I/N` picks a deterministic share of a
//! command's work (the items whose position `k`, 0-based, in the full
//! ordered list has `k mod N = I − 1`), each shard writes its own results
//! with the positions of its items, and `nearmiss merge` puts the shards'
//! results back in order: what one machine would have written.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::SuiteCase;

/// One share of the work: the `index`-th (1-based) of `count`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which share, from 1 to `count`.
    pub index: usize,
    /// How many shares.
    pub count: usize,
}

impl Shard {
    /// Whether the item at `position` (0-based, in the full list) is this
    /// shard's.
    pub fn picks(&self, position: usize) -> bool {
        position % self.count == self.index - 1
    }

    /// This shard's items of `items`, with their positions in the full list.
    pub fn select<T>(&self, items: Vec<T>) -> Vec<(usize, T)> {
        items.into_iter().enumerate().filter(|(k, _)| self.picks(*k)).collect()
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(text: &str) -> Result<Shard, String> {
        let wrong = || format!("`{text}`: give the shard as I/N, with 1 ≤ I ≤ N (e.g. 2/8)");
        let (index, count) = text.split_once('/').ok_or_else(wrong)?;
        let (index, count): (usize, usize) =
            (index.trim().parse().map_err(|_| wrong())?, count.trim().parse().map_err(|_| wrong())?);
        if count == 0 || index == 0 || index > count {
            return Err(wrong());
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What a shard of `nearmiss test` writes (`--json` with `--shard`): its
/// cases, each with its position in the whole suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuiteShard {
    /// Which shard.
    pub shard: Shard,
    /// The whole suite's number of cases.
    pub total: usize,
    /// This shard's cases with their positions, in order.
    pub cases: Vec<(usize, SuiteCase)>,
}

impl SuiteShard {
    /// As JSON.
    pub fn to_json(&self) -> String {
        // Strings and finite numbers: serialising cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}

/// Puts the shards of one suite back together: every case in its place,
/// checked (one shard each of the same count, the same total, every
/// position once). The merged cases give the same `suite_json` and
/// `junit_xml` as one machine's run, apart from wall times.
pub fn merge_suite(shards: &[SuiteShard]) -> Result<Vec<SuiteCase>, String> {
    let first = shards.first().ok_or("no shard given")?;
    let (count, total) = (first.shard.count, first.total);
    let mut seen = vec![false; count];
    let mut cases: Vec<Option<SuiteCase>> = vec![None; total];
    for part in shards {
        if part.shard.count != count || part.total != total {
            return Err(format!(
                "shard {} of a suite of {} cases does not belong with shard {} of {} cases",
                part.shard, part.total, first.shard, total
            ));
        }
        if std::mem::replace(&mut seen[part.shard.index - 1], true) {
            return Err(format!("shard {} given twice", part.shard));
        }
        for (position, case) in &part.cases {
            if *position >= total || !part.shard.picks(*position) {
                return Err(format!("shard {} holds case {position}, which is not its", part.shard));
            }
            cases[*position] = Some(case.clone());
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(format!("shard {}/{count} is missing", missing + 1));
    }
    cases
        .into_iter()
        .enumerate()
        .map(|(k, case)| case.ok_or_else(|| format!("case {k} is in no shard")))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_split_the_work_once() {
        assert_eq!("2/8".parse::<Shard>(), Ok(Shard { index: 2, count: 8 }));
        for bad in ["0/3", "4/3", "1/0", "2", "a/b", "1/2/3"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        let shards: Vec<Shard> = (1..=3).map(|index| Shard { index, count: 3 }).collect();
        for k in 0..10 {
            assert_eq!(shards.iter().filter(|s| s.picks(k)).count(), 1);
        }
    }
}
