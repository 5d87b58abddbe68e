//! The field a TOML error is about: the dotted path (`shapes[2].radius`) of the key or value at
//! the error's position, so that errors from the TOML layer name their field as the build
//! layer's do. Found by parsing the text again into toml's positioned tree.

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// The dotted path of the deepest key or value whose span holds byte `offset` of `text`; for
/// a "missing field `x`" message, the path of the table at `offset` and `x`. `None` when the
/// text does not parse or nothing holds the offset.
pub fn field_at(text: &str, offset: usize, message: &str) -> Option<String> {
    let Ok(root) = DeTable::parse(text) else {
        return field_near(text, offset);
    };
    let mut path = String::new();
    let found = search_table(root.get_ref(), offset, &mut path);
    let missing = missing_field(message);
    match (found, missing) {
        (_, Some(missing)) if path.is_empty() => Some(missing.to_owned()),
        (_, Some(missing)) => Some(format!("{path}.{missing}")),
        (true, None) => Some(path),
        (false, None) => None,
    }
}

/// For text that does not parse (a duplicate key, a syntax error): the key on the line of
/// `offset`, in the table whose header comes last before it (`[[name]]` headers counted to
/// give the element's index). Read from the lines, not parsed, so only an approximation for
/// the rare key or header that spans lines.
fn field_near(text: &str, offset: usize) -> Option<String> {
    let before = &text[..offset.min(text.len())];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("");
    let key = line
        .split_once('=')
        .map(|(key, _)| key.trim())
        .filter(|key| !key.is_empty() && !key.starts_with('[') && !key.starts_with('#'));
    let mut table: Option<String> = None;
    let mut counts: Vec<(String, usize)> = Vec::new();
    for header in before[..line_start].lines().map(str::trim) {
        if let Some(name) = header.strip_prefix("[[").and_then(|h| h.split("]]").next()) {
            let name = name.trim().to_owned();
            let index = match counts.iter_mut().find(|(n, _)| *n == name) {
                Some((_, count)) => {
                    *count += 1;
                    *count - 1
                }
                None => {
                    counts.push((name.clone(), 1));
                    0
                }
            };
            table = Some(format!("{name}[{index}]"));
        } else if let Some(name) = header.strip_prefix('[').and_then(|h| h.split(']').next()) {
            table = Some(name.trim().to_owned());
        }
    }
    match (table, key) {
        (Some(table), Some(key)) => Some(format!("{table}.{key}")),
        (None, Some(key)) => Some(key.to_owned()),
        (table, None) => table,
    }
}

/// The field named by serde's "missing field `x`" message.
fn missing_field(message: &str) -> Option<&str> {
    let rest = message.strip_prefix("missing field `")?;
    rest.split('`').next()
}

/// Extends `path` towards the deepest entry of `table` that holds `offset`; true when one does.
fn search_table(table: &DeTable<'_>, offset: usize, path: &mut String) -> bool {
    for (key, value) in table.iter() {
        let before = path.len();
        if !path.is_empty() {
            path.push('.');
        }
        path.push_str(key.get_ref());
        if key.span().contains(&offset) {
            return true;
        }
        if search_value(value, offset, path) {
            return true;
        }
        path.truncate(before);
    }
    false
}

/// As [`search_table`], inside a value: true when `value` or a part of it holds `offset`.
fn search_value(value: &Spanned<DeValue<'_>>, offset: usize, path: &mut String) -> bool {
    let inner = match value.get_ref() {
        DeValue::Table(table) => search_table(table, offset, path),
        DeValue::Array(array) => array.iter().enumerate().any(|(index, element)| {
            let before = path.len();
            path.push_str(&format!("[{index}]"));
            let found = search_value(element, offset, path);
            if !found {
                path.truncate(before);
            }
            found
        }),
        _ => false,
    };
    // A table's span may be only its header; its entries are searched whatever it covers.
    inner || value.span().contains(&offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str =
        "background = 1\n[camera]\nwidth = 8\n[[shapes]]\ntype = \"sphere\"\nradius = \"one\"\n";

    #[test]
    fn names_the_value_key_and_array_element() {
        let at = |needle: &str| TEXT.find(needle).expect("needle");
        assert_eq!(field_at(TEXT, at("8"), "").as_deref(), Some("camera.width"));
        assert_eq!(field_at(TEXT, at("\"one\""), "").as_deref(), Some("shapes[0].radius"));
        assert_eq!(field_at(TEXT, at("radius"), "").as_deref(), Some("shapes[0].radius"));
        assert_eq!(field_at(TEXT, at("1\n"), "").as_deref(), Some("background"));
    }

    #[test]
    fn a_duplicate_key_is_named_from_the_lines() {
        let text = "[render]\nspp = 1\nspp = 2\n[[shapes]]\n[[shapes]]\nradius = = 1\n";
        assert_eq!(
            field_at(text, text.rfind("spp").unwrap(), "duplicate key").as_deref(),
            Some("render.spp")
        );
        assert_eq!(field_at(text, text.find("= =").unwrap(), "").as_deref(), Some("shapes[1].radius"));
    }

    #[test]
    fn a_missing_field_is_named_inside_its_table() {
        // serde reports a missing field at the table that lacks it.
        let at = TEXT.find("[[shapes]]").expect("table");
        assert_eq!(field_at(TEXT, at, "missing field `center`").as_deref(), Some("shapes[0].center"));
    }
}
