//! Transcendental functions with the same bits on every machine: the `libm` crate's (a Rust port
//! of musl's, no FMA contraction, nothing chosen at run time), never the host's C library.
//!
//! Why: `f32::sin` and friends call the host's C library, which is another implementation on
//! macOS, musl or Windows, and which glibc itself switches at run time: it picks an FMA variant
//! of `cos`, `exp`, `log`, … on CPUs that have FMA, and the variants round differently (here f64
//! `exp` and `sin` on 0.07% of arguments, f32 `cosf` on a few in 10⁷; tests/portable_bits.rs).
//! A frame rendered on a laptop and the same frame of a cluster's run must not depend on the
//! node, so `clippy.toml` forbids the `std` methods and everything calls these. They cost a
//! little more than glibc's (`sincosf`: about 50 against 28 instructions a call).
//! `sqrt`, `powi`, `mul_add` and arithmetic are correctly rounded (or exact) everywhere and stay.

/// The functions, for `f32` and `f64`; callers use the generic free functions below.
pub trait Portable: Copy {
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn tan(self) -> Self;
    fn sin_cos(self) -> (Self, Self);
    fn asin(self) -> Self;
    fn acos(self) -> Self;
    fn atan(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn exp(self) -> Self;
    fn exp2(self) -> Self;
    fn exp_m1(self) -> Self;
    fn ln(self) -> Self;
    fn log2(self) -> Self;
    fn powf(self, e: Self) -> Self;
    fn hypot(self, y: Self) -> Self;
    fn cbrt(self) -> Self;
    fn cosh(self) -> Self;
    fn tanh(self) -> Self;
    fn atanh(self) -> Self;
}

macro_rules! portable {
    ($t:ty, $sin:ident, $cos:ident, $tan:ident, $sincos:ident, $asin:ident, $acos:ident,
     $atan:ident, $atan2:ident, $exp:ident, $exp2:ident, $expm1:ident, $log:ident,
     $log2:ident, $pow:ident, $hypot:ident, $cbrt:ident, $cosh:ident, $tanh:ident, $atanh:ident) => {
        impl Portable for $t {
            #[inline]
            fn sin(self) -> Self {
                libm::$sin(self)
            }
            #[inline]
            fn cos(self) -> Self {
                libm::$cos(self)
            }
            #[inline]
            fn tan(self) -> Self {
                libm::$tan(self)
            }
            #[inline]
            fn sin_cos(self) -> (Self, Self) {
                libm::$sincos(self)
            }
            #[inline]
            fn asin(self) -> Self {
                libm::$asin(self)
            }
            #[inline]
            fn acos(self) -> Self {
                libm::$acos(self)
            }
            #[inline]
            fn atan(self) -> Self {
                libm::$atan(self)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                libm::$atan2(self, x)
            }
            #[inline]
            fn exp(self) -> Self {
                libm::$exp(self)
            }
            #[inline]
            fn exp2(self) -> Self {
                libm::$exp2(self)
            }
            #[inline]
            fn exp_m1(self) -> Self {
                libm::$expm1(self)
            }
            #[inline]
            fn ln(self) -> Self {
                libm::$log(self)
            }
            #[inline]
            fn log2(self) -> Self {
                libm::$log2(self)
            }
            #[inline]
            fn powf(self, e: Self) -> Self {
                libm::$pow(self, e)
            }
            #[inline]
            fn hypot(self, y: Self) -> Self {
                libm::$hypot(self, y)
            }
            #[inline]
            fn cbrt(self) -> Self {
                libm::$cbrt(self)
            }
            #[inline]
            fn cosh(self) -> Self {
                libm::$cosh(self)
            }
            #[inline]
            fn tanh(self) -> Self {
                libm::$tanh(self)
            }
            #[inline]
            fn atanh(self) -> Self {
                libm::$atanh(self)
            }
        }
    };
}

portable!(
    f32, sinf, cosf, tanf, sincosf, asinf, acosf, atanf, atan2f, expf, exp2f, expm1f, logf, log2f,
    powf, hypotf, cbrtf, coshf, tanhf, atanhf
);
portable!(
    f64, sin, cos, tan, sincos, asin, acos, atan, atan2, exp, exp2, expm1, log, log2, pow, hypot,
    cbrt, cosh, tanh, atanh
);

macro_rules! free {
    ($($name:ident),*) => {$(
        #[inline]
        pub fn $name<T: Portable>(x: T) -> T {
            <T as Portable>::$name(x)
        }
    )*};
}

free!(sin, cos, tan, asin, acos, atan, exp, exp2, exp_m1, ln, log2, cbrt, cosh, tanh, atanh);

/// (sin x, cos x).
#[inline]
pub fn sin_cos<T: Portable>(x: T) -> (T, T) {
    Portable::sin_cos(x)
}

/// The angle of (x, y), as `y.atan2(x)`.
#[inline]
pub fn atan2<T: Portable>(y: T, x: T) -> T {
    Portable::atan2(y, x)
}

/// sqrt(x² + y²) without overflow.
#[inline]
pub fn hypot<T: Portable>(x: T, y: T) -> T {
    Portable::hypot(x, y)
}

/// x^e.
#[inline]
pub fn powf<T: Portable>(x: T, e: T) -> T {
    Portable::powf(x, e)
}
