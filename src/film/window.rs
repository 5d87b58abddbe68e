//! [`PixelWindow`]: the pixels a render or a part covers, `x0 ≤ x < x1`, `y0 ≤ y < y1`, in the
//! coordinates of the whole image (column from the left, row from the top). Written to the EXR
//! as its data window, inside a display window of the whole image, as OpenEXR places crops.

use std::fmt;

/// A rectangle of pixels, half-open.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PixelWindow {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelWindow {
    /// The whole `width`×`height` image.
    pub fn full(width: u32, height: u32) -> Self {
        Self { x0: 0, y0: 0, x1: width, y1: height }
    }

    /// Parses `X0,Y0,X1,Y1` and checks it is a non-empty window of a `width`×`height` image.
    pub fn parse(text: &str, width: u32, height: u32) -> Result<Self, String> {
        let numbers: Vec<Option<u32>> = text.split(',').map(|n| n.trim().parse().ok()).collect();
        let [Some(x0), Some(y0), Some(x1), Some(y1)] = numbers[..] else {
            return Err(format!("\"{text}\" is not a pixel window X0,Y0,X1,Y1 (e.g. 0,0,400,225)"));
        };
        let window = Self { x0, y0, x1, y1 };
        if x0 >= x1 || y0 >= y1 || x1 > width || y1 > height {
            return Err(format!(
                "the window {window} is not a non-empty part of the {width}×{height} image \
                 (X0 < X1 ≤ {width}, Y0 < Y1 ≤ {height})"
            ));
        }
        Ok(window)
    }

    /// Columns.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }
    /// Rows.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }
    /// Pixels.
    pub fn pixels(&self) -> usize {
        self.width() as usize * self.height() as usize
    }
    /// True when pixel (`x`, `y`) is inside.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        (self.x0..self.x1).contains(&x) && (self.y0..self.y1).contains(&y)
    }
    /// True when `other` lies inside this window.
    pub fn contains_window(&self, other: &Self) -> bool {
        self.x0 <= other.x0 && self.y0 <= other.y0 && other.x1 <= self.x1 && other.y1 <= self.y1
    }
    /// True when the two windows share a pixel.
    pub fn overlaps(&self, other: &Self) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }
    /// The smallest window holding both.
    pub fn bounding(&self, other: &Self) -> Self {
        Self {
            x0: self.x0.min(other.x0),
            y0: self.y0.min(other.y0),
            x1: self.x1.max(other.x1),
            y1: self.y1.max(other.y1),
        }
    }
}

impl fmt::Display for PixelWindow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_checks_against_the_image() {
        let window = PixelWindow::parse("10, 20, 30, 45", 64, 48).expect("valid");
        assert_eq!((window.width(), window.height(), window.pixels()), (20, 25, 500));
        assert_eq!(window.to_string(), "10,20,30,45");
        assert!(window.contains(10, 44) && !window.contains(30, 20));
        for bad in ["1,2,3", "0,0,65,10", "5,5,5,9", "a,b,c,d", "0,0,10,10,10"] {
            assert!(PixelWindow::parse(bad, 64, 48).is_err(), "{bad}");
        }
        let other = PixelWindow { x0: 30, y0: 0, x1: 64, y1: 48 };
        assert!(!window.overlaps(&other));
        assert_eq!(window.bounding(&other), PixelWindow { x0: 10, y0: 0, x1: 64, y1: 48 });
    }
}
