//! A mixture of weighted leaf lobes, each on its side (`blend`, `mask`, `twosided`).

use super::{BsdfLike, BsdfSample, Lobe, MAX_LOBES};
use crate::spectrum::Spectrum;
use arrayvec::ArrayVec;
use glam::{Vec2, Vec3};

/// Leaf lobes whose weights sum to 1, each on its side (`twosided` mirrors the back side).
#[derive(Clone, Debug, Default)]
pub struct Mixture<'a, const N: usize> {
    // An ArrayVec rather than a filled array: most hits have one lobe, and initialising all
    // MAX_LOBES slots of the largest lobe variant at every hit showed in profiles.
    pub(super) lobes: ArrayVec<(Lobe<'a, N>, f32, bool), MAX_LOBES>,
}

/// Mirrors a local direction through the tangent plane (the back side of a `twosided`).
#[inline]
fn mirror(v: Vec3, flip: bool) -> Vec3 {
    if flip {
        Vec3::new(v.x, v.y, -v.z)
    } else {
        v
    }
}

// Out of line, so that the integrator's copy of its per-hit code for mixtures stays small.
impl<const N: usize> BsdfLike<N> for Mixture<'_, N> {
    #[inline(never)]
    fn eval(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        let mut f = Spectrum::zero();
        for (lobe, w, flip) in &self.lobes[..] {
            f += lobe.eval(mirror(wi, *flip), mirror(wo, *flip)) * *w;
        }
        f
    }

    #[inline(never)]
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.lobes[..]
            .iter()
            .map(|(l, w, flip)| w * l.pdf(mirror(wi, *flip), mirror(wo, *flip)))
            .sum()
    }

    #[inline(never)]
    fn pdf_lanes(&self, wi: Vec3, wo: Vec3) -> Spectrum<N> {
        let mut p = Spectrum::zero();
        for (lobe, w, flip) in &self.lobes[..] {
            p += lobe.pdf_lanes(mirror(wi, *flip), mirror(wo, *flip)) * *w;
        }
        p
    }

    #[inline(never)]
    fn sample(&self, wi: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample<N>> {
        // No lobe (every weight 0 or NaN): nothing to sample, rather than an index past the end.
        if self.lobes.is_empty() {
            return None;
        }
        if self.lobes.len() == 1 {
            let (lobe, w, flip) = &self.lobes[0];
            let mut s = lobe.sample(mirror(wi, *flip), uc, u)?;
            s.wo = mirror(s.wo, *flip);
            // A lone lobe of weight < 1 (a mask's inner part when fully opaque is weight 1).
            s.weight *= *w;
            return Some(s);
        }
        // Choose lobe i with probability w_i (the weights sum to 1), reusing uc.
        let mut acc = 0.0;
        let mut chosen = self.lobes.len() - 1;
        let mut uc_lobe = uc;
        for (i, (_, w, _)) in self.lobes[..].iter().enumerate() {
            if uc < acc + w || i == self.lobes.len() - 1 {
                chosen = i;
                uc_lobe = ((uc - acc) / w).clamp(0.0, 1.0 - f32::EPSILON);
                break;
            }
            acc += w;
        }
        let (lobe, w, flip) = &self.lobes[chosen];
        let mut s = lobe.sample(mirror(wi, *flip), uc_lobe, u)?;
        s.wo = mirror(s.wo, *flip);
        if s.delta {
            // A Dirac lobe: the mixture's probability of this exact direction is w·p.
            s.pdf *= w;
            s.pdf_lanes *= *w;
            return Some(s);
        }
        // A smooth direction: every smooth lobe could have produced it.
        let pdf = self.pdf(wi, s.wo);
        if pdf <= 0.0 {
            return None;
        }
        let f = self.eval(wi, s.wo);
        Some(BsdfSample {
            pdf,
            pdf_lanes: self.pdf_lanes(wi, s.wo),
            weight: f / pdf,
            ..s
        })
    }

    #[inline]
    fn has_smooth(&self) -> bool {
        self.lobes[..].iter().any(|(l, _, _)| l.has_smooth())
    }

    #[inline]
    fn dispersive(&self) -> bool {
        self.lobes[..].iter().any(|(l, _, _)| l.dispersive())
    }

    #[inline]
    fn glossy(&self, max_alpha: f32) -> bool {
        !self.lobes.is_empty() && self.lobes[..].iter().all(|(l, _, _)| l.glossy(max_alpha))
    }
}
