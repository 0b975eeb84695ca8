//! The packet kernel: each thread traces W paths at once, one per lane, W chosen at run time
//! (16 with AVX-512, 8 with AVX2, 4 with SSE2/NEON, 1 as the reference), on one binary.
//!
//! **Work.** A lane takes a pixel of the tile and traces its samples one after another; when
//! the pixel has them all, the lane takes the tile's next pixel. So spp 1 fills the lanes as
//! well as spp 1024, and a lane's sampler makes its pixel's scrambles once (lanes that hopped
//! between pixels' samples remade them: +45% `PixelSampler::fill_group` instructions on the
//! materials scene). A path runs as stages over all busy lanes: trace (one ray per lane through
//! the BVH), emission at the hit or from the environment, the BSDF built at the hit, one
//! masked scatter pass per kind of BSDF present in the packet (emitter sampling with its
//! shadow ray, MIS, BSDF sampling), then Russian roulette.
//!
//! **Bits.** Every lane does exactly the IEEE operations the scalar integrator
//! (`integrator::path`) does for its path, in the same order, with the same sampler
//! dimensions; a lane's sampler depends only on (seed, pixel, sample index); a finished path
//! is summed into its pixel at once, and a pixel's samples finish in sample order (one lane
//! traces them all). So the image is bit-identical at W = 1, 4, 8, 16, at any thread count,
//! and to the scalar integrator (tests/packet.rs). No stage reduces across lanes. Rust never
//! contracts a·b + c into an FMA, and `#[target_feature]` does not switch glam's compile-time
//! `cfg(target_feature = "fma")` paths on, so the wider entry points change instructions, not
//! results.
//!
//! **Fallback.** What is not in lanes renders with the scalar integrator, by the one rule in
//! `unsupported` (stated in docs/performance.md, "Paths in lanes").

mod kernel;
mod passes;

use crate::scene::Scene;
use crate::sensor::Sensor;

use super::caustics::Caustics;
use super::{RenderSettings, TileOut};

/// `--simd`: the packet width, or the scalar integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Simd {
    /// The fastest width the CPU runs: 8 with AVX2 (AVX-512 CPUs too, where 16 lanes measured
    /// slower), else 4.
    #[default]
    #[value(name = "auto")]
    Auto,
    /// One path per packet: the reference every width matches bit for bit.
    #[value(name = "1")]
    W1,
    #[value(name = "4")]
    W4,
    #[value(name = "8")]
    W8,
    #[value(name = "16")]
    W16,
    /// No packets: the scalar integrator, as fallback scenes use (for comparisons).
    #[value(name = "off")]
    Off,
}

impl Simd {
    /// The lanes this setting asks for (None: `off`); `auto` resolves to [`auto_width`].
    pub fn lanes(self) -> Option<usize> {
        match self {
            Simd::Auto => Some(auto_width()),
            Simd::W1 => Some(1),
            Simd::W4 => Some(4),
            Simd::W8 => Some(8),
            Simd::W16 => Some(16),
            Simd::Off => None,
        }
    }

    /// Err with the reason if this CPU cannot run the width asked for.
    pub fn check(self) -> Result<(), String> {
        match self.lanes() {
            Some(w) if !runs(w) => Err(format!(
                "--simd {w} needs {}, which this CPU lacks; use --simd auto (here: {}) or --simd {}",
                needs(w),
                auto_width(),
                widest()
            )),
            _ => Ok(()),
        }
    }
}

/// The instruction set a width is compiled for.
fn needs(w: usize) -> &'static str {
    match w {
        16 => "AVX-512F",
        8 => "AVX2",
        _ => "nothing beyond the baseline",
    }
}

/// True if this CPU runs the packet kernel at width `w`.
pub fn runs(w: usize) -> bool {
    match w {
        1 | 4 => true,
        #[cfg(target_arch = "x86_64")]
        8 => std::is_x86_feature_detected!("avx2"),
        #[cfg(target_arch = "x86_64")]
        16 => std::is_x86_feature_detected!("avx512f"),
        _ => false,
    }
}

/// The widest packet this CPU runs.
pub fn widest() -> usize {
    [16, 8, 4].into_iter().find(|&w| runs(w)).unwrap_or(1)
}

/// The width `auto` takes: 8 where AVX2 runs, else 4. Not 16 on AVX-512 CPUs: there the
/// 16-lane kernel rendered the Cornell box 12% slower than the 8-lane one (2.49 s against
/// 2.24 s, 256², 64 spp, 2 threads, 3 rounds; docs/performance.md), the bits being the same.
pub fn auto_width() -> usize {
    [8, 4].into_iter().find(|&w| runs(w)).unwrap_or(1)
}

/// The fallback rule: why `scene` under `settings` renders with the scalar integrator instead
/// of the packet kernel, or None if it renders in packets. Everything else (every camera,
/// material, emitter, texture, sensor, AOV layer, instancing, clamp, stderr, adaptive
/// sampling, caustic light tracing's camera paths) is in packets.
pub fn unsupported(scene: &Scene, _settings: &RenderSettings) -> Option<&'static str> {
    if scene.materials.iter().any(|m| m.dispersive()) {
        // Spectral MIS reweights a path's wavelengths at each dispersive event.
        return Some("a dispersive material");
    }
    None
}

/// The packet width a render of `scene` under `settings` takes; None: the scalar integrator.
pub fn width(scene: &Scene, settings: &RenderSettings) -> Option<usize> {
    match unsupported(scene, settings) {
        Some(_) => None,
        None => settings.simd.lanes(),
    }
}

/// In words, for the EXR header: the width used, or why the scalar integrator ran.
pub fn describe(scene: &Scene, settings: &RenderSettings) -> String {
    match (settings.simd, unsupported(scene, settings)) {
        (Simd::Off, _) => "off (scalar integrator, --simd off)".into(),
        (_, Some(why)) => format!("off (scalar integrator: {why} is not in packets yet)"),
        (s, None) => format!("{} paths per packet", s.lanes().unwrap_or(1)),
    }
}

/// Renders the tile at (x0, y0) in packets of `w` paths (`w` as `width` gave it).
#[allow(clippy::too_many_arguments)]
pub(super) fn render_tile<const N: usize, const SE: bool>(
    w: usize,
    scene: &Scene,
    settings: &RenderSettings,
    sensor: &Sensor,
    caustics: Option<&Caustics>,
    progress: &(dyn Fn(u64) + Sync),
    x0: u32,
    y0: u32,
) -> TileOut {
    let a = (scene, settings, sensor, caustics, progress, x0, y0);
    // Caustic light tracing's split chosen here, so each copy of the kernel is compiled (and
    // inlined) on its own, and a render without caustics runs the code it ran before them.
    match caustics {
        None => tile::<N, SE, false>(w, a),
        Some(_) => tile::<N, SE, true>(w, a),
    }
}

/// `render_tile` at width `w`, with (`C`) or without caustic light tracing's split.
#[inline(always)]
fn tile<const N: usize, const SE: bool, const C: bool>(w: usize, a: TileArgs) -> TileOut {
    match w {
        #[cfg(target_arch = "x86_64")]
        16 if runs(16) => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { tile_avx512::<N, SE, C>(a) }
        }
        #[cfg(target_arch = "x86_64")]
        8 if runs(8) => {
            // SAFETY: the CPU has AVX2 (checked just above).
            unsafe { tile_avx2::<N, SE, C>(a) }
        }
        4 => kernel::tile::<N, 4, SE, C>(a),
        1 => kernel::tile::<N, 1, SE, C>(a),
        w => panic!("packet width {w} is not available here (Simd::check lets it through only where it runs)"),
    }
}

type TileArgs<'a> = (
    &'a Scene,
    &'a RenderSettings,
    &'a Sensor,
    Option<&'a Caustics<'a>>,
    &'a (dyn Fn(u64) + Sync),
    u32,
    u32,
);

/// The kernel at W = 8, compiled for AVX2 (its inlined stages use 256-bit registers).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn tile_avx2<const N: usize, const SE: bool, const C: bool>(a: TileArgs) -> TileOut {
    kernel::tile::<N, 8, SE, C>(a)
}

/// The kernel at W = 16, compiled for AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn tile_avx512<const N: usize, const SE: bool, const C: bool>(a: TileArgs) -> TileOut {
    kernel::tile::<N, 16, SE, C>(a)
}
