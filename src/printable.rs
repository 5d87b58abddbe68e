//! Text from files, made safe to print: a part's header, an EXR attribute or a decoder's
//! message is input, and may hold terminal control sequences (ESC, OSC 52 clipboard writes) or
//! kilobytes of binary. Everything prisma prints that came from a file goes through [`quote`],
//! and every error line through [`one_line`].

use std::fmt::Write as _;

/// The longest text [`quote`] shows, in characters: longer values are cut with a count of
/// what was left out (a header's settings JSON is about 300).
pub const MAX_QUOTED_CHARS: usize = 512;

/// `text` with every control character (C0, DEL, C1: ESC, BEL, CR, LF, …) written as a Rust
/// escape (`\u{1b}`, `\n`), so that it prints as the characters it is and on one line.
pub fn one_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        push_printable(&mut out, c);
    }
    out
}

/// [`one_line`] of `text`, cut after [`MAX_QUOTED_CHARS`] characters.
pub fn quote(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars();
    for c in chars.by_ref().take(MAX_QUOTED_CHARS) {
        push_printable(&mut out, c);
    }
    let rest = chars.count();
    if rest > 0 {
        let _ = write!(out, "… ({rest} more characters)");
    }
    out
}

fn push_printable(out: &mut String, c: char) {
    if c.is_control() {
        out.extend(c.escape_default());
    } else {
        out.push(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_sequences_print_as_text_on_one_line() {
        let hostile = "\u{1b}[2J\u{1b}]52;c;cHduZWQ=\u{7}line\nnext\u{9b}0m é";
        let shown = one_line(hostile);
        assert!(!shown.chars().any(char::is_control), "{shown}");
        assert_eq!(shown, "\\u{1b}[2J\\u{1b}]52;c;cHduZWQ=\\u{7}line\\nnext\\u{9b}0m é");
        assert_eq!(one_line("plain 0..64 ✓"), "plain 0..64 ✓");
    }

    #[test]
    fn long_values_are_cut_with_a_count() {
        let long = "x".repeat(MAX_QUOTED_CHARS + 10);
        assert_eq!(quote(&long), format!("{}… (10 more characters)", "x".repeat(MAX_QUOTED_CHARS)));
        assert_eq!(quote("short"), "short");
    }
}
