//! `prisma export`: a scene as prisma resolved it, for other renderers: `spectra.json` (every
//! spectrum and IOR tabulated per nm) and `mesh_<k>.obj` (the k-th mesh or prism shape of the
//! file, triangles in scene space, counter-clockwise seen from outside).
//!
//! The Mitsuba translation scripts in `validation/mitsuba/` read these instead of re-implementing
//! prisma's RGB upsampling or prism construction, so a difference there can neither cause nor
//! hide a validation failure.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::anyhow;
use clap::Args;
use serde_json::{json, Map, Value};

use super::{output_error, say, CliError};
use prisma::light::Light;
use prisma::material::{Conductor, Material, Thickness};
use prisma::optics::Ior;
use prisma::output::file::{check_destination, check_not_inputs, text_into, Outputs};
use prisma::spectrum::{DenseSpectrum, LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// Arguments of `prisma export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Scene file.
    scene: PathBuf,
    /// Output directory (created if needed; removed again if the export fails).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Wavelength step in nm.
    #[arg(long, value_name = "NM", default_value_t = 1.0, allow_negative_numbers = true)]
    step_nm: f32,
}

/// Runs `prisma export`.
pub fn run(args: &ExportArgs) -> Result<(), CliError> {
    if !(args.step_nm.is_finite() && args.step_nm >= 0.1 && args.step_nm <= 100.0) {
        return Err(CliError::Input(anyhow!("--step-nm must be in [0.1, 100], got {}", args.step_nm)));
    }
    let scene = prisma::scene::load(&args.scene).map_err(|e| CliError::Input(e.into()))?;
    let spectra_path = args.output.join("spectra.json");
    check_destination(&spectra_path).map_err(|e| CliError::Input(e.into()))?;
    let mesh_paths: Vec<PathBuf> =
        (0..scene.geometry.meshes().len()).map(|k| args.output.join(format!("mesh_{k}.obj"))).collect();
    let mut inputs: Vec<(&Path, &str)> = vec![(&args.scene, "the scene file")];
    inputs.extend(scene.input_files.iter().map(|(file, what)| (file.as_path(), *what)));
    let outputs = std::iter::once(&spectra_path).chain(&mesh_paths).map(|path| ("-o", path.as_path()));
    check_not_inputs(outputs, &inputs).map_err(|e| CliError::Input(e.into()))?;
    let count = ((LAMBDA_MAX_NM - LAMBDA_MIN_NM) / args.step_nm).floor() as usize + 1;
    let grid: Vec<f32> = (0..count).map(|i| LAMBDA_MIN_NM + i as f32 * args.step_nm).collect();
    let table =
        |s: &DenseSpectrum| Value::from(grid.iter().map(|&l| f64::from(s.eval(l))).collect::<Vec<_>>());
    let ior_table = |n: &Ior| Value::from(grid.iter().map(|&l| f64::from(n.eval(l))).collect::<Vec<_>>());

    let mut materials = Map::new();
    for (name, material) in scene.material_names.iter().zip(&scene.materials) {
        let value = match material {
            Material::Diffuse(d) => json!({ "type": "diffuse", "albedo": table(&d.albedo) }),
            Material::Mirror(m) => json!({
                "type": "mirror",
                "reflectance": table(&m.reflectance),
                "metal": match m.conductor {
                    Conductor::Metal(metal) => Some(metal.name()),
                    _ => None,
                },
                "complex_ior": match m.conductor {
                    Conductor::Index(eta) => Some([eta.re, eta.im]),
                    _ => None,
                },
            }),
            Material::Polarizer(p) => json!({
                "type": "polarizer",
                "axis": p.axis.to_array(),
                "transmittance": table(&p.transmittance),
            }),
            Material::Retarder(r) => json!({
                "type": "retarder",
                "fast_axis": r.fast_axis.to_array(),
                "retardance_deg": r.retardance_rad.to_degrees(),
            }),
            Material::Dielectric(d) => json!({
                "type": "dielectric",
                "ior": ior_table(&d.ior),
                "dispersive": d.ior.is_dispersive(),
                "absorption": d.absorption.as_ref().map(table),
            }),
            Material::Film(f) => json!({
                "type": "film",
                "ior": ior_table(&f.ior),
                "thickness_nm": match &f.thickness {
                    Thickness::Constant(nm) => json!(nm),
                    Thickness::Drained { top_nm, bottom_nm, axis, low, high } => json!({
                        "top": top_nm, "bottom": bottom_nm, "axis": axis.to_array(), "heights": [low, high],
                    }),
                    Thickness::Textured(texture) => json!({
                        "texture_size": texture.size(), "min": texture.min_nm, "max": texture.max_nm,
                    }),
                },
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
            Light::Spot(s) => json!({ "type": "spot", "intensity": table(&s.intensity) }),
            Light::Beam(b) => json!({ "type": "beam", "irradiance": table(&b.irradiance) }),
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
    let mut outputs = Outputs::new();
    let mut written = vec![spectra_path.clone()];
    outputs
        .stage(&spectra_path, |sink| text_into(sink, &spectra_path, &text))
        .map_err(|e| output_error(e, "writing the spectra"))?;
    for (k, (mesh, path)) in scene.geometry.meshes().iter().zip(mesh_paths).enumerate() {
        let mut obj = format!("# mesh {k} of {} as resolved by prisma (scene space)\n", args.scene.display());
        for p in &mesh.positions {
            let _ = writeln!(obj, "v {} {} {}", p.x, p.y, p.z);
        }
        for t in &mesh.triangles {
            let _ = writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        outputs
            .stage(&path, |sink| text_into(sink, &path, &obj))
            .map_err(|e| output_error(e, "writing a mesh"))?;
        written.push(path);
    }
    outputs.commit().map_err(|e| output_error(e, "writing the export"))?;
    for path in written {
        say!("wrote {}", path.display());
    }
    Ok(())
}
