//! The memory check's estimate against the memory renders really take: the peak resident memory
//! of `prisma render` at two sizes (its slope per pixel, so that fixed costs drop out), for the
//! layouts whose per-pixel cost differs. The estimate must cover the measurement (a render it
//! lets through must fit) and not exceed it by more than 35 % (a 12000×8000 unpolarised render
//! needing about 15 GB was refused as 30.9 GB by the old estimate, 752 and 320 bytes per pixel
//! against 445 and 156 measured).

use std::process::Command;

use prisma::film::{FilmLayout, SpectralBands};

/// Peak resident memory in bytes of `prisma render ARGS` (the child's `ru_maxrss`).
fn peak_bytes(args: &[&str]) -> u64 {
    // Reaped by wait4 below, which also gives its peak memory (std's wait does not).
    #[allow(clippy::zombie_processes)]
    let child = Command::new(env!("CARGO_BIN_EXE_prisma")).args(args).spawn().expect("prisma runs");
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for the child this test started, with pointers to live locals.
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t, "wait4");
    assert!(libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0, "{args:?}: status {status}");
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn the_memory_estimate_covers_measured_renders_within_a_third() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/tp6_mirror_glass.toml");
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("m.exr");
    let out = out.to_str().expect("utf-8");
    let bands = SpectralBands { count: 8, min_nm: 360.0, max_nm: 830.0 };
    let layouts: [(&str, &[&str], FilmLayout); 4] = [
        (
            "unpolarised",
            &["--unpolarized"],
            FilmLayout { stokes: false, bands: None, monochromatic_nm: None },
        ),
        ("polarised", &[], FilmLayout { stokes: true, bands: None, monochromatic_nm: None }),
        (
            "monochromatic",
            &["--wavelength", "550"],
            FilmLayout { stokes: true, bands: None, monochromatic_nm: Some(550.0) },
        ),
        (
            "8 bands",
            &["--spectral-bands", "8"],
            FilmLayout { stokes: true, bands: Some(bands), monochromatic_nm: None },
        ),
    ];
    let mut report = Vec::new();
    for (name, extra, layout) in layouts {
        let peak = |side: u32| {
            let side = side.to_string();
            let mut args =
                vec!["render", scene, "--width", &side, "--height", &side, "--spp", "1", "-q", "-o", out];
            args.extend_from_slice(extra);
            peak_bytes(&args)
        };
        let (small, large) = (peak(512), peak(1024));
        let measured = (large.saturating_sub(small)) as f64 / (1024.0 * 1024.0 - 512.0 * 512.0);
        let estimated = prisma::memory::estimate(1, 1, &layout, 0, 0) as f64;
        report.push(format!("{name}: measured {measured:.0} B/pixel, estimated {estimated:.0}"));
        assert!(
            measured <= estimated && estimated <= 1.35 * measured,
            "{name}: the estimate {estimated:.0} B/pixel against {measured:.0} measured\n{}",
            report.join("\n")
        );
    }
    println!("{}", report.join("\n"));
}
