//! Affine transforms with their inverses (normals transform by the inverse transpose).

use super::float::gamma;
use glam::{Mat3, Mat4, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub m: Mat4,
    pub inv: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Self = Self {
        m: Mat4::IDENTITY,
        inv: Mat4::IDENTITY,
    };

    /// None if the matrix is singular or not finite (the config reports that as an error).
    pub fn from_matrix(m: Mat4) -> Option<Self> {
        let det = m.determinant();
        if !det.is_finite() || det.abs() < 1e-30 || !m.is_finite() {
            return None;
        }
        let inv = m.inverse();
        inv.is_finite().then_some(Self { m, inv })
    }

    /// `self` applied after `first` (i.e. the matrix product self · first).
    pub fn after(&self, first: &Transform) -> Transform {
        Transform {
            m: self.m * first.m,
            inv: first.inv * self.inv,
        }
    }

    pub fn inverse(&self) -> Transform {
        Transform {
            m: self.inv,
            inv: self.m,
        }
    }

    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.m.transform_point3(p)
    }

    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3(v)
    }

    /// Transforms a normal (not normalised).
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        Mat3::from_mat4(self.inv).transpose() * n
    }

    /// Transforms a point and bounds the rounding error of the result (per component).
    #[inline]
    pub fn point_with_error(&self, p: Vec3) -> (Vec3, Vec3) {
        let m = &self.m;
        let r = |row: usize| {
            let a = m.row(row);
            (a.x * p.x).abs() + (a.y * p.y).abs() + (a.z * p.z).abs() + a.w.abs()
        };
        (self.point(p), gamma(3) * Vec3::new(r(0), r(1), r(2)))
    }

    /// True if the transform flips orientation (negative determinant), which swaps which side
    /// of a surface its normal faces.
    pub fn flips_handedness(&self) -> bool {
        Mat3::from_mat4(self.m).determinant() < 0.0
    }

    /// Mitsuba's look-at: the camera looks along local +z, local +y is up and local +x is left.
    pub fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Self> {
        let dir = (target - origin).normalize_or_zero();
        let left = up.normalize_or_zero().cross(dir).normalize_or_zero();
        if dir == Vec3::ZERO || left == Vec3::ZERO {
            return None;
        }
        let new_up = dir.cross(left);
        Self::from_matrix(Mat4::from_cols(
            left.extend(0.0),
            new_up.extend(0.0),
            dir.extend(0.0),
            origin.extend(1.0),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_stay_perpendicular_under_nonuniform_scale() {
        let t = Transform::from_matrix(Mat4::from_scale(Vec3::new(2.0, 1.0, 0.5))).unwrap();
        let (a, b) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0));
        let n = a.cross(b);
        assert!(t.normal(n).dot(t.vector(a)).abs() < 1e-5);
        assert!(t.normal(n).dot(t.vector(b)).abs() < 1e-5);
        assert!(Transform::from_matrix(Mat4::ZERO).is_none());
    }

    #[test]
    fn look_at_matches_mitsuba_cornell_camera() {
        // mi.cornell_box(): to_world = [[-1,0,0,0],[0,1,0,0],[0,0,-1,3.9]].
        let t = Transform::look_at(Vec3::new(0.0, 0.0, 3.9), Vec3::ZERO, Vec3::Y).unwrap();
        let expect = Mat4::from_cols_array_2d(&[
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, -1.0, 0.0],
            [0.0, 0.0, 3.9, 1.0],
        ]);
        assert!(t.m.abs_diff_eq(expect, 1e-6), "{:?}", t.m);
    }
}
