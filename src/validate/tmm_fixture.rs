//! The thin-film fixtures of the `tmm` package (Byrnes, arXiv:1603.02720; tmm 0.2.0, written by
//! `validation/thinfilm/make_fixtures.py` into `tests/fixtures/thin_film_<case>.csv`), embedded
//! so that `prisma validate` can compare coated renders with an external transfer-matrix code
//! rather than with prisma's own (`optics::thin_film`). Each file's `#` header holds the stack;
//! its rows hold the amplitudes in prisma's conventions (e^{+iωt}, Hecht's r_p; the generator
//! conjugates tmm's).

use num_complex::Complex64;

use super::ValidateError;

/// 100 nm of SiO₂ (1.46) on gold (0.18 + 3.43i), from air.
pub const SIO2_ON_GOLD: &str = include_str!("../../tests/fixtures/thin_film_sio2_on_gold.csv");
/// A quarter wave of MgF₂ (1.38) at 550 nm on N-BK7 (1.5168), from air.
pub const MGF2_ON_BK7: &str = include_str!("../../tests/fixtures/thin_film_mgf2_on_bk7.csv");

/// One fixture: its stack and its rows (λ nm, θ degrees, r_s, r_p).
#[derive(Debug, Clone)]
pub struct TmmFixture {
    /// The file's name, for messages.
    pub name: String,
    /// Layers from the ambient side: (n + ik, thickness nm).
    pub layers: Vec<(Complex64, f64)>,
    /// The substrate's n + ik.
    pub substrate: Complex64,
    rows: Vec<(f64, f64, Complex64, Complex64)>,
}

/// Column header of the fixtures.
const COLUMNS: &str = "wavelength_nm,theta_deg,R_s,R_p,T_s,T_p,psi_deg,delta_deg,\
r_s_re,r_s_im,r_p_re,r_p_im,t_s_re,t_s_im,t_p_re,t_p_im";

impl TmmFixture {
    /// Reads the fixture `text` (named `name` in errors). The ambient must be vacuum (n = 1),
    /// as in a scene.
    pub fn parse(name: &str, text: &str) -> Result<Self, ValidateError> {
        let bad = |what: &str| ValidateError::Input(format!("{name}: {what}"));
        let header = |key: &str| {
            text.lines()
                .find_map(|line| line.strip_prefix(&format!("# {key}: ")))
                .ok_or_else(|| bad(&format!("no '# {key}:' line")))
        };
        let numbers = |line: &str| -> Result<Vec<f64>, ValidateError> {
            line.split(|c: char| c.is_whitespace() || c == ',')
                .filter(|field| !field.is_empty())
                .map(|field| field.parse().map_err(|_| bad(&format!("not a number: {field:?}"))))
                .collect()
        };
        if numbers(header("ambient")?)? != [1.0, 0.0] {
            return Err(bad("the ambient is not vacuum"));
        }
        let mut layers = Vec::new();
        for layer in header("layers")?.split(';') {
            match numbers(layer)?[..] {
                [n, k, thickness_nm] => layers.push((Complex64::new(n, k), thickness_nm)),
                _ => return Err(bad(&format!("layer {layer:?} is not `n k thickness`"))),
            }
        }
        let substrate = match numbers(header("substrate")?)?[..] {
            [n, k] => Complex64::new(n, k),
            _ => return Err(bad("the substrate is not `n k`")),
        };
        let mut lines = text.lines().filter(|line| !line.starts_with('#'));
        if lines.next() != Some(COLUMNS) {
            return Err(bad("unexpected columns"));
        }
        let rows = lines
            .map(|line| {
                let v = numbers(line)?;
                if v.len() != 16 {
                    return Err(bad(&format!("row {line:?}")));
                }
                Ok((v[0], v[1], Complex64::new(v[8], v[9]), Complex64::new(v[10], v[11])))
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { name: name.into(), layers, substrate, rows })
    }

    /// (r_s, r_p) at `lambda_nm` and `theta_deg`, if the fixture has that row.
    pub fn reflection(&self, lambda_nm: f64, theta_deg: f64) -> Option<(Complex64, Complex64)> {
        self.rows
            .iter()
            .find(|row| row.0 == lambda_nm && row.1 == theta_deg)
            .map(|&(_, _, r_s, r_p)| (r_s, r_p))
    }

    /// The stack as a scene's `coating = [...]` list (without the brackets).
    pub fn coating_toml(&self) -> String {
        self.layers
            .iter()
            .map(|(index, thickness_nm)| {
                if index.im == 0.0 {
                    format!("{{ ior = {}, thickness_nm = {thickness_nm} }}", index.re)
                } else {
                    format!("{{ complex_ior = [{}, {}], thickness_nm = {thickness_nm} }}", index.re, index.im)
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}
