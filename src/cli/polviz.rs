//! `prisma polviz`: false-colour maps of a polarised render's EXR, one PNG with four panels: S0
//! as a preview, the degree of linear polarisation DoLP = √(S1² + S2²)/S0, the angle of linear
//! polarisation AoLP = ½·atan2(S2, S1) (grey where DoLP is below `--min-dolp`), and the
//! circular part S3/S0, each with its colour bar and labels.
//!
//! Which numbers are the Stokes components:
//! - a colour render (layers `S0`–`S3`, channels R, G, B in linear sRGB): by default the CIE Y
//!   of each component, Y = 0.2126 R + 0.7152 G + 0.0722 B (the Rec. 709 weights, which give
//!   back exactly the Y the film computed, since each component's RGB is a linear map of its
//!   XYZ). Y weighs wavelengths by ȳ(λ) ≥ 0, so |S1|, |S2|, |S3| ≤ S0 hold for it as for each
//!   wavelength; `--channel R|G|B` takes one channel instead, where saturated colours can break
//!   that bound (the RGB matrix has negative entries), and values are clamped for display.
//!   `--wavelength NM` takes the spectral band (Fichet channels `S<k>.<λ>nm`) nearest NM.
//! - a single-wavelength render (only `S<k>.<λ>nm` channels): those channels.
//!
//! The frame is the EXR's: x = image right, y = image up for the viewer, AoLP counter-clockwise
//! from image right, S3 > 0 when the field turns clockwise for the viewer (see
//! `prisma::polarization`).

mod colour;
mod figure;

use std::path::{Path, PathBuf};

use anyhow::anyhow;
use clap::{Args, ValueEnum};

use super::plot::encode_png_compact;
use super::{output_error, say, CliError};
use figure::{Options, StokesImage};
use prisma::output::exr::{read_exr, ExrImage};
use prisma::output::file::{check_destination, check_not_inputs, write_file};
use prisma::output::OutputError;

/// Arguments of `prisma polviz`.
#[derive(Debug, Args)]
pub struct PolvizArgs {
    /// A polarised EXR written by `prisma render` (layers S0–S3, or S<k>.<λ>nm channels).
    input: PathBuf,
    /// Output PNG [default: the input path with `_polviz.png`].
    #[arg(short, long, value_name = "OUT.png")]
    output: Option<PathBuf>,
    /// Which colour channel's Stokes components to map (colour renders): Y = the CIE Y of each
    /// component from its RGB with the Rec. 709 weights [default: Y].
    #[arg(long, value_enum, ignore_case = true)]
    channel: Option<Channel>,
    /// Map the spectral band (S<k>.<λ>nm channels of `render --spectral-bands`) nearest this
    /// wavelength in nm instead of a colour channel.
    #[arg(long, value_name = "NM", conflicts_with = "channel")]
    wavelength: Option<f32>,
    /// Below this degree of linear polarisation the angle is not shown (grey).
    #[arg(long, value_name = "DOLP", default_value_t = 0.02)]
    min_dolp: f32,
    /// Panels per row: 4 side by side, 2 for a 2 × 2 grid, 1 for a column.
    #[arg(long, value_name = "N", default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=4))]
    columns: u32,
    /// Exposure of the S0 preview in stops.
    #[arg(long, value_name = "EV", default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
}

/// A colour channel of the Stokes layers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Channel {
    /// Red.
    #[value(name = "R")]
    R,
    /// Green.
    #[value(name = "G")]
    G,
    /// Blue.
    #[value(name = "B")]
    B,
    /// CIE Y, 0.2126 R + 0.7152 G + 0.0722 B.
    #[value(name = "Y")]
    Y,
}

impl Channel {
    /// The weights of (R, G, B).
    fn weights(self) -> [f32; 3] {
        match self {
            Channel::R => [1.0, 0.0, 0.0],
            Channel::G => [0.0, 1.0, 0.0],
            Channel::B => [0.0, 0.0, 1.0],
            Channel::Y => [0.2126, 0.7152, 0.0722],
        }
    }
}

/// Runs `prisma polviz`.
pub fn run(args: &PolvizArgs) -> Result<(), CliError> {
    if !(args.min_dolp.is_finite() && (0.0..=1.0).contains(&args.min_dolp)) {
        return Err(CliError::Input(anyhow!("--min-dolp must be in [0, 1], got {}", args.min_dolp)));
    }
    if !args.exposure.is_finite() {
        return Err(CliError::Input(anyhow!("--exposure must be finite, got {}", args.exposure)));
    }
    let output = args.output.clone().unwrap_or_else(|| default_output(&args.input));
    let is_png = output.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        return Err(CliError::Input(anyhow!("{}: the output must be a .png file", output.display())));
    }
    check_destination(&output).map_err(|e| CliError::Input(e.into()))?;
    check_not_inputs([("-o", output.as_path())], &[(args.input.as_path(), "the image being mapped")])
        .map_err(|e| CliError::Input(e.into()))?;
    let exr = read_input(&args.input).map_err(CliError::Input)?;
    let image = stokes_image(&exr, &args.input, args.channel, args.wavelength).map_err(CliError::Input)?;
    let options =
        Options { min_dolp: args.min_dolp, columns: args.columns as usize, exposure_ev: args.exposure };
    let canvas = figure::draw(&image, &options).map_err(CliError::Input)?;
    write_file(&output, |sink| {
        encode_png_compact(sink, &output, &canvas.pixels, (canvas.width, canvas.height))
    })
    .map_err(|e| output_error(e, "writing the figure"))?;
    say!("{}", summary(&image, args.min_dolp));
    say!("wrote {}", output.display());
    Ok(())
}

/// `dir/NAME_polviz.png` for `dir/NAME.exr`.
fn default_output(input: &Path) -> PathBuf {
    let stem = input.file_stem().map_or_else(|| "polviz".into(), |s| s.to_string_lossy().into_owned());
    input.with_file_name(format!("{stem}_polviz.png"))
}

fn read_input(path: &Path) -> anyhow::Result<ExrImage> {
    if !path.is_file() {
        return Err(anyhow!("{}: no such file", path.display()));
    }
    read_exr(path).map_err(|e| match e {
        OutputError::Codec { message, .. } => {
            anyhow!("{}: not a readable OpenEXR image ({message})", path.display())
        }
        OutputError::Io { source, .. } => anyhow!("{}: {source}", path.display()),
        e @ OutputError::Destination { .. } => e.into(),
    })
}

/// The wavelength (nm) of a Fichet channel `S<k>.<λ>nm` of component `k`, e.g.
/// `S1.550,000000nm` → 550.
fn spectral_channel_nm(name: &str, k: usize) -> Option<f32> {
    let number = name.strip_prefix(&format!("S{k}."))?.strip_suffix("nm")?;
    number.replace(',', ".").parse::<f32>().ok().filter(|nm| nm.is_finite())
}

/// The Stokes components of the channel asked for.
fn stokes_image(
    exr: &ExrImage,
    path: &Path,
    channel: Option<Channel>,
    wavelength: Option<f32>,
) -> anyhow::Result<StokesImage> {
    let name = path.display();
    let has = |channel: &str| exr.channel(channel).is_some();
    let spectral: Vec<(f32, String)> =
        exr.channel_names().filter_map(|n| spectral_channel_nm(n, 0).map(|nm| (nm, n.to_owned()))).collect();
    let colour_stokes = (1..4).all(|k| has(&format!("S{k}.R")));
    let spectral_stokes = spectral
        .iter()
        .any(|(nm, _)| (1..4).all(|k| exr.channel_names().any(|n| spectral_channel_nm(n, k) == Some(*nm))));
    if !colour_stokes && !spectral_stokes {
        return Err(if has("S0.R") || has("R") || !spectral.is_empty() {
            anyhow!("{name}: no Stokes layers S1–S3: an unpolarised render (render it without --unpolarized or `polarized = false`)")
        } else {
            anyhow!("{name}: no Stokes layers S0–S3: not a polarised prisma render")
        });
    }
    let pixels = exr.width as usize * exr.height as usize;
    if colour_stokes && wavelength.is_none() {
        let channel = channel.unwrap_or(Channel::Y);
        let weights = channel.weights();
        let component = |k: usize| -> anyhow::Result<Vec<f32>> {
            let rgb = ["R", "G", "B"].map(|c| {
                exr.channel(&format!("S{k}.{c}")).ok_or_else(|| anyhow!("{name}: channel S{k}.{c} missing"))
            });
            let [r, g, b] = rgb;
            let (r, g, b) = (r?, g?, b?);
            Ok((0..pixels).map(|i| weights[0] * r[i] + weights[1] * g[i] + weights[2] * b[i]).collect())
        };
        let components = [component(0)?, component(1)?, component(2)?, component(3)?];
        let preview = exr
            .rgb(["S0.R", "S0.G", "S0.B"])
            .ok_or_else(|| anyhow!("{name}: channels S0.R, S0.G, S0.B missing"))?
            .into_iter()
            .map(|v| v.to_array())
            .collect();
        let description = match channel {
            Channel::Y => format!("{name}: CIE Y of S0–S3 (Rec. 709 weights of their linear sRGB)"),
            other => format!("{name}: channel {other:?} of S0–S3 (linear sRGB)"),
        };
        return Ok(StokesImage {
            width: exr.width,
            height: exr.height,
            components,
            preview,
            preview_title: "S0 (linear sRGB preview)".into(),
            description,
        });
    }
    if channel.is_some() {
        return Err(anyhow!(
            "{name}: --channel needs the RGB Stokes layers, and this single-wavelength render has none"
        ));
    }
    // A spectral band (colour render with --wavelength) or the one wavelength of a
    // monochromatic render: the S0 band nearest the wavelength asked for that has S1–S3 too.
    let target = wavelength.unwrap_or(0.0);
    let (nm, _) = spectral
        .iter()
        .filter(|(nm, _)| (1..4).all(|k| exr.channel_names().any(|n| spectral_channel_nm(n, k) == Some(*nm))))
        .min_by(|a, b| (a.0 - target).abs().total_cmp(&(b.0 - target).abs()))
        .ok_or_else(|| {
            anyhow!("{name}: no spectral Stokes channels S0–S3.<λ>nm; render with --spectral-bands N")
        })?;
    let component = |k: usize| -> anyhow::Result<Vec<f32>> {
        let channel = exr
            .channel_names()
            .find(|n| spectral_channel_nm(n, k) == Some(*nm))
            .and_then(|n| exr.channel(n))
            .ok_or_else(|| anyhow!("{name}: channel S{k} at {nm} nm missing"))?;
        Ok(channel.to_vec())
    };
    let components = [component(0)?, component(1)?, component(2)?, component(3)?];
    let preview = components[0].iter().map(|&v| [v; 3]).collect();
    Ok(StokesImage {
        width: exr.width,
        height: exr.height,
        components,
        preview,
        preview_title: format!("S0 at {nm} nm (radiance)"),
        description: format!("{name}: Stokes components at {nm} nm (S<k>.<λ>nm channels)"),
    })
}

/// One line on what the maps show: the largest DoLP and |S3/S0| over lit pixels.
fn summary(image: &StokesImage, min_dolp: f32) -> String {
    let floor = figure::s0_floor(&image.components[0]);
    let (mut lit, mut polarised, mut max_dolp, mut max_circular) = (0usize, 0usize, 0f32, 0f32);
    for i in 0..image.components[0].len() {
        let s = [0, 1, 2, 3].map(|k| image.components[k][i]);
        if let Some(p) = figure::polarisation(s, floor) {
            lit += 1;
            polarised += usize::from(p.dolp >= min_dolp);
            max_dolp = max_dolp.max(p.dolp);
            max_circular = max_circular.max(p.circular.abs());
        }
    }
    format!(
        "{}×{}: {lit} lit pixels, {polarised} with DoLP ≥ {min_dolp}; largest DoLP {max_dolp:.3}, largest |S3/S0| {max_circular:.3}",
        image.width, image.height
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fichet_channel_names_give_their_wavelength() {
        assert_eq!(spectral_channel_nm("S0.550,000000nm", 0), Some(550.0));
        assert_eq!(spectral_channel_nm("S3.372,500000nm", 3), Some(372.5));
        assert_eq!(spectral_channel_nm("S3.372,500000nm", 1), None);
        assert_eq!(spectral_channel_nm("S0.R", 0), None);
        assert_eq!(spectral_channel_nm("S0.xnm", 0), None);
    }

    #[test]
    fn default_output_sits_beside_the_input() {
        assert_eq!(default_output(Path::new("out/tp6.exr")), PathBuf::from("out/tp6_polviz.png"));
    }
}
