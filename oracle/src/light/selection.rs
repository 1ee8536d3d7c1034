//! Which emitter next-event estimation samples from a shading point p, and with what
//! probability.
//!
//! - **Few local emitters** (fewer than [`GRID_MIN_LIGHTS`]): ∝ power everywhere, pbrt-v4
//!   §12.6.2 (PowerLightSampler): emitter i with probability Φ_i / Σ Φ_j, lights of zero power
//!   never, all uniformly when every power is zero.
//! - **Many local emitters**: the scene's bounding box is cut into a grid of at most
//!   [`MAX_CELLS`] cells, and each cell holds its own distribution. The distant emitters (sun
//!   disks, environment) keep their power share Φ_i / Σ Φ_j in every cell; the local ones share
//!   the rest in proportion to
//!
//!   p(i | cell) ∝ (1 − α)·I_i / Σ_k I_k + α·Φ_i / Σ_k Φ_k,
//!
//!   with I_i = Φ_i / d², d the distance from the cell's centre to the emitter's bounding-box
//!   centre, at least the two boxes' half-diagonals summed, and I_i = 0 where the cell lies
//!   wholly behind a one-sided planar emitter (which lights nothing there). I_i is the
//!   importance of Conty Estevez & Kulla 2018, "Importance Sampling of Many Lights with
//!   Adaptive Tree Splitting" (HPG, §4.1), without its orientation-cone bound, evaluated per
//!   region as Shirley, Wang & Zimmerman 1996 ("Monte Carlo Techniques for Direct Lighting
//!   Calculations", ACM TOG 15(1), §4) choose lights per region of the scene.
//!
//! The estimator stays unbiased whatever the importance: the power term is a defensive
//! mixture (Hesterberg 1995, "Weighted Average Importance Sampling and Defensive Mixture
//! Distributions", Technometrics 37(2)), so every emitter of non-zero power keeps at least
//! α·Φ_i / Σ Φ_j of the selection in every cell, and a light's own pdf and the MIS weights read
//! the same cell for the same point (`pmf(i, p)`). Points outside the box use the nearest
//! cell. The choice only moves variance.

use glam::Vec3;

use super::distribution::Distribution1D;

/// Local (non-distant) emitters from which the grid is used.
pub const GRID_MIN_LIGHTS: usize = 16;
/// Cells along the longest side of the scene's box.
const CELLS_PER_SIDE: usize = 16;
/// Most cells.
pub const MAX_CELLS: usize = CELLS_PER_SIDE * CELLS_PER_SIDE * CELLS_PER_SIDE;
/// Most (cell, emitter) entries: 2²² (two f32 each, 32 MiB); more emitters get coarser cells.
const MAX_ENTRIES: usize = 1 << 22;
/// The defensive share α of the power distribution within each cell.
pub const DEFENSIVE: f32 = 0.2;

/// Where a local emitter lies, for its importance: its bounding box and, for a one-sided
/// planar emitter, its front normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmitterBounds {
    /// Box corners.
    pub lo: Vec3,
    /// Box corners.
    pub hi: Vec3,
    /// Front normal of a one-sided rectangle or disk: it lights only points x with
    /// (x − centre)·n > 0.
    pub front: Option<Vec3>,
}

/// The selection distribution(s).
#[derive(Clone, Debug)]
pub enum Selection {
    /// ∝ power everywhere.
    Power(Distribution1D),
    /// One distribution per grid cell.
    Grid(Grid),
}

/// Per-cell distributions over the scene's box.
#[derive(Clone, Debug)]
pub struct Grid {
    lo: Vec3,
    /// Cells per unit length along each axis.
    inv_cell: Vec3,
    res: [usize; 3],
    cells: Vec<Distribution1D>,
}

impl Selection {
    /// The selection for emitters of power `powers`; `bounds[i]` is `Some` for local emitters
    /// and `None` for distant ones; (`lo`, `hi`) is the scene's box.
    pub fn new(powers: &[f32], bounds: &[Option<EmitterBounds>], lo: Vec3, hi: Vec3) -> Selection {
        let phi = |i: usize| {
            if powers[i] > 0.0 && powers[i].is_finite() {
                powers[i]
            } else {
                0.0
            }
        };
        let local: Vec<(usize, EmitterBounds)> = bounds
            .iter()
            .enumerate()
            .filter_map(|(i, b)| Some((i, (*b)?)))
            .collect();
        let local_power: f32 = local.iter().map(|&(i, _)| phi(i)).sum();
        let total: f32 = (0..powers.len()).map(phi).sum();
        let box_ok = lo.is_finite() && hi.is_finite() && hi.cmpge(lo).all();
        if local.len() < GRID_MIN_LIGHTS || !(local_power > 0.0 && total.is_finite()) || !box_ok {
            return Selection::Power(Distribution1D::new(powers));
        }
        let res = resolution(hi - lo, powers.len());
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        let cell = extent / Vec3::new(res[0] as f32, res[1] as f32, res[2] as f32);
        let half_diagonal = 0.5 * cell.length();
        let mut cells = Vec::with_capacity(res[0] * res[1] * res[2]);
        // Every emitter's power share: the distant ones' in every cell, the local ones' where
        // the importance is zero throughout.
        let power_shares: Vec<f32> = (0..powers.len()).map(|i| phi(i) / total).collect();
        let mut weights = power_shares.clone();
        for z in 0..res[2] {
            for y in 0..res[1] {
                for x in 0..res[0] {
                    let cell_lo = lo + cell * Vec3::new(x as f32, y as f32, z as f32);
                    let importance: Vec<f32> = local
                        .iter()
                        .map(|(i, b)| importance(phi(*i), b, cell_lo, cell, half_diagonal))
                        .collect();
                    let sum: f32 = importance.iter().sum();
                    weights.copy_from_slice(&power_shares);
                    if sum > 0.0 && sum.is_finite() {
                        let share = local_power / total;
                        for (&(i, _), &imp) in local.iter().zip(&importance) {
                            weights[i] =
                                share * ((1.0 - DEFENSIVE) * imp / sum + DEFENSIVE * phi(i) / local_power);
                        }
                    }
                    cells.push(Distribution1D::new(&weights));
                }
            }
        }
        Selection::Grid(Grid {
            lo,
            inv_cell: Vec3::ONE / cell,
            res,
            cells,
        })
    }

    /// Picks an emitter for a point `p` with `u`: its index and probability.
    pub fn sample(&self, p: Vec3, u: f32) -> (usize, f32) {
        let (i, pmf, _) = self.distribution(p).sample_discrete(u);
        (i, pmf)
    }

    /// Probability that [`Selection::sample`] at `p` picks emitter `i` (< the emitter count).
    pub fn pmf(&self, i: usize, p: Vec3) -> f32 {
        self.distribution(p).pmf(i)
    }

    fn distribution(&self, p: Vec3) -> &Distribution1D {
        match self {
            Selection::Power(d) => d,
            Selection::Grid(g) => {
                // f32::max ignores NaN: a NaN coordinate lands in cell 0.
                let c = ((p - g.lo) * g.inv_cell).to_array();
                let index = |a: usize| (c[a].max(0.0) as usize).min(g.res[a] - 1);
                &g.cells[(index(2) * g.res[1] + index(1)) * g.res[0] + index(0)]
            }
        }
    }
}

/// Cells per axis for a box of `extent` and `emitters` distributions' entries each: up to
/// [`CELLS_PER_SIDE`] along the longest side, proportionally fewer along the others, halved
/// until cells × emitters ≤ [`MAX_ENTRIES`].
fn resolution(extent: Vec3, emitters: usize) -> [usize; 3] {
    let longest = extent.max_element().max(f32::MIN_POSITIVE);
    let mut side = CELLS_PER_SIDE;
    loop {
        let res = extent
            .to_array()
            .map(|e| ((e / longest * side as f32).round() as usize).clamp(1, side));
        if side == 1 || res.iter().product::<usize>() * emitters.max(1) <= MAX_ENTRIES {
            return res;
        }
        side /= 2;
    }
}

/// I = Φ / d² of an emitter seen from the cell with corner `cell_lo` and size `cell`; 0 when
/// the cell lies wholly behind a one-sided planar emitter.
fn importance(phi: f32, b: &EmitterBounds, cell_lo: Vec3, cell: Vec3, half_diagonal: f32) -> f32 {
    let centre = 0.5 * (b.lo + b.hi);
    if let Some(n) = b.front {
        let lit = (0..8).any(|k| {
            let corner = cell_lo + cell * Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, (k >> 2) as f32);
            (corner - centre).dot(n) > 0.0
        });
        if !lit {
            return 0.0;
        }
    }
    let reach = half_diagonal + 0.5 * (b.hi - b.lo).length();
    let d2 = (cell_lo + 0.5 * cell - centre)
        .length_squared()
        .max(reach * reach);
    phi / d2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::test_support::Pcg32;

    /// 64 one-sided ceiling lights over a 6 × 3 × 6 m room plus one distant emitter, powers
    /// varying 1:4.
    fn room() -> (Vec<f32>, Vec<Option<EmitterBounds>>) {
        let mut powers = Vec::new();
        let mut bounds = Vec::new();
        for k in 0..64 {
            let (x, z) = (-2.625 + 0.75 * (k % 8) as f32, -2.625 + 0.75 * (k / 8) as f32);
            powers.push(1.0 + 3.0 * ((k * 7) % 5) as f32 / 4.0);
            bounds.push(Some(EmitterBounds {
                lo: Vec3::new(x - 0.06, 3.0, z - 0.06),
                hi: Vec3::new(x + 0.06, 3.0, z + 0.06),
                front: Some(-Vec3::Y),
            }));
        }
        powers.push(20.0);
        bounds.push(None);
        (powers, bounds)
    }

    fn room_selection() -> Selection {
        let (powers, bounds) = room();
        // The box reaches 1 m above the ceiling, as a roof space would.
        Selection::new(
            &powers,
            &bounds,
            Vec3::new(-3.0, 0.0, -3.0),
            Vec3::new(3.0, 4.0, 3.0),
        )
    }

    #[test]
    fn selection_uses_power_below_the_threshold() {
        let (powers, bounds) = room();
        let few = Selection::new(&powers[..8], &bounds[..8], Vec3::splat(-3.0), Vec3::splat(3.0));
        assert!(matches!(few, Selection::Power(_)));
        assert!(matches!(room_selection(), Selection::Grid(_)));
    }

    /// Unbiasedness: in every cell, at points inside, outside and NaN, the pmf sums to 1,
    /// keeps the defensive floor α·Φ_i/ΣΦ for every emitter, gives distant emitters exactly
    /// their power share, and is what `sample` reports.
    #[test]
    fn selection_grid_pmf_sums_to_one_and_keeps_the_defensive_floor() {
        let (powers, _) = room();
        let s = room_selection();
        let total: f32 = powers.iter().sum();
        let mut rng = Pcg32::new(3, 1);
        let mut points: Vec<Vec3> = (0..300)
            .map(|_| {
                Vec3::new(
                    rng.next_f32() * 8.0 - 4.0,
                    rng.next_f32() * 4.0 - 0.5,
                    rng.next_f32() * 8.0 - 4.0,
                )
            })
            .collect();
        points.push(Vec3::NAN);
        points.push(Vec3::splat(1e30));
        for p in points {
            let sum: f32 = (0..powers.len()).map(|i| s.pmf(i, p)).sum();
            assert!((sum - 1.0).abs() < 1e-5, "{p}: Σ pmf = {sum}");
            for (i, &phi) in powers.iter().enumerate() {
                let floor = if i == 64 {
                    phi / total
                } else {
                    DEFENSIVE * phi / total
                };
                assert!(
                    s.pmf(i, p) >= floor * (1.0 - 1e-4),
                    "{p}: pmf[{i}] = {} < {floor}",
                    s.pmf(i, p)
                );
            }
            assert!((s.pmf(64, p) - 20.0 / total).abs() < 1e-6, "distant share at {p}");
            let (i, pmf) = s.sample(p, rng.next_f32());
            assert_eq!(pmf, s.pmf(i, p));
        }
    }

    /// Under a light the grid picks it far more often than a light across the room, and a
    /// cell above every one-sided light (behind them all) falls back to the power shares.
    #[test]
    fn selection_grid_prefers_near_lights() {
        let (powers, _) = room();
        let s = room_selection();
        let under_first = Vec3::new(-2.625, 1.0, -2.625);
        let (near, far) = (s.pmf(0, under_first), s.pmf(63, under_first));
        let power_ratio = powers[0] / powers[63];
        // 1/d² alone gives (7.7 m / 2 m)² ≈ 15 between them; the defensive power share and
        // the 62 other lights dilute it to ≈ 7 times what power selection gives.
        assert!(near / far > 5.0 * power_ratio, "near {near}, far {far}");
        let total: f32 = powers.iter().sum();
        let above = Vec3::new(0.0, 3.9, 0.0);
        for (i, &phi) in powers.iter().enumerate() {
            assert!((s.pmf(i, above) - phi / total).abs() < 1e-6);
        }
    }

    #[test]
    fn selection_grid_resolution_follows_the_box_and_the_entry_budget() {
        assert_eq!(resolution(Vec3::new(6.0, 3.0, 6.0), 65), [16, 8, 16]);
        assert_eq!(resolution(Vec3::new(10.0, 0.0, 1.0), 65), [16, 1, 2]);
        let r = resolution(Vec3::splat(1.0), 100_000);
        assert!(r.iter().product::<usize>() * 100_000 <= MAX_ENTRIES, "{r:?}");
        assert_eq!(resolution(Vec3::splat(1.0), 10_000_000), [1, 1, 1]);
    }
}
