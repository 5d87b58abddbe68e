//! Large arrays placed on 2 MiB pages where the system allows it: the BVH's nodes and leaf
//! packets (read-mostly, for the TLB), and a render's per-pixel sums (`crate::film`, written
//! all over, for fewer page faults).
//!
//! Incoherent rays jump across the whole BVH, so with 4 KiB pages nearly every node and leaf
//! they touch also misses the TLB: on a 1M-triangle mesh (about 60 MB of nodes and packets),
//! asking Linux for transparent huge pages (`madvise(MADV_HUGEPAGE)`, which Linux honours when
//! its THP mode is `madvise` or `always`) traced 14 % more incoherent rays per second
//! (`prisma bench-rays`, validation/bench/PROFILE.md). Elsewhere, or when the kernel declines,
//! the arrays stay as they are: nothing depends on it but speed.

/// Arrays smaller than this are left where they are: they span only a few huge pages at most.
const MIN_BYTES: usize = 4 << 20;

/// `items`, moved to a fresh allocation that the kernel has been asked to back with huge pages
/// (on Linux, for arrays of at least 4 MiB; otherwise `items` itself).
pub(crate) fn on_huge_pages<T: Copy>(items: Vec<T>) -> Vec<T> {
    let bytes = std::mem::size_of_val(items.as_slice());
    if !cfg!(target_os = "linux") || bytes < MIN_BYTES {
        return items;
    }
    let mut moved: Vec<T> = Vec::with_capacity(items.len());
    advise(moved.as_mut_ptr().cast(), bytes);
    // Written after the advice, so that the first touch of each 2 MiB range faults in a huge
    // page directly instead of waiting for the kernel to merge small ones.
    moved.extend_from_slice(&items);
    moved
}

/// `len` copies of `value` in an allocation the kernel has been asked to back with huge pages
/// (as [`on_huge_pages`]): for large arrays written all over, such as a render's per-pixel
/// sums, whose 4 KiB pages each cost a fault when first touched.
pub(crate) fn filled_on_huge_pages<T: Copy>(value: T, len: usize) -> Vec<T> {
    let mut items: Vec<T> = Vec::with_capacity(len);
    let bytes = std::mem::size_of::<T>() * len;
    if cfg!(target_os = "linux") && bytes >= MIN_BYTES {
        advise(items.as_mut_ptr().cast(), bytes);
    }
    items.resize(len, value);
    items
}

/// Asks for huge pages on the whole 2 MiB pages inside `bytes` bytes from `start`.
#[cfg(target_os = "linux")]
fn advise(start: *mut u8, bytes: usize) {
    const HUGE: usize = 2 << 20;
    let begin = (start as usize).next_multiple_of(HUGE);
    let end = (start as usize + bytes) / HUGE * HUGE;
    if end > begin {
        // SAFETY: [begin, end) lies inside an allocation of at least `bytes` bytes from `start`
        // that this process owns; MADV_HUGEPAGE only changes how the kernel backs those pages
        // (never their contents), and a refusal is reported as an error code, ignored here.
        unsafe {
            libc::madvise(begin as *mut libc::c_void, end - begin, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_start: *mut u8, _bytes: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_and_small_arrays_keep_their_contents() {
        for len in [0usize, 10, MIN_BYTES / 4 + 12_345] {
            let items: Vec<u32> = (0..len as u32).map(|i| i.wrapping_mul(2_654_435_761)).collect();
            assert_eq!(on_huge_pages(items.clone()), items);
        }
    }
}
