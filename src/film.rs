//! [`Film`]: the rendered image as per-pixel mean CIE XYZ (or, in monochromatic mode, mean
//! spectral radiance at one wavelength), with its linear sRGB view.

use glam::Vec3;

use crate::spectrum::color::xyz_to_linear_srgb;

/// A pixel whose value is not a finite number: radiance overflowed f32 somewhere in its samples.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "pixel ({x}, {y}) is not finite (XYZ = {xyz}): the scene's radiance overflows 32-bit floats there \
     (see the limits in scenes/README.md)"
)]
pub struct NonFinitePixel {
    /// Column, from the left.
    pub x: u32,
    /// Row, from the top.
    pub y: u32,
    /// Its value.
    pub xyz: Vec3,
}

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
    /// The first pixel (row-major) that is not finite in XYZ or in linear sRGB (the conversion
    /// can overflow a finite XYZ near f32's limit), if any. Checked in every build: a NaN would
    /// otherwise be silently black in the PNG preview.
    pub fn check_finite(&self) -> Result<(), NonFinitePixel> {
        let bad = |&(_, xyz): &(usize, &Vec3)| match self.monochromatic_nm {
            Some(_) => !xyz.is_finite(),
            None => !(xyz.is_finite() && xyz_to_linear_srgb(*xyz).is_finite()),
        };
        match self.xyz.iter().enumerate().find(bad) {
            None => Ok(()),
            Some((index, &xyz)) => Err(NonFinitePixel {
                x: (index % self.width as usize) as u32,
                y: (index / self.width as usize) as u32,
                xyz,
            }),
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A NaN or infinite pixel is an error naming its column and row (row-major, top first);
    /// it used to be written, and showed as black in the PNG.
    #[test]
    fn nan_pixels_are_named() {
        let mut xyz = vec![Vec3::splat(0.5); 6];
        let film = Film::new(3, 2, xyz.clone(), None);
        assert_eq!(film.check_finite(), Ok(()));
        xyz[4] = Vec3::new(0.1, f32::NAN, 0.2);
        let error = Film::new(3, 2, xyz.clone(), None).check_finite().expect_err("NaN");
        assert_eq!((error.x, error.y), (1, 1));
        assert!(error.to_string().contains("pixel (1, 1)"), "{error}");
        // A finite XYZ near f32's limit whose sRGB overflows is caught too.
        xyz[4] = Vec3::new(3e38, 0.0, 0.0);
        assert!(Film::new(3, 2, xyz, None).check_finite().is_err());
    }
}
