//! Work split over machines: `--shard I/N` picks a deterministic share of a
//! command's work (the items whose position `k`, 0-based, in the full
//! ordered list has `k mod N = I − 1`), each shard writes its own results
//! with the positions of its items, and `nearmiss merge` puts the shards'
//! results back in order: what one machine would have written.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::{FileReport, SuiteCase, SweepShard};

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

/// What a shard writes (`--json` with `--shard`), for `nearmiss merge`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShardFile {
    /// A shard of `nearmiss test`.
    Suite(SuiteShard),
    /// A shard of `nearmiss queries`.
    Queries(QueriesShard),
    /// A shard of `nearmiss sweep`.
    Sweep(SweepShard),
}

impl ShardFile {
    /// As JSON.
    pub fn to_json(&self) -> String {
        // Strings and finite numbers: serialising cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}

/// A shard of `nearmiss queries`: its files' reports, each with its
/// position in the whole list of files.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QueriesShard {
    /// Which shard.
    pub shard: Shard,
    /// The whole run's number of files.
    pub total: usize,
    /// This shard's files (path as given, report) with their positions.
    pub files: Vec<(usize, (String, FileReport))>,
}

/// A shard of `nearmiss test`: its cases, each with its position in the
/// whole suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuiteShard {
    /// Which shard.
    pub shard: Shard,
    /// The whole suite's number of cases.
    pub total: usize,
    /// This shard's cases with their positions, in order.
    pub cases: Vec<(usize, SuiteCase)>,
}

/// Puts the shards of one suite back together: every case in its place,
/// checked (see `merge_positions`). The merged cases give the same
/// `suite_json` and `junit_xml` as one machine's run, apart from wall times.
pub fn merge_suite(shards: &[SuiteShard]) -> Result<Vec<SuiteCase>, String> {
    let parts: Vec<_> = shards.iter().map(|s| (s.shard, s.total, s.cases.as_slice())).collect();
    merge_positions(&parts)
}

/// Puts the shards of one `queries` run back together (see
/// `merge_positions`): each file's path and report, in order.
pub fn merge_queries(shards: &[QueriesShard]) -> Result<Vec<(String, FileReport)>, String> {
    let parts: Vec<_> = shards.iter().map(|s| (s.shard, s.total, s.files.as_slice())).collect();
    merge_positions(&parts)
}

/// One shard's part of a run: the shard, the run's number of items, and
/// the shard's items with their positions.
pub(crate) type ShardPart<'a, T> = (Shard, usize, &'a [(usize, T)]);

/// The items of the shards `(shard, total, items with positions)` in one
/// list, checked: one shard each of the same count, the same total, every
/// position once and in its shard.
pub(crate) fn merge_positions<T: Clone>(shards: &[ShardPart<'_, T>]) -> Result<Vec<T>, String> {
    let &(first, total, _) = shards.first().ok_or("no shard given")?;
    let count = first.count;
    let mut seen = vec![false; count];
    let mut items: Vec<Option<T>> = vec![None; total];
    for &(shard, part_total, part) in shards {
        if shard.count != count || part_total != total {
            return Err(format!(
                "shard {shard} of {part_total} items does not belong with shard {first} of {total} items"
            ));
        }
        if std::mem::replace(&mut seen[shard.index - 1], true) {
            return Err(format!("shard {shard} given twice"));
        }
        for (position, item) in part {
            if *position >= total || !shard.picks(*position) {
                return Err(format!("shard {shard} holds item {position}, which is not its"));
            }
            items[*position] = Some(item.clone());
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(format!("shard {}/{count} is missing", missing + 1));
    }
    items
        .into_iter()
        .enumerate()
        .map(|(k, item)| item.ok_or_else(|| format!("item {k} is in no shard")))
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
