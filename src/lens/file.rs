//! Reading a lens file from disk: the format chosen by the extension (`.zmx` → Zemax, anything
//! else → a pbrt-v4 lens file), the text decoded from UTF-8 or UTF-16 with a byte-order mark (as
//! Zemax OpticStudio writes it), then parsed and [validated](LensSystem::validate).

use std::io::Read;
use std::path::Path;

use super::{pbrt, zmx, LensError, LensSystem};

/// The largest lens file read, in bytes: a long Zemax prescription in UTF-16 is ~100 KB, so
/// 4 MiB leaves room and stops a wrong path (an image, a log) from being read whole.
pub const MAX_LENS_FILE_BYTES: u64 = 4 << 20;

/// Reads, parses and validates the lens file at `path`: `.zmx` (any case) as Zemax, anything
/// else as a pbrt-v4 lens file.
///
/// # Errors
/// [`LensError::System`] when the file cannot be read, is larger than [`MAX_LENS_FILE_BYTES`]
/// or is not text; otherwise the parser's or [`LensSystem::validate`]'s error.
pub fn read_lens_file(path: &Path) -> Result<LensSystem, LensError> {
    let system_error = |message: String| LensError::System { file: path.display().to_string(), message };
    let file = std::fs::File::open(path).map_err(|err| system_error(format!("cannot open: {err}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_LENS_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|err| system_error(format!("cannot read: {err}")))?;
    if bytes.len() as u64 > MAX_LENS_FILE_BYTES {
        return Err(system_error(format!(
            "larger than {MAX_LENS_FILE_BYTES} bytes: not a lens file (a prescription is a few KB)"
        )));
    }
    let text = decode_text(&bytes).map_err(system_error)?;
    let is_zemax =
        path.extension().and_then(|ext| ext.to_str()).is_some_and(|ext| ext.eq_ignore_ascii_case("zmx"));
    if is_zemax {
        zmx::parse_zmx(&text, path)
    } else {
        pbrt::parse_pbrt(&text, path)
    }
}

/// The text of a lens file: UTF-16 little- or big-endian when it starts with the matching
/// byte-order mark, otherwise UTF-8 (a UTF-8 byte-order mark is dropped).
///
/// # Errors
/// A message naming the 1-based line of the first byte that is not valid text.
pub fn decode_text(bytes: &[u8]) -> Result<String, String> {
    let utf16 = |little_endian: bool| -> Result<String, String> {
        let body = &bytes[2..];
        if !body.len().is_multiple_of(2) {
            return Err("UTF-16 text with an odd number of bytes".to_owned());
        }
        let units = body.chunks_exact(2).map(|pair| {
            if little_endian {
                u16::from_le_bytes([pair[0], pair[1]])
            } else {
                u16::from_be_bytes([pair[0], pair[1]])
            }
        });
        let mut text = String::with_capacity(body.len() / 2);
        for decoded in char::decode_utf16(units) {
            match decoded {
                Ok(c) => text.push(c),
                Err(_) => {
                    let line = text.matches('\n').count() + 1;
                    return Err(format!("line {line}: not valid UTF-16 (an unpaired surrogate)"));
                }
            }
        }
        Ok(text)
    };
    match bytes {
        [0xFF, 0xFE, ..] => utf16(true),
        [0xFE, 0xFF, ..] => utf16(false),
        _ => {
            let body = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]).unwrap_or(bytes);
            match std::str::from_utf8(body) {
                Ok(text) => Ok(text.to_owned()),
                Err(err) => {
                    let line = body[..err.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
                    Err(format!(
                        "line {line}: not text (a lens file is UTF-8, or UTF-16 with a byte-order mark)"
                    ))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn utf16(text: &str, little_endian: bool) -> Vec<u8> {
        let mut bytes = if little_endian { vec![0xFF, 0xFE] } else { vec![0xFE, 0xFF] };
        for unit in text.encode_utf16() {
            bytes.extend(if little_endian { unit.to_le_bytes() } else { unit.to_be_bytes() });
        }
        bytes
    }

    #[test]
    fn utf8_and_utf16_with_a_bom_decode_to_the_same_text() {
        let text = "SURF 0\r\n  DISZ INFINITY\r\nNOTE 0 \"f/2 – 50 mm\"\n";
        assert_eq!(decode_text(text.as_bytes()).as_deref(), Ok(text));
        let mut with_bom = vec![0xEF, 0xBB, 0xBF];
        with_bom.extend(text.as_bytes());
        assert_eq!(decode_text(&with_bom).as_deref(), Ok(text));
        assert_eq!(decode_text(&utf16(text, true)).as_deref(), Ok(text));
        assert_eq!(decode_text(&utf16(text, false)).as_deref(), Ok(text));
    }

    #[test]
    fn bytes_that_are_not_text_name_the_line() {
        assert_eq!(
            decode_text(b"1 2 3 4\n5 6 \xff 8\n"),
            Err("line 2: not text (a lens file is UTF-8, or UTF-16 with a byte-order mark)".to_owned())
        );
        assert!(decode_text(&[0xFF, 0xFE, 0x41]).expect_err("odd").contains("odd number"));
        // A lone high surrogate (0xD800) on the second line.
        let mut bytes = utf16("a\n", true);
        bytes.extend([0x00, 0xD8, 0x41, 0x00]);
        assert_eq!(decode_text(&bytes), Err("line 2: not valid UTF-16 (an unpaired surrogate)".to_owned()));
    }

    #[test]
    fn files_that_cannot_be_read_are_system_errors() {
        let missing = Path::new("/nonexistent/prisma/lens.dat");
        let Err(LensError::System { file, message }) = read_lens_file(missing) else {
            panic!("a missing file must fail")
        };
        assert_eq!(file, "/nonexistent/prisma/lens.dat");
        assert!(message.starts_with("cannot open"), "{message}");
        let dir = tempfile::tempdir().expect("temporary directory");
        let big = dir.path().join("big.dat");
        std::fs::write(&big, vec![b'#'; MAX_LENS_FILE_BYTES as usize + 1]).expect("write");
        let Err(LensError::System { message, .. }) = read_lens_file(&big) else { panic!("too big") };
        assert!(message.starts_with("larger than"), "{message}");
    }
}
