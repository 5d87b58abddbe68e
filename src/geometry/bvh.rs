//! The BVH over finite shapes (TODO(geometry helper)).
