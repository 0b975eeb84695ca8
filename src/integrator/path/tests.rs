//! `LeMemo`: each light's radiance kept apart.

use super::*;
use crate::shape::{Shape, Sphere};
use crate::spectrum::{Curve, WavelengthSampler, WavelengthSampling};

/// The memo is keyed by emitter: two lights of different spectra, asked for in turn, each
/// get their own radiance, evaluated at the path's lanes.
#[test]
fn le_memo_keeps_each_light_apart() {
    let sphere = Shape::Sphere(Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
        flip: false,
    });
    let red = AreaEmitter::new(0, &sphere, Curve::rgb_illuminant([4.0, 0.1, 0.1]));
    let blue = AreaEmitter::new(1, &sphere, Curve::rgb_illuminant([0.1, 0.1, 4.0]));
    let wl: Wavelengths<8> =
        WavelengthSampler::new(WavelengthSampling::Visible, 360.0, 830.0).sample(0.3);
    let want = |a: &AreaEmitter| a.radiance.eval(Vec2::ZERO, &wl);
    let mut memo = LeMemo {
        emitter: LeMemo::<8>::NONE,
        le: Spectrum::zero(),
    };
    for (e, em) in [
        (0, &red),
        (0, &red),
        (1, &blue),
        (0, &red),
        (1, &blue),
        (1, &blue),
    ] {
        assert_eq!(memo.get(e, em, Vec2::ZERO, &wl), want(em), "emitter {e}");
    }
    assert_ne!(want(&red), want(&blue));
}
