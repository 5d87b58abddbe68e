//! [`SceneError`]: everything that can be wrong with a scene file, as one-line messages that name
//! the file, the line and the field.

use std::path::PathBuf;

/// A scene file that cannot be loaded. `Display` is a single line.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file cannot be read (the OS error follows in the error chain).
    #[error("{}: cannot read the scene file", file.display())]
    Io {
        /// The scene file.
        file: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// TOML syntax, an unknown key, a missing field or a wrong type.
    #[error("{}:{line}:{column}: {message}", file.display())]
    Syntax {
        /// The scene file.
        file: PathBuf,
        /// 1-based line of the problem.
        line: usize,
        /// 1-based column of the problem.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A value that parses but makes no sense (negative radius, unknown material, ...).
    #[error("{}:{line}: {field}: {message}", file.display())]
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// 1-based line of the table that holds the field.
        line: usize,
        /// Dotted path of the field, e.g. `shapes[2].radius`.
        field: String,
        /// What is wrong.
        message: String,
    },
}

/// 1-based (line, column) of byte `offset` in `text`.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Longest word kept whole in a message: longer ones (a 5 MB key echoed by the TOML parser, a
/// pasted path) are cut, so that every message stays a readable line.
const MAX_WORD_CHARS: usize = 80;

/// Collapses a multi-line message into one line and shortens every word longer than
/// `MAX_WORD_CHARS` (80) characters to its start, an ellipsis and its length.
pub fn one_line(message: &str) -> String {
    message.split_whitespace().map(shorten).collect::<Vec<_>>().join(" ")
}

/// `text` itself, or its first characters and how long it was when it is too long to echo.
pub fn shorten(text: &str) -> String {
    match text.char_indices().nth(MAX_WORD_CHARS) {
        None => text.to_owned(),
        Some(_) => {
            let head: String = text.chars().take(MAX_WORD_CHARS - 20).collect();
            format!("{head}…[{} characters]", text.chars().count())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_words_are_cut_so_messages_stay_short() {
        let key = "k".repeat(5_000_000);
        let message = one_line(&format!("unknown field `{key}`, expected one of `a`, `b`"));
        assert!(message.len() < 200, "{} bytes", message.len());
        assert!(
            message.contains("5000003 characters") && message.ends_with("expected one of `a`, `b`"),
            "{message}"
        );
        assert_eq!(one_line("short words\n stay"), "short words stay");
    }

    #[test]
    fn line_column_counts_from_one() {
        let text = "a = 1\nbb = 2\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        assert_eq!(line_column(text, 9), (2, 4));
    }
}
