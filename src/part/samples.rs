//! [`SampleSet`]: which sample indices of every pixel a render or a part holds, as sorted,
//! disjoint half-open ranges (`0..64,128..192`).
//!
//! A camera sample is a function of (seed, pixel, sample index) alone, and so is light-tracer
//! pass `i` (its light paths are numbers `i·L .. (i+1)·L` for `L` paths per pass), so any set of
//! indices can be rendered on its own and added to any disjoint set.

use std::fmt;
use std::ops::Range;

/// Sorted, disjoint, non-adjacent, non-empty ranges of sample indices.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SampleSet {
    ranges: Vec<Range<u32>>,
}

impl SampleSet {
    /// The indices `range` (empty when `range` is).
    pub fn range(range: Range<u32>) -> Self {
        let mut set = Self::default();
        set.insert(range);
        set
    }

    /// Parses `A..B` or a comma-separated list of them (A < B); the error says what is wrong.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut set = Self::default();
        for item in text.split(',') {
            let parsed = item
                .trim()
                .split_once("..")
                .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)));
            let Some((start, end)) = parsed else {
                return Err(format!("\"{item}\" is not a sample range A..B (e.g. 0..64)"));
            };
            if start >= end {
                return Err(format!("the sample range {start}..{end} is empty: A..B needs A < B"));
            }
            if set.overlaps(&Self::range(start..end)) {
                return Err(format!("the sample range {start}..{end} overlaps another in \"{text}\""));
            }
            set.insert(start..end);
        }
        Ok(set)
    }

    /// Adds the indices of `range`, merging it with the ranges it touches.
    fn insert(&mut self, range: Range<u32>) {
        if range.is_empty() {
            return;
        }
        self.ranges.push(range);
        self.ranges.sort_by_key(|r| r.start);
        let mut merged: Vec<Range<u32>> = Vec::with_capacity(self.ranges.len());
        for r in self.ranges.drain(..) {
            match merged.last_mut() {
                Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
                _ => merged.push(r),
            }
        }
        self.ranges = merged;
    }

    /// The ranges, in increasing order.
    pub fn ranges(&self) -> &[Range<u32>] {
        &self.ranges
    }

    /// Number of indices held.
    pub fn len(&self) -> u64 {
        self.ranges.iter().map(|r| u64::from(r.end - r.start)).sum()
    }

    /// True when no index is held.
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// One past the largest index held (0 when empty).
    pub fn end(&self) -> u32 {
        self.ranges.last().map_or(0, |r| r.end)
    }

    /// True when some index is in both sets.
    pub fn overlaps(&self, other: &Self) -> bool {
        self.ranges.iter().any(|a| other.ranges.iter().any(|b| a.start < b.end && b.start < a.end))
    }

    /// Every index in either set.
    pub fn union(&self, other: &Self) -> Self {
        let mut set = self.clone();
        for r in &other.ranges {
            set.insert(r.clone());
        }
        set
    }

    /// The indices of `0..total` not in this set.
    pub fn missing_below(&self, total: u32) -> Self {
        let mut set = Self::default();
        let mut next = 0;
        for r in &self.ranges {
            set.insert(next.min(total)..r.start.min(total));
            next = r.end;
        }
        set.insert(next.min(total)..total);
        set
    }

    /// The first `count` indices, in increasing order.
    pub fn first(&self, count: u64) -> Self {
        let mut left = count;
        let mut set = Self::default();
        for r in &self.ranges {
            let take = left.min(u64::from(r.end - r.start)) as u32;
            set.insert(r.start..r.start + take);
            left -= u64::from(take);
        }
        set
    }
}

impl fmt::Display for SampleSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.ranges.is_empty() {
            return write!(f, "none");
        }
        let items: Vec<String> = self.ranges.iter().map(|r| format!("{}..{}", r.start, r.end)).collect();
        write!(f, "{}", items.join(","))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_prints_and_combines() {
        let set = SampleSet::parse("64..128, 0..32").expect("valid");
        assert_eq!(set.to_string(), "0..32,64..128");
        assert_eq!(set.len(), 96);
        assert_eq!(set.missing_below(160).to_string(), "32..64,128..160");
        assert_eq!(set.union(&SampleSet::range(32..64)).to_string(), "0..128");
        assert_eq!(set.first(40).to_string(), "0..32,64..72");
        assert!(set.overlaps(&SampleSet::range(100..200)));
        assert!(!set.overlaps(&SampleSet::range(32..64)));
        for bad in ["", "5", "3..3", "4..2", "0..8,4..12", "a..b"] {
            assert!(SampleSet::parse(bad).is_err(), "{bad}");
        }
    }
}
