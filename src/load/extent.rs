//! How far from the origin a scene may reach. Geometry is 32-bit: a ray's distances, squared
//! lengths and the products of a sphere or light test square the coordinates, and f32 holds
//! 3.4e38, so a coordinate beyond ~1e19 makes them overflow into infinities and NaNs (a NaN ray
//! enters every box of the BVH). The fuzzer found that with a sphere at x = −1e38; positions
//! are therefore checked at load against `MAX_COORD`, 1e18 (squared, 1e36, leaves two orders
//! of headroom), 13 orders beyond the 1e5 scale of scenes/stress/scale_1e5.ron.

use crate::error::InputError;
use crate::math::Transform;
use crate::shape::Shape;
use glam::Vec3;
use std::path::Path;

/// The largest coordinate magnitude a shape, the camera or a light may have.
pub const MAX_COORD: f32 = 1e18;

fn too_far(file: &Path, field: &str, what: &str, v: f32) -> InputError {
    InputError::new(
        file,
        format!(
            "{what} reaches {v:e} from the origin, beyond {MAX_COORD:e}, the most prism's 32-bit \
             geometry handles"
        ),
    )
    .field(field)
    .hint("move the scene nearer the origin or change its units (scale it down)")
}

/// Refuses a point (a camera or light position) beyond `MAX_COORD`.
pub fn check_point(p: Vec3, file: &Path, field: &str, what: &str) -> Result<(), InputError> {
    let m = p.abs().max_element();
    if m.is_finite() && m <= MAX_COORD {
        Ok(())
    } else {
        Err(too_far(file, field, what, m))
    }
}

/// Refuses a shape any of whose (non-degenerate) primitives reaches beyond `MAX_COORD`.
pub fn check_shape(shape: &Shape, file: &Path, field: &str) -> Result<(), InputError> {
    let mut far = 0.0f32;
    for i in 0..shape.prim_count() {
        if shape.prim_is_degenerate(i) {
            continue;
        }
        let (lo, hi) = shape.prim_geom(i).bounds();
        far = far.max(lo.abs().max_element()).max(hi.abs().max_element());
        if !(lo.is_finite() && hi.is_finite()) || far > MAX_COORD {
            return Err(too_far(file, field, "the shape", far));
        }
    }
    Ok(())
}

/// Refuses a transform whose matrix or inverse has an entry beyond `MAX_COORD`: a scale
/// outside [1e-18, 1e18] on some axis. Normals go through the inverse; squared, such an entry
/// overflows or underflows f32, and the normal normalises to NaN (the fuzzer found a disk
/// scaled by −1e38 along its flat axis, which has finite bounds but NaN normals).
pub fn check_transform(t: &Transform, file: &Path, field: &str) -> Result<(), InputError> {
    let m = t.m.to_cols_array();
    let inv = t.inv.to_cols_array();
    let big = m.iter().chain(&inv).fold(0.0f32, |a, v| a.max(v.abs()));
    if big <= MAX_COORD {
        return Ok(());
    }
    Err(InputError::new(
        file,
        format!(
            "the transform (or its inverse) has an entry of {big:e}: a scale beyond \
             [1e-18, 1e18] on some axis, which prism's 32-bit geometry cannot normalise"
        ),
    )
    .field(field)
    .hint("check the Scale and Matrix steps for a misplaced exponent"))
}
