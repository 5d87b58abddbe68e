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
    /// Linear in the text's length but for one sort of the ranges (a part's header is input:
    /// a file with 100,000 ranges must not take quadratic time).
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut ranges = Vec::new();
        for item in text.split(',') {
            let parsed = item
                .trim()
                .split_once("..")
                .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)));
            let Some((start, end)) = parsed else {
                return Err(format!(
                    "\"{}\" is not a sample range A..B (e.g. 0..64)",
                    crate::printable::quote(item)
                ));
            };
            if start >= end {
                return Err(format!("the sample range {start}..{end} is empty: A..B needs A < B"));
            }
            ranges.push(start..end);
        }
        ranges.sort_unstable_by_key(|r| r.start);
        let mut merged: Vec<Range<u32>> = Vec::with_capacity(ranges.len());
        for r in ranges {
            match merged.last_mut() {
                Some(last) if r.start < last.end => {
                    return Err(format!(
                        "the sample range {}..{} overlaps {}..{}",
                        r.start, r.end, last.start, last.end
                    ));
                }
                Some(last) if r.start == last.end => last.end = r.end,
                _ => merged.push(r),
            }
        }
        Ok(Self { ranges: merged })
    }

    /// Adds the indices of `range`, merging it with the ranges it touches.
    fn insert(&mut self, range: Range<u32>) {
        if range.is_empty() {
            return;
        }
        // In increasing order (as every caller but `range` inserts): extend or append, in
        // constant time, so that building a set range by range stays linear.
        match self.ranges.last_mut() {
            None => return self.ranges.push(range),
            Some(last) if range.start >= last.start && range.start <= last.end => {
                last.end = last.end.max(range.end);
                return;
            }
            Some(last) if range.start > last.end => return self.ranges.push(range),
            Some(_) => {}
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

    /// True when some index is in both sets (linear in the number of ranges).
    pub fn overlaps(&self, other: &Self) -> bool {
        let (mut i, mut j) = (0, 0);
        while let (Some(a), Some(b)) = (self.ranges.get(i), other.ranges.get(j)) {
            if a.start < b.end && b.start < a.end {
                return true;
            }
            if a.end <= b.end {
                i += 1;
            } else {
                j += 1;
            }
        }
        false
    }

    /// Every index in either set (linear in the number of ranges).
    pub fn union(&self, other: &Self) -> Self {
        let mut all: Vec<Range<u32>> = Vec::with_capacity(self.ranges.len() + other.ranges.len());
        let (mut a, mut b) = (self.ranges.iter().peekable(), other.ranges.iter().peekable());
        while let Some(next) = match (a.peek(), b.peek()) {
            (Some(x), Some(y)) if y.start < x.start => b.next(),
            (Some(_), _) => a.next(),
            (None, _) => b.next(),
        } {
            match all.last_mut() {
                Some(last) if next.start <= last.end => last.end = last.end.max(next.end),
                _ => all.push(next.clone()),
            }
        }
        Self { ranges: all }
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
        for bad in ["", "5", "3..3", "4..2", "0..8,4..12", "a..b", "4..12,0..8", "0..8,0..8"] {
            assert!(SampleSet::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(SampleSet::parse("8..16,0..8").expect("adjacent").to_string(), "0..16");
        let (odd, even) =
            (SampleSet::parse("1..2,5..6").expect("valid"), SampleSet::parse("0..1,2..5").expect("valid"));
        assert_eq!(odd.union(&even).to_string(), "0..6");
        assert!(!odd.overlaps(&even) && odd.overlaps(&SampleSet::range(5..9)));
    }

    /// A header is input: 100,000 ranges (a 1.4 MB attribute) took 23 s to parse when every
    /// range was inserted by sorting the set again. Counted in operations rather than timed:
    /// the set of 200,000 ranges must come out whole and the same from both orders.
    #[test]
    fn many_ranges_parse_in_either_order() {
        let ranges: Vec<String> = (0..200_000u32).map(|i| format!("{}..{}", 2 * i, 2 * i + 1)).collect();
        let forward = SampleSet::parse(&ranges.join(",")).expect("valid");
        let backward =
            SampleSet::parse(&ranges.iter().rev().cloned().collect::<Vec<_>>().join(",")).expect("valid");
        assert_eq!(forward.ranges().len(), 200_000);
        assert_eq!(forward, backward);
        assert_eq!(forward.missing_below(400_000).len(), 200_000);
    }
}
