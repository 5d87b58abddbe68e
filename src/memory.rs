//! Memory a render needs, estimated before it starts, against what the process may use, so that
//! a resolution that cannot fit is refused at once instead of aborting after the whole render
//! (32768² pixels need about 600 GB polarised).
//!
//! The estimate is per pixel and per value summed per pixel (3 XYZ values per Stokes component,
//! 1 for a monochromatic render, plus the spectral band values), fitted to the peak resident
//! memory of `prisma render scenes/tp6_mirror_glass.toml --spp 1` at 1024² and 2048² (the slope
//! between the two sizes, so that fixed costs drop out; `tests/memory_estimate.rs` measures it
//! again):
//!
//! | render | values | measured bytes per pixel |
//! |---|---|---|
//! | unpolarised | 3 | 156 |
//! | polarised (the default) | 12 | 445 |
//! | polarised, `--part` | 12 | 511 |
//! | polarised, `--spectral-bands 16` | 76 | 2481 |
//! | polarised, `--caustics` (light sums of S0: 3 values) | 12 + 3 | 518 |
//!
//! | monochromatic (`--wavelength`), polarised | 4 | 216 |
//!
//! A least-squares reading of these: about 60 bytes per pixel (camera and PNG buffers), 12 per
//! Stokes component (the film's XYZ, three f32 even when monochromatic), 28 per colour value (its
//! exact sum, 24 bytes, and its EXR channel), 32 per band value (its sum, the film's f32 and its
//! channel), 24 per light-tracer value, and a part's stored sum channels about 5.5 more per
//! value (implied words are left out). The constants below keep a margin of 5 to 25 % over these
//! (the part allowance is counted for every render: the renderer does not know whether its sums
//! will be written). What the process may use is the smallest of the
//! memory the kernel reports available, the address-space limit (`ulimit -v`) less what is mapped
//! already, and the cgroup's limit less its usage; where none of these can be read, nothing is
//! refused.

use crate::film::FilmLayout;

/// Bytes per pixel of every render (measured about 60; see the module doc).
pub const BYTES_PER_PIXEL: u64 = 64;
/// Bytes per pixel for each Stokes component (measured 12).
pub const BYTES_PER_COMPONENT: u64 = 12;
/// Bytes per pixel for each colour value (measured 28).
pub const BYTES_PER_COLOUR_VALUE: u64 = 29;
/// Bytes per pixel for each spectral band value (measured 32).
pub const BYTES_PER_BAND_VALUE: u64 = 33;
/// Bytes per pixel for each value of a part's stored sum channels (measured 5.5; up to 24 when
/// every word of a sum must be stored).
pub const PART_BYTES_PER_VALUE: u64 = 6;
/// Bytes per pixel for each light-tracer value (measured 24).
pub const LIGHT_BYTES_PER_VALUE: u64 = 26;

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

/// Bytes a `width`×`height` render of `layout` with `light_values` light-tracer values per
/// pixel needs, with `extra` bytes of fixed cost (thread stacks).
pub fn estimate(width: u32, height: u32, layout: &FilmLayout, light_values: usize, extra: u64) -> u64 {
    let per_pixel = BYTES_PER_PIXEL
        + layout.components() as u64 * BYTES_PER_COMPONENT
        + (layout.colour_values() * layout.components()) as u64 * BYTES_PER_COLOUR_VALUE
        + layout.band_values() as u64 * BYTES_PER_BAND_VALUE
        + layout.values_per_pixel() as u64 * PART_BYTES_PER_VALUE
        + light_values as u64 * LIGHT_BYTES_PER_VALUE;
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

    /// The largest accepted image, 32768², needs 181 B × 2³⁰ ≈ 194 GB unpolarised: more than
    /// any of the project's machines (24 GB), so it must be refused up front. The estimate is
    /// the sum of its per-pixel parts (see the module doc).
    #[test]
    fn the_largest_accepted_image_needs_tens_of_gigabytes() {
        let unpolarized = FilmLayout { stokes: false, bands: None, monochromatic_nm: None };
        assert_eq!(estimate(32_768, 32_768, &unpolarized, 0, 0), 181 << 30);
        let bands = crate::film::SpectralBands { count: 16, min_nm: 400.0, max_nm: 700.0 };
        let polarized = FilmLayout { stokes: true, bands: Some(bands), monochromatic_nm: None };
        // 64 + 4·12 + 12·29 + 64·33 + 76·6 + 3·26 bytes per pixel.
        assert_eq!(
            estimate(1000, 1000, &polarized, 3, 7),
            1000 * 1000 * (64 + 48 + 348 + 2112 + 456 + 78) + 7
        );
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
