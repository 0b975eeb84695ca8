//! Area lights on shapes that move while the shutter is open. Such a shape is kept in object
//! space (`accel::moving`), so its light samples a point there and carries it to the world by
//! the shape's transform at the receiving point's time. A BSDF-sampled hit on it is already in
//! the world at its ray's time (`accel::moving`), and its density is read through the same
//! transform, so both strategies see the light in one pose per path and MIS stays consistent.
//!
//! An affine map M scales the area element at a point of object normal n by
//! |det M| · |M⁻ᵀ n| (the "stretch"), so the world area density is the object one over it.
//! A sphere is sampled by area here: the cone it subtends is not what an uneven scale maps it to.

use super::area::{AreaEmitter, AreaLightSample};
use crate::interaction::SurfaceInteraction;
use crate::math::float::gamma;
use crate::motion::Motion;
use crate::shape::Shape;
use glam::{Mat3, Mat4, Vec2, Vec3};

/// An area light on a shape (in object space) moving by `motion` while the shutter is open.
/// Its own kind, sampled among the other kinds (`Emitter::sample_li_other`), so the path loop's
/// code for still area lights is what it was (callgrind, docs/performance.md "Paths in lanes"). It keeps its own
/// copy of the object-space shape for that, which that call does not receive (a moving light's
/// shape is small; the scene's copy is the one rays hit).
#[derive(Clone, Debug)]
pub struct MovingArea {
    pub area: AreaEmitter,
    pub motion: Motion,
    pub shape: Shape,
}

impl MovingArea {
    /// `AreaEmitter::sample_point` for the moving light: a point sampled in object space,
    /// carried to its pose at `si.time`. Out of line and cold: still lights never reach it,
    /// and the path loop's code for them stays as it was.
    #[cold]
    #[inline(never)]
    pub fn sample_point(&self, si: &SurfaceInteraction, u: Vec2) -> Option<AreaLightSample> {
        let (s, uv) = self.area.sample_area_uv(u, &self.shape);
        let m = self.motion.matrix(si.time);
        let lin = Mat3::from_mat4(m);
        let nw = lin.inverse().transpose() * s.n;
        let stretch = lin.determinant().abs() * nw.length();
        if !(stretch > 0.0 && stretch.is_finite()) {
            return None; // a scale through 0 at this instant: the light has no area
        }
        let n = nw.normalize();
        let p = m.transform_point3(s.p);
        let to = p - si.p;
        let d2 = to.length_squared();
        let dist = d2.sqrt();
        // One-sided: nothing leaves the back of the emitter.
        let cos = n.dot(-to) / dist;
        let pdf = s.pdf_area / stretch * d2 / cos;
        if !(cos > 0.0 && pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(AreaLightSample {
            wi: to / dist,
            shadow: si.spawn_to(p, carried_error(s.p, s.p_error, &m), Some(n)),
            pdf,
            uv,
        })
    }

    /// `AreaEmitter::pdf_li` for the moving light at the hit `light` (world space, at its
    /// ray's time). With ng = M⁻ᵀn / |M⁻ᵀn|, Mᵀ ng = n / |M⁻ᵀn|, so the stretch is
    /// |det M| / |Mᵀ ng|.
    #[cold]
    #[inline(never)]
    pub fn pdf_li(&self, p: Vec3, light: &SurfaceInteraction) -> f32 {
        let lin = Mat3::from_mat4(self.motion.matrix(light.time));
        let stretch = lin.determinant().abs() / (lin.transpose() * light.ng).length();
        let to = light.p - p;
        let d2 = to.length_squared();
        let cos = light.ng.dot(-to) / d2.sqrt();
        let pdf = self.area.pdf_area(light.prim) / stretch * d2 / cos;
        if cos > 0.0 && pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }
}

/// The rounding bound of object point `p` (bound `e`) carried by `m`, with that of the shadow
/// ray's end carried back into object space when the moving light is traced (γ3 each way,
/// PBR 4th ed. §6.8.4), as `accel::moving` bounds its hits.
fn carried_error(p: Vec3, e: Vec3, m: &Mat4) -> Vec3 {
    let lin = Mat3::from_mat4(*m).abs();
    let e_obj = e + gamma(3) * (lin * p.abs() + m.w_axis.truncate().abs());
    let world = m.transform_point3(p);
    let inv = m.inverse();
    let back = gamma(3) * (Mat3::from_mat4(inv).abs() * world.abs() + inv.w_axis.truncate().abs());
    (1.0 + gamma(3)) * (lin * (e_obj + back))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::motion::{Interp, Track};
    use crate::shape::{Disk, Sphere};

    fn track<T: Clone>(values: Vec<T>) -> Track<T> {
        Track {
            times: vec![0.0, 1.0],
            values,
            tangents: Vec::new(),
            interp: Interp::Linear,
        }
    }

    /// Slides, turns and scales unevenly (so the stretch differs over a sphere's surface).
    fn motion() -> Motion {
        Motion {
            translation: track(vec![Vec3::new(-1.0, 0.0, 3.0), Vec3::new(1.0, 0.5, 3.0)]),
            rotation: track(vec![
                crate::math::rotation::quat(Vec3::X, 3.0),
                crate::math::rotation::quat(Vec3::X, 3.0)
                    * crate::math::rotation::quat(Vec3::Y, 0.8),
            ]),
            scale: track(vec![Vec3::new(0.5, 0.3, 0.8), Vec3::new(0.2, 0.6, 0.4)]),
            parent: None,
        }
    }

    fn receiver(time: f32) -> SurfaceInteraction {
        SurfaceInteraction {
            p: Vec3::new(0.1, -0.2, 0.0),
            p_error: Vec3::ZERO,
            ng: Vec3::Z,
            frame: crate::math::Frame::from_normal(Vec3::Z),
            uv: Vec2::ZERO,
            t: 1.0,
            shape: 1,
            prim: 0,
            time,
            bary: Vec2::ZERO,
        }
    }

    /// Where the ray from `o` along `d` first meets the unit sphere or the unit disk carried
    /// by `m`, with the world normal there: an analytic intersection in object space, in f64
    /// (the quadratic's cancellation far from an unevenly scaled sphere is too large in f32).
    fn hit(sphere: bool, m: Mat4, o: Vec3, d: Vec3) -> Option<(Vec3, Vec3)> {
        let m = m.as_dmat4();
        let inv = m.inverse();
        let (ol, dl) = (
            inv.transform_point3(o.as_dvec3()),
            inv.transform_vector3(d.as_dvec3()),
        );
        let t = if sphere {
            let (a, b, c) = (dl.dot(dl), ol.dot(dl), ol.dot(ol) - 1.0);
            let disc = b * b - a * c;
            (disc >= 0.0).then(|| (-b - disc.sqrt()) / a)?
        } else {
            let t = -ol.z / dl.z;
            ((ol + t * dl).truncate().length() <= 1.0).then_some(t)?
        };
        let local = ol + t * dl;
        let n = if sphere { local } else { glam::DVec3::Z };
        let nw = (glam::DMat3::from_mat4(m).inverse().transpose() * n).normalize();
        Some((m.transform_point3(local).as_vec3(), nw.as_vec3()))
    }

    /// The density a sample reports is the one `pdf_li` reads back where a ray along the
    /// sample's direction meets the moved shape (as a BSDF-sampled hit there would), to 1e-3
    /// relative (f32 rounding of the transforms and the analytic hit; grazing points, whose
    /// density 1/cos magnifies that rounding, are skipped), for a sphere and a disk
    /// scaled unevenly, at three times. The mean of 1/pdf over the samples estimates the solid
    /// angle of the light's front, which must equal a dense grid's sum over the moved disk
    /// (3%: 4096 stratified samples, spread far below that): the density's scale is right.
    #[test]
    fn sampled_density_is_the_density_at_the_hit() {
        let sphere = Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
            flip: false,
        });
        let disk = Shape::Disk(Disk {
            to_world: Transform::IDENTITY,
            flip: false,
        });
        for (is_sphere, shape) in [(true, sphere), (false, disk)] {
            let light = MovingArea {
                area: AreaEmitter::new(0, &shape, crate::spectrum::Curve::Constant(1.0)),
                motion: motion(),
                shape: shape.clone(),
            };
            for time in [0.0, 0.37, 1.0] {
                let si = receiver(time);
                let m = motion().matrix(time);
                let (mut checked, mut solid) = (0, 0.0f64);
                let n = 64;
                for k in 0..n * n {
                    let u = Vec2::new(
                        ((k % n) as f32 + 0.5) / n as f32,
                        ((k / n) as f32 + 0.5) / n as f32,
                    );
                    let Some(s) = light.sample_point(&si, u) else {
                        continue;
                    };
                    solid += 1.0 / s.pdf as f64 / (n * n) as f64;
                    // A grazing direction may miss the analytic shape by rounding.
                    let Some((p, ng)) = hit(is_sphere, m, si.p, s.wi) else {
                        continue;
                    };
                    let at = SurfaceInteraction {
                        p,
                        ng,
                        shape: 0,
                        ..receiver(time)
                    };
                    // Near grazing, 1/cos magnifies that rounding in the density.
                    if ng.dot(-s.wi) < 0.1 {
                        continue;
                    }
                    let back = light.pdf_li(si.p, &at);
                    assert!(
                        (back - s.pdf).abs() <= 1e-3 * s.pdf,
                        "t {time}: sampled {} vs read back {back}",
                        s.pdf
                    );
                    checked += 1;
                }
                assert!(checked > 500, "only {checked} samples reach the receiver");
                if !is_sphere {
                    // The disk's solid angle from si.p by a 400 × 400 grid over its square.
                    let g = 400;
                    let mut want = 0.0f64;
                    for j in 0..g * g {
                        let x = -1.0 + 2.0 * ((j % g) as f32 + 0.5) / g as f32;
                        let y = -1.0 + 2.0 * ((j / g) as f32 + 0.5) / g as f32;
                        if x * x + y * y > 1.0 {
                            continue;
                        }
                        let lin = Mat3::from_mat4(m);
                        let nw = lin.inverse().transpose() * Vec3::Z;
                        let da =
                            (lin.determinant().abs() * nw.length()) as f64 * 4.0 / (g * g) as f64;
                        let to = m.transform_point3(Vec3::new(x, y, 0.0)) - si.p;
                        let cos = nw.normalize().dot(-to.normalize()) as f64;
                        want += cos.max(0.0) * da / to.length_squared() as f64;
                    }
                    assert!(
                        (solid - want).abs() < 0.03 * want,
                        "t {time}: solid angle {solid} vs {want}"
                    );
                }
            }
        }
    }
}
