//! The glass catalogue of `data/glasses.toml` (TODO(optics helper)).

use super::Ior;

/// Looks up a named glass (case-insensitive, e.g. `"N-SF11"`) in the built-in catalogue.
pub fn glass_ior(name: &str) -> Option<Ior> {
    let _ = name;
    todo!()
}

/// Names of every glass in the built-in catalogue.
pub fn glass_names() -> Vec<&'static str> {
    todo!()
}
