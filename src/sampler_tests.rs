//! Tests of the per-pixel sample streams (sampler.rs): streams that depend only on (seed, pixel,
//! sample), decorrelated Sobol groups and pixels, both scramble paths and the groups past the
//! cache against the sobol_burley crate, stratification and (0, 2)-nets.

use super::*;

#[test]
fn streams_depend_only_on_seed_pixel_sample() {
    for kind in [SamplerKind::Independent, SamplerKind::Sobol] {
        let mut a = PixelSampler::new(kind, 7, 100);
        let mut b = PixelSampler::new(kind, 7, 100);
        a.start(5);
        let xa: Vec<f32> = (0..20).map(|_| a.next_1d()).collect();
        b.start(4);
        b.next_1d();
        b.start(5);
        let xb: Vec<f32> = (0..20).map(|_| b.next_1d()).collect();
        assert_eq!(xa, xb, "{kind:?}");
        assert!(xa.iter().all(|x| (0.0..1.0).contains(x)));
    }
}

#[test]
fn sobol_pairs_are_0_2_nets_in_every_group() {
    // Each group's first two lanes are a scrambled (0,2)-sequence: its first 64 points put
    // exactly one point in every elementary interval of area 1/64 (64x1, 32x2, ..., 1x64),
    // in the camera group and in bounce groups alike, in any pixel.
    for (pixel, group) in [(0u64, 0u32), (3, 1), (77, 2), (1000, 9), (5, 200)] {
        let mut s = PixelSampler::new(SamplerKind::Sobol, 11, pixel);
        let pts: Vec<Vec2> = (0..64)
            .map(|i| {
                s.start(i);
                s.set_dimension(group * 4);
                s.next_2d()
            })
            .collect();
        for kx in 0..=6 {
            let (nx, ny) = (1usize << kx, 1usize << (6 - kx));
            let mut hits = vec![0u32; 64];
            for p in &pts {
                let (i, j) = ((p.x * nx as f32) as usize, (p.y * ny as f32) as usize);
                hits[j * nx + i] += 1;
            }
            assert!(
                hits.iter().all(|&h| h == 1),
                "pixel {pixel} group {group} {nx}x{ny}"
            );
        }
    }
}

#[test]
fn sobol_groups_and_pixels_are_decorrelated() {
    // Padding: groups (and pixels) get their own scramble and sample order, so lanes of
    // different groups are not the same sequence; the sample mean of a product of two
    // groups' lanes is near 1/4 as for independent numbers (256 points: sd 0.014;
    // tolerance 3.6 sd).
    let mut s = PixelSampler::new(SamplerKind::Sobol, 2, 9);
    let mut t = PixelSampler::new(SamplerKind::Sobol, 2, 10);
    let (mut prod, mut same_g, mut same_p) = (0.0f64, 0, 0);
    for i in 0..256 {
        s.start(i);
        let a = s.next_1d();
        s.set_dimension(4);
        let b = s.next_1d();
        t.start(i);
        let c = t.next_1d();
        prod += a as f64 * b as f64;
        same_g += (a == b) as u32;
        same_p += (a == c) as u32;
    }
    assert!((prod / 256.0 - 0.25).abs() < 0.05, "{}", prod / 256.0);
    assert!(same_g < 4 && same_p < 4, "{same_g} {same_p}");
}

#[test]
fn fast_sobol_matches_the_crate() {
    for seed in [0u32, 1, 0xdead_beef, 12345] {
        let g = GroupScramble::new(seed);
        for index in (0..4096).chain([65535, 40000, 1 << 15]) {
            assert_eq!(
                g.sample(index),
                sobol_burley::sample_4d(index, 0, seed),
                "{seed} {index}"
            );
        }
    }
}

/// Both scramble paths, whichever `sample` takes on this CPU, against each other on random
/// inputs (every bit pattern of points and scrambles matters to the multiplies).
#[test]
#[cfg_attr(
    not(prism_host_sse41),
    ignore = "this CPU lacks SSE4.1/SSSE3: only the portable scramble runs"
)]
fn sse41_scramble_matches_the_portable_one() {
    #[cfg(target_arch = "x86_64")]
    {
        assert!(
            sse41(),
            "built on a CPU with SSE4.1, run on one without: rebuild here"
        );
        let mut rng = crate::math::rng::Pcg32::new(11, 2);
        for _ in 0..100_000 {
            let sobol: [u32; 4] = std::array::from_fn(|_| rng.next_u32());
            let lanes: [u32; 4] = std::array::from_fn(|_| rng.next_u32());
            let fast = unsafe { scramble_sse41(sobol, lanes) };
            let portable = GroupScramble::scramble(sobol, lanes);
            assert_eq!(
                fast.map(f32::to_bits),
                portable.map(f32::to_bits),
                "{sobol:x?} {lanes:x?}"
            );
        }
    }
}

#[test]
fn deep_groups_hash_their_scrambles_alike() {
    // Groups past the per-pixel cache give the crate's numbers, as cached groups do.
    let mut s = PixelSampler::new(SamplerKind::Sobol, 4, 8);
    s.start(3);
    s.set_dimension(40 * 4 + 1);
    let deep = s.next_1d();
    assert_eq!(deep, sobol_burley::sample_4d(3, 0, s.group_seed(40))[1]);
    s.set_dimension(2 * 4);
    let cached = s.next_1d();
    assert_eq!(cached, sobol_burley::sample_4d(3, 0, s.group_seed(2))[0]);
}

#[test]
fn sobol_is_stratified() {
    // The first 2^k Sobol points put exactly one point in each of 2^k strata of a dimension.
    let mut s = PixelSampler::new(SamplerKind::Sobol, 1, 3);
    let mut hits = [0u32; 64];
    for i in 0..64 {
        s.start(i);
        s.set_dimension(2);
        hits[(s.next_1d() * 64.0) as usize] += 1;
    }
    assert!(hits.iter().all(|&h| h == 1), "{hits:?}");
}
