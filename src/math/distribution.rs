//! Piecewise-constant 1D distributions: discrete choices by weight (triangles by area, emitters)
//! and continuous tabulated functions (pixel filters, environment-map rows).

/// Tables of at least this many cells get a guide table (`Distribution1D::guide`); below it a
/// binary search takes at most four steps.
const GUIDED: usize = 16;

/// Entries of the cdf `walk` compares with u at once, from the guide's start.
const WINDOW: usize = 8;

/// A distribution over `n` cells proportional to non-negative weights.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f32>,
    /// cdf[0] = 0, cdf[n] = 1; a guided table's is followed by `WINDOW` +∞ pads, so `walk`
    /// reads a whole window from any start (`cdf()` is the table without them).
    cdf: Vec<f32>,
    integral: f32,
    /// Guide table (Chen's): `guide[k]` is where the cdf passes k / guide.len(), so `find`
    /// starts a short walk there instead of a binary search (two of those were half of an
    /// environment map's sampling). Empty for small or unsorted tables (binary search).
    guide: Vec<u32>,
    /// A sorted cdf too small for a guide: `count_at_most` counts it.
    small_sorted: bool,
}

impl Distribution1D {
    /// Weights must be finite and non-negative; if they are all zero the distribution is uniform
    /// (so a degenerate table never yields NaN).
    pub fn new(weights: &[f32]) -> Self {
        assert!(
            !weights.is_empty(),
            "a distribution needs at least one cell"
        );
        let n = weights.len();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f32);
        let mut acc = 0.0f64;
        for &w in weights {
            debug_assert!(w.is_finite() && w >= 0.0);
            acc += w.max(0.0) as f64;
            cdf.push(acc as f32);
        }
        let integral = acc as f32;
        if integral > 0.0 {
            for c in &mut cdf[1..] {
                *c = (*c as f64 / acc) as f32;
            }
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f32 / n as f32;
            }
        }
        cdf[n] = 1.0;
        let func = if integral > 0.0 {
            weights.to_vec()
        } else {
            vec![1.0; n]
        };
        let integral = if integral > 0.0 { integral } else { n as f32 };
        // The walk equals the binary search only on a sorted cdf (rounding could in principle
        // put the last normalised sum above the final 1).
        let sorted = cdf.windows(2).all(|w| w[0] <= w[1]);
        let guide: Vec<u32> = if n >= GUIDED && sorted {
            (0..n)
                .map(|k| cdf.partition_point(|&c| c <= k as f32 / n as f32) as u32)
                .collect()
        } else {
            Vec::new()
        };
        if !guide.is_empty() {
            cdf.extend([f32::INFINITY; WINDOW]);
        }
        Self {
            func,
            cdf,
            integral,
            guide,
            small_sorted: n < GUIDED && sorted,
        }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }

    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// Sum of the weights.
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// The cdf: n + 1 entries from 0 to 1.
    fn cdf(&self) -> &[f32] {
        &self.cdf[..=self.func.len()]
    }

    /// Probability of cell `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.cdf[i + 1] - self.cdf[i]
    }

    #[inline]
    fn find(&self, u: f32) -> usize {
        // Largest i with cdf[i] <= u, kept within [0, n-1]; skips zero-width cells.
        let i = self.count_at_most(u);
        i.saturating_sub(1).min(self.func.len() - 1)
    }

    /// How many cdf entries are <= u: `partition_point`'s answer (exactly: the walk stops at
    /// the one place where the sorted cdf crosses u, wherever it starts, and on a sorted cdf
    /// the count of entries <= u is that place).
    #[inline]
    fn count_at_most(&self, u: f32) -> usize {
        if self.guide.is_empty() || u.is_nan() {
            if self.small_sorted {
                // A small table counted without branches: an area light's triangle is a coin
                // toss per sample (two triangles), which the binary search's branch mispredicted
                // half the time.
                return self.cdf.iter().map(|&c| (c <= u) as usize).sum();
            }
            return self.cdf().partition_point(|&c| c <= u);
        }
        self.walk(u)
    }

    /// `count_at_most` of a guided table: the guide's bucket gives where the count starts, and
    /// one SIMD comparison of the next `WINDOW` entries with u ends it (the entries ≤ u are a
    /// prefix of the sorted cdf). The walk's loops before mispredicted on the short, varying
    /// spans of an environment map's rows and a Gaussian pixel filter's tails (6% of the
    /// tabletop dataset's frames). A start past u (u rounded into the next bucket) or a span
    /// longer than the window walks as before.
    #[inline(always)]
    fn walk(&self, u: f32) -> usize {
        use wide::{f32x4, CmpLe};
        let m = self.guide.len();
        // Saturating: a negative u takes bucket 0, and the walk goes back to 0.
        let g = self.guide[((u * m as f32) as usize).min(m - 1)] as usize;
        let w = &self.cdf[g..g + WINDOW];
        let uv = f32x4::splat(u);
        let lo = f32x4::from([w[0], w[1], w[2], w[3]]).cmp_le(uv).move_mask() as u32;
        let hi = f32x4::from([w[4], w[5], w[6], w[7]]).cmp_le(uv).move_mask() as u32;
        let below = (!((lo & 0xf) | (hi & 0xf) << 4)).trailing_zeros() as usize;
        if below < WINDOW && (g == 0 || self.cdf[g - 1] <= u) {
            return g + below;
        }
        self.walk_far(g, u)
    }

    /// The walk from `g` one entry at a time, both ways.
    #[cold]
    #[inline(never)]
    fn walk_far(&self, mut i: usize, u: f32) -> usize {
        let n = self.func.len() + 1;
        while i < n && self.cdf[i] <= u {
            i += 1;
        }
        while i > 0 && self.cdf[i - 1] > u {
            i -= 1;
        }
        i
    }

    /// Picks a cell; returns it, its probability, and `u` rescaled to [0,1) within the cell
    /// (so the same number can drive the next decision).
    #[inline]
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let mut i = self.find(u);
        while self.pmf(i) == 0.0 && i > 0 {
            i -= 1;
        }
        let p = self.pmf(i);
        let rescaled = ((u - self.cdf[i]) / p).clamp(0.0, 1.0 - f32::EPSILON * 0.5);
        (i, p, rescaled)
    }

    /// Samples x in [0,1) with density func(x)/∫func (cells of width 1/n); returns (x, pdf, cell).
    #[inline]
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (i, p, du) = self.sample_discrete(u);
        let n = self.func.len() as f32;
        ((i as f32 + du) / n, p * n, i)
    }

    /// Density at x in [0,1) of `sample_continuous`.
    #[inline]
    pub fn pdf_continuous(&self, x: f32) -> f32 {
        let n = self.func.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.pmf(i) * n as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_probabilities_follow_weights() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert!(
            (d.pmf(0) - 0.25).abs() < 1e-6 && d.pmf(1) == 0.0 && (d.pmf(2) - 0.75).abs() < 1e-6
        );
        assert_eq!(d.sample_discrete(0.1).0, 0);
        assert_eq!(
            d.sample_discrete(0.25).0,
            2,
            "zero-weight cell is never chosen"
        );
        assert_eq!(d.sample_discrete(0.999_999).0, 2);
        let (i, _, r) = d.sample_discrete(0.625);
        assert_eq!(i, 2);
        assert!((r - 0.5).abs() < 1e-6);
    }

    /// A xorshift stream of floats in [0, 1).
    fn uniforms() -> impl FnMut() -> f32 {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// Probes of `count_at_most`: uniform ones, every cdf value and the floats next to it,
    /// bucket edges (`m` buckets), out of range, infinities and NaN.
    fn probes(d: &Distribution1D, m: usize, rnd: &mut impl FnMut() -> f32) -> Vec<f32> {
        let mut us: Vec<f32> = (0..5000).map(|_| rnd()).collect();
        for &c in d.cdf() {
            us.extend([c, c.next_up(), c.next_down()]);
        }
        us.extend((0..=m).map(|k| k as f32 / m as f32));
        us.extend([
            -1.0,
            -0.0,
            0.0,
            1.0,
            1.5,
            f32::INFINITY,
            -f32::INFINITY,
            f32::NAN,
        ]);
        us
    }

    /// For each size n: random weights; mostly zero (cell k nonzero where k mod p = r, for
    /// `(p, r) = sparse`); and one spike at n / `spike` holding nearly everything.
    fn random_tables(
        sizes: impl IntoIterator<Item = usize>,
        (p, r): (usize, usize),
        spike: usize,
        rnd: &mut impl FnMut() -> f32,
    ) -> Vec<Vec<f32>> {
        let mut tables = Vec::new();
        for n in sizes {
            tables.push((0..n).map(|_| rnd()).collect());
            tables.push(
                (0..n)
                    .map(|k| if k % p == r { rnd() } else { 0.0 })
                    .collect(),
            );
            let mut s: Vec<f32> = (0..n).map(|_| rnd() * 1e-6).collect();
            s[n / spike] = 1e4;
            tables.push(s);
        }
        tables
    }

    /// The branch-free count of a small table gives `partition_point`'s index for every u:
    /// tables of 1 to 15 cells, with zero cells, all zero, and one cell holding nearly all.
    #[test]
    fn small_count_is_the_binary_search() {
        let mut rnd = uniforms();
        let mut tables: Vec<Vec<f32>> = vec![vec![1.0], vec![0.0; 3], vec![1.0, 0.0, 3.0]];
        tables.extend(random_tables(1..GUIDED, (3, 1), 2, &mut rnd));
        for w in &tables {
            let d = Distribution1D::new(w);
            assert!(
                d.small_sorted && d.guide.is_empty(),
                "{} cells are counted",
                w.len()
            );
            for u in probes(&d, w.len(), &mut rnd) {
                let want = d.cdf().partition_point(|&c| c <= u);
                assert_eq!(d.count_at_most(u), want, "u {u}, table {w:?}");
            }
        }
    }

    /// The guided walk gives `partition_point`'s index for every u: on tables with zero
    /// cells, spikes (a sun), all-zero rows, many cells per bucket and one, at every cdf
    /// value, the floats next to them, bucket edges, out of range and NaN.
    #[test]
    fn guided_find_is_the_binary_search() {
        let mut rnd = uniforms();
        let mut tables: Vec<Vec<f32>> = vec![vec![0.0; 40], vec![1.0; 16], vec![1.0; 1000]];
        let sizes = [16, 17, 63, 128, 1000, 4097];
        tables.extend(random_tables(sizes, (7, 3), 3, &mut rnd));
        for w in &tables {
            let d = Distribution1D::new(w);
            assert!(!d.guide.is_empty(), "{} cells are guided", w.len());
            for u in probes(&d, d.guide.len(), &mut rnd) {
                let want = d.cdf().partition_point(|&c| c <= u);
                assert_eq!(d.count_at_most(u), want, "u {u}, {} cells", w.len());
            }
        }
    }

    #[test]
    fn all_zero_weights_are_uniform() {
        let d = Distribution1D::new(&[0.0, 0.0]);
        assert!((d.pmf(0) - 0.5).abs() < 1e-6);
        let (x, pdf, _) = d.sample_continuous(0.7);
        assert!((x - 0.7).abs() < 1e-6 && (pdf - 1.0).abs() < 1e-6);
    }
}
