//! Rotations from angles with `math::portable`'s sine and cosine: glam's own constructors
//! (`Mat4::from_axis_angle`, `Quat::slerp`, …) call the C library or per-architecture
//! approximations, so `clippy.toml` sends callers here (see `math::portable` for why).

use crate::math::portable;
use glam::{Mat4, Quat, Vec3, Vec4};

/// The rotation by `angle` radians about the unit vector `axis` (right-handed), as a matrix.
pub fn axis_angle(axis: Vec3, angle: f32) -> Mat4 {
    // Rodrigues' formula, column by column.
    let (sin, cos) = portable::sin_cos(angle);
    let s = axis * sin;
    let omc = 1.0 - cos;
    let (xy, xz, yz) = (
        axis.x * axis.y * omc,
        axis.x * axis.z * omc,
        axis.y * axis.z * omc,
    );
    Mat4::from_cols(
        Vec4::new(axis.x * axis.x * omc + cos, xy + s.z, xz - s.y, 0.0),
        Vec4::new(xy - s.z, axis.y * axis.y * omc + cos, yz + s.x, 0.0),
        Vec4::new(xz + s.y, yz - s.x, axis.z * axis.z * omc + cos, 0.0),
        Vec4::W,
    )
}

/// The rotation by `angle` radians about the unit vector `axis`, as a unit quaternion.
pub fn quat(axis: Vec3, angle: f32) -> Quat {
    let (s, c) = portable::sin_cos(0.5 * angle);
    let v = axis * s;
    Quat::from_xyzw(v.x, v.y, v.z, c)
}

/// Spherical linear interpolation of unit quaternions along the shorter arc: `a` at t = 0, `b`
/// (or −b) at t = 1, at constant angular speed. Nearly equal ends are interpolated linearly
/// and normalised, where sin θ would divide by almost zero.
pub fn slerp(a: Quat, b: Quat, t: f32) -> Quat {
    let d = a.dot(b);
    let (b, dot) = if d < 0.0 { (-b, -d) } else { (b, d) };
    if dot > 1.0 - f32::EPSILON {
        return (a * (1.0 - t) + b * t).normalize();
    }
    let theta = portable::acos(dot);
    let sin_theta = portable::sin(theta);
    (a * portable::sin((1.0 - t) * theta) + b * portable::sin(t * theta)) / sin_theta
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The matrix and the quaternion turn vectors alike, and agree with a quarter turn worked
    /// by hand (x to y about z; y to z about x), to f32 rounding (1e-6).
    #[test]
    fn matrix_and_quaternion_turn_alike() {
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-6;
        let quarter = std::f32::consts::FRAC_PI_2;
        assert!(close(
            axis_angle(Vec3::Z, quarter).transform_vector3(Vec3::X),
            Vec3::Y
        ));
        assert!(close(quat(Vec3::X, quarter) * Vec3::Y, Vec3::Z));
        let axis = Vec3::new(1.0, -2.0, 0.5).normalize();
        for angle in [-2.5f32, 0.3, 1.7, 3.1] {
            let v = Vec3::new(0.3, 0.8, -1.1);
            let m = axis_angle(axis, angle).transform_vector3(v);
            assert!(close(m, quat(axis, angle) * v), "angle {angle}");
            assert!((m.length() - v.length()).abs() < 1e-6);
        }
    }

    /// Slerp runs at constant angular speed along the shorter arc: at t of a turn of 2.4 rad it
    /// has turned t · 2.4; from the other hemisphere's −b it takes the same path; and t = 0, 1
    /// give the ends.
    #[test]
    fn slerp_turns_at_constant_speed_along_the_shorter_arc() {
        let axis = Vec3::new(0.2, 1.0, -0.4).normalize();
        let (a, b) = (quat(axis, 0.0), quat(axis, 2.4));
        for t in [0.0f32, 0.25, 0.5, 0.9, 1.0] {
            let want = quat(axis, 2.4 * t);
            for end in [b, -b] {
                let got = slerp(a, end, t);
                assert!(got.abs_diff_eq(want, 1e-6), "t {t}: {got} against {want}");
            }
        }
        let near = quat(axis, 1e-5);
        assert!(slerp(a, near, 0.5).is_normalized());
    }
}
