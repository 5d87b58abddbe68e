//! Axis-aligned bounding boxes (TODO(geometry helper)).
