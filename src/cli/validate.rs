//! `prisma validate`: renders every validation case, compares it with its Mitsuba 3 reference or
//! analytic answer, prints a table, optionally writes an HTML + Markdown report, and exits
//! non-zero when a case fails.

use std::fmt::Write as _;
use std::io::{IsTerminal, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::anyhow;
use clap::{Args, ValueEnum};
use glam::Vec3;
use indicatif::{ProgressBar, ProgressState, ProgressStyle};

use super::{output_error, say, CliError};
use prisma::integrator::Fault;
use prisma::output::file::{check_destination, text_into, Outputs};
use prisma::output::png::encode_png;
use prisma::validate::metrics::{Planes, Z_OUTLIER};
use prisma::validate::mitsuba::{run_case, CaseImages, RunOptions};
use prisma::validate::summary::{self, Verdict};
use prisma::validate::{analytic, cases, CaseResult, Kind};

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
    /// The path tracer's MIS weights do not add up to one (direct light counted twice).
    MisWeights,
    /// The path tracer's diffuse bounces drop the cosine.
    NoDiffuseCosine,
    /// The background lights nothing in the path tracer.
    DarkBackground,
    /// The path tracer counts the light tracer's paths too (caustic paths counted twice).
    CausticsTwice,
    /// The light tracer stops at its first diffuse vertex in full transport (paths counted never).
    CausticsNever,
    /// Every coating's layers without their phase thickness (a film without interference).
    CoatingPhase,
    /// The s and p amplitudes of every coating exchanged.
    CoatingSpSwapped,
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
    /// Do not print progress on standard error (the table and the verdict are still printed).
    #[arg(short, long)]
    quiet: bool,
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
        FaultArg::MisWeights => Fault::MisWeightsUnnormalized,
        FaultArg::NoDiffuseCosine => Fault::NoDiffuseCosine,
        FaultArg::DarkBackground => Fault::DarkBackground,
        FaultArg::CausticsTwice => Fault::CausticsCountedTwice,
        FaultArg::CausticsNever => Fault::CausticsCountedNever,
        FaultArg::CoatingPhase => Fault::CoatingPhaseDropped,
        FaultArg::CoatingSpSwapped => Fault::CoatingSpSwapped,
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
            // Names that hold what was typed first (`tp6_quad` → `tp6_quad_polarized`, …).
            let close: Vec<&str> =
                known.iter().copied().filter(|name| name.contains(wanted.as_str())).collect();
            let hint = match close.is_empty() {
                true => String::new(),
                false => format!("did you mean {}? ", close.join(", ")),
            };
            return Err(CliError::Input(anyhow!(
                "unknown case \"{wanted}\"; {hint}all {}: {}",
                known.len(),
                known.join(", ")
            )));
        }
    }
    let selected = |name: &str| args.cases.is_empty() || args.cases.iter().any(|c| c == name);

    let planned: Vec<Planned> = analytic::CASES
        .iter()
        .filter(|n| selected(n))
        .map(|&name| Planned::Analytic(name))
        .chain(mitsuba_cases.iter().filter(|c| selected(&c.name)).map(Planned::Mitsuba))
        .collect();
    let mut progress = Progress::new(&planned, args.quiet);
    let options = RunOptions { downsample: args.downsample as usize, spp: args.spp, threads, fault };
    let mut results: Vec<Ran> = Vec::new();
    for (index, case) in planned.iter().enumerate() {
        progress.start(index);
        let start = Instant::now();
        let outcome = match case {
            Planned::Analytic(name) => analytic::run(name, threads, fault).map(|result| (result, None)),
            Planned::Mitsuba(case) => {
                run_case(&args.dir, case, &options).map(|(result, images)| (result, Some(images)))
            }
        };
        let (result, images) = outcome.map_err(|e| {
            progress.finish();
            CliError::Failed(e.into())
        })?;
        let seconds = start.elapsed().as_secs_f64();
        progress.end(index, result.passed(), seconds);
        results.push(Ran { result, images, kind: case.kind(), seconds });
    }
    progress.finish();

    // The report first: what it prints (the Fresnel fixtures' figures) comes before the
    // table, so that the verdict is the last line.
    let report = args.report.as_ref().map(|dir| write_report(dir, &args.dir, &results, fault));
    if let (Some(dir), Some(Ok(()))) = (&args.report, &report) {
        say!("wrote {}", dir.join("index.html").display());
    }
    let rows: Vec<(&CaseResult, Kind)> = results.iter().map(|ran| (&ran.result, ran.kind)).collect();
    // Ignoring errors as `say!` does: a closed pipe must not turn the verdict into a panic.
    let _ = write!(std::io::stdout(), "{}", summary::table(&rows));
    report.transpose()?;
    let verdict = Verdict::of(results.iter().map(|ran| &ran.result));
    if verdict.failed.is_empty() {
        Ok(())
    } else {
        Err(CliError::Failed(anyhow!("validation failed: {}", verdict.failed.join(", "))))
    }
}

/// A case to run.
enum Planned<'a> {
    /// One of [`analytic::CASES`].
    Analytic(&'static str),
    /// A case with Mitsuba references.
    Mitsuba(&'a cases::Case),
}

impl Planned<'_> {
    fn name(&self) -> &str {
        match self {
            Planned::Analytic(name) => name,
            Planned::Mitsuba(case) => &case.name,
        }
    }

    fn kind(&self) -> Kind {
        match self {
            Planned::Analytic(name) => analytic::kind(name),
            Planned::Mitsuba(case) => case.kind,
        }
    }
}

/// A case that has run.
struct Ran {
    result: CaseResult,
    /// The images compared, for a case with Mitsuba references.
    images: Option<CaseImages>,
    kind: Kind,
    /// Wall time of the case.
    seconds: f64,
}

/// Progress on standard error: on a terminal, the running case with its time so far and the
/// time left, each finished case printed above it as a line; elsewhere (CI, a log), one plain
/// line per finished case, never a carriage return; with `--quiet`, nothing.
struct Progress {
    names: Vec<String>,
    kinds: Vec<Kind>,
    name_width: usize,
    /// The cases done: kind and seconds.
    done: Vec<(Kind, f64)>,
    mode: ProgressMode,
}

enum ProgressMode {
    Quiet,
    Lines,
    /// The bar, and the estimates its running line reads on every tick: the running case's
    /// time and the time of the cases after it, as f64 bits (NaN when not known yet).
    Terminal(ProgressBar, Arc<[AtomicU64; 2]>),
}

impl Progress {
    fn new(planned: &[Planned], quiet: bool) -> Self {
        let names: Vec<String> = planned.iter().map(|case| case.name().to_owned()).collect();
        let mode = if quiet {
            ProgressMode::Quiet
        } else if std::io::stderr().is_terminal() {
            let estimates =
                Arc::new([AtomicU64::new(f64::NAN.to_bits()), AtomicU64::new(f64::NAN.to_bits())]);
            let shared = Arc::clone(&estimates);
            let note = move |state: &ProgressState, out: &mut dyn std::fmt::Write| {
                let known = |bits: &AtomicU64| {
                    Some(f64::from_bits(bits.load(Ordering::Relaxed))).filter(|s| !s.is_nan())
                };
                let text = summary::running_note(
                    state.elapsed().as_secs_f64(),
                    known(&shared[0]),
                    known(&shared[1]),
                );
                let _ = out.write_str(&text);
            };
            let bar = ProgressBar::new(planned.len() as u64);
            if let Ok(style) = ProgressStyle::with_template("{prefix} {note}") {
                bar.set_style(style.with_key("note", note));
            }
            bar.enable_steady_tick(Duration::from_millis(250));
            ProgressMode::Terminal(bar, estimates)
        } else {
            ProgressMode::Lines
        };
        Progress {
            name_width: names.iter().map(|n| n.chars().count()).max().unwrap_or(0),
            kinds: planned.iter().map(Planned::kind).collect(),
            names,
            done: Vec::new(),
            mode,
        }
    }

    /// Case `index` starts.
    fn start(&self, index: usize) {
        if let ProgressMode::Terminal(bar, estimates) = &self.mode {
            let current = summary::time_left(&self.done, &self.kinds[index..=index]);
            let rest = summary::time_left(&self.done, &self.kinds[index + 1..]);
            for (estimate, value) in estimates.iter().zip([current, rest]) {
                estimate.store(value.unwrap_or(f64::NAN).to_bits(), Ordering::Relaxed);
            }
            bar.reset_elapsed();
            bar.set_position(index as u64);
            bar.set_prefix(summary::progress_line(
                index,
                self.names.len(),
                &self.names[index],
                self.name_width,
                None,
            ));
        }
    }

    /// Case `index` ended after `seconds`.
    fn end(&mut self, index: usize, passed: bool, seconds: f64) {
        self.done.push((self.kinds[index], seconds));
        let line = summary::progress_line(
            index,
            self.names.len(),
            &self.names[index],
            self.name_width,
            Some((passed, seconds)),
        );
        match &self.mode {
            ProgressMode::Quiet => {}
            ProgressMode::Lines => eprintln!("{line}"),
            ProgressMode::Terminal(bar, _) => bar.println(line),
        }
    }

    /// Every case has run, or one could not (its error follows): the running line goes.
    fn finish(&self) {
        if let ProgressMode::Terminal(bar, _) = &self.mode {
            bar.finish_and_clear();
        }
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

/// `text` with its first letter in capitals.
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map(|first| first.to_uppercase().chain(chars).collect()).unwrap_or_default()
}

/// The kind and the time of a case, as the report's contents and sections show them.
fn kind_and_time(ran: &Ran) -> String {
    format!("{} · {}", ran.kind.label(), summary::duration(ran.seconds))
}

/// Writes the report's files into `dir`, all or none (staged, then committed together): the
/// verdict first, with links to the failing cases, then the contents (a link to each case's
/// section, anchored by its name), the result table, and a section per case.
fn write_report(
    dir: &Path,
    validation_dir: &Path,
    results: &[Ran],
    fault: Option<Fault>,
) -> Result<(), CliError> {
    let failed = |e| output_error(e, "writing the report");
    let mut outputs = Outputs::new();
    let verdict = Verdict::of(results.iter().map(|ran| &ran.result));
    let verdict_class = if verdict.passed() { "pass" } else { "fail" };
    let total_seconds: f64 = results.iter().map(|ran| ran.seconds).sum();
    let mut md = String::from("# prisma validation report\n\n");
    let mut html = String::from(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>prisma validation</title><style>\
         body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse}\
         td,th{border:1px solid #ccc;padding:4px 8px}td.num{text-align:right;font-family:monospace}\
         .pass{color:#060}.fail{color:#b00;font-weight:bold}\
         p.verdict{font-size:1.4em;padding:.6em 1em;border-radius:4px;margin:0 0 1em}\
         p.verdict.pass{background:#e8f5e8;border:1px solid #8c8}p.verdict.fail{background:#fbeaea;border:1px solid #d88}\
         ol.toc{columns:3;column-gap:2em;padding-left:2.5em}ol.toc li{break-inside:avoid;margin:2px 0}\
         .kind{color:#666;font-size:.9em}section{border-top:1px solid #ddd;margin-top:2em}\
         img{image-rendering:pixelated;margin:4px;border:1px solid #ddd}figure{display:inline-block;margin:0}</style></head><body>\
         <h1 id=\"top\">prisma validation report</h1>",
    );

    // The verdict, the failing cases named and linked.
    let headline = capitalised(&verdict.headline());
    if verdict.failed.is_empty() {
        let _ = writeln!(md, "**{headline}** ({}).\n", summary::duration(total_seconds));
        let _ = write!(
            html,
            "<p class=\"verdict {verdict_class}\">{headline} <span class=\"kind\">({})</span></p>",
            summary::duration(total_seconds)
        );
    } else {
        let md_links: Vec<String> = verdict.failed.iter().map(|n| format!("[{n}](#{n})")).collect();
        let html_links: Vec<String> =
            verdict.failed.iter().map(|n| format!("<a href=\"#{0}\">{0}</a>", html_text(n))).collect();
        let _ = writeln!(md, "**{headline}:** {}\n", md_links.join(", "));
        let _ = write!(html, "<p class=\"verdict fail\">{headline}: {}</p>", html_links.join(", "));
    }
    if let Some(fault) = fault {
        let _ = writeln!(md, "**Injected fault: {fault:?}** — cases that can see it must FAIL.\n");
        let _ = write!(
            html,
            "<p class=\"fail\">Injected fault: {fault:?} — cases that can see it must FAIL.</p>"
        );
    }

    // Contents: every case's section, with its verdict, kind and time.
    let _ = writeln!(md, "## Contents\n");
    html.push_str("<h2 id=\"contents\">Contents</h2><ol class=\"toc\">");
    for ran in results {
        let (name, word) = (&ran.result.name, summary::verdict_word(ran.result.passed()));
        let _ = writeln!(md, "1. [{name}](#{name}) {word}, {}", kind_and_time(ran));
        let _ = write!(
            html,
            "<li><a href=\"#{0}\">{0}</a> <span class=\"{1}\">{word}</span> <span class=\"kind\">{2}</span></li>",
            html_text(name),
            word.to_lowercase(),
            html_text(&kind_and_time(ran))
        );
    }
    let _ = writeln!(md, "1. [Fresnel curves](#fresnel-curves-mitsuba-3-fixtures-against-prisma)\n");
    html.push_str("<li><a href=\"#fresnel\">Fresnel curves</a></li></ol>");

    // The result table, one row per check.
    let header = summary::TABLE_HEADER.join(" | ");
    let _ = writeln!(md, "| {header} |\n|{}", "---|".repeat(summary::TABLE_HEADER.len()));
    html.push_str("<h2 id=\"results\">Results</h2><table><tr>");
    for column in summary::TABLE_HEADER {
        let _ = write!(html, "<th>{column}</th>");
    }
    html.push_str("</tr>");
    for ran in results {
        let name = &ran.result.name;
        for check in &ran.result.checks {
            let verdict = summary::verdict_word(check.passed());
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {verdict} |",
                md_cell(name),
                ran.kind.label(),
                md_cell(&check.metric),
                summary::scientific(check.value),
                summary::scientific(check.threshold)
            );
            let _ = write!(
                html,
                "<tr><td><a href=\"#{0}\">{0}</a></td><td>{1}</td><td>{2}</td><td class=\"num\">{3}</td>\
                 <td class=\"num\">{4}</td><td class=\"{5}\">{verdict}</td></tr>",
                html_text(name),
                ran.kind.label(),
                html_text(&check.metric),
                summary::scientific(check.value),
                summary::scientific(check.threshold),
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

    for ran in results {
        let (result, word) = (&ran.result, summary::verdict_word(ran.result.passed()));
        let _ =
            writeln!(md, "\n## {}\n\n**{word}** · {}\n\n{}\n", result.name, kind_and_time(ran), result.why);
        let _ = write!(
            html,
            "<section id=\"{0}\"><h2>{0} <span class=\"{1}\">{word}</span></h2><p class=\"kind\">{2} · \
             <a href=\"#top\">top</a></p><p>{3}</p>",
            html_text(&result.name),
            word.to_lowercase(),
            html_text(&kind_and_time(ran)),
            html_text(&result.why)
        );
        let checks: Vec<String> = result
            .checks
            .iter()
            .map(|check| {
                format!(
                    "{} = {} (≤ {}) <span class=\"{}\">{}</span>",
                    html_text(&check.metric),
                    summary::scientific(check.value),
                    summary::scientific(check.threshold),
                    summary::verdict_word(check.passed()).to_lowercase(),
                    summary::verdict_word(check.passed())
                )
            })
            .collect();
        let _ = write!(html, "<p>{}</p>", checks.join("<br>"));
        let Some(images) = &ran.images else {
            html.push_str("</section>");
            continue;
        };
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
        let _ = write!(html, "<figure><img src=\"z_scale.png\" width=\"256\"><figcaption>z from −{Z_OUTLIER} to +{Z_OUTLIER}</figcaption></figure></section>");
    }

    let _ = writeln!(md, "\n## Fresnel curves: Mitsuba 3 fixtures against prisma\n");
    html.push_str("<section id=\"fresnel\"><h2>Fresnel curves: Mitsuba 3 fixtures against prisma</h2>");
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
    html.push_str("</section></body></html>");
    for (file, text) in [("report.md", &md), ("index.html", &html)] {
        let path = dir.join(file);
        outputs.stage(&path, |sink| text_into(sink, &path, text)).map_err(failed)?;
    }
    outputs.commit().map_err(failed)
}
