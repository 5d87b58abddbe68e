//! Fresnel reflectance of a conductor with complex index n + ik (TODO(optics helper)).
