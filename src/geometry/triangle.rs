//! Ray–triangle intersection (TODO(geometry helper)).
