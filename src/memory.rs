//! Memory a render needs, estimated before it starts, against what the process may use, so that
//! a resolution that cannot fit is refused at once instead of aborting after the whole render
//! (32768² pixels need about 70 GB).
//!
//! The estimate is per pixel, measured (peak resident memory of `prisma render` of
//! `scenes/tp6_mirror_glass.toml` at 2048², 1 spp, EXR and PNG written): the tiles' means and the
//! assembled film (XYZ of S0, and of S1–S3 when polarised), the linear sRGB copies, the EXR
//! channels and the encoder's compressed blocks, the PNG bytes: 142 bytes per pixel unpolarised,
//! 158 polarised, and about 8.5 more per spectral band value (`--spectral-bands 16`, polarised:
//! 64 values, 705 bytes per pixel). [`BYTES_PER_PIXEL`] and [`BYTES_PER_BAND_VALUE`] keep a
//! margin over these. What the process may use is
//! the smallest of the memory the kernel reports available, the address-space limit
//! (`ulimit -v`) less what is mapped already, and the cgroup's limit less its usage; where none
//! of these can be read, nothing is refused.

/// Bytes of memory a render and its output need per pixel without spectral bands (measured 142
/// unpolarised, 158 polarised; see the module doc).
pub const BYTES_PER_PIXEL: u64 = 176;
/// Bytes more per pixel for each spectral band value (bands × Stokes components; measured 8.5).
pub const BYTES_PER_BAND_VALUE: u64 = 10;

/// A render that would not fit.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "a {width}×{height} image needs about {} of memory, but only {} is available ({limit}); \
     render at a lower resolution",
    gigabytes(*needed),
    gigabytes(*available)
)]
pub struct TooLarge {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Bytes the render would need.
    pub needed: u64,
    /// Bytes available.
    pub available: u64,
    /// Which limit that is.
    pub limit: &'static str,
}

fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 * 1e-9)
}

/// Bytes a `width`×`height` render with `band_values` spectral band values per pixel needs,
/// with `extra` bytes of fixed cost (thread stacks).
pub fn estimate(width: u32, height: u32, band_values: usize, extra: u64) -> u64 {
    let per_pixel = BYTES_PER_PIXEL + band_values as u64 * BYTES_PER_BAND_VALUE;
    u64::from(width) * u64::from(height) * per_pixel + extra
}

/// Refuses a render needing `needed` bytes when a known limit leaves less.
pub fn check(width: u32, height: u32, needed: u64) -> Result<(), TooLarge> {
    match available() {
        Some((available, limit)) if needed > available => {
            Err(TooLarge { width, height, needed, available, limit })
        }
        _ => Ok(()),
    }
}

/// The smallest known limit on what this process may still allocate, and its name.
pub fn available() -> Option<(u64, &'static str)> {
    [
        (mem_available(), "memory available to the system"),
        (address_space_left(), "address-space limit, ulimit -v"),
        (cgroup_left(), "cgroup memory limit"),
    ]
    .into_iter()
    .filter_map(|(bytes, name)| bytes.map(|b| (b, name)))
    .min_by_key(|&(bytes, _)| bytes)
}

/// The value in kB of `key:` in a /proc file of `key: value kB` lines, in bytes.
fn proc_kilobytes(path: &str, key: &str) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().find_map(|line| line.strip_prefix(key)?.strip_prefix(':'))?;
    let kilobytes: u64 = line.trim().trim_end_matches("kB").trim().parse().ok()?;
    kilobytes.checked_mul(1024)
}

fn mem_available() -> Option<u64> {
    proc_kilobytes("/proc/meminfo", "MemAvailable")
}

#[cfg(target_os = "linux")]
fn address_space_left() -> Option<u64> {
    let mut limit = libc::rlimit { rlim_cur: 0, rlim_max: 0 };
    // SAFETY: getrlimit writes one `rlimit` into the struct it is given, which lives here.
    let status = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) };
    if status != 0 || limit.rlim_cur == libc::RLIM_INFINITY {
        return None;
    }
    let mapped = proc_kilobytes("/proc/self/status", "VmSize").unwrap_or(0);
    Some(limit.rlim_cur.saturating_sub(mapped))
}

#[cfg(not(target_os = "linux"))]
fn address_space_left() -> Option<u64> {
    None
}

fn cgroup_left() -> Option<u64> {
    let read = |file: &str| std::fs::read_to_string(format!("/sys/fs/cgroup/{file}")).ok();
    let max: u64 = read("memory.max")?.trim().parse().ok()?; // "max" (no limit) does not parse
    let current: u64 = read("memory.current")?.trim().parse().ok()?;
    Some(max.saturating_sub(current))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The largest accepted image, 32768², needs 176 B × 2³⁰ ≈ 189 GB: more than any of the
    /// project's machines (24 GB), so it must be refused up front. Spectral bands add to it.
    #[test]
    fn the_largest_accepted_image_needs_tens_of_gigabytes() {
        assert_eq!(estimate(32_768, 32_768, 0, 0), 176 << 30);
        assert_eq!(estimate(1000, 1000, 16, 7), 1000 * 1000 * (176 + 160) + 7);
    }

    #[test]
    fn refusal_names_the_sizes_and_the_limit() {
        let error = TooLarge {
            width: 16_384,
            height: 16_384,
            needed: 17_200_000_000,
            available: 4e9 as u64,
            limit: "x",
        };
        let message = error.to_string();
        assert!(message.contains("16384×16384") && message.contains("17.2 GB") && message.contains("4.0 GB"));
    }

    #[test]
    fn proc_values_parse_in_bytes() {
        // This process has a VmSize line on Linux; elsewhere the reader gives None.
        if cfg!(target_os = "linux") {
            assert!(proc_kilobytes("/proc/self/status", "VmSize").is_some_and(|b| b > 0));
        }
        assert_eq!(proc_kilobytes("/proc/self/status", "NoSuchKey"), None);
    }
}
