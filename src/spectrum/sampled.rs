//! `Spectrum<N>`: a quantity (radiance, throughput, reflectance) at a path's N wavelengths.
//!
//! N is a const generic so the lanes live in registers and every loop over them unrolls; the
//! renderer is monomorphised for the wavelength counts it supports (see `integrator`).

use std::ops::{Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Sub};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spectrum<const N: usize>(pub [f32; N]);

impl<const N: usize> Spectrum<N> {
    #[inline]
    pub const fn splat(v: f32) -> Self {
        Self([v; N])
    }

    #[inline]
    pub const fn zero() -> Self {
        Self([0.0; N])
    }

    #[inline]
    pub const fn one() -> Self {
        Self([1.0; N])
    }

    /// Lane i = f(i). A plain loop: `std::array::from_fn` does not always inline its closure
    /// wrapper, which showed up as a per-lane function call in profiles.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        let mut a = [0.0; N];
        for (i, v) in a.iter_mut().enumerate() {
            *v = f(i);
        }
        Self(a)
    }

    #[inline]
    pub fn map(self, mut f: impl FnMut(f32) -> f32) -> Self {
        Self(self.0.map(&mut f))
    }

    #[inline]
    pub fn max_value(&self) -> f32 {
        self.0.iter().copied().fold(f32::NEG_INFINITY, f32::max)
    }

    #[inline]
    pub fn sum(&self) -> f32 {
        self.0.iter().sum()
    }

    #[inline]
    pub fn is_zero(&self) -> bool {
        self.0.iter().all(|&v| v == 0.0)
    }

    /// True if every lane is finite (no NaN or infinity).
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }

    /// Lane-wise division that yields 0 where the divisor is 0 (a zero-pdf lane contributes nothing).
    #[inline]
    pub fn safe_div(self, d: Self) -> Self {
        Self::from_fn(|i| {
            if d.0[i] != 0.0 {
                self.0[i] / d.0[i]
            } else {
                0.0
            }
        })
    }
}

impl<const N: usize> Default for Spectrum<N> {
    fn default() -> Self {
        Self::zero()
    }
}

impl<const N: usize> Index<usize> for Spectrum<N> {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}

impl<const N: usize> IndexMut<usize> for Spectrum<N> {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

macro_rules! lanewise {
    ($trait:ident, $fn:ident, $assign_trait:ident, $assign_fn:ident, $op:tt) => {
        impl<const N: usize> $trait for Spectrum<N> {
            type Output = Self;
            #[inline]
            fn $fn(self, rhs: Self) -> Self {
                Self::from_fn(|i| self.0[i] $op rhs.0[i])
            }
        }
        impl<const N: usize> $trait<f32> for Spectrum<N> {
            type Output = Self;
            #[inline]
            fn $fn(self, rhs: f32) -> Self {
                Self::from_fn(|i| self.0[i] $op rhs)
            }
        }
        impl<const N: usize> $assign_trait for Spectrum<N> {
            #[inline]
            fn $assign_fn(&mut self, rhs: Self) {
                for i in 0..N {
                    self.0[i] = self.0[i] $op rhs.0[i];
                }
            }
        }
        impl<const N: usize> $assign_trait<f32> for Spectrum<N> {
            #[inline]
            fn $assign_fn(&mut self, rhs: f32) {
                for v in &mut self.0 {
                    *v = *v $op rhs;
                }
            }
        }
    };
}

lanewise!(Add, add, AddAssign, add_assign, +);
lanewise!(Mul, mul, MulAssign, mul_assign, *);
lanewise!(Div, div, DivAssign, div_assign, /);

impl<const N: usize> Sub for Spectrum<N> {
    type Output = Self;
    #[inline]
    fn sub(self, rhs: Self) -> Self {
        Self::from_fn(|i| self.0[i] - rhs.0[i])
    }
}

impl<const N: usize> Mul<Spectrum<N>> for f32 {
    type Output = Spectrum<N>;
    #[inline]
    fn mul(self, rhs: Spectrum<N>) -> Spectrum<N> {
        rhs * self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_is_lanewise() {
        let a = Spectrum([1.0, 2.0, 3.0, 4.0]);
        let b = Spectrum([2.0, 0.0, 1.0, 0.5]);
        assert_eq!((a * b).0, [2.0, 0.0, 3.0, 2.0]);
        assert_eq!((a + 1.0).0, [2.0, 3.0, 4.0, 5.0]);
        assert_eq!(a.safe_div(b).0, [0.5, 0.0, 3.0, 8.0]);
        assert_eq!(a.max_value(), 4.0);
        assert!(!Spectrum([f32::NAN, 0.0]).is_finite());
    }
}
