//! A tile's camera samples as one stream in (pixel, sample index) order, and the ring that puts
//! finished paths back in that order: lanes finish out of order (paths differ in length), but
//! each pixel sums its samples in sample order, as the scalar loop does, so the sums do not
//! depend on the packet width.

use crate::integrator::{add_sample, finish_pixel, Sums, TileCounts, TileOut};
use crate::sensor::Sensor;
use crate::spectrum::{Spectrum, Wavelengths};

/// Finished samples a tile may hold ahead of the oldest unfinished one. The widest packet
/// (16) times 4: a long path holds back at most this many finished ones before lanes idle.
pub(super) const RING: usize = 64;

/// Stream position of a camera sample within its tile.
pub(super) type Item = u64;

/// The stream of one tile: which item comes next, and the ring of finished ones.
pub(super) struct Stream<const N: usize> {
    /// Samples per pixel.
    spp: u64,
    /// Items in the tile (pixels × spp).
    total: Item,
    /// The next item to hand to a lane.
    next: Item,
    /// The oldest item not yet summed.
    flushed: Item,
    done: [Option<(Spectrum<N>, Wavelengths<N>)>; RING],
    sums: Sums,
    clamp: f32,
}

impl<const N: usize> Stream<N> {
    pub(super) fn new(pixels: u64, spp: u32, slots: usize, squares: bool, clamp: f32) -> Self {
        Stream {
            spp: spp as u64,
            total: pixels * spp as u64,
            next: 0,
            flushed: 0,
            done: [None; RING],
            sums: Sums::new(slots, squares),
            clamp,
        }
    }

    /// The next item and its (pixel in tile, sample index), if the stream has one and the
    /// ring has room for it.
    #[inline]
    pub(super) fn take(&mut self) -> Option<(Item, u64, u32)> {
        if self.next == self.total || self.next - self.flushed == RING as u64 {
            return None;
        }
        let i = self.next;
        self.next += 1;
        Some((i, i / self.spp, (i % self.spp) as u32))
    }

    /// True once every item was handed out and summed.
    pub(super) fn finished(&self) -> bool {
        self.flushed == self.total
    }

    /// Records item `i`'s radiance `l` at `wl`.
    #[inline]
    pub(super) fn put(&mut self, i: Item, l: Spectrum<N>, wl: Wavelengths<N>) {
        self.done[(i % RING as u64) as usize] = Some((l, wl));
    }

    /// Sums the finished items that are next in order into their pixels, appending each
    /// pixel to `out` as its last sample is summed.
    #[inline]
    pub(super) fn flush<const SE: bool>(&mut self, sensor: &Sensor, out: &mut TileOut) {
        while let Some((l, wl)) = self.done[(self.flushed % RING as u64) as usize].take() {
            let counts: &mut TileCounts = &mut out.counts;
            add_sample::<N, SE>(sensor, self.clamp, l, &wl, &mut self.sums, counts);
            self.flushed += 1;
            if self.flushed % self.spp == 0 {
                out.counts.samples += self.spp;
                finish_pixel::<SE>(&self.sums, self.spp as u32, out);
                self.sums.clear();
            }
        }
    }
}
