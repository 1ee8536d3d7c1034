//! Piecewise-constant distributions on [0, 1) and [0, 1)², pbrt-v4 Appendix A.4
//! (PiecewiseConstant1D) and A.5 (PiecewiseConstant2D).
//!
//! A 1D function given by `n` non-negative cell values f_i on [0, 1) has the density
//! p(x) = f_⌊nx⌋ / I with I = Σ f_i / n, and the CDF P(k/n) = Σ_{i<k} f_i / (n I). Sampling inverts
//! the CDF by binary search and linear interpolation inside the cell. A 2D function on an
//! `nu`×`nv` grid (row-major, rows along v) is sampled as the marginal p(v) of the row integrals
//! times the conditional p(u | v) of the chosen row; its density is p(u, v) = f(u, v) / I₂ with
//! I₂ = Σ f / (nu·nv).
//!
//! A function that is zero everywhere becomes uniform (pbrt-v4 does the same for its CDF), so a
//! distribution always has a valid density. Running sums are taken in f64, so the CDF of a
//! multi-megapixel environment map stays monotone and ends at exactly 1.
//!
//! | parameter | type | default | unit |
//! |---|---|---|---|
//! | `func` | `&[f32]`, ≥ 0 (negative and NaN count as 0) | — | any |
//! | `nu`, `nv` (2D) | `usize` | — | cells |

use glam::Vec2;

/// Largest f32 below 1: sample coordinates are clamped to [0, ONE_MINUS_EPSILON].
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A piecewise-constant density on [0, 1) with `len()` equal cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// Cell values (all ones when the input was zero everywhere).
    func: Vec<f32>,
    /// CDF at the cell boundaries, `func.len() + 1` entries, cdf[0] = 0, cdf[n] = 1.
    cdf: Vec<f32>,
    /// Guide table (Chen & Asau 1974, "On Generating Random Variates from an Empirical
    /// Distribution", AIIE Transactions 6(2)): `guide[k]` is the cell of u = k/n, so the cell
    /// of any u lies between `guide[⌊u·n⌋]` and `guide[⌊u·n⌋ + 1]`, and the binary search
    /// runs over those few entries instead of all n. Same cell as the full search, bit for bit.
    guide: Vec<u32>,
    /// ∫₀¹ f(x) dx = Σ f_i / n.
    integral: f32,
}

impl Distribution1D {
    /// Distribution proportional to `func` (an empty or all-zero `func` gives the uniform
    /// distribution over max(len, 1) cells).
    pub fn new(func: &[f32]) -> Self {
        let mut func: Vec<f32> = func
            .iter()
            .map(|&f| if f > 0.0 && f.is_finite() { f } else { 0.0 })
            .collect();
        if func.is_empty() {
            func.push(0.0);
        }
        let mut sum: f64 = func.iter().map(|&f| f as f64).sum();
        if sum <= 0.0 {
            func.iter_mut().for_each(|f| *f = 1.0);
            sum = func.len() as f64;
        }
        let n = func.len();
        let mut cdf = Vec::with_capacity(n + 1);
        let mut running = 0.0f64;
        cdf.push(0.0);
        for &f in &func {
            running += f as f64;
            cdf.push((running / sum) as f32);
        }
        cdf[n] = 1.0;
        let guide = (0..=n)
            .map(|k| {
                let t = k as f32 / n as f32;
                ((cdf.partition_point(|&c| c <= t) - 1).min(n - 1)) as u32
            })
            .collect();
        Distribution1D {
            func,
            cdf,
            guide,
            integral: (sum / n as f64) as f32,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Always false: a distribution has at least one cell.
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// ∫₀¹ f(x) dx of the (possibly uniformised) function.
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// The cell `o` with cdf[o] ≤ u < cdf[o+1] and the position of u inside it, in [0, 1).
    fn find(&self, u: f32) -> (usize, f32) {
        // A NaN u (never from the samplers) is read as 0 rather than wrapping the search.
        let u = if u.is_nan() {
            0.0
        } else {
            u.clamp(0.0, ONE_MINUS_EPSILON)
        };
        // Largest o with cdf[o] ≤ u; zero-width cells are skipped because the last of equal
        // CDF entries is taken, and cdf[n] = 1 > u bounds o by n − 1.
        let n = self.func.len();
        let b = ((u * n as f32) as usize).min(n - 1);
        let (lo, hi) = (self.guide[b] as usize, self.guide[b + 1] as usize + 1);
        // The window cdf[lo..hi] holds the answer when cdf[lo] ≤ u < cdf[hi]; rounding of
        // u·n can put u one bucket off, and then the whole CDF is searched.
        let last = if self.cdf[lo] <= u && u < self.cdf[hi] {
            lo + self.cdf[lo..hi].partition_point(|&c| c <= u) - 1
        } else {
            self.cdf.partition_point(|&c| c <= u) - 1
        };
        let o = last.min(n - 1);
        let width = self.cdf[o + 1] - self.cdf[o];
        let du = if width > 0.0 {
            ((u - self.cdf[o]) / width).clamp(0.0, ONE_MINUS_EPSILON)
        } else {
            0.0
        };
        (o, du)
    }

    /// Continuous sample: (x ∈ [0, 1), density p(x), cell index).
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (o, du) = self.find(u);
        let n = self.func.len() as f32;
        let x = keep_in_cell((o as f32 + du) / n, o, self.func.len());
        (x, self.func[o] / self.integral, o)
    }

    /// Discrete sample: (cell index, its probability, u remapped to [0, 1) inside the cell so
    /// the caller can reuse it).
    pub fn sample_discrete(&self, u: f32) -> (usize, f32, f32) {
        let (o, du) = self.find(u);
        (o, self.pmf(o), du)
    }

    /// Density p(x) of [`Distribution1D::sample_continuous`] at x ∈ [0, 1); 0 outside.
    pub fn pdf(&self, x: f32) -> f32 {
        if !(0.0..=1.0).contains(&x) {
            return 0.0;
        }
        let n = self.func.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.func[i] / self.integral
    }

    /// Probability of cell `i` under [`Distribution1D::sample_discrete`]: f_i / Σ f.
    pub fn pmf(&self, i: usize) -> f32 {
        match self.func.get(i) {
            Some(&f) => f / (self.integral * self.func.len() as f32),
            None => 0.0,
        }
    }
}

/// Nudges `x` by ulps until ⌊x·n⌋ = o, so a sample's reported density is its own cell's even
/// where (o + du)/n rounds onto the next cell boundary.
fn keep_in_cell(x: f32, o: usize, n: usize) -> f32 {
    let mut x = x.clamp(0.0, ONE_MINUS_EPSILON);
    for _ in 0..8 {
        let i = ((x * n as f32) as usize).min(n - 1);
        if i == o {
            break;
        }
        // x ≥ 0, so one ulp down/up is ∓1 on the bit pattern (and i > o implies x > 0).
        x = f32::from_bits(if i > o { x.to_bits() - 1 } else { x.to_bits() + 1 });
    }
    x
}

/// A piecewise-constant density on [0, 1)² over an `nu`×`nv` grid of cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    /// p(u | v) for each row v.
    conditional: Vec<Distribution1D>,
    /// p(v) from the row integrals.
    marginal: Distribution1D,
}

impl Distribution2D {
    /// Distribution proportional to the row-major grid `func` (`nv` rows of `nu` cells; row
    /// index along v). A grid whose size does not match `nu`·`nv` is padded with zeros or cut.
    pub fn new(func: &[f32], nu: usize, nv: usize) -> Self {
        let (nu, nv) = (nu.max(1), nv.max(1));
        let conditional: Vec<Distribution1D> = (0..nv)
            .map(|v| {
                let start = (v * nu).min(func.len());
                let end = ((v + 1) * nu).min(func.len());
                let mut row = func[start..end].to_vec();
                row.resize(nu, 0.0);
                Distribution1D::new(&row)
            })
            .collect();
        // A row that was all zero was uniformised; its marginal weight must stay zero.
        let row_integrals: Vec<f32> = (0..nv)
            .map(|v| {
                let start = (v * nu).min(func.len());
                let end = ((v + 1) * nu).min(func.len());
                let sum: f64 = func[start..end]
                    .iter()
                    .map(|&f| if f > 0.0 && f.is_finite() { f as f64 } else { 0.0 })
                    .sum();
                (sum / nu as f64) as f32
            })
            .collect();
        Distribution2D {
            conditional,
            marginal: Distribution1D::new(&row_integrals),
        }
    }

    /// Row index of coordinate v.
    fn row(&self, v: f32) -> usize {
        let nv = self.conditional.len();
        ((v * nv as f32) as usize).min(nv - 1)
    }

    /// Sample a point: `u.y` picks the row from the marginal, `u.x` the position in the row.
    /// Returns (point in [0, 1)², density p(u, v)).
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (v, pdf_v, iv) = self.marginal.sample_continuous(u.y);
        let (x, pdf_u, _) = self.conditional[iv].sample_continuous(u.x);
        (Vec2::new(x, v), pdf_u * pdf_v)
    }

    /// Density p(u, v) of [`Distribution2D::sample`]; 0 outside [0, 1]².
    pub fn pdf(&self, p: Vec2) -> f32 {
        if !(0.0..=1.0).contains(&p.x) || !(0.0..=1.0).contains(&p.y) {
            return 0.0;
        }
        // p(u | v)·p(v) = (f/I_row)·(I_row/I₂); a zero row that was uniformised in its
        // conditional keeps density zero through its marginal.
        self.conditional[self.row(p.y)].pdf(p.x) * self.marginal.pdf(p.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::test_support::{assert_chi_square, Pcg32};

    #[test]
    fn light_distribution_1d_pmf_and_pdf_are_normalised() {
        let d = Distribution1D::new(&[0.0, 1.0, 3.0, 0.0, 0.5, 2.5]);
        let pmf_sum: f32 = (0..d.len()).map(|i| d.pmf(i)).sum();
        let n = 60_000;
        let pdf_int: f32 = (0..n)
            .map(|k| d.pdf((k as f32 + 0.5) / n as f32) / n as f32)
            .sum();
        assert!((pmf_sum - 1.0).abs() < 1e-6, "Σ pmf = {pmf_sum}, expected 1");
        assert!((pdf_int - 1.0).abs() < 1e-4, "∫ pdf = {pdf_int}, expected 1");
        assert!(
            (d.pmf(2) - 3.0 / 7.0).abs() < 1e-6,
            "pmf(2) = {}, expected 3/7",
            d.pmf(2)
        );
        let uniform = Distribution1D::new(&[0.0, 0.0, 0.0, 0.0]);
        assert!(
            (uniform.pmf(3) - 0.25).abs() < 1e-7,
            "all-zero pmf {}",
            uniform.pmf(3)
        );
        assert!(
            (uniform.pdf(0.3) - 1.0).abs() < 1e-7,
            "all-zero pdf {}",
            uniform.pdf(0.3)
        );
    }

    #[test]
    fn light_distribution_1d_samples_follow_the_function() {
        let func = [0.0, 1.0, 3.0, 0.0, 0.5, 2.5, 1e-3, 7.0];
        let d = Distribution1D::new(&func);
        let mut rng = Pcg32::new(1, 1);
        let n = 400_000u64;
        let mut counts = vec![0u64; func.len()];
        for _ in 0..n {
            let u = rng.next_f32();
            let (x, pdf, i) = d.sample_continuous(u);
            assert!(
                ((x * func.len() as f32) as usize) == i && pdf == d.pdf(x),
                "x {x} cell {i} pdf {pdf}"
            );
            let (j, pmf, du) = d.sample_discrete(u);
            assert!(
                j == i && pmf == d.pmf(j) && (0.0..1.0).contains(&du),
                "discrete {j} {pmf} {du}"
            );
            counts[i] += 1;
        }
        let expected: Vec<f64> = (0..func.len()).map(|i| d.pmf(i) as f64 * n as f64).collect();
        assert!(counts[0] == 0 && counts[3] == 0, "zero cells sampled: {counts:?}");
        assert_chi_square(&counts, &expected, "1D histogram");
    }

    /// The guide table only narrows the search: every u, the CDF's own values and their
    /// neighbours included, lands in the cell the full binary search finds.
    #[test]
    fn light_distribution_1d_guided_search_finds_the_full_searchs_cell() {
        let mut rng = Pcg32::new(5, 3);
        let mut funcs: Vec<Vec<f32>> = vec![
            vec![1.0],
            vec![0.0, 2.0, 0.0],
            vec![1e-30, 1.0, 1e-30, 0.0, 0.0, 1e6, 0.0],
            vec![0.0; 9],
        ];
        funcs.push(
            (0..1000)
                .map(|i| if i % 7 == 0 { 0.0 } else { rng.next_f32().powi(8) })
                .collect(),
        );
        funcs.push(
            (0..513)
                .map(|i| ((i as f32) * 0.1).sin().max(0.0) * 50.0)
                .collect(),
        );
        for func in &funcs {
            let d = Distribution1D::new(func);
            let full = |u: f32| {
                let u = u.clamp(0.0, ONE_MINUS_EPSILON);
                (d.cdf.partition_point(|&c| c <= u) - 1).min(d.len() - 1)
            };
            let mut us: Vec<f32> = (0..20_000).map(|_| rng.next_f32()).collect();
            for &c in &d.cdf {
                us.extend([
                    c,
                    f32::from_bits(c.to_bits().saturating_sub(1)),
                    f32::from_bits(c.to_bits() + 1),
                ]);
            }
            us.extend([0.0, ONE_MINUS_EPSILON, 1.0, -1.0, 2.0]);
            for u in us {
                assert_eq!(d.find(u).0, full(u), "n = {}, u = {u:e}", d.len());
            }
            assert_eq!(d.find(f32::NAN).0, full(0.0), "NaN is read as 0");
        }
    }

    #[test]
    fn light_distribution_1d_edge_samples_stay_in_nonzero_cells() {
        let d = Distribution1D::new(&[0.0, 2.0, 0.0]);
        for u in [0.0, 1e-9, 0.5, 1.0 - 1e-7, 1.0, 2.0] {
            let (x, pdf, i) = d.sample_continuous(u);
            assert!(
                i == 1 && pdf == 3.0 && (1.0 / 3.0..2.0 / 3.0).contains(&x),
                "u {u}: x {x} pdf {pdf} cell {i}"
            );
        }
    }

    #[test]
    fn light_distribution_2d_pdf_integrates_to_one_and_histogram_matches() {
        let (nu, nv) = (13usize, 7usize);
        let mut rng = Pcg32::new(5, 2);
        let func: Vec<f32> = (0..nu * nv)
            .map(|k| {
                if k % 11 == 3 || k / nu == 4 {
                    0.0
                } else {
                    rng.next_f32().powi(3) * 10.0
                }
            })
            .collect();
        let d = Distribution2D::new(&func, nu, nv);
        // ∫ pdf over [0,1]² by the midpoint rule (exact for a piecewise-constant pdf).
        let (gu, gv) = (nu * 4, nv * 4);
        let integral: f64 = (0..gu * gv)
            .map(|k| {
                let p = Vec2::new(
                    ((k % gu) as f32 + 0.5) / gu as f32,
                    ((k / gu) as f32 + 0.5) / gv as f32,
                );
                d.pdf(p) as f64 / (gu * gv) as f64
            })
            .sum();
        assert!((integral - 1.0).abs() < 1e-5, "∫ pdf = {integral}, expected 1");
        let total: f64 = func.iter().map(|&f| f as f64).sum();
        let n = 1_000_000u64;
        let mut counts = vec![0u64; nu * nv];
        for _ in 0..n {
            let (p, pdf) = d.sample(rng.next_2d());
            let cell = ((p.y * nv as f32) as usize) * nu + (p.x * nu as f32) as usize;
            assert!(
                pdf == d.pdf(p) && pdf > 0.0,
                "point {p}: sample pdf {pdf}, pdf() {}",
                d.pdf(p)
            );
            counts[cell] += 1;
        }
        let expected: Vec<f64> = func.iter().map(|&f| f as f64 / total * n as f64).collect();
        for (k, &f) in func.iter().enumerate() {
            assert!(
                f > 0.0 || counts[k] == 0,
                "cell {k} has weight 0 but {} samples",
                counts[k]
            );
        }
        assert_chi_square(&counts, &expected, "2D histogram");
    }
}
