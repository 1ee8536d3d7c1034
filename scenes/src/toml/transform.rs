//! `transform = [ {translate = …}, {rotate = {axis, angle}}, {scale = …}, {matrix = …} ]`:
//! affine maps applied in list order (the first entry acts on the shape first).

use glam::{Affine3A, Mat3, Vec3};

use super::read::Field;
use crate::SceneError;

const STEPS: &[&str] = &["translate", "rotate", "scale", "matrix"];

/// Reads a transform list into one affine map M = Tₙ ∘ … ∘ T₁. Singular maps are refused.
pub(crate) fn read(field: &Field) -> Result<Affine3A, SceneError> {
    let mut m = Affine3A::IDENTITY;
    for step in field.array()? {
        let t = step.table()?;
        t.only(STEPS, "a transform step")?;
        let kind = t.one_of(STEPS)?.ok_or_else(|| {
            step.err("empty transform step").hint(
                "each step is one of {translate = [x, y, z]}, {rotate = {axis = [x, y, z], angle = deg}}, \
                     {scale = s or [sx, sy, sz]}, {matrix = [[4 numbers] × 3 or 4 rows]}",
            )
        })?;
        let f = t.req(kind)?;
        let s = match kind {
            "translate" => Affine3A::from_translation(f.position()?),
            "rotate" => rotation(&f)?,
            "scale" => scaling(&f)?,
            _ => matrix(&f)?,
        };
        m = s * m;
        if !(m.is_finite() && m.to_cols_array().iter().all(|v| v.abs() <= crate::MAX_COORD)) {
            return Err(f
                .err(format!(
                    "the transform reaches beyond ±{:e} (factors or offsets)",
                    crate::MAX_COORD
                ))
                .hint("scene coordinates are limited so that products of them stay finite in f32"));
        }
    }
    // In f64: the product of three factors of up to 1e15 overflows f32.
    let det = Mat3::from(m.matrix3).as_dmat3().determinant();
    let size = Mat3::from(m.matrix3)
        .to_cols_array()
        .iter()
        .fold(0.0f32, |a, v| a.max(v.abs()));
    if det.abs() <= 1e-9 * f64::from(size).powi(3) {
        return Err(field
            .err(format!("the transform is singular (determinant {det})"))
            .hint("a zero scale flattens the shape; use a small non-zero scale or remove the shape"));
    }
    Ok(m)
}

/// `rotate = { axis = [x, y, z], angle = degrees }`, counter-clockwise looking down the axis
/// towards the origin (right-hand rule).
fn rotation(f: &Field) -> Result<Affine3A, SceneError> {
    let t = f.table()?;
    t.only(&["axis", "angle"], "a rotation")?;
    let axis = t.req("axis")?.direction()?;
    let angle = t.req("angle")?.f32()?;
    Ok(Affine3A::from_axis_angle(axis, angle.to_radians()))
}

/// `scale = s` or `scale = [sx, sy, sz]`.
fn scaling(f: &Field) -> Result<Affine3A, SceneError> {
    Ok(Affine3A::from_scale(f.rgb()?))
}

/// `matrix = [[a, b, c, tx], [d, e, f, ty], [g, h, i, tz]]` (row-major), optionally with a
/// fourth row that must be `[0, 0, 0, 1]`.
fn matrix(f: &Field) -> Result<Affine3A, SceneError> {
    let rows = f.array()?;
    if !(rows.len() == 3 || rows.len() == 4) {
        return Err(f.err(format!(
            "expected 3 or 4 rows of 4 numbers, found {} rows",
            rows.len()
        )));
    }
    let r: Vec<[f32; 4]> = rows.iter().map(Field::floats::<4>).collect::<Result<_, _>>()?;
    if r.len() == 4 && r[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(rows[3].err("the last row of an affine matrix must be [0, 0, 0, 1]"));
    }
    let col = |j: usize| Vec3::new(r[0][j], r[1][j], r[2][j]);
    Ok(Affine3A::from_cols(
        col(0).into(),
        col(1).into(),
        col(2).into(),
        col(3).into(),
    ))
}

/// The uniform scale of a similarity (rotation × uniform scale × translation), or None.
pub(crate) fn uniform_scale(m: &Affine3A) -> Option<f32> {
    let c = [m.matrix3.x_axis, m.matrix3.y_axis, m.matrix3.z_axis].map(Vec3::from);
    let s = c[0].length();
    let tol = 1e-4 * s * s;
    let lengths_equal = c.iter().all(|v| (v.length_squared() - s * s).abs() <= tol);
    let orthogonal =
        c[0].dot(c[1]).abs() <= tol && c[1].dot(c[2]).abs() <= tol && c[0].dot(c[2]).abs() <= tol;
    (lengths_equal && orthogonal).then_some(s)
}
