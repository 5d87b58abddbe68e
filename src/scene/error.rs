//! [`SceneError`]: everything that can be wrong with a scene file, as one-line messages that name
//! the file, the line and the field.

use std::path::PathBuf;

/// A scene file that cannot be loaded. `Display` is a single line.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file cannot be read.
    #[error("{}: cannot read the scene file: {source}", file.display())]
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

/// Collapses a multi-line message into one line.
pub fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_column_counts_from_one() {
        let text = "a = 1\nbb = 2\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        assert_eq!(line_column(text, 9), (2, 4));
    }
}
