//! Light maps: the irradiance E (W/m²) over every static planar shape, one chart per shape
//! packed into one atlas image, as the oracle bakes it (`oracle::bake`, `verity bake`) and a
//! realtime renderer reads it.
//!
//! **What a texel holds.** The irradiance on the front side of the surface, not the outgoing
//! radiance: a diffuse surface of albedo ρ(uv) leaves L_o = ρ(uv)/π · E, so the map can be
//! stored at a far coarser resolution than the albedo texture and multiplied by it per pixel
//! (the classic light-map × albedo), and one bake serves any diffuse albedo. What the map
//! cannot hold is view-dependent light (a glossy lobe) and anything that changes after the
//! bake (a dynamic object's shadow).
//!
//! **Charts.** A rectangle or disk `center + s·half_u + t·half_v` has the chart coordinates
//! (c_u, c_v) = ((s + 1)/2, (t + 1)/2) ∈ [0, 1]² (for a rectangle its texture uv; a disk's
//! chart is its bounding parallelogram, the texels outside the ellipse filled by dilation).
//! `resolution` is the chart's texel count along its longer side; the other side keeps the
//! aspect ratio (at least one texel). Texel (i, j) of a W×H chart is centred at c = ((i + ½)/W,
//! (j + ½)/H) with j = 0 at c_v = 0, as every texture's texel centres (scenes::texture): a
//! bilinear lookup at c returns texel (i, j) exactly. A triangle mesh's chart is its second
//! uv set (`Mesh::uv1`: glTF `TEXCOORD_1`; a box's six faces in the cells of a 3 × 2 grid),
//! `resolution` texels square over [0, 1]²; its texel centres outside every triangle are
//! filled by dilation, and uvs outside [0, 1]² or triangles that overlap in uv (two surface
//! points sharing a texel) are errors naming the vertex or triangles. Spheres have no chart
//! and a mesh without TEXCOORD_1 none either: both are refused by name.
//!
//! **Atlas.** Charts are packed on shelves (tallest first, left to right) with `padding`
//! texels around each, into an atlas `verity.lightmap.charts` lists (shape, x, y, W, H per
//! chart, in atlas texels); the padding and the texels a chart does not cover (outside a
//! disk) are filled by dilation: each is given the mean of its covered 8-neighbours, ring by
//! ring (`dilation` rings), so that bilinear lookups near a chart's edge read the chart's own
//! values and not a neighbour's or black.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::layered::LayeredImage;
use crate::model::{Geometry, Mesh, Scene};

/// Largest chart side a bake accepts (texels): 8192² texels × 16 bytes is 1 GiB.
pub const MAX_RESOLUTION: u32 = 8192;

/// One shape's chart: where it is in the atlas and its size.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    /// Index into `scene.shapes`.
    pub shape: usize,
    /// The shape's name.
    pub name: String,
    /// Atlas texel of the chart's texel (0, 0).
    pub x: u32,
    /// Atlas texel row of the chart's texel (0, 0).
    pub y: u32,
    /// Texels along c_u.
    pub width: u32,
    /// Texels along c_v.
    pub height: u32,
    /// What the chart coordinates parameterize.
    pub surface: ChartSurface,
}

/// The surface a chart covers.
#[derive(Clone, Debug, PartialEq)]
pub enum ChartSurface {
    /// A rectangle or disk `center + s·half_u + t·half_v`, c = ((s + 1)/2, (t + 1)/2).
    Plane {
        /// Centre, half_u, half_v.
        frame: [Vec3; 3],
        /// Whether (s, t) outside the unit disk is off the shape.
        disk: bool,
    },
    /// A triangle mesh, c its `uv1`.
    Mesh(MeshChart),
}

/// A mesh's chart: the mesh and its triangles binned by their uv1 bounds (a uniform grid over
/// [0, 1]², about one triangle per cell), to find the triangle under a chart point.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshChart {
    mesh: Arc<Mesh>,
    side: usize,
    bins: Vec<Vec<u32>>,
}

/// Barycentric coordinates of `c` in the uv triangle `t` (None: degenerate in uv).
fn barycentric(t: [Vec2; 3], c: Vec2) -> Option<Vec3> {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], c - t[0]);
    let det = e1.perp_dot(e2);
    if det.abs() < 1e-12 {
        return None;
    }
    let b1 = d.perp_dot(e2) / det;
    let b2 = e1.perp_dot(d) / det;
    Some(Vec3::new(1.0 - b1 - b2, b1, b2))
}

impl MeshChart {
    /// Bins the triangles of `mesh` by uv1. Errors name the vertex whose uv1 is outside
    /// [0, 1]² (or the count that does not match the vertices).
    fn new(mesh: &Arc<Mesh>) -> Result<MeshChart, String> {
        if mesh.uv1.len() != mesh.positions.len() {
            return Err(format!(
                "TEXCOORD_1 has {} entries for {} vertices",
                mesh.uv1.len(),
                mesh.positions.len()
            ));
        }
        let inside = |uv: &Vec2| uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all();
        if let Some(i) = mesh.uv1.iter().position(|uv| !inside(uv)) {
            return Err(format!(
                "TEXCOORD_1 of vertex {i} is {}, outside the chart's [0, 1]²",
                mesh.uv1[i]
            ));
        }
        let side = ((mesh.indices.len() as f64).sqrt().ceil() as usize).clamp(1, 256);
        let mut bins = vec![Vec::new(); side * side];
        let cell = |x: f32| ((x * side as f32) as usize).min(side - 1);
        for (k, tri) in mesh.indices.iter().enumerate() {
            let uv = tri.map(|i| mesh.uv1[i as usize]);
            let (lo, hi) = (uv[0].min(uv[1]).min(uv[2]), uv[0].max(uv[1]).max(uv[2]));
            for y in cell(lo.y)..=cell(hi.y) {
                for x in cell(lo.x)..=cell(hi.x) {
                    bins[y * side + x].push(k as u32);
                }
            }
        }
        Ok(MeshChart {
            mesh: mesh.clone(),
            side,
            bins,
        })
    }

    /// The triangles whose uv1 contains `c`, with their barycentrics: those whose smallest
    /// barycentric exceeds `eps` (> 0: interior points only; < 0: edges too).
    fn triangles_at(&self, c: Vec2, eps: f32) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        let cell = |x: f32| ((x.clamp(0.0, 1.0) * self.side as f32) as usize).min(self.side - 1);
        self.bins[cell(c.y) * self.side + cell(c.x)]
            .iter()
            .filter_map(move |&k| {
                let tri = self.mesh.indices[k as usize];
                let b = barycentric(tri.map(|i| self.mesh.uv1[i as usize]), c)?;
                (b.min_element() > eps).then_some((k, b))
            })
    }

    /// The first two triangles whose uv1 overlap at a texel centre of a `w`×`h` chart, and
    /// that centre.
    fn overlap(&self, w: u32, h: u32) -> Option<(u32, u32, Vec2)> {
        for j in 0..h {
            for i in 0..w {
                let c = Vec2::new((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                let mut inside = self.triangles_at(c, 1e-4);
                if let (Some((a, _)), Some((b, _))) = (inside.next(), inside.next()) {
                    return Some((a, b, c));
                }
            }
        }
        None
    }
}

/// A surface point of a chart, where the bake starts its paths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChartPoint {
    /// Position.
    pub p: Vec3,
    /// Unit front geometric normal.
    pub ng: Vec3,
    /// Unit shading normal (a mesh's interpolated vertex normals; ng elsewhere).
    pub ns: Vec3,
    /// A unit tangent.
    pub dpdu: Vec3,
    /// The mesh triangle under it (0 for planes).
    pub triangle: u32,
}

impl Chart {
    /// The surface point at chart coordinates `c`, or None where the shape does not cover it
    /// (outside a disk; between a mesh's triangles in uv).
    pub fn point(&self, c: Vec2) -> Option<ChartPoint> {
        match &self.surface {
            ChartSurface::Plane { frame, disk } => {
                let [center, hu, hv] = *frame;
                let (s, t) = (2.0 * c.x - 1.0, 2.0 * c.y - 1.0);
                if *disk && s * s + t * t > 1.0 {
                    return None;
                }
                let n = hu.cross(hv).normalize();
                Some(ChartPoint {
                    p: center + hu * s + hv * t,
                    ng: n,
                    ns: n,
                    dpdu: hu.normalize(),
                    triangle: 0,
                })
            }
            ChartSurface::Mesh(m) => {
                let (k, b) = m.triangles_at(c, -1e-5).next()?;
                let idx = m.mesh.indices[k as usize].map(|i| i as usize);
                let q = idx.map(|i| m.mesh.positions[i]);
                let ng = (q[1] - q[0]).cross(q[2] - q[0]).try_normalize()?;
                let ns = match m.mesh.normals.is_empty() {
                    true => ng,
                    false => {
                        let n = idx.map(|i| m.mesh.normals[i]);
                        (n[0] * b.x + n[1] * b.y + n[2] * b.z)
                            .try_normalize()
                            .unwrap_or(ng)
                    }
                };
                Some(ChartPoint {
                    p: q[0] * b.x + q[1] * b.y + q[2] * b.z,
                    ng,
                    ns,
                    dpdu: (q[1] - q[0]).normalize(),
                    triangle: k,
                })
            }
        }
    }

    /// Chart coordinates of texel (i, j)'s centre, moved by `offset` texels (0: the centre a
    /// bilinear lookup reads back exactly; ½: the classic half-texel mistake).
    pub fn texel_centre(&self, i: u32, j: u32, offset: f32) -> glam::Vec2 {
        glam::Vec2::new(
            (i as f32 + 0.5 + offset) / self.width as f32,
            (j as f32 + 0.5 + offset) / self.height as f32,
        )
    }
}

/// The atlas layout of a scene's static shapes.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Atlas width in texels.
    pub width: u32,
    /// Atlas height in texels.
    pub height: u32,
    /// One chart per static shape, in scene order.
    pub charts: Vec<Chart>,
}

/// The charts of every shape of `scene` not named in `dynamic`, `resolution` texels along
/// each chart's longer side, packed with `padding` texels around each. Errors name the
/// shape (a sphere or mesh has no chart) or the resolution.
pub fn layout(scene: &Scene, resolution: u32, padding: u32, dynamic: &[String]) -> Result<Layout, String> {
    if !(1..=MAX_RESOLUTION).contains(&resolution) {
        return Err(format!(
            "light-map resolution {resolution} is outside 1..={MAX_RESOLUTION} texels per chart side"
        ));
    }
    if padding > 64 {
        return Err(format!("light-map padding {padding} is above 64 texels"));
    }
    for name in dynamic {
        if !scene.shapes.iter().any(|s| s.name == *name) {
            let names: Vec<&str> = scene.shapes.iter().map(|s| s.name.as_str()).collect();
            return Err(format!(
                "dynamic shape `{name}` is not in the scene; shapes: {}",
                names.join(", ")
            ));
        }
    }
    let mut charts = Vec::new();
    for (i, shape) in scene.shapes.iter().enumerate() {
        if dynamic.contains(&shape.name) {
            continue;
        }
        let surface = chart_surface(&shape.geometry).map_err(|e| format!("shape `{}`: {e}", shape.name))?;
        let (width, height) = match &surface {
            ChartSurface::Plane { frame, .. } => {
                let (lu, lv) = (frame[1].length(), frame[2].length());
                let long = lu.max(lv);
                let side = |l: f32| ((resolution as f32 * l / long).round() as u32).clamp(1, resolution);
                (side(lu), side(lv))
            }
            ChartSurface::Mesh(m) => {
                if let Some((a, b, c)) = m.overlap(resolution, resolution) {
                    return Err(format!(
                        "shape `{}`: its TEXCOORD_1 triangles {a} and {b} overlap at ({}, {}): a light-map chart \
                         must give every surface point texels of its own",
                        shape.name, c.x, c.y
                    ));
                }
                (resolution, resolution)
            }
        };
        charts.push(Chart {
            shape: i,
            name: shape.name.clone(),
            x: 0,
            y: 0,
            width,
            height,
            surface,
        });
    }
    if charts.is_empty() {
        return Err("the scene has no static shape to bake".into());
    }
    let (width, height) = pack(&mut charts, padding);
    Ok(Layout {
        width,
        height,
        charts,
    })
}

/// The chart surface of a shape's geometry; errors say why it has none.
fn chart_surface(g: &Geometry) -> Result<ChartSurface, String> {
    match g {
        Geometry::Rectangle {
            center,
            half_u,
            half_v,
        } => Ok(ChartSurface::Plane {
            frame: [*center, *half_u, *half_v],
            disk: false,
        }),
        Geometry::Disk {
            center,
            half_u,
            half_v,
        } => Ok(ChartSurface::Plane {
            frame: [*center, *half_u, *half_v],
            disk: true,
        }),
        Geometry::Sphere { .. } => Err("a sphere has no light-map chart: list it as dynamic (lit per pixel)".into()),
        Geometry::Mesh(m) if m.uv1.is_empty() => Err(
            "a triangle mesh without a second uv set (glTF TEXCOORD_1) has no light-map chart: add one, or list \
             it as dynamic (lit per pixel)"
                .into(),
        ),
        Geometry::Mesh(m) => MeshChart::new(m).map(ChartSurface::Mesh),
    }
}

/// Shelf packing, tallest chart first: the atlas is as wide as √(total area) (at least the
/// widest chart); returns its size.
fn pack(charts: &mut [Chart], padding: u32) -> (u32, u32) {
    let padded = |c: &Chart| (c.width + 2 * padding, c.height + 2 * padding);
    let area: u64 = charts
        .iter()
        .map(|c| {
            let (w, h) = padded(c);
            u64::from(w) * u64::from(h)
        })
        .sum();
    let widest = charts.iter().map(|c| padded(c).0).max().unwrap_or(1);
    let width = ((area as f64).sqrt().ceil() as u32).max(widest);
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(charts[k].height));
    let (mut x, mut y, mut shelf) = (0u32, 0u32, 0u32);
    for k in order {
        let (w, h) = padded(&charts[k]);
        if x + w > width {
            y += shelf;
            x = 0;
            shelf = 0;
        }
        charts[k].x = x + padding;
        charts[k].y = y + padding;
        x += w;
        shelf = shelf.max(h);
    }
    (width, y + shelf)
}

/// A baked light map: the layout and, per atlas texel, the irradiance, its variance (of the
/// mean) and whether a chart covers it (dilated texels are not covered).
#[derive(Clone, Debug, PartialEq)]
pub struct LightMap {
    /// The atlas layout.
    pub layout: Layout,
    /// E per atlas texel, W/m², row-major, row 0 at the top.
    pub irradiance: Vec<Vec3>,
    /// Variance of each texel's mean (per channel).
    pub variance: Vec<Vec3>,
    /// Whether the texel is a chart's own (baked) rather than padding or dilated.
    pub covered: Vec<bool>,
}

impl LightMap {
    /// Fills the uncovered texels within `rings` texels of a covered one: each ring takes
    /// the mean of its already-filled 8-neighbours (variance likewise), so bilinear lookups
    /// across a chart's edge read the chart's own values. Texels still unfilled stay 0.
    pub fn dilate(&mut self, rings: u32) {
        let (w, h) = (self.layout.width as i64, self.layout.height as i64);
        let mut filled = self.covered.clone();
        for _ in 0..rings {
            let before = filled.clone();
            let mut changed = false;
            for y in 0..h {
                for x in 0..w {
                    let k = (y * w + x) as usize;
                    if before[k] {
                        continue;
                    }
                    let (mut e, mut v, mut n) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
                    for (dx, dy) in [
                        (-1, -1),
                        (0, -1),
                        (1, -1),
                        (-1, 0),
                        (1, 0),
                        (-1, 1),
                        (0, 1),
                        (1, 1),
                    ] {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx < 0 || ny < 0 || nx >= w || ny >= h {
                            continue;
                        }
                        let q = (ny * w + nx) as usize;
                        if before[q] {
                            e += self.irradiance[q];
                            v += self.variance[q];
                            n += 1.0;
                        }
                    }
                    if n > 0.0 {
                        self.irradiance[k] = e / n;
                        self.variance[k] = v / n;
                        filled[k] = true;
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
    }

    /// The atlas as an EXR: `E.R/G/B` (irradiance), `E_variance.R/G/B`, `covered.Y` (1 on a
    /// chart's own texels), and the chart table in the attribute `verity.lightmap.charts`
    /// (`name x y width height` per chart, `;`-separated, in atlas texels).
    pub fn to_image(&self) -> LayeredImage {
        let mut img = LayeredImage::new(self.layout.width, self.layout.height);
        img.push_rgb("E", &self.irradiance);
        img.push_rgb("E_variance", &self.variance);
        img.push_channel(
            "covered.Y",
            self.covered.iter().map(|&c| f32::from(u8::from(c))).collect(),
        );
        let table: Vec<String> = self
            .layout
            .charts
            .iter()
            .map(|c| format!("{} {} {} {} {}", c.name, c.x, c.y, c.width, c.height))
            .collect();
        img.set_attribute("verity.lightmap.charts", table.join("; "));
        img
    }
}

impl LightMap {
    /// A 64-bit FNV-1a digest of the atlas size, the chart table and the texels (E, then
    /// coverage), for labels and cache keys.
    pub fn digest(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |bytes: &[u8]| {
            for &b in bytes {
                h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
        };
        eat(&self.layout.width.to_le_bytes());
        eat(&self.layout.height.to_le_bytes());
        for c in &self.layout.charts {
            eat(c.name.as_bytes());
            for v in [c.x, c.y, c.width, c.height] {
                eat(&v.to_le_bytes());
            }
        }
        for e in &self.irradiance {
            for v in e.to_array() {
                eat(&v.to_bits().to_le_bytes());
            }
        }
        for &c in &self.covered {
            eat(&[u8::from(c)]);
        }
        h
    }

    /// Reads a baked atlas ([`LightMap::to_image`], `verity bake`) for `scene`: each chart of
    /// `verity.lightmap.charts` must name a shape of the scene that has a chart, once, lie inside the
    /// atlas and overlap no other chart; E must be finite and non-negative. Errors name the
    /// chart or channel (the caller adds the file).
    pub fn from_image(img: &LayeredImage, scene: &Scene) -> Result<LightMap, String> {
        let table = img
            .attribute("verity.lightmap.charts")
            .ok_or("no `verity.lightmap.charts` attribute: not a light map written by `verity bake`")?;
        let (width, height) = (img.width, img.height);
        let mut charts: Vec<Chart> = Vec::new();
        for (k, entry) in table
            .split(';')
            .map(str::trim)
            .filter(|e| !e.is_empty())
            .enumerate()
        {
            let at = |why: String| format!("verity.lightmap.charts entry {k} (`{entry}`): {why}");
            let fields: Vec<&str> = entry.split_whitespace().collect();
            let [name, rest @ ..] = fields.as_slice() else {
                return Err(at("empty".into()));
            };
            let numbers: Vec<u32> = rest
                .iter()
                .map(|f| f.parse::<u32>())
                .collect::<Result<_, _>>()
                .map_err(|_| at("expected `name x y width height` in whole texels".into()))?;
            let [x, y, w, h] = numbers[..] else {
                return Err(at("expected `name x y width height` in whole texels".into()));
            };
            if w == 0
                || h == 0
                || u64::from(x) + u64::from(w) > u64::from(width)
                || u64::from(y) + u64::from(h) > u64::from(height)
            {
                return Err(at(format!(
                    "the chart {w}x{h} at ({x}, {y}) is empty or leaves the {width}x{height} atlas"
                )));
            }
            let shape = scene
                .shapes
                .iter()
                .position(|s| s.name == *name)
                .ok_or_else(|| at(format!("the scene has no shape `{name}`")))?;
            let surface = chart_surface(&scene.shapes[shape].geometry)
                .map_err(|e| at(format!("shape `{name}`: {e}")))?;
            let chart = Chart {
                shape,
                name: name.to_string(),
                x,
                y,
                width: w,
                height: h,
                surface,
            };
            if let Some(other) = charts.iter().find(|c| c.shape == shape) {
                return Err(at(format!("shape `{}` has a second chart", other.name)));
            }
            if let Some(other) = charts.iter().find(|c| overlap(c, &chart)) {
                return Err(at(format!("the chart overlaps the chart of `{}`", other.name)));
            }
            charts.push(chart);
        }
        if charts.is_empty() {
            return Err("verity.lightmap.charts lists no chart".into());
        }
        let irradiance = img.rgb("E").ok_or("no `E.R/G/B` channels (the irradiance)")?;
        if let Some(i) = irradiance
            .iter()
            .position(|e| !(e.is_finite() && e.min_element() >= 0.0))
        {
            return Err(format!(
                "E at texel ({}, {}) is {} (expected finite and ≥ 0)",
                i as u32 % width,
                i as u32 / width,
                irradiance[i]
            ));
        }
        let variance = img
            .rgb("E_variance")
            .unwrap_or_else(|| vec![Vec3::ZERO; irradiance.len()]);
        let covered = match img.channel("covered.Y") {
            Some(c) => c.iter().map(|&v| v > 0.5).collect(),
            None => vec![true; irradiance.len()],
        };
        Ok(LightMap {
            layout: Layout {
                width,
                height,
                charts,
            },
            irradiance,
            variance,
            covered,
        })
    }
}

/// Whether two charts share a texel.
fn overlap(a: &Chart, b: &Chart) -> bool {
    a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chart(width: u32, height: u32) -> Chart {
        Chart {
            shape: 0,
            name: "c".into(),
            x: 0,
            y: 0,
            width,
            height,
            surface: ChartSurface::Plane {
                frame: [Vec3::ZERO, Vec3::X, Vec3::Y],
                disk: false,
            },
        }
    }

    #[test]
    fn shelves_keep_charts_apart_by_twice_the_padding() {
        let mut charts = vec![chart(8, 4), chart(3, 7), chart(5, 5), chart(2, 2)];
        let (w, h) = pack(&mut charts, 2);
        for (a, ca) in charts.iter().enumerate() {
            assert!(ca.x >= 2 && ca.y >= 2 && ca.x + ca.width + 2 <= w && ca.y + ca.height + 2 <= h);
            for cb in &charts[a + 1..] {
                let apart = ca.x + ca.width + 4 <= cb.x
                    || cb.x + cb.width + 4 <= ca.x
                    || ca.y + ca.height + 4 <= cb.y
                    || cb.y + cb.height + 4 <= ca.y;
                assert!(apart, "{ca:?} and {cb:?} overlap or touch");
            }
        }
    }

    #[test]
    fn texel_centres_are_where_a_bilinear_lookup_reads_the_texel() {
        let c = chart(4, 2);
        assert_eq!(c.texel_centre(0, 0, 0.0), glam::Vec2::new(0.125, 0.25));
        assert_eq!(c.texel_centre(3, 1, 0.0), glam::Vec2::new(0.875, 0.75));
        assert_eq!(c.texel_centre(0, 0, 0.5), glam::Vec2::new(0.25, 0.5));
        let q = c.point(glam::Vec2::new(0.75, 0.25)).unwrap();
        assert!((q.p - Vec3::new(0.5, -0.5, 0.0)).length() < 1e-6 && q.ng == Vec3::Z && q.ns == Vec3::Z);
    }

    #[test]
    fn a_map_reads_back_and_bad_tables_are_refused() {
        let scene = crate::toml::load_str(
            "[camera]\neye = [0, 1, 3]\ntarget = [0, 0, 0]\nup = [0, 1, 0]\nfov = 40\n[film]\nwidth = 8\nheight = 8\n\
             [[material]]\nname = \"m\"\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
             [[shape]]\nname = \"a\"\ntype = \"rectangle\"\ncenter = [0, 0, 0]\nhalf_u = [1, 0, 0]\nhalf_v = [0, 0, -1]\nmaterial = \"m\"\n\
             [[shape]]\nname = \"b\"\ntype = \"disk\"\ncenter = [0, 1, 0]\nhalf_u = [1, 0, 0]\nhalf_v = [0, 0, -2]\nmaterial = \"m\"\n",
            std::path::Path::new("t.toml"),
        )
        .unwrap();
        let layout = layout(&scene, 4, 1, &[]).unwrap();
        let n = (layout.width * layout.height) as usize;
        let map = LightMap {
            layout,
            irradiance: (0..n).map(|i| Vec3::splat(i as f32)).collect(),
            variance: vec![Vec3::ONE; n],
            covered: (0..n).map(|i| i % 3 == 0).collect(),
        };
        let img = map.to_image();
        assert_eq!(LightMap::from_image(&img, &scene).unwrap(), map);
        let with = |table: &str| {
            let mut bad = img.clone();
            bad.set_attribute("verity.lightmap.charts", table);
            LightMap::from_image(&bad, &scene).unwrap_err()
        };
        let e = with("a 0 0 3 3; b 2 2 3 3");
        assert!(e.contains("overlaps the chart of `a`"), "{e}");
        let e = with("a 0 0 3 3; c 4 0 1 1");
        assert!(e.contains("no shape `c`"), "{e}");
        let e = with("a 0 0 300 3");
        assert!(e.contains("leaves"), "{e}");
        let e = with("a 0 0 x 3");
        assert!(e.contains("whole texels"), "{e}");
        let e = with("a 0 0 1 1; a 2 2 1 1");
        assert!(e.contains("second chart"), "{e}");
    }

    #[test]
    fn dilation_fills_rings_from_the_covered_texels() {
        let layout = Layout {
            width: 5,
            height: 1,
            charts: vec![chart(1, 1)],
        };
        let mut m = LightMap {
            layout,
            irradiance: vec![Vec3::ZERO, Vec3::ZERO, Vec3::splat(3.0), Vec3::ZERO, Vec3::ZERO],
            variance: vec![Vec3::ZERO; 5],
            covered: vec![false, false, true, false, false],
        };
        m.dilate(1);
        assert_eq!(m.irradiance[1], Vec3::splat(3.0));
        assert_eq!(m.irradiance[0], Vec3::ZERO);
        m.dilate(2);
        assert_eq!(m.irradiance[0], Vec3::splat(3.0));
        assert_eq!(m.covered, vec![false, false, true, false, false]);
    }
}
