//! Byte-level surgery on prisma's part files, for the tests that feed `merge`, `--resume` and
//! `info` altered parts (`tests/part_trust.rs`, `tests/part_fuzz.rs`).
//!
//! A part is a single-part scan-line EXR written uncompressed: the magic and version (8 bytes),
//! attributes (name, NUL, type, NUL, i32 size, value) up to a NUL, then an offset table of one
//! u64 per chunk (absolute file offsets), then the chunks. Changing an attribute's length moves
//! every chunk, so [`ExrFile::to_bytes`] rewrites the offset table by the difference.

#![allow(dead_code)] // Each test binary uses a different part of this module.

use std::path::Path;

/// An EXR's header attributes, and everything after them (offset table and chunks).
#[derive(Debug, Clone)]
pub struct ExrFile {
    /// The 8 bytes of magic number and version.
    pub start: [u8; 8],
    /// (name, type, value bytes) in file order.
    pub attributes: Vec<(String, String, Vec<u8>)>,
    /// The bytes after the header's closing NUL.
    pub rest: Vec<u8>,
    /// Chunks in the offset table (the data window's height for a part).
    pub chunks: usize,
}

impl ExrFile {
    /// Parses `bytes` (panics on a file that is not a prisma part: tests only).
    pub fn parse(bytes: &[u8]) -> Self {
        assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01], "not an EXR");
        let mut start = [0u8; 8];
        start.copy_from_slice(&bytes[..8]);
        let mut position = 8;
        let mut attributes = Vec::new();
        let text_to_nul = |position: &mut usize| {
            let end = *position + bytes[*position..].iter().position(|&b| b == 0).expect("NUL");
            let text = String::from_utf8_lossy(&bytes[*position..end]).into_owned();
            *position = end + 1;
            text
        };
        while bytes[position] != 0 {
            let name = text_to_nul(&mut position);
            let kind = text_to_nul(&mut position);
            let size =
                i32::from_le_bytes(bytes[position..position + 4].try_into().expect("4 bytes")) as usize;
            position += 4;
            attributes.push((name, kind, bytes[position..position + size].to_vec()));
            position += size;
        }
        let mut file = Self { start, attributes, rest: bytes[position + 1..].to_vec(), chunks: 0 };
        let (_, y0, _, y1) = file.data_window();
        file.chunks = (y1 - y0 + 1) as usize;
        file
    }

    /// Reads the part at `path`.
    pub fn read(path: &Path) -> Self {
        Self::parse(&std::fs::read(path).expect("readable part"))
    }

    /// The bytes of the file, with the offset table moved by the header's change in length.
    pub fn to_bytes(&self, original_header_length: usize) -> Vec<u8> {
        let mut out = self.start.to_vec();
        for (name, kind, value) in &self.attributes {
            out.extend(name.as_bytes());
            out.push(0);
            out.extend(kind.as_bytes());
            out.push(0);
            out.extend((value.len() as i32).to_le_bytes());
            out.extend(value);
        }
        out.push(0);
        let shift = out.len() as i64 - original_header_length as i64;
        let mut rest = self.rest.clone();
        for chunk in 0..self.chunks.min(rest.len() / 8) {
            let entry = &mut rest[chunk * 8..chunk * 8 + 8];
            let offset = u64::from_le_bytes(entry.try_into().expect("8 bytes")) as i64 + shift;
            entry.copy_from_slice(&(offset as u64).to_le_bytes());
        }
        out.extend(rest);
        out
    }

    /// The header's length in bytes (magic to closing NUL), as [`Self::to_bytes`] needs it.
    pub fn header_length(&self) -> usize {
        8 + self.attributes.iter().map(|(n, k, v)| n.len() + k.len() + 6 + v.len()).sum::<usize>() + 1
    }

    /// The text of a string attribute.
    pub fn text(&self, name: &str) -> Option<String> {
        self.attributes
            .iter()
            .find(|(n, _, _)| n == name)
            .map(|(_, _, value)| String::from_utf8_lossy(value).into_owned())
    }

    /// Sets a string attribute (added when missing).
    pub fn set_text(&mut self, name: &str, text: &str) {
        match self.attributes.iter_mut().find(|(n, _, _)| n == name) {
            Some(attribute) => attribute.2 = text.as_bytes().to_vec(),
            None => self.attributes.push((name.into(), "string".into(), text.as_bytes().to_vec())),
        }
    }

    /// A box2i attribute (xMin, yMin, xMax, yMax, inclusive).
    pub fn window(&self, name: &str) -> (i32, i32, i32, i32) {
        let value = &self.attributes.iter().find(|(n, _, _)| n == name).expect("box2i").2;
        let number = |k: usize| i32::from_le_bytes(value[4 * k..4 * k + 4].try_into().expect("4 bytes"));
        (number(0), number(1), number(2), number(3))
    }

    /// The data window.
    pub fn data_window(&self) -> (i32, i32, i32, i32) {
        self.window("dataWindow")
    }

    /// Sets a box2i attribute.
    pub fn set_window(&mut self, name: &str, window: (i32, i32, i32, i32)) {
        let value = &mut self.attributes.iter_mut().find(|(n, _, _)| n == name).expect("box2i").2;
        value.clear();
        for number in [window.0, window.1, window.2, window.3] {
            value.extend(number.to_le_bytes());
        }
    }

    /// Recomputes `prisma.headerBlake3` as prisma does, as someone who edits a header on
    /// purpose would: only the field checks can then refuse the edit.
    pub fn forge_digest(&mut self) {
        let texts: Vec<(String, String)> = self
            .attributes
            .iter()
            .filter(|(name, kind, _)| name.starts_with("prisma.") && kind == "string")
            .map(|(name, _, value)| (name.clone(), String::from_utf8_lossy(value).into_owned()))
            .collect();
        let (dx0, dy0, dx1, dy1) = self.window("displayWindow");
        let (x0, y0, x1, y1) = self.data_window();
        let display = ((dx1 - dx0 + 1) as u32, (dy1 - dy0 + 1) as u32);
        let window = prisma::part::PixelWindow {
            x0: (x0 - dx0) as u32,
            y0: (y0 - dy0) as u32,
            x1: (x1 - dx0 + 1) as u32,
            y1: (y1 - dy0 + 1) as u32,
        };
        let digest = prisma::part::header::header_digest(
            texts.iter().map(|(n, t)| (n.as_str(), t.as_str())),
            display,
            window,
        );
        self.set_text(prisma::part::header::HEADER_DIGEST, &digest);
    }
}

/// `path`'s part with the string attributes `edits` replaced, written to `to`; with `forge`,
/// the header digest is recomputed.
pub fn edit(path: &Path, to: &Path, edits: &[(&str, &str)], forge: bool) {
    let mut file = ExrFile::read(path);
    let length = file.header_length();
    for (name, text) in edits {
        file.set_text(name, text);
    }
    if forge {
        file.forge_digest();
    }
    std::fs::write(to, file.to_bytes(length)).expect("writable");
}
