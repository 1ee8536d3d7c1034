//! What a render will allocate, estimated from the scene before anything is allocated, and
//! charged to the job's memory ledger (`scenes::budget`): a film of 16384² or a million
//! displaced micro-triangles is refused with the bytes it needs, never an abort of the process.
//!
//! | buffer | bytes |
//! |---|---|
//! | the film's accumulators ([`PixelStats`]: AOVs, 4 per replicate) | W·H·(30 + L)·8 |
//! | the object-id pass and the EXR image written at the end | W·H·(1 + 21 + L)·4 |
//! | a checkpoint's serialised copy of the film (when checkpoints are on) | W·H·(30 + L)·8 |
//! | the acceleration structure | [`ACCEL_BYTES_PER_PRIMITIVE`] per triangle or analytic shape |
//! | a displaced rectangle's height grid and its min/max hierarchy | 8 per height texel |
//! | a displaced mesh's micro-triangles (`scenes::displacement::displace_mesh`) | N²·T·([`ACCEL_BYTES_PER_PRIMITIVE`] + 48) |
//!
//! L is the number of named lights (one visibility channel each). The figures are the large
//! buffers only; the limit's default (half the machine's memory) leaves room for the rest.

use scenes::budget::{Exceeded, Ledger};
use scenes::displacement::dicing_level;
use scenes::{Geometry, Scene};

use crate::film::PixelStats;

/// Bytes the acceleration structure holds per primitive, an upper estimate: the primitive
/// (a triangle's three vertices, 40 B), its id (8 B) and padded box (32 B), the compressed
/// wide BVH's share of nodes (80 B per node of up to 8 children, built with leaves of up to 3)
/// and the PLOC builder's temporaries (two boxes and indices per cluster), which are alive
/// together at build time.
pub const ACCEL_BYTES_PER_PRIMITIVE: u64 = 256;

/// Bytes per micro-vertex and per micro-triangle of a displaced mesh beyond the accelerator's
/// share: position, normal, uv and tangent (48 B per vertex, about one per two triangles) and
/// the index triple (12 B).
const MICRO_MESH_BYTES_PER_TRIANGLE: u64 = 48;

/// Bytes per height texel of a displaced rectangle: the f32 grid of corner heights and its
/// min/max quadtree (a third of the texels again, two f32 each).
const PATCH_BYTES_PER_TEXEL: u64 = 8;

/// What did not fit: the film (set by the resolution) or the geometry (set by the shapes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Over {
    /// The film's accumulators, the output image or the checkpoint copy.
    Film(Exceeded),
    /// The acceleration structure, displaced micro-triangles or height grids.
    Geometry(Exceeded),
}

impl Over {
    /// The charge that did not fit.
    pub fn exceeded(&self) -> &Exceeded {
        match self {
            Over::Film(e) | Over::Geometry(e) => e,
        }
    }
}

/// Charges what rendering `scene` allocates to `ledger` (module table), so the error names
/// the buffer that does not fit. `checkpoints`: whether the film is also serialised for
/// checkpoints.
pub fn charge(scene: &Scene, checkpoints: bool, ledger: &Ledger) -> Result<(), Over> {
    charge_film(scene, checkpoints, ledger).map_err(Over::Film)?;
    charge_geometry(scene, ledger).map_err(Over::Geometry)
}

/// The film's part of [`charge`].
fn charge_film(scene: &Scene, checkpoints: bool, ledger: &Ledger) -> Result<(), Exceeded> {
    let (w, h) = (u64::from(scene.film.width), u64::from(scene.film.height));
    let lights = scene.light_names().len();
    let pixels = w.saturating_mul(h);
    let stride = PixelStats::stride(lights) as u64;
    let film = pixels.saturating_mul(stride * 8);
    ledger.charge(
        film,
        format!("the oracle's {w}×{h} film ({stride} f64 accumulators per pixel)"),
    )?;
    ledger.charge(
        pixels.saturating_mul((1 + 21 + lights as u64) * 4),
        format!("the {w}×{h} object-id pass and output image"),
    )?;
    if checkpoints {
        ledger.charge(film, format!("the {w}×{h} film's checkpoint copy"))?;
    }
    Ok(())
}

/// The geometry's part of [`charge`].
fn charge_geometry(scene: &Scene, ledger: &Ledger) -> Result<(), Exceeded> {
    let mut primitives: u64 = 0;
    let mut patch_texels: u64 = 0;
    let mut micro: u64 = 0;
    for shape in &scene.shapes {
        let texture = shape
            .displacement
            .as_ref()
            .and_then(|d| scene.textures.get(d.texture));
        match (&shape.geometry, texture) {
            (Geometry::Mesh(mesh), Some(t)) => {
                let level = u64::from(dicing_level(mesh, t));
                micro = micro.saturating_add(level * level * mesh.indices.len() as u64);
            }
            (Geometry::Mesh(mesh), None) => primitives = primitives.saturating_add(mesh.indices.len() as u64),
            (Geometry::Rectangle { .. }, Some(t)) => {
                patch_texels = patch_texels.saturating_add(u64::from(t.width) * u64::from(t.height));
                primitives += 1;
            }
            _ => primitives += 1,
        }
    }
    ledger.charge(
        micro.saturating_mul(ACCEL_BYTES_PER_PRIMITIVE + MICRO_MESH_BYTES_PER_TRIANGLE),
        format!("{micro} displaced micro-triangles"),
    )?;
    ledger.charge(
        primitives.saturating_mul(ACCEL_BYTES_PER_PRIMITIVE),
        format!("the acceleration structure over {primitives} primitives"),
    )?;
    ledger.charge(
        patch_texels.saturating_mul(PATCH_BYTES_PER_TEXEL),
        format!("the height grids of {patch_texels} displaced texels"),
    )
}
