//! `prisma validate`: renders every validation case, compares it with its Mitsuba 3 reference or
//! analytic answer, prints a table, optionally writes an HTML + Markdown report, and exits
//! non-zero when a case fails.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::anyhow;
use clap::{Args, ValueEnum};
use glam::Vec3;

use super::{output_error, say, CliError};
use prisma::integrator::Fault;
use prisma::output::file::{check_destination, text_into, Outputs};
use prisma::output::png::encode_png;
use prisma::validate::metrics::{Planes, Z_OUTLIER};
use prisma::validate::mitsuba::{run_case, CaseImages, RunOptions};
use prisma::validate::{analytic, cases, CaseResult};

/// A deliberate physics error to inject, proving that validation catches it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FaultArg {
    /// Schlick's approximation instead of the exact Fresnel equations.
    Schlick,
    /// Every index of refraction 1 % too high.
    IorPlus1Percent,
    /// Every change of Stokes frame turned the wrong way (a rotation matrix built transposed).
    TransposedRotation,
    /// The sign of every phase term flipped (circular polarisation of the wrong handedness).
    FlippedPhase,
    /// Polarisation dropped: each interface's reflectance averaged over s and p.
    Unpolarized,
    /// The light tracer scales flux at refractions as radiance is scaled (1/η² per refraction).
    LightRadianceScaling,
    /// The light tracer misses the cosine at the diffuse receiver toward the camera.
    NoReceiverCosine,
}

/// Arguments of `prisma validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Run only these cases (repeatable); all of them by default.
    #[arg(long = "case", value_name = "NAME")]
    cases: Vec<String>,
    /// Write an HTML and Markdown report with images into this directory.
    #[arg(long, value_name = "DIR")]
    report: Option<PathBuf>,
    /// The validation directory (cases.toml, scenes/, references/) of a prisma source tree:
    /// `validation` in the working directory by default, so run from the project's root.
    #[arg(long, value_name = "DIR", default_value = "validation")]
    dir: PathBuf,
    /// Compare at the references' resolution divided by this factor.
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
    downsample: u32,
    /// prisma samples per pixel of each of its two renders (default: the case's).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    spp: Option<u32>,
    /// Render threads [default: one per core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Inject a deliberate physics error: every case that can see it must then FAIL.
    #[arg(long, value_enum)]
    fault: Option<FaultArg>,
}

/// Runs `prisma validate`.
pub fn run(args: &ValidateArgs) -> Result<(), CliError> {
    let fault = args.fault.map(|f| match f {
        FaultArg::Schlick => Fault::SchlickFresnel,
        FaultArg::IorPlus1Percent => Fault::IorScale(1.01),
        FaultArg::TransposedRotation => Fault::TransposedRotation,
        FaultArg::FlippedPhase => Fault::FlippedPhase,
        FaultArg::Unpolarized => Fault::Unpolarized,
        FaultArg::LightRadianceScaling => Fault::LightPathRadianceScaling,
        FaultArg::NoReceiverCosine => Fault::NoReceiverCosine,
    });
    let threads = args.threads.unwrap_or(0) as usize;
    if !args.dir.join("cases.toml").is_file() {
        return Err(CliError::Input(anyhow!(
            "{}: no validation directory here (cases.toml not found); run `prisma validate` from the \
             root of a prisma source tree, or give --dir PATH/validation",
            args.dir.display()
        )));
    }
    if let Some(dir) = &args.report {
        check_destination(&dir.join("index.html")).map_err(|e| CliError::Input(e.into()))?;
    }
    let mitsuba_cases = cases::load(&args.dir).map_err(|e| CliError::Input(e.into()))?;
    let known: Vec<&str> =
        analytic::CASES.iter().copied().chain(mitsuba_cases.iter().map(|c| c.name.as_str())).collect();
    for wanted in &args.cases {
        if !known.contains(&wanted.as_str()) {
            return Err(CliError::Input(anyhow!("unknown case \"{wanted}\"; known: {}", known.join(", "))));
        }
    }
    let selected = |name: &str| args.cases.is_empty() || args.cases.iter().any(|c| c == name);

    let mut results: Vec<(CaseResult, Option<CaseImages>)> = Vec::new();
    for name in analytic::CASES.iter().filter(|n| selected(n)) {
        let result = analytic::run(name, threads, fault).map_err(|e| CliError::Failed(e.into()))?;
        print_result(&result);
        results.push((result, None));
    }
    let options = RunOptions { downsample: args.downsample as usize, spp: args.spp, threads, fault };
    for case in mitsuba_cases.iter().filter(|c| selected(&c.name)) {
        let (result, images) = run_case(&args.dir, case, &options).map_err(|e| CliError::Failed(e.into()))?;
        print_result(&result);
        results.push((result, Some(images)));
    }
    let failed: Vec<&str> =
        results.iter().filter(|(r, _)| !r.passed()).map(|(r, _)| r.name.as_str()).collect();
    say!("{} of {} cases passed", results.len() - failed.len(), results.len());

    if let Some(dir) = &args.report {
        write_report(dir, &args.dir, &results, fault)?;
        say!("wrote {}", dir.join("index.html").display());
    }
    if failed.is_empty() {
        Ok(())
    } else {
        Err(CliError::Failed(anyhow!("validation failed: {}", failed.join(", "))))
    }
}

fn print_result(result: &CaseResult) {
    for check in &result.checks {
        say!(
            "{:<28} {:<30} {:>12.4e} {:>12.4e}  {}",
            result.name,
            check.metric,
            check.value,
            check.threshold,
            if check.passed() { "PASS" } else { "FAIL" }
        );
    }
}

/// Linear image → preview pixels (grey for one channel), exposed so the reference's 99th
/// percentile maps to 1.
fn preview_pixels(planes: &Planes, scale: f64) -> Vec<Vec3> {
    (0..planes.width * planes.height)
        .map(|i| {
            let c = |k: usize| (planes.data[k.min(planes.data.len() - 1)][i] * scale) as f32;
            Vec3::new(c(0), c(1), c(2))
        })
        .collect()
}

fn exposure_scale(planes: &Planes) -> f64 {
    let mut values: Vec<f64> = planes.data.iter().flatten().copied().filter(|v| v.is_finite()).collect();
    values.sort_by(f64::total_cmp);
    let p99 = values.get(values.len() * 99 / 100).copied().unwrap_or(1.0);
    if p99 > 0.0 {
        1.0 / p99
    } else {
        1.0
    }
}

/// Diverging blue–white–red colour of z clamped to ±[`Z_OUTLIER`] (linear sRGB).
fn z_colour(z: f64) -> Vec3 {
    let t = (z / Z_OUTLIER).clamp(-1.0, 1.0) as f32;
    if t >= 0.0 {
        Vec3::new(1.0, 1.0 - t, 1.0 - t)
    } else {
        Vec3::new(1.0 + t, 1.0 + t, 1.0)
    }
}

/// `text` as a Markdown table cell: `|` escaped, line breaks as spaces.
fn md_cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

/// `text` as HTML text.
fn html_text(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Writes the report's files into `dir`, all or none (staged, then committed together).
fn write_report(
    dir: &Path,
    validation_dir: &Path,
    results: &[(CaseResult, Option<CaseImages>)],
    fault: Option<Fault>,
) -> Result<(), CliError> {
    let failed = |e| output_error(e, "writing the report");
    let mut outputs = Outputs::new();
    let mut md = String::from("# prisma validation report\n\n");
    let mut html = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>prisma validation</title><style>\
         body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse}\
         td,th{border:1px solid #ccc;padding:4px 8px}.pass{color:#060}.fail{color:#b00;font-weight:bold}\
         img{image-rendering:pixelated;margin:4px;border:1px solid #ddd}figure{display:inline-block;margin:0}</style></head><body>\
         <h1>prisma validation report</h1>",
    );
    if let Some(fault) = fault {
        let _ = writeln!(md, "**Injected fault: {fault:?}** — cases that can see it must FAIL.\n");
        let _ = write!(
            html,
            "<p class=\"fail\">Injected fault: {fault:?} — cases that can see it must FAIL.</p>"
        );
    }
    let _ = writeln!(md, "| case | metric | value | threshold | result |\n|---|---|---|---|---|");
    html.push_str(
        "<table><tr><th>case</th><th>metric</th><th>value</th><th>threshold</th><th>result</th></tr>",
    );
    for (result, _) in results {
        for check in &result.checks {
            let verdict = if check.passed() { "PASS" } else { "FAIL" };
            let _ = writeln!(
                md,
                "| {} | {} | {:.4e} | {:.4e} | {verdict} |",
                md_cell(&result.name),
                md_cell(&check.metric),
                check.value,
                check.threshold
            );
            let _ = write!(
                html,
                "<tr><td>{}</td><td>{}</td><td>{:.4e}</td><td>{:.4e}</td><td class=\"{}\">{verdict}</td></tr>",
                html_text(&result.name),
                html_text(&check.metric),
                check.value,
                check.threshold,
                verdict.to_lowercase()
            );
        }
    }
    html.push_str("</table>");

    // The colour scale of the z maps.
    let scale_width = 256;
    let scale: Vec<Vec3> = (0..scale_width * 16)
        .map(|i| z_colour(((i % scale_width) as f64 / (scale_width - 1) as f64 * 2.0 - 1.0) * Z_OUTLIER))
        .collect();
    let z_scale = dir.join("z_scale.png");
    outputs
        .stage(&z_scale, |sink| encode_png(sink, &z_scale, scale_width as u32, 16, &scale, 0.0))
        .map_err(failed)?;

    for (result, images) in results {
        let _ = writeln!(md, "\n## {}\n\n{}\n", result.name, result.why);
        let _ = write!(html, "<h2>{}</h2><p>{}</p>", html_text(&result.name), html_text(&result.why));
        let Some(images) = images else { continue };
        let (w, h) = (images.mitsuba.width as u32, images.mitsuba.height as u32);
        let scale = exposure_scale(&images.mitsuba);
        let files = [
            (format!("{}_prisma.png", result.name), preview_pixels(&images.prisma, scale), "prisma"),
            (format!("{}_mitsuba.png", result.name), preview_pixels(&images.mitsuba, scale), "Mitsuba 3"),
            (
                format!("{}_z.png", result.name),
                images.comparison.z_map.iter().map(|&z| z_colour(z)).collect(),
                "per-pixel z (blue −5 … white 0 … red +5)",
            ),
        ];
        let ratios: Vec<String> = images.comparison.mean_ratio.iter().map(|r| format!("{r:.4}")).collect();
        let _ = writeln!(md, "mean prisma / Mitsuba per channel: {}\n", ratios.join(", "));
        let _ = write!(html, "<p>mean prisma / Mitsuba per channel: {}</p>", ratios.join(", "));
        for (file, pixels, caption) in &files {
            let path = dir.join(file);
            outputs.stage(&path, |sink| encode_png(sink, &path, w, h, pixels, 0.0)).map_err(failed)?;
            let _ = writeln!(md, "![{caption}]({file}) ");
            let _ = write!(
                html,
                "<figure><img src=\"{file}\" width=\"{}\"><figcaption>{caption}</figcaption></figure>",
                (w * 2).min(420)
            );
        }
        let _ = write!(html, "<figure><img src=\"z_scale.png\" width=\"256\"><figcaption>z from −{Z_OUTLIER} to +{Z_OUTLIER}</figcaption></figure>");
    }

    let _ = writeln!(md, "\n## Fresnel curves: Mitsuba 3 fixtures against prisma\n");
    html.push_str("<h2>Fresnel curves: Mitsuba 3 fixtures against prisma</h2>");
    let fixtures = validation_dir.parent().unwrap_or(Path::new(".")).join("tests/fixtures");
    for name in ["fresnel_dielectric", "fresnel_polarized", "fresnel_conductor"] {
        let csv = fixtures.join(format!("{name}.csv"));
        if !csv.exists() {
            continue;
        }
        let png = format!("{name}.png");
        let largest = super::fresnel::fixture_overlay(&csv, Some(&dir.join(&png)), &mut outputs)?;
        let _ = writeln!(md, "![{name}]({png})\n\nlargest |prisma − Mitsuba| = {largest:.2e}\n");
        let _ = write!(html, "<figure><img src=\"{png}\" width=\"900\"><figcaption>{name}: largest |prisma − Mitsuba| = {largest:.2e}</figcaption></figure>");
    }
    html.push_str("</body></html>");
    for (file, text) in [("report.md", &md), ("index.html", &html)] {
        let path = dir.join(file);
        outputs.stage(&path, |sink| text_into(sink, &path, text)).map_err(failed)?;
    }
    outputs.commit().map_err(failed)
}
