//! What one run of the packet kernel over a tile does with each pixel: which of its samples
//! the lanes trace, the sums they start from, and where the sums go. A fixed-spp tile is one
//! pass; an adaptive tile is two, in the scalar loop's order (`integrator::adaptive` says why
//! it is unbiased): every pixel's pilot, then each pixel's samples from `min` up to the count
//! its neighbours' pilots ask for, summed on top of its pilot.

use crate::integrator::adaptive::Pilot;
use crate::integrator::{finish_pixel_at, Sums, TileOut};

/// One pass over a tile's pixels (indices in the tile, row-major).
pub(super) trait Pass {
    /// The seed of the pixels' sampler streams.
    fn seed(&self) -> u64;
    /// Samples `from..to` of pixel `p` are this pass's.
    fn range(&self, p: usize) -> (u32, u32);
    /// Sets a lane's `sums` to where pixel `p`'s samples start.
    fn begin(&self, p: usize, sums: &mut Sums);
    /// Pixel `p`'s sums once the pass's samples of it are in.
    fn end(&mut self, p: usize, sums: &Sums, out: &mut TileOut);
}

/// A fixed-spp tile: every pixel's `spp` samples, written out as it finishes.
pub(super) struct Fixed<const SE: bool> {
    pub(super) seed: u64,
    pub(super) spp: u32,
}

impl<const SE: bool> Pass for Fixed<SE> {
    #[inline(always)]
    fn seed(&self) -> u64 {
        self.seed
    }
    #[inline(always)]
    fn range(&self, _: usize) -> (u32, u32) {
        (0, self.spp)
    }
    #[inline(always)]
    fn begin(&self, _: usize, sums: &mut Sums) {
        sums.clear();
    }
    #[inline(always)]
    fn end(&mut self, p: usize, sums: &Sums, out: &mut TileOut) {
        finish_pixel_at::<SE>(sums, self.spp, out, p);
    }
}

/// Every pixel's first `min` samples of the stream `seed`, their sums (with squares) kept.
pub(super) struct Pilots {
    pub(super) seed: u64,
    pub(super) min: u32,
    pub(super) sums: Vec<Sums>,
}

impl Pass for Pilots {
    fn seed(&self) -> u64 {
        self.seed
    }
    fn range(&self, _: usize) -> (u32, u32) {
        (0, self.min)
    }
    fn begin(&self, _: usize, sums: &mut Sums) {
        sums.clear();
    }
    fn end(&mut self, p: usize, sums: &Sums, _: &mut TileOut) {
        self.sums[p].acc.clone_from(&sums.acc);
        self.sums[p].acc2.clone_from(&sums.acc2);
    }
}

impl Pilots {
    /// Each pilot's mean and variance at the judged slots.
    pub(super) fn pilots(&self, slots: &[usize]) -> Vec<Pilot> {
        let of = |s: &Sums| Pilot::of(self.min, &s.acc, &s.acc2, slots);
        self.sums.iter().map(of).collect()
    }
}

/// The rest of an adaptive tile: pixel p's samples `min..counts[p]`, on top of its pilot.
pub(super) struct Rest<const SE: bool> {
    pub(super) seed: u64,
    pub(super) min: u32,
    pub(super) counts: Vec<u32>,
    pub(super) pilots: Vec<Sums>,
}

impl<const SE: bool> Pass for Rest<SE> {
    fn seed(&self) -> u64 {
        self.seed
    }
    fn range(&self, p: usize) -> (u32, u32) {
        (self.min, self.counts[p])
    }
    fn begin(&self, p: usize, sums: &mut Sums) {
        sums.acc.clone_from(&self.pilots[p].acc);
        sums.acc2.clone_from(&self.pilots[p].acc2);
    }
    fn end(&mut self, p: usize, sums: &Sums, out: &mut TileOut) {
        finish_pixel_at::<SE>(sums, self.counts[p], out, p);
    }
}
