//! Bounds-checked accessor reading (glTF 2.0 spec, "Accessors", including "Sparse
//! Accessors"). Every byte range is checked against its buffer view before it is read, so a
//! malformed file yields an error naming the field instead of a panic.
//!
//! Normalized integers decode with the glTF 2.0 spec's int-to-float table (given in
//! "Animations", reused by `KHR_mesh_quantization`): i8 → max(c/127, −1), u8 → c/255, i16 → max(c/32767, −1),
//! u16 → c/65535. Non-normalized integers convert to float by value.
//!
//! What an accessor's `count` makes the loader allocate is charged to the load's memory
//! ledger before the allocation (an accessor without a buffer view declares any count, and
//! becomes that many zeros).

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::Accessor;

use super::source::Asset;
use crate::budget::bytes_of;
use crate::error::SceneError;

/// A component storage a use of an accessor accepts: (component type, normalized).
pub(super) type Storage = (DataType, bool);

/// Only 32-bit floats (core glTF for POSITION, NORMAL, TANGENT).
pub(super) const FLOAT: &[Storage] = &[(DataType::F32, false)];

/// Any integer or float storage (KHR_mesh_quantization positions and texture coordinates).
pub(super) const ANY: &[Storage] = &[
    (DataType::F32, false),
    (DataType::I8, false),
    (DataType::I8, true),
    (DataType::U8, false),
    (DataType::U8, true),
    (DataType::I16, false),
    (DataType::I16, true),
    (DataType::U16, false),
    (DataType::U16, true),
];

/// Core glTF texture coordinates: float, or normalized u8/u16.
pub(super) const TEXCOORD: &[Storage] = &[
    (DataType::F32, false),
    (DataType::U8, true),
    (DataType::U16, true),
];

/// Unit vectors under KHR_mesh_quantization: float, or normalized i8/i16.
pub(super) const UNIT_QUANTIZED: &[Storage] = &[
    (DataType::F32, false),
    (DataType::I8, true),
    (DataType::I16, true),
];

/// A contiguous strided run of elements inside one buffer view.
struct Span<'a> {
    data: &'a [u8],
    stride: usize,
    elem: usize,
}

impl Span<'_> {
    fn element(&self, i: usize) -> &[u8] {
        &self.data[i * self.stride..i * self.stride + self.elem]
    }
}

/// Reads `accessor` as `count` vectors of `N` floats, checking its type against `allowed`.
/// `field` names the use (e.g. `meshes[0].primitives[1].attributes.NORMAL`).
pub(super) fn read_vec<const N: usize>(
    asset: &Asset,
    accessor: &Accessor,
    allowed: &[Storage],
    field: &str,
) -> Result<Vec<[f32; N]>, SceneError> {
    let want = match N {
        1 => Dimensions::Scalar,
        2 => Dimensions::Vec2,
        3 => Dimensions::Vec3,
        _ => Dimensions::Vec4,
    };
    let (ty, normalized) = (accessor.data_type(), accessor.normalized());
    if accessor.dimensions() != want || !allowed.contains(&(ty, normalized)) {
        let norm = if normalized { " normalized" } else { "" };
        return Err(asset.err(
            field,
            format!(
                "accessors[{}] is {:?} of{norm} {ty:?}; this attribute needs {want:?} of {}",
                accessor.index(),
                accessor.dimensions(),
                describe(allowed)
            ),
        ));
    }
    let size = ty.size();
    read(asset, accessor, field, N * size, [0.0; N], |b| {
        std::array::from_fn(|c| decode(&b[c * size..], ty, normalized))
    })
}

/// Reads an index accessor (unsigned byte, short or int scalars; glTF 2.0 "Meshes").
pub(super) fn read_indices(asset: &Asset, accessor: &Accessor, field: &str) -> Result<Vec<u32>, SceneError> {
    let ty = accessor.data_type();
    let ok = matches!(ty, DataType::U8 | DataType::U16 | DataType::U32);
    if accessor.dimensions() != Dimensions::Scalar || !ok || accessor.normalized() {
        return Err(asset.err(
            field,
            format!(
                "accessors[{}] is {:?} of {ty:?}; indices must be SCALAR of unsigned byte, short or int",
                accessor.index(),
                accessor.dimensions()
            ),
        ));
    }
    read(asset, accessor, field, ty.size(), 0, |b| decode_index(b, ty))
}

/// Reads every element of `accessor` (dense, then sparse substitutions) with `decode`,
/// which receives exactly `elem` bytes.
fn read<T: Copy>(
    asset: &Asset,
    accessor: &Accessor,
    field: &str,
    elem: usize,
    zero: T,
    decode: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, SceneError> {
    let count = accessor.count();
    let what = format!("accessors[{}]", accessor.index());
    asset.charge(
        bytes_of(count as u64, std::mem::size_of::<T>() as u64),
        &format!("the {count} values read for {field}"),
        &format!("{what}.count"),
    )?;
    let mut out = match accessor.view() {
        Some(view) => {
            let span = span(asset, &view, accessor.offset(), count, elem, field, &what)?;
            (0..count).map(|i| decode(span.element(i))).collect()
        }
        None => vec![zero; count],
    };
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        let indices = sparse.indices();
        let idx_ty = match indices.index_type() {
            ::gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            ::gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            ::gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let idx_what = format!("{what}.sparse.indices");
        let idx = span(
            asset,
            &indices.view(),
            indices.offset(),
            n,
            idx_ty.size(),
            field,
            &idx_what,
        )?;
        let values = sparse.values();
        let val_what = format!("{what}.sparse.values");
        let val = span(asset, &values.view(), values.offset(), n, elem, field, &val_what)?;
        for k in 0..n {
            let i = decode_index(idx.element(k), idx_ty) as usize;
            let slot = out.get_mut(i).ok_or_else(|| {
                asset.err(
                    field,
                    format!("{idx_what}[{k}] = {i} is out of range (count {count})"),
                )
            })?;
            *slot = decode(val.element(k));
        }
    }
    Ok(out)
}

/// The strided run of `count` elements of `elem` bytes at `offset` in `view`, checked to
/// lie inside the view (glTF 2.0 "Data Alignment": stride ≥ element size).
fn span<'a>(
    asset: &'a Asset,
    view: &::gltf::buffer::View,
    offset: usize,
    count: usize,
    elem: usize,
    field: &str,
    what: &str,
) -> Result<Span<'a>, SceneError> {
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(asset.err(
            field,
            format!(
                "{what}: bufferViews[{}].byteStride {stride} is smaller than one element ({elem} bytes)",
                view.index()
            ),
        ));
    }
    let data = asset.view_bytes(view);
    if count == 0 {
        return Ok(Span {
            data: &[],
            stride,
            elem,
        });
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|x| x.checked_add(elem))
        .and_then(|x| x.checked_add(offset));
    match end {
        Some(end) if end <= data.len() => Ok(Span {
            data: &data[offset..end],
            stride,
            elem,
        }),
        _ => Err(asset.err(
            field,
            format!(
                "{what}: {count} elements of {elem} bytes (stride {stride}) from byte {offset} run past the end of bufferViews[{}] ({} bytes)",
                view.index(),
                data.len()
            ),
        )),
    }
}

/// One component as f32 (normalized-integer table in the module header).
fn decode(b: &[u8], ty: DataType, normalized: bool) -> f32 {
    let raw = match ty {
        DataType::F32 => return f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        DataType::I8 => b[0] as i8 as f32,
        DataType::U8 => b[0] as f32,
        DataType::I16 => i16::from_le_bytes([b[0], b[1]]) as f32,
        DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as f32,
        DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
    };
    if !normalized {
        return raw;
    }
    match ty {
        DataType::I8 => (raw / 127.0).max(-1.0),
        DataType::U8 => raw / 255.0,
        DataType::I16 => (raw / 32767.0).max(-1.0),
        DataType::U16 => raw / 65535.0,
        _ => raw,
    }
}

/// One unsigned index.
fn decode_index(b: &[u8], ty: DataType) -> u32 {
    match ty {
        DataType::U8 => b[0] as u32,
        DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// "float, normalized unsigned byte, …" for messages.
fn describe(allowed: &[Storage]) -> String {
    let names: Vec<String> = allowed
        .iter()
        .map(|(ty, n)| format!("{}{ty:?}", if *n { "normalized " } else { "" }))
        .collect();
    names.join(" or ")
}
