//! [`Film`]: the rendered image as per-pixel mean CIE XYZ (or, in monochromatic mode, mean
//! spectral radiance at one wavelength), with its linear sRGB view.

use glam::Vec3;

use crate::spectrum::color::xyz_to_linear_srgb;

/// A finished image: row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    xyz: Vec<Vec3>,
    monochromatic_nm: Option<f32>,
}

impl Film {
    /// A film from per-pixel XYZ values (or radiance in all three channels when
    /// `monochromatic_nm` is set). Panics if `xyz.len() != width·height`.
    pub fn new(width: u32, height: u32, xyz: Vec<Vec3>, monochromatic_nm: Option<f32>) -> Self {
        assert_eq!(xyz.len(), width as usize * height as usize, "film size mismatch");
        Self { width, height, xyz, monochromatic_nm }
    }
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Per-pixel CIE XYZ (monochromatic mode: radiance L in every channel).
    pub fn xyz(&self) -> &[Vec3] {
        &self.xyz
    }
    /// The wavelength (nm) of a monochromatic render.
    pub fn monochromatic_nm(&self) -> Option<f32> {
        self.monochromatic_nm
    }
    /// Per-pixel linear sRGB (Rec. 709 primaries, D65 white). In monochromatic mode, the
    /// radiance in all three channels (a grey image).
    pub fn linear_srgb(&self) -> Vec<Vec3> {
        match self.monochromatic_nm {
            Some(_) => self.xyz.clone(),
            None => self.xyz.iter().map(|&xyz| xyz_to_linear_srgb(xyz)).collect(),
        }
    }
}
