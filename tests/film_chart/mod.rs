//! Shared by the film tests (`soap_film.rs`, `film_texture.rs`): the interference colour chart
//! as `prisma fresnel --film-colours` writes it.

use std::path::Path;
use std::process::Command;

/// The rows (thickness nm, X, Y, Z) of `prisma fresnel --film-colours --ior 1.333` (a water
/// film in air, D65 normalised to Y = 1), written to `chart.csv` in `dir` and read back.
pub fn water_film_chart(dir: &Path) -> Vec<[f64; 4]> {
    let csv = dir.join("chart.csv");
    let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
        .args(["fresnel", "--film-colours", "--ior", "1.333", "-o"])
        .arg(&csv)
        .output()
        .expect("prisma runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    std::fs::read_to_string(&csv)
        .expect("the chart was written")
        .lines()
        .skip(1)
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().expect("a number")).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}
