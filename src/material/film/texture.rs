//! A film's thickness read from a greyscale image (issue 41: "a soap film of a thickness that
//! may vary across the surface, e.g. … from a texture").
//!
//! **Projection**: planar. The image is laid on the parallelogram `corner + s·edge1 + t·edge2`
//! (s, t in [0, 1]; the same three vectors as a `quad` shape), its columns along `edge1` (left to
//! right) and its rows along `edge2` (bottom to top: the image's first row is at t = 1), and
//! projected onto the surface along `edge1 × edge2`: a point p of the surface takes the (s, t)
//! of its projection onto the parallelogram's plane. Beyond the parallelogram the edge pixels
//! continue (clamp to edge). prisma's shapes carry no texture coordinates, so a planar projection
//! is the one mapping every shape shares; a curved film (a bubble) is seen through it like a
//! slide projected onto it.
//!
//! **Lookup**: bilinear between pixel centres (pixel (i, j) is the value at
//! s = (i + ½)/width, t = 1 − (j + ½)/height). **Value**: the grey level g in [0, 1] (8-bit
//! levels / 255, 16-bit / 65535) maps linearly to `min + g·(max − min)` nm.
//!
//! ```toml
//! [materials.soap]
//! type = "film"
//! thickness_nm = { texture = "soap_film_thickness.png", min = 150, max = 900,
//!                  corner = [-1, -1, 0], edge1 = [2, 0, 0], edge2 = [0, 2, 0] }
//! ```
//! The path is relative to the scene file; the image's bytes enter the scene digest
//! (`scene::digest`), so parts of a render cannot merge across an edited texture.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

/// Largest accepted width or height of a thickness texture, in pixels (a 16-bit 8192² image is
/// 128 MiB decoded; its f32 grey levels 256 MiB).
pub const MAX_TEXTURE_SIZE: u32 = 8192;

/// A greyscale image mapped onto a surface by a planar projection (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct ThicknessTexture {
    /// Grey levels in [0, 1], row by row from the top row, `width` per row.
    levels: Arc<[f32]>,
    width: u32,
    height: u32,
    /// Thickness (nm) at grey level 0.
    pub min_nm: f32,
    /// Thickness (nm) at grey level 1, ≥ `min_nm`.
    pub max_nm: f32,
    /// The parallelogram's corner at (s, t) = (0, 0) (scene units).
    corner: Vec3,
    /// s = (p − corner)·`dual1`, t = (p − corner)·`dual2`: the dual basis of edge1, edge2 in
    /// their plane (so a point off the plane projects along their normal).
    dual1: Vec3,
    dual2: Vec3,
}

impl ThicknessTexture {
    /// Reads the greyscale PNG (8 or 16 bits, with or without alpha, which is ignored) at
    /// `path` and lays it on `corner + s·edge1 + t·edge2`; thickness `min_nm` at black and
    /// `max_nm` at white. The caller has checked the numbers (finite, 0 ≤ min ≤ max, edges
    /// not parallel); the error is a one-line message naming the file.
    pub fn load(
        path: &Path,
        min_nm: f32,
        max_nm: f32,
        corner: Vec3,
        edge1: Vec3,
        edge2: Vec3,
    ) -> Result<Self, String> {
        let shown = path.display();
        let bytes = std::fs::read(path).map_err(|err| format!("cannot read '{shown}': {err}"))?;
        let image = image::load_from_memory(&bytes)
            .map_err(|err| format!("'{shown}' is not a readable PNG image: {err}"))?;
        let (width, height) = (image.width(), image.height());
        if width == 0 || height == 0 || width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE {
            return Err(format!(
                "'{shown}' is {width}×{height} pixels: width and height must be 1–{MAX_TEXTURE_SIZE}"
            ));
        }
        let levels: Arc<[f32]> = match image {
            image::DynamicImage::ImageLuma8(grey) => {
                grey.pixels().map(|p| f32::from(p.0[0]) / 255.0).collect()
            }
            image::DynamicImage::ImageLumaA8(grey) => {
                grey.pixels().map(|p| f32::from(p.0[0]) / 255.0).collect()
            }
            image::DynamicImage::ImageLuma16(grey) => {
                grey.pixels().map(|p| f32::from(p.0[0]) / 65535.0).collect()
            }
            image::DynamicImage::ImageLumaA16(grey) => {
                grey.pixels().map(|p| f32::from(p.0[0]) / 65535.0).collect()
            }
            other => {
                return Err(format!(
                    "'{shown}' must be a greyscale image (8 or 16 bits), got {:?}",
                    other.color()
                ))
            }
        };
        let normal = edge1.cross(edge2);
        let normal_sqr = normal.length_squared();
        Ok(Self {
            levels,
            width,
            height,
            min_nm,
            max_nm,
            corner,
            dual1: edge2.cross(normal) / normal_sqr,
            dual2: normal.cross(edge1) / normal_sqr,
        })
    }

    /// Image width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The thickness (nm) at the surface point `point` (scene units).
    #[inline]
    pub fn at(&self, point: Vec3) -> f32 {
        let offset = point - self.corner;
        let (s, t) = (offset.dot(self.dual1), offset.dot(self.dual2));
        // Continuous pixel coordinates, pixel centres at integers: x from the left, y from the
        // top row.
        let x = (s * self.width as f32 - 0.5).clamp(0.0, (self.width - 1) as f32);
        let y = ((1.0 - t) * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        // NaN (a non-finite point) clamps to NaN; `as` takes it to 0, a valid pixel.
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i0, j0) = (x0 as usize, y0 as usize);
        let i1 = (i0 + 1).min(self.width as usize - 1);
        let j1 = (j0 + 1).min(self.height as usize - 1);
        let row = self.width as usize;
        let level = |i: usize, j: usize| self.levels.get(j * row + i).copied().unwrap_or(0.0);
        let top = level(i0, j0) + (level(i1, j0) - level(i0, j0)) * fx;
        let bottom = level(i0, j1) + (level(i1, j1) - level(i0, j1)) * fx;
        let grey = top + (bottom - top) * fy;
        let thickness = self.min_nm + (self.max_nm - self.min_nm) * grey;
        if thickness.is_finite() {
            thickness
        } else {
            self.min_nm
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes a 16-bit greyscale PNG of `width` × `height` levels (row by row from the top).
    fn png16(dir: &Path, width: u32, height: u32, levels: &[u16]) -> std::path::PathBuf {
        let path = dir.join("t.png");
        image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(width, height, levels.to_vec())
            .expect("the buffer fits")
            .save(&path)
            .expect("the PNG is written");
        path
    }

    /// A 2 × 2 image on the unit square of the z = 0 plane: the pixel centres take their own
    /// levels exactly, the middle their mean, and the corners of the square (beyond the centres)
    /// the nearest pixel; points off the plane project along z; min + g·(max − min).
    #[test]
    fn bilinear_lookup_and_planar_projection() {
        let dir = tempfile::tempdir().expect("a temporary directory");
        // Top row: 0, 65535; bottom row: 13107 (0.2), 65535.
        let path = png16(dir.path(), 2, 2, &[0, 65535, 13107, 65535]);
        let texture = ThicknessTexture::load(&path, 100.0, 600.0, Vec3::ZERO, Vec3::X, Vec3::Y)
            .expect("the texture loads");
        assert_eq!(texture.size(), (2, 2));
        let at = |s: f32, t: f32, z: f32| texture.at(Vec3::new(s, t, z));
        assert_eq!(at(0.25, 0.75, 0.0), 100.0); // top left
        assert_eq!(at(0.75, 0.75, 0.0), 600.0); // top right
        assert!((at(0.25, 0.25, 0.0) - 200.0).abs() < 1e-3); // bottom left: 0.2
        assert_eq!(at(0.0, 1.0, 0.0), 100.0); // clamped to the top-left pixel
        assert_eq!(at(-5.0, 9.0, 3.0), 100.0);
        // The middle: the mean of 0, 1, 0.2, 1 = 0.55 → 375 nm.
        assert!((at(0.5, 0.5, 0.0) - 375.0).abs() < 1e-3);
        assert!((at(0.5, 0.5, -7.0) - 375.0).abs() < 1e-3);
    }

    /// Colour images are refused with a message naming the file.
    #[test]
    fn a_colour_image_is_refused() {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let path = dir.path().join("rgb.png");
        image::RgbImage::new(2, 2).save(&path).expect("the PNG is written");
        let err = ThicknessTexture::load(&path, 100.0, 600.0, Vec3::ZERO, Vec3::X, Vec3::Y)
            .expect_err("an RGB image is refused");
        assert!(err.contains("rgb.png") && err.contains("greyscale"), "{err}");
    }
}
