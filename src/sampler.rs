//! Per-pixel sample streams. Every number is a function of (seed, pixel, sample index,
//! dimension) only, so renders are bit-identical whatever the thread count or tile order.
//!
//! Dimensions come in groups of four, laid out so that every 2D decision uses a group's first
//! two lanes: camera (film x, film y, wavelength, -), then per bounce (emitter point u, v,
//! emitter choice, lobe) and (direction u, v, Russian roulette, -).

use crate::math::rng::{hash3, Pcg32};
use glam::Vec2;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
pub enum SamplerKind {
    /// Independent uniform numbers (PCG32): error falls as 1/spp, the textbook rate.
    Independent,
    /// Padded Owen-scrambled Sobol (Burley 2020, the `sobol_burley` crate): every group of four
    /// dimensions is the first four Sobol dimensions under a scramble and index shuffle of its
    /// own, fresh per pixel. Unbiased like `Independent`, with lower error at equal spp (film,
    /// wavelength and each bounce's light and direction samples are stratified). Best with
    /// power-of-two spp; at most 65536 spp.
    #[default]
    Sobol,
}

/// The most samples per pixel the Sobol sampler supports (sobol_burley's index limit).
pub const SOBOL_MAX_SPP: u32 = 1 << 16;

/// Dimensions used before the first bounce: film position (2), wavelength (1), one spare so
/// that bounces start on a group boundary.
pub const CAMERA_DIMS: u32 = 4;
/// Dimensions reserved per bounce: emitter point 2, emitter choice 1, lobe 1 | direction 2,
/// Russian roulette 1, spare 1.
pub const BOUNCE_DIMS: u32 = 8;

#[derive(Clone, Debug)]
pub struct PixelSampler {
    kind: SamplerKind,
    pixel_seed: u64,
    sample: u32,
    dim: u32,
    rng: Pcg32,
    /// Sobol: the group of four dimensions in `cache` (u32::MAX: none yet for this sample).
    group: u32,
    cache: [f32; 4],
    /// Sobol: each group's scrambles, made once per pixel (bit g of `seeded`: group g's are).
    seeded: u32,
    scrambles: [GroupScramble; CACHED_GROUPS],
}

/// How many groups' scrambles a pixel keeps: the camera and 15 bounces; deeper groups hash
/// theirs at each use.
const CACHED_GROUPS: usize = 32;

impl PixelSampler {
    pub fn new(kind: SamplerKind, seed: u64, pixel: u64) -> Self {
        let pixel_seed = hash3(seed, pixel, 0x5eed);
        Self {
            kind,
            pixel_seed,
            sample: 0,
            dim: 0,
            rng: Pcg32::new(pixel_seed, 0),
            group: u32::MAX,
            cache: [0.0; 4],
            seeded: 0,
            scrambles: [GroupScramble::default(); CACHED_GROUPS],
        }
    }

    /// Makes this sampler `new(kind, seed, pixel)`'s equal without rebuilding its scramble
    /// cache (the packet kernel moves a lane's sampler from pixel to pixel): a group's cached
    /// scrambles are read only once `seeded` says they were made for this pixel.
    #[inline]
    pub fn reset(&mut self, kind: SamplerKind, seed: u64, pixel: u64) {
        let pixel_seed = hash3(seed, pixel, 0x5eed);
        self.kind = kind;
        self.pixel_seed = pixel_seed;
        self.sample = 0;
        self.dim = 0;
        self.rng = Pcg32::new(pixel_seed, 0);
        self.group = u32::MAX;
        self.cache = [0.0; 4];
        self.seeded = 0;
    }

    /// Starts sample `index` of this pixel at dimension 0.
    #[inline]
    pub fn start(&mut self, index: u32) {
        self.sample = index;
        self.dim = 0;
        match self.kind {
            SamplerKind::Independent => {
                self.rng = Pcg32::new(hash3(self.pixel_seed, index as u64, 1), self.pixel_seed)
            }
            SamplerKind::Sobol => self.group = u32::MAX,
        }
    }

    /// Jumps to a dimension, so each bounce's decisions use the same dimensions in every path.
    #[inline]
    pub fn set_dimension(&mut self, dim: u32) {
        self.dim = dim;
    }

    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let d = self.dim;
        self.dim += 1;
        match self.kind {
            SamplerKind::Independent => self.rng.next_f32(),
            SamplerKind::Sobol => {
                let g = d >> 2;
                if g != self.group {
                    self.fill_group(g);
                }
                self.cache[(d & 3) as usize]
            }
        }
    }

    /// Padding (Burley 2020, section 4): every group is the first four Sobol dimensions, whose
    /// projections are the best stratified, decorrelated from the other groups by a seed of
    /// its own that scrambles the values and shuffles the sample order.
    #[inline(never)]
    fn fill_group(&mut self, g: u32) {
        let scr = if (g as usize) < CACHED_GROUPS {
            if self.seeded & (1 << g) == 0 {
                self.scrambles[g as usize] = GroupScramble::new(self.group_seed(g));
                self.seeded |= 1 << g;
            }
            self.scrambles[g as usize]
        } else {
            GroupScramble::new(self.group_seed(g))
        };
        self.cache = scr.sample(self.sample);
        self.group = g;
    }

    fn group_seed(&self, g: u32) -> u32 {
        hash3(self.pixel_seed, g as u64, 0x50b0) as u32
    }

    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let x = self.next_1d();
        Vec2::new(x, self.next_1d())
    }
}

/// The 4D Owen-scrambled Sobol points of `sobol_burley::sample_4d(index, 0, seed)`, bit for bit
/// (tested), computed faster: the crate walks the index bit by bit through the generator
/// matrices and re-derives the seed's hashes at each call (13.7% of a Cornell render in perf);
/// here the matrices are applied a byte at a time from tables and the hashes are made once per
/// pixel and group.
#[derive(Clone, Copy, Debug, Default)]
struct GroupScramble {
    index: u32,
    lanes: [u32; 4],
}

impl GroupScramble {
    fn new(seed: u32) -> Self {
        use sobol_burley::parts::{hash, hash_int4, Int4};
        let s = seed.wrapping_mul(0x9c8f2d3b);
        // The crate's per-lane constants for dimension set 0.
        let lanes = Int4::from([
            s ^ 0x912f69ba,
            s ^ 0x174f18ab,
            s ^ 0x691e72ca,
            s ^ 0xb40cc1b8,
        ]);
        Self {
            index: hash(seed ^ 0x79c68e4a),
            lanes: hash_int4(lanes).into(),
        }
    }

    #[inline]
    fn sample(&self, index: u32) -> [f32; 4] {
        let rev = sobol_burley::parts::owen_scramble_rev(index.reverse_bits(), self.index);
        let t = sobol_tables();
        let (hi, lo) = (
            &t[0][(rev >> 24) as usize],
            &t[1][(rev >> 16 & 0xff) as usize],
        );
        let sobol = [hi[0] ^ lo[0], hi[1] ^ lo[1], hi[2] ^ lo[2], hi[3] ^ lo[3]];
        #[cfg(target_arch = "x86_64")]
        if sse41() {
            // SAFETY: the CPU has SSE4.1 and SSSE3 (checked at run time).
            return unsafe { scramble_sse41(sobol, self.lanes) };
        }
        Self::scramble(sobol, self.lanes)
    }

    /// The lanes' Owen scramble, bit reversal and conversion to [0, 1), as the crate does them
    /// (with baseline x86-64's SSE2, its 32-bit multiplies are emulated).
    fn scramble(sobol: [u32; 4], lanes: [u32; 4]) -> [f32; 4] {
        use sobol_burley::parts::{owen_scramble_int4_rev, Int4};
        owen_scramble_int4_rev(Int4::from(sobol), Int4::from(lanes))
            .reverse_bits()
            .to_f32_norm()
    }
}

/// True if the CPU runs `scramble_sse41` (std caches the answer; the check is a load and a bit
/// test).
#[cfg(target_arch = "x86_64")]
#[inline]
fn sse41() -> bool {
    std::is_x86_feature_detected!("sse4.1") && std::is_x86_feature_detected!("ssse3")
}

/// `GroupScramble::scramble` with SSE4.1's 32-bit multiply (the crate emulates it with 7 SSE2
/// operations when the build targets baseline x86-64, as prism's does) and an SSSE3 bit
/// reversal (bytes by one shuffle, bits within bytes by two nibble-table shuffles, instead of
/// five mask-and-shift rounds). The same integer operations: the same bits (tested).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse4.1,ssse3")]
unsafe fn scramble_sse41(sobol: [u32; 4], lanes: [u32; 4]) -> [f32; 4] {
    use std::arch::x86_64::*;
    // SAFETY: unaligned loads and stores of 16-byte arrays.
    let (mut n, s) = unsafe {
        (
            _mm_loadu_si128(sobol.as_ptr().cast()),
            _mm_loadu_si128(lanes.as_ptr().cast()),
        )
    };
    // Owen scramble in the reversed-bit domain (Burley 2020; constants as in `sobol_burley`).
    n = _mm_xor_si128(n, _mm_mullo_epi32(n, _mm_set1_epi32(0x3d20adea)));
    n = _mm_add_epi32(n, s);
    n = _mm_mullo_epi32(n, _mm_or_si128(_mm_srli_epi32(s, 16), _mm_set1_epi32(1)));
    n = _mm_xor_si128(n, _mm_mullo_epi32(n, _mm_set1_epi32(0x05526c56)));
    n = _mm_xor_si128(n, _mm_mullo_epi32(n, _mm_set1_epi32(0x53a22864)));
    // Reverse each lane's bits: its bytes in reverse order, then each byte's two nibbles
    // reversed and swapped.
    n = _mm_shuffle_epi8(
        n,
        _mm_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12),
    );
    // Nibble i reversed, in a byte's low half and in its high half.
    const REV: [u8; 16] = [0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15];
    const REV_HIGH: [u8; 16] = [
        0x00, 0x80, 0x40, 0xc0, 0x20, 0xa0, 0x60, 0xe0, 0x10, 0x90, 0x50, 0xd0, 0x30, 0xb0, 0x70,
        0xf0,
    ];
    // SAFETY: unaligned loads of 16-byte arrays.
    let (to_high, to_low) = unsafe {
        (
            _mm_loadu_si128(REV_HIGH.as_ptr().cast()),
            _mm_loadu_si128(REV.as_ptr().cast()),
        )
    };
    let nibble = _mm_set1_epi8(0x0f);
    let low = _mm_and_si128(n, nibble);
    let high = _mm_and_si128(_mm_srli_epi16(n, 4), nibble);
    n = _mm_or_si128(
        _mm_shuffle_epi8(to_high, low),
        _mm_shuffle_epi8(to_low, high),
    );
    // The top 23 bits as a float in [1, 2), minus 1.
    let one = _mm_set1_epi32(0x3f80_0000);
    let f = _mm_sub_ps(
        _mm_castsi128_ps(_mm_or_si128(_mm_srli_epi32(n, 9), one)),
        _mm_set1_ps(1.0),
    );
    let mut out = [0.0f32; 4];
    // SAFETY: an unaligned store into a 16-byte array.
    unsafe { _mm_storeu_ps(out.as_mut_ptr(), f) };
    out
}

/// The first four Sobol dimensions' generator matrices (bit-reversed, as the crate keeps them)
/// applied to one byte of the reversed 16-bit index: `[0]` for its high byte, `[1]` for the low.
fn sobol_tables() -> &'static [[[u32; 4]; 256]; 2] {
    static TABLES: std::sync::OnceLock<Box<[[[u32; 4]; 256]; 2]>> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        // Column i of the matrices: the points of the index whose reversed form has only bit
        // 31 - i set.
        let column =
            |i: u32| -> [u32; 4] { sobol_burley::parts::sobol_int4_rev(1 << (31 - i), 0).into() };
        let mut t = Box::new([[[0u32; 4]; 256]; 2]);
        for (half, table) in t.iter_mut().enumerate() {
            for (b, entry) in table.iter_mut().enumerate() {
                for bit in 0..8u32 {
                    if b & (0x80 >> bit) != 0 {
                        let c = column(half as u32 * 8 + bit);
                        for k in 0..4 {
                            entry[k] ^= c[k];
                        }
                    }
                }
            }
        }
        t
    })
}

#[cfg(test)]
#[path = "sampler_tests.rs"]
mod tests;
