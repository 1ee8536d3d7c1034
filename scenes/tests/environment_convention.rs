//! The environment-map convention against values measured from Mitsuba 3.9.1 `envmap`
//! (`emitter.eval` on an 8×4 image whose texel (i, j) holds (i, j, 1)); docs/ARCHITECTURE.md
//! "Environment map".

use glam::{Vec2, Vec3, Vec4};
use scenes::texture::Texture;
use scenes::{environment_lookup, equirect_direction, equirect_uv, WrapMode};

fn probe_image() -> Texture {
    let (w, h) = (8u32, 4u32);
    let texels = (0..h)
        .flat_map(|j| (0..w).map(move |i| Vec4::new(i as f32, j as f32, 1.0, 1.0)))
        .collect();
    Texture::from_texels(w, h, texels, [WrapMode::Repeat, WrapMode::Clamp])
}

#[test]
fn lookup_matches_mitsuba_envmap() {
    let tex = probe_image();
    // (u, v) → Mitsuba's (R, G) at the direction with those equirectangular coordinates.
    let measured = [
        ((0.0625, 0.125), (0.0, 0.375)),
        ((0.1875, 0.375), (1.0, 1.125)),
        ((0.125, 0.25), (0.5, 0.75)),
        ((0.0, 0.5), (3.5, 1.5)),
        ((0.25, 0.5), (1.5, 1.5)),
        ((0.999, 0.5), (3.556, 1.5)),
    ];
    for ((u, v), (r, g)) in measured {
        let got = environment_lookup(&tex, equirect_direction(Vec2::new(u, v)));
        assert!(
            (got.x - r).abs() < 2e-3 && (got.y - g).abs() < 2e-3,
            "uv ({u}, {v}): got ({}, {}), Mitsuba ({r}, {g})",
            got.x,
            got.y
        );
    }
}

#[test]
fn equirect_orientation_is_mitsubas() {
    let cases = [
        (Vec3::NEG_Z, 0.0),
        (Vec3::X, 0.25),
        (Vec3::Z, 0.5),
        (Vec3::NEG_X, 0.75),
    ];
    for (d, u) in cases {
        let uv = equirect_uv(d);
        let du = (uv.x - u).abs().min(1.0 - (uv.x - u).abs());
        assert!(
            du < 1e-6 && (uv.y - 0.5).abs() < 1e-6,
            "{d}: uv {uv}, expected ({u}, 0.5)"
        );
    }
    assert!(equirect_uv(Vec3::Y).y < 1e-6, "+Y must be row 0");
    for uv in [Vec2::new(0.1, 0.2), Vec2::new(0.7, 0.9), Vec2::new(0.45, 0.5)] {
        let back = equirect_uv(equirect_direction(uv));
        assert!((back - uv).length() < 1e-5, "{uv} → {back}");
    }
}
