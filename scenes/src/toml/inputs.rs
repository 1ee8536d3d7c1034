//! Material inputs: constants or image textures (loaded once per file, colour space and
//! wrap mode), and the registry of the scene's textures.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;

use super::read::Field;
use crate::budget::{Exceeded, Ledger};
use crate::model::{NormalMap, Rgb, TexRgb, TexScalar, WrapMode};
use crate::texture::{load_texture_in, ColorSpace, Texture};
use crate::SceneError;

/// The range a reflectance-like or radiance-like constant must lie in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Bound {
    /// Every component in [0, 1] (reflectances: more would create energy).
    Unit,
    /// Every component in [0, [`crate::MAX_RADIANCE`]] (radiance, intensity, irradiance).
    NonNegative,
}

impl Bound {
    fn check(self, field: &Field, values: &[f32]) -> Result<(), SceneError> {
        let ok = |v: f32| match self {
            Bound::Unit => (0.0..=1.0).contains(&v),
            Bound::NonNegative => (0.0..=crate::MAX_RADIANCE).contains(&v),
        };
        if values.iter().all(|&v| ok(v)) {
            return Ok(());
        }
        let (what, hint) = match self {
            Bound::Unit => (
                "must lie in [0, 1]",
                "a reflectance above 1 creates energy; scale the lights instead",
            ),
            Bound::NonNegative => (
                "must lie in [0, 1e20]",
                "negative light is not physical, and more than 1e20 overflows f32 once multiplied by a BSDF and a pdf",
            ),
        };
        Err(field.err(format!("{what}, got {values:?}")).hint(hint))
    }
}

/// The scene's textures, each file loaded once per (colour space, wrap mode), charged to the
/// scene's memory ledger as they load.
pub(crate) struct Textures<'a> {
    pub list: Vec<Arc<Texture>>,
    /// (source, colour space, wrap) of each entry of `list`.
    keys: Vec<(Source, ColorSpace, [WrapMode; 2])>,
    /// The scene's memory budget.
    pub ledger: &'a Ledger,
}

/// Where a texture of the registry came from.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Source {
    /// An image file (resolved path).
    File(PathBuf),
    /// Generated at load time, named by its parameters.
    Generated(String),
}

impl<'a> Textures<'a> {
    /// An empty registry charging `ledger`.
    pub fn new(ledger: &'a Ledger) -> Self {
        Textures {
            list: Vec::new(),
            keys: Vec::new(),
            ledger,
        }
    }

    /// Loads (or reuses) the image named by the string `file`, relative to the scene file.
    pub fn load(
        &mut self,
        file: &Field,
        space: ColorSpace,
        wrap: [WrapMode; 2],
    ) -> Result<usize, SceneError> {
        let path = file.ctx.resolve(file.str()?);
        let key = (Source::File(path.clone()), space, wrap);
        if let Some(i) = self.keys.iter().position(|k| *k == key) {
            return Ok(i);
        }
        file.input_file(&path)?;
        let texture = load_texture_in(&path, space, wrap, self.ledger)
            .map_err(|e| file.err(format!("cannot load the texture: {e}")))?;
        self.list.push(Arc::new(texture));
        self.keys.push(key);
        Ok(self.list.len() - 1)
    }

    /// Adds (or reuses) a linear `side`² texture generated at load time, named uniquely by
    /// `name` (its generator and parameters); its texels are charged to the ledger first.
    pub fn generated(
        &mut self,
        name: String,
        side: u32,
        wrap: [WrapMode; 2],
        make: impl FnOnce() -> Texture,
    ) -> Result<usize, Exceeded> {
        let key = (Source::Generated(name.clone()), ColorSpace::Linear, wrap);
        if let Some(i) = self.keys.iter().position(|k| *k == key) {
            return Ok(i);
        }
        let texels = u64::from(side) * u64::from(side);
        self.ledger.charge(
            texels * std::mem::size_of::<glam::Vec4>() as u64,
            format!("the {name} texels"),
        )?;
        self.list.push(Arc::new(make()));
        self.keys.push(key);
        Ok(self.list.len() - 1)
    }
}

const RGB_FIELDS: &[&str] = &["texture", "factor", "wrap", "color_space"];
const SCALAR_FIELDS: &[&str] = &["texture", "channel", "factor", "wrap", "color_space"];

/// A colour input: `[r, g, b]`, a number, or `{ texture, factor, wrap, color_space }`
/// (colour space defaults to sRGB).
pub(crate) fn rgb_input(field: &Field, bound: Bound, textures: &mut Textures) -> Result<TexRgb, SceneError> {
    if !field.is_table() {
        let c = field.rgb()?;
        bound.check(field, &c.to_array())?;
        return Ok(TexRgb::Constant(c));
    }
    let t = field.table()?;
    t.only(RGB_FIELDS, "a texture input")?;
    let factor = match t.get("factor") {
        Some(f) => {
            let c = f.rgb()?;
            bound.check(&f, &c.to_array())?;
            c
        }
        None => Vec3::ONE,
    };
    let texture = load_input(&t.req("texture")?, &t, ColorSpace::Srgb, textures)?;
    Ok(TexRgb::Image { texture, factor })
}

/// A scalar input: a number, or `{ texture, channel, factor, wrap, color_space }` (colour
/// space defaults to linear; `default_channel` follows glTF: roughness G = 1, metallic B = 2).
pub(crate) fn scalar_input(
    field: &Field,
    default_channel: usize,
    textures: &mut Textures,
) -> Result<TexScalar, SceneError> {
    if !field.is_table() {
        let v = field.f32()?;
        Bound::Unit.check(field, &[v])?;
        return Ok(TexScalar::Constant(v));
    }
    let t = field.table()?;
    t.only(SCALAR_FIELDS, "a texture input")?;
    let channel = match t.get("channel") {
        Some(c) => c.int_in(0, 3)? as usize,
        None => default_channel,
    };
    let factor = match t.get("factor") {
        Some(f) => {
            let v = f.f32()?;
            Bound::Unit.check(&f, &[v])?;
            v
        }
        None => 1.0,
    };
    let texture = load_input(&t.req("texture")?, &t, ColorSpace::Linear, textures)?;
    Ok(TexScalar::Image {
        texture,
        channel,
        factor,
    })
}

/// A tangent-space normal map: `{ texture, scale = 1, wrap }`, always linear.
pub(crate) fn normal_map(field: &Field, textures: &mut Textures) -> Result<NormalMap, SceneError> {
    let t = field.table()?;
    t.only(&["texture", "scale", "wrap"], "a normal map")?;
    let scale = t.f32_or("scale", 1.0)?;
    let wrap = match t.get("wrap") {
        Some(w) => wrap_modes(&w)?,
        None => [WrapMode::Repeat; 2],
    };
    let texture = textures.load(&t.req("texture")?, ColorSpace::Linear, wrap)?;
    Ok(NormalMap { texture, scale })
}

/// The shared part of texture inputs: wrap mode, colour space override, loading.
fn load_input(
    file: &Field,
    t: &super::read::Table,
    default_space: ColorSpace,
    textures: &mut Textures,
) -> Result<usize, SceneError> {
    let wrap = match t.get("wrap") {
        Some(w) => wrap_modes(&w)?,
        None => [WrapMode::Repeat; 2],
    };
    let space = match t.get("color_space") {
        Some(c) => match c.keyword(&["srgb", "linear"])? {
            "srgb" => ColorSpace::Srgb,
            _ => ColorSpace::Linear,
        },
        None => default_space,
    };
    textures.load(file, space, wrap)
}

/// `"repeat"` for both axes, or `["repeat", "clamp"]` for u and v.
pub(crate) fn wrap_modes(field: &Field) -> Result<[WrapMode; 2], SceneError> {
    const WORDS: &[&str] = &["repeat", "clamp", "mirror"];
    let one = |f: &Field| {
        f.keyword(WORDS).map(|w| match w {
            "clamp" => WrapMode::Clamp,
            "mirror" => WrapMode::Mirror,
            _ => WrapMode::Repeat,
        })
    };
    if field.str().is_ok() {
        let m = one(field)?;
        return Ok([m, m]);
    }
    let items = field
        .array()
        .map_err(|_| field.err("expected \"repeat\", \"clamp\", \"mirror\" or an array [u_mode, v_mode]"))?;
    match items.as_slice() {
        [u, v] => Ok([one(u)?, one(v)?]),
        _ => Err(field.err(format!("expected 2 wrap modes [u, v], found {}", items.len()))),
    }
}

/// A plain RGB constant (no textures) within `bound`, or `default` when absent.
pub(crate) fn rgb_const(field: Option<Field>, bound: Bound, default: Rgb) -> Result<Rgb, SceneError> {
    match field {
        Some(f) => {
            let c = f.rgb()?;
            bound.check(&f, &c.to_array())?;
            Ok(c)
        }
        None => Ok(default),
    }
}
