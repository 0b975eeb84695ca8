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

/// `impl Portable for $t`, each method calling the `libm` function named beside it.
macro_rules! portable {
    ($t:ty, $sincos:ident; $($name:ident($($arg:ident),*) => $libm:ident),* $(,)?) => {
        impl Portable for $t {
            #[inline]
            fn sin_cos(self) -> (Self, Self) {
                libm::$sincos(self)
            }
            $(
                #[inline]
                fn $name(self $(, $arg: Self)*) -> Self {
                    libm::$libm(self $(, $arg)*)
                }
            )*
        }
    };
}

portable!(f32, sincosf;
    sin() => sinf, cos() => cosf, tan() => tanf, asin() => asinf, acos() => acosf,
    atan() => atanf, atan2(x) => atan2f, exp() => expf, exp2() => exp2f, exp_m1() => expm1f,
    ln() => logf, log2() => log2f, powf(e) => powf, hypot(y) => hypotf, cbrt() => cbrtf,
    cosh() => coshf, tanh() => tanhf, atanh() => atanhf,
);
portable!(f64, sincos;
    sin() => sin, cos() => cos, tan() => tan, asin() => asin, acos() => acos, atan() => atan,
    atan2(x) => atan2, exp() => exp, exp2() => exp2, exp_m1() => expm1, ln() => log,
    log2() => log2, powf(e) => pow, hypot(y) => hypot, cbrt() => cbrt, cosh() => cosh,
    tanh() => tanh, atanh() => atanh,
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

/// ln Γ(x) (f64): musl's `lgamma`, for the acceptance test of Poisson draws.
#[inline]
pub fn ln_gamma(x: f64) -> f64 {
    libm::lgamma(x)
}
