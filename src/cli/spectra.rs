//! `prisma spectra`: every spectrum of a scene as prisma evaluates it, tabulated per nm, as JSON.
//!
//! The Mitsuba translation scripts in `validation/mitsuba/` read this instead of re-implementing
//! prisma's RGB upsampling, so a difference in upsampling can neither cause nor hide a validation
//! failure.

use std::path::PathBuf;

use anyhow::{anyhow, Context};
use clap::Args;
use serde_json::{json, Map, Value};

use super::CliError;
use prisma::light::Light;
use prisma::material::Material;
use prisma::optics::Ior;
use prisma::spectrum::{Spectrum, LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// Arguments of `prisma spectra`.
#[derive(Debug, Args)]
pub struct SpectraArgs {
    /// Scene file.
    scene: PathBuf,
    /// Output JSON file [default: standard output].
    #[arg(short, long, value_name = "OUT.json")]
    output: Option<PathBuf>,
    /// Wavelength step in nm.
    #[arg(long, value_name = "NM", default_value_t = 1.0)]
    step_nm: f32,
}

/// Runs `prisma spectra`.
pub fn run(args: &SpectraArgs) -> Result<(), CliError> {
    if !(args.step_nm.is_finite() && args.step_nm >= 0.1 && args.step_nm <= 100.0) {
        return Err(CliError::Input(anyhow!("--step-nm must be in [0.1, 100], got {}", args.step_nm)));
    }
    let scene = prisma::scene::load(&args.scene).map_err(|e| CliError::Input(e.into()))?;
    let count = ((LAMBDA_MAX_NM - LAMBDA_MIN_NM) / args.step_nm).floor() as usize + 1;
    let grid: Vec<f32> = (0..count).map(|i| LAMBDA_MIN_NM + i as f32 * args.step_nm).collect();
    let table = |s: &Spectrum| Value::from(grid.iter().map(|&l| f64::from(s.eval(l))).collect::<Vec<_>>());
    let ior_table = |n: &Ior| Value::from(grid.iter().map(|&l| f64::from(n.eval(l))).collect::<Vec<_>>());

    let mut materials = Map::new();
    for (name, material) in scene.material_names.iter().zip(&scene.materials) {
        let value = match material {
            Material::Diffuse(d) => json!({ "type": "diffuse", "albedo": table(&d.albedo) }),
            Material::Mirror(m) => json!({ "type": "mirror", "reflectance": table(&m.reflectance) }),
            Material::Dielectric(d) => json!({
                "type": "dielectric",
                "ior": ior_table(&d.ior),
                "dispersive": d.ior.is_dispersive(),
                "absorption": d.absorption.as_ref().map(table),
            }),
            Material::Black => json!({ "type": "black" }),
        };
        materials.insert(name.clone(), value);
    }
    let lights: Vec<Value> = scene
        .lights
        .iter()
        .map(|light| match light {
            Light::Point(p) => json!({ "type": "point", "intensity": table(&p.intensity) }),
            Light::Quad(q) => json!({ "type": "quad", "radiance": table(&q.radiance) }),
        })
        .collect();
    let document = json!({
        "scene": args.scene.display().to_string(),
        "wavelengths_nm": grid.iter().map(|&l| f64::from(l)).collect::<Vec<_>>(),
        "background": table(&scene.background),
        "materials": materials,
        "lights": lights,
    });
    let text = serde_json::to_string_pretty(&document).map_err(|e| CliError::Failed(e.into()))?;
    match &args.output {
        Some(path) => prisma::output::atomic::write_atomically(path, |tmp| {
            std::fs::write(tmp, &text).map_err(|source| prisma::output::OutputError::Io {
                path: path.display().to_string(),
                source,
            })
        })
        .context("writing the spectra")
        .map_err(CliError::Failed)?,
        None => println!("{text}"),
    }
    Ok(())
}
