//! The CPU time this process has used, all its threads together (user and system), for the
//! render's figures: benchmarks compare it with a peer's CPU time over the same span (the
//! render alone, without loading the scene or writing the image).

use std::time::Duration;

/// CPU time used by every thread of this process so far (`getrusage(RUSAGE_SELF)`: user + system),
/// or `None` where it cannot be read.
#[cfg(unix)]
pub fn process_cpu_time() -> Option<Duration> {
    // SAFETY: an all-zero `rusage` is a valid value of this plain C struct, and getrusage
    // writes one `rusage` into the struct it is given, which lives here.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: as above.
    let status = unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) };
    if status != 0 {
        return None;
    }
    let of = |t: libc::timeval| {
        Duration::from_secs(u64::try_from(t.tv_sec).ok()?)
            .checked_add(Duration::from_micros(u64::try_from(t.tv_usec).ok()?))
    };
    of(usage.ru_utime)?.checked_add(of(usage.ru_stime)?)
}

/// CPU time used by every thread of this process so far: unknown on this platform.
#[cfg(not(unix))]
pub fn process_cpu_time() -> Option<Duration> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_time_grows_with_work() {
        let before = process_cpu_time().expect("getrusage");
        // Busy work the optimiser cannot drop; ~10 ms or more of CPU.
        let mut x = 1.0_f64;
        let start = std::time::Instant::now();
        while start.elapsed() < Duration::from_millis(30) {
            x = std::hint::black_box(x.mul_add(1.000_000_1, 1e-9));
        }
        let after = process_cpu_time().expect("getrusage");
        assert!(after > before, "{before:?} → {after:?} ({x})");
    }
}
